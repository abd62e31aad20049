// Skinning on the GPU (glTF skins, one JOINTS_0/WEIGHTS_0 set), vertex stage only. With
// SKINNED, the uploaded mesh is in bind space (the file's mesh-space positions, normals and
// tangents) and uJoints holds its skin's joint matrices in the scene's local coordinates
// (T(-origin) * up rotation * joint world * inverse bind), SKIN_JOINTS of them; without, the
// names are the identity, textually, so the other programs compile exactly as before.
#ifdef SKINNED
IN vec4 aJoints;    // joint indices as floats (GLSL 1.20 has no integer attributes)
IN vec4 aWeights;
uniform mat4 uJoints[SKIN_JOINTS];

mat4 skinMatrix() {
    return aWeights.x * uJoints[int(aJoints.x)] + aWeights.y * uJoints[int(aJoints.y)]
         + aWeights.z * uJoints[int(aJoints.z)] + aWeights.w * uJoints[int(aJoints.w)];
}

vec3 skinPoint(vec3 p) {
    return (skinMatrix() * vec4(p, 1.0)).xyz;
}

// Normals go by the cofactor matrix (the inverse transpose times the determinant: GLSL 1.20
// has no inverse()), its sign taken out, as the CPU pose's inverse transpose; normalised.
vec3 skinNormal(vec3 n) {
    mat4 s = skinMatrix();
    vec3 a = s[0].xyz;
    vec3 b = s[1].xyz;
    vec3 c = s[2].xyz;
    vec3 m = mat3(cross(b, c), cross(c, a), cross(a, b)) * n * sign(dot(a, cross(b, c)));
    float l = length(m);
    return l > 0.0 ? m / l : n;
}

// Tangents follow the linear part, normalised; a mirroring matrix flips the handedness.
vec3 skinDirection(vec3 t) {
    vec3 m = mat3(skinMatrix()) * t;
    float l = length(m);
    return l > 0.0 ? m / l : t;
}

float skinHanded(float w) {
    mat4 s = skinMatrix();
    return dot(s[0].xyz, cross(s[1].xyz, s[2].xyz)) < 0.0 ? -w : w;
}
#else
#define skinPoint(p) (p)
#define skinNormal(n) (n)
#define skinDirection(t) (t)
#define skinHanded(w) (w)
#endif
