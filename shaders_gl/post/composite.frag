// The end of an offscreen frame: scene + strength * bloom (upsampled bilinearly), then the
// output step (the legacy clamp, or exposure, tone mapping and sRGB for PBR).
// FRAME_RGBM: both inputs are RGBM (nearest); the bloom's bilinear upsampling is done here on
// decoded texels, and alpha is 1 (the frame's alpha held the multiplier).
IN vec2 vUv;
uniform sampler2D uImage;
uniform sampler2D uBloom;
uniform vec2 uBloomSize;      // texels of the bloom level (FRAME_RGBM)
uniform float uStrength;
uniform float uSceneWeight;   // 0 for the bloom teaching view
#include "rgbm.glsl"
#include "output.glsl"

#ifdef FRAME_RGBM
vec3 glviewBloomAt(vec2 uv) {
    vec2 p = uv * uBloomSize - 0.5;
    vec2 f = fract(p);
    vec2 t0 = (floor(p) + 0.5) / uBloomSize;
    vec2 d = 1.0 / uBloomSize;
    vec3 a = glviewRgbmDecode(TEX2D(uBloom, t0));
    vec3 b = glviewRgbmDecode(TEX2D(uBloom, t0 + vec2(d.x, 0.0)));
    vec3 c = glviewRgbmDecode(TEX2D(uBloom, t0 + vec2(0.0, d.y)));
    vec3 e = glviewRgbmDecode(TEX2D(uBloom, t0 + d));
    return mix(mix(a, b, f.x), mix(c, e, f.x), f.y);
}
#endif

void main() {
#ifdef FRAME_RGBM
    vec3 c = uSceneWeight * glviewRgbmDecode(TEX2D(uImage, vUv)) + uStrength * glviewBloomAt(vUv);
    FRAG_COLOR = vec4(glviewOutput(c), 1.0);
#else
    vec4 s = TEX2D(uImage, vUv);
    vec3 c = uSceneWeight * s.rgb + uStrength * TEX2D(uBloom, vUv).rgb;
    FRAG_COLOR = vec4(glviewOutput(c), s.a);
#endif
}
