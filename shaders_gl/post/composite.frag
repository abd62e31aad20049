// The end of an offscreen frame: scene + strength * bloom (upsampled bilinearly), then the
// output step (the legacy clamp, or exposure, tone mapping and sRGB for PBR).
IN vec2 vUv;
uniform sampler2D uImage;
uniform sampler2D uBloom;
uniform float uStrength;
uniform float uSceneWeight;   // 0 for the bloom teaching view
#include "output.glsl"

void main() {
    vec4 s = TEX2D(uImage, vUv);
    vec3 c = uSceneWeight * s.rgb + uStrength * TEX2D(uBloom, vUv).rgb;
    FRAG_COLOR = vec4(glviewOutput(c), s.a);
}
