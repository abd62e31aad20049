// The legacy-tier formula of src/shading.rs, one light at a time, in eye space.
// x = diffuse factor (max(N.L, 0), or (1 + N.L)/2 with uWrap), y = specular factor
// (0 where N.L <= 0; 1 where Ns <= 0, the limit x^0 = 1, so pow never sees 0^0 or a
// negative base).
uniform vec4 uLightPos[NUM_LIGHTS];   // w = 0: unit direction towards the light; w = 1: position
uniform vec3 uLightColor[NUM_LIGHTS];
uniform float uWrap;
uniform float uNs;

// A point light exactly at the surface has no direction: no diffuse or specular there,
// rather than normalize(0) = NaN.
vec3 toLight(vec4 lp, vec3 p) {
    if (lp.w == 0.0) return lp.xyz;
    vec3 d = lp.xyz - p;
    float len = length(d);
    return len > 0.0 ? d / len : vec3(0.0);
}

vec2 lightFactors(vec3 l, vec3 n, vec3 v) {
    float nl = dot(n, l);
    float d = uWrap > 0.5 ? (1.0 + nl) * 0.5 : max(nl, 0.0);
    float s = 0.0;
    if (nl > 0.0) {
        if (uNs <= 0.0) {
            s = 1.0;
        } else {
            float rv = dot(reflect(-l, n), v);
            s = rv > 0.0 ? pow(rv, uNs) : 0.0;
        }
    }
    return vec2(d, s);
}

// A unit normal even when interpolation or the file gave a zero vector.
vec3 safeNormalize(vec3 n) {
    float len = length(n);
    return len > 0.0 ? n / len : vec3(0.0, 0.0, 1.0);
}
