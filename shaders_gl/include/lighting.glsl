// The legacy-tier formula of src/shading.rs, one light at a time, in eye space.
// x = diffuse factor (max(N.L, 0), or (1 + N.L)/2 with WRAP), y = specular factor
// (0 where N.L <= 0; 1 where Ns <= 0, the limit x^0 = 1, so pow never sees 0^0 or a
// negative base). Branch-free: llvmpipe runs both sides of a branch for every 4x4 block of
// a triangle, and on small triangles the fragment shader is most of a frame's time.
uniform vec4 uLightPos[NUM_LIGHTS];   // w = 0: unit direction towards the light; w = 1: position
uniform float uNs;

// Without POINT_LIGHTS every light is directional and its direction is the uniform. A point
// light exactly at the surface has no direction: no diffuse or specular there, rather than
// normalize(0) = NaN.
vec3 toLight(vec4 lp, vec3 p) {
#ifdef POINT_LIGHTS
    vec3 d = lp.xyz - lp.w * p;
    float len2 = dot(d, d);
    return len2 > 0.0 ? d * inversesqrt(len2) : vec3(0.0);
#else
    return lp.xyz;
#endif
}

vec2 lightFactors(vec3 l, vec3 n, vec3 v) {
    float nl = dot(n, l);
#ifdef WRAP
    float d = (1.0 + nl) * 0.5;
#else
    float d = max(nl, 0.0);
#endif
    float rv = max(dot(reflect(-l, n), v), 0.0);
    float s = uNs > 0.0 ? pow(rv, uNs) : 1.0;
    return vec2(d, nl > 0.0 ? s : 0.0);
}

// A unit normal even when interpolation or the file gave a zero vector.
vec3 safeNormalize(vec3 n) {
    float len2 = dot(n, n);
    return len2 > 0.0 ? n * inversesqrt(len2) : vec3(0.0, 0.0, 1.0);
}
