// Background: the environment (one specular level: sharp, or blurred) through the PBR output
// step, so it matches what the model reflects.
IN vec3 vEyeDir;
uniform samplerCube uSky;
uniform mat3 uEnvFromEye;
uniform float uIblIntensity;
#include "output.glsl"

void main() {
    vec4 t = TEXCUBE(uSky, uEnvFromEye * normalize(vEyeDir));
#ifdef IBL_RGBM
    vec3 c = t.rgb * t.a * 16.0;
#else
    vec3 c = t.rgb;
#endif
    FRAG_COLOR = glviewOutputRgba(c * uIblIntensity, 1.0);
}
