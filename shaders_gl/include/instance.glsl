// EXT_mesh_gpu_instancing, vertex stage only. With INSTANCED, the uploaded mesh is the first
// instance's copy and each instance's matrix (its local coordinates from that copy's, one
// column per attribute, advancing once per instance) moves it; without, the three names are
// the identity, textually, so the other programs compile exactly as before.
#ifdef INSTANCED
IN vec4 aInstance0;
IN vec4 aInstance1;
IN vec4 aInstance2;
IN vec4 aInstance3;

vec3 instancePoint(vec3 p) {
    return (mat4(aInstance0, aInstance1, aInstance2, aInstance3) * vec4(p, 1.0)).xyz;
}

// Normals go by the cofactor matrix (the inverse transpose times the determinant: GLSL 1.20
// has no inverse()), its sign taken out, then normalised like the loader's copies.
vec3 instanceNormal(vec3 n) {
    vec3 a = aInstance0.xyz;
    vec3 b = aInstance1.xyz;
    vec3 c = aInstance2.xyz;
    vec3 m = mat3(cross(b, c), cross(c, a), cross(a, b)) * n * sign(dot(a, cross(b, c)));
    float l = length(m);
    return l > 0.0 ? m / l : n;
}

// Tangents follow the linear part, normalised like the loader's.
vec3 instanceDirection(vec3 t) {
    vec3 m = mat3(aInstance0.xyz, aInstance1.xyz, aInstance2.xyz) * t;
    float l = length(m);
    return l > 0.0 ? m / l : t;
}
#else
#define instancePoint(p) (p)
#define instanceNormal(n) (n)
#define instanceDirection(t) (t)
#endif
