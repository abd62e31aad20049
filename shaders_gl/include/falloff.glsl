// KHR_lights_punctual's falloff of light i at the eye-space point p: src/light.rs
// `Falloff::at`, the same steps. window(d) / d² (the range's window clamp(1 - (d/range)^4,
// 0, 1) and the inverse square) times the spot's cone clamp(cos * scale + offset, 0, 1)^2.
// Only programs of frames with a file's light have FALLOFF; glview's own lights there have
// (0, 0, 0, 1): exactly 1. Needs uLightPos declared before it.
uniform vec4 uLightFalloff[NUM_LIGHTS];  // 1/range^2 (0: none), 1: inverse square, spot scale, offset
uniform vec3 uLightSpotDir[NUM_LIGHTS];  // unit, eye space, the way the spot shines (0: no spot)

float glviewFalloff(int i, vec3 p) {
#ifdef CONST_INDEX_ONLY
    vec4 f = vec4(0.0);
    vec4 lightPos = vec4(0.0);
    vec3 spotDir = vec3(0.0);
    for (int k = 0; k < NUM_LIGHTS; ++k) {
        if (k == i) {
            f = uLightFalloff[k];
            lightPos = uLightPos[k];
            spotDir = uLightSpotDir[k];
        }
    }
#else
    vec4 f = uLightFalloff[i];
    vec4 lightPos = uLightPos[i];
    vec3 spotDir = uLightSpotDir[i];
#endif
    vec3 d = lightPos.xyz - p;
    float d2 = dot(d, d);
    float r = d2 * f.x;
    float window = clamp(1.0 - r * r, 0.0, 1.0);
    float inv = f.y > 0.0 ? 1.0 / max(d2, 1e-8) : 1.0;
    float cd = d2 > 0.0 ? dot(spotDir, -d) * inversesqrt(d2) : 1.0;
    float a = clamp(cd * f.z + f.w, 0.0, 1.0);
    return window * inv * a * a;
}
