// Hardware depth comparison (sampler2DShadow) with percentage-closer filtering: PCF_TAPS
// compared lookups on a regular grid around the projected point, averaged. Each lookup is
// itself bilinearly filtered where the driver supports LINEAR on depth textures.
uniform mat4 uShadowMatrix[NUM_SHADOWS];   // eye space -> shadow texture space (homogeneous)
uniform float uShadowTexel;                // 1 / map size
uniform float uShadowBias;                 // constant depth bias in [0,1] depth units
uniform float uShadowNormalOffset;         // eye-space distance along the normal

float shadowLookup(sampler2DShadow map, vec4 c) {
    if (c.w <= 0.0) return 1.0;
    vec3 q = c.xyz / c.w;
    // Outside the light's frustum nothing was rendered into the map: treat as lit.
    if (q.x < 0.0 || q.x > 1.0 || q.y < 0.0 || q.y > 1.0 || q.z > 1.0) return 1.0;
    q.z -= uShadowBias;
#if PCF_TAPS == 1
    return SHADOW2D(map, q);
#else
#if PCF_TAPS == 4
    const int N = 2;
#elif PCF_TAPS == 9
    const int N = 3;
#else
    const int N = 4;
#endif
    float sum = 0.0;
    float start = -0.5 * float(N - 1);
    for (int i = 0; i < N; ++i) {
        for (int j = 0; j < N; ++j) {
            vec2 o = vec2(start + float(i), start + float(j)) * uShadowTexel;
            sum += SHADOW2D(map, vec3(q.xy + o, q.z));
        }
    }
    return sum / float(N * N);
#endif
}

#if NUM_SHADOWS > 0
uniform sampler2DShadow uShadowMap0;
#endif
#if NUM_SHADOWS > 1
uniform sampler2DShadow uShadowMap1;
#endif
#if NUM_SHADOWS > 2
uniform sampler2DShadow uShadowMap2;
#endif
#if NUM_SHADOWS > 3
uniform sampler2DShadow uShadowMap3;
#endif
