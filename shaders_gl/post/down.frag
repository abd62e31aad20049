// Bloom, downsampling: one bilinear tap at the centre of each 2x2 block is their exact mean.
// FRAME_RGBM: RGBM does not interpolate, so the four texels are read (nearest, a quarter texel
// inside each) and decoded one by one.
IN vec2 vUv;
uniform sampler2D uImage;
uniform vec2 uSrcTexel;   // 1 / source size
#include "rgbm.glsl"

void main() {
#ifdef FRAME_RGBM
    vec2 o = 0.25 * uSrcTexel;
    vec3 c = glviewRgbmDecode(TEX2D(uImage, vUv + vec2(-o.x, -o.y)))
           + glviewRgbmDecode(TEX2D(uImage, vUv + vec2(o.x, -o.y)))
           + glviewRgbmDecode(TEX2D(uImage, vUv + vec2(-o.x, o.y)))
           + glviewRgbmDecode(TEX2D(uImage, vUv + vec2(o.x, o.y)));
    FRAG_COLOR = glviewRgbmEncode(0.25 * c);
#else
    FRAG_COLOR = vec4(TEX2D(uImage, vUv).rgb, 1.0);
#endif
}
