// Bloom, step 1: the bright part of the linear image: max channel b above the threshold t,
// with a quadratic soft knee of width k below it (zero under t - k):
//   w = max(b - t, (clamp(b - t + k, 0, 2k))^2 / 4k) / b,  out = colour * w.
// FRAME_RGBM: input and output are RGBM-encoded 8-bit (no float render targets).
IN vec2 vUv;
uniform sampler2D uImage;
uniform float uThreshold;
uniform float uKnee;
#include "rgbm.glsl"

void main() {
#ifdef FRAME_RGBM
    vec3 c = glviewRgbmDecode(TEX2D(uImage, vUv));
#else
    vec3 c = max(TEX2D(uImage, vUv).rgb, vec3(0.0));
#endif
    float b = max(c.r, max(c.g, c.b));
    float soft = clamp(b - uThreshold + uKnee, 0.0, 2.0 * uKnee);
    soft = uKnee > 0.0 ? soft * soft / (4.0 * uKnee) : 0.0;
    float w = max(b - uThreshold, soft) / max(b, 1e-6);
#ifdef FRAME_RGBM
    FRAG_COLOR = glviewRgbmEncode(c * max(w, 0.0));
#else
    FRAG_COLOR = vec4(c * max(w, 0.0), 1.0);
#endif
}
