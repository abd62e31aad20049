// Bloom, one axis of the separable Gaussian: taps at whole texels (nearest filtering), weights
// normalised on the CPU; texels beyond the edge read the edge (clamp).
// FRAME_RGBM: each tap decoded, the sum encoded.
IN vec2 vUv;
uniform sampler2D uImage;
uniform vec2 uStep;            // one texel along the blur axis
uniform float uWeights[33];    // centre first
uniform int uRadius;
#include "rgbm.glsl"

vec3 glviewTap(vec2 uv) {
#ifdef FRAME_RGBM
    return glviewRgbmDecode(TEX2D(uImage, uv));
#else
    return TEX2D(uImage, uv).rgb;
#endif
}

void main() {
    vec3 c = glviewTap(vUv) * uWeights[0];
    for (int i = 1; i <= 32; ++i) {
        if (i > uRadius) break;
        float fi = float(i);
        c += (glviewTap(vUv + uStep * fi) + glviewTap(vUv - uStep * fi)) * uWeights[i];
    }
#ifdef FRAME_RGBM
    FRAG_COLOR = glviewRgbmEncode(c);
#else
    FRAG_COLOR = vec4(c, 1.0);
#endif
}
