// Skinning on the GPU (glTF skins: JOINTS_0/WEIGHTS_0, and JOINTS_1/WEIGHTS_1 with
// SKIN_SETS 2, in the first two morph attributes' places), vertex stage only. With
// SKINNED, the uploaded mesh is in bind space (the file's mesh-space positions, normals and
// tangents) and uJoints holds its skin's joint matrices in the scene's local coordinates
// (T(-origin) * up rotation * joint world * inverse bind), SKIN_JOINTS of them; without, the
// names are the identity, textually, so the other programs compile exactly as before.
//
// Morph targets on the GPU (MORPHED, always with SKINNED: a morphed part is drawn as a
// one-joint skin, its node's matrix): MORPH_ATTRIBUTES delta streams aMorph0.., each one
// target's position, normal or tangent deltas; uMorphPosition/Normal/Tangent give, per
// slot, the weight of the target it carries for that kind (0 for the other kinds' slots),
// so the shader needs no table of which slot is what. Deltas are added before skinning,
// as the spec orders it.
#ifdef MORPHED
IN vec3 aMorph0;
#if MORPH_ATTRIBUTES > 1
IN vec3 aMorph1;
#endif
#if MORPH_ATTRIBUTES > 2
IN vec3 aMorph2;
#endif
#if MORPH_ATTRIBUTES > 3
IN vec3 aMorph3;
#endif
uniform vec4 uMorphPosition;
uniform vec4 uMorphNormal;
uniform vec4 uMorphTangent;

vec3 morphSum(vec4 w) {
    vec3 d = w.x * aMorph0;
#if MORPH_ATTRIBUTES > 1
    d += w.y * aMorph1;
#endif
#if MORPH_ATTRIBUTES > 2
    d += w.z * aMorph2;
#endif
#if MORPH_ATTRIBUTES > 3
    d += w.w * aMorph3;
#endif
    return d;
}
#define morphPoint(p) ((p) + morphSum(uMorphPosition))
#define morphNormal(n) ((n) + morphSum(uMorphNormal))
#define morphTangent(t) ((t) + morphSum(uMorphTangent))
#else
#define morphPoint(p) (p)
#define morphNormal(n) (n)
#define morphTangent(t) (t)
#endif

#ifdef SKINNED
IN vec4 aJoints;    // joint indices as floats (GLSL 1.20 has no integer attributes)
IN vec4 aWeights;
uniform mat4 uJoints[SKIN_JOINTS];
#if defined(SKIN_SETS) && SKIN_SETS > 1
IN vec4 aJoints1;
IN vec4 aWeights1;
#endif

// The sets in the file's order, as the CPU pose sums them.
mat4 skinMatrix() {
    mat4 m = aWeights.x * uJoints[int(aJoints.x)] + aWeights.y * uJoints[int(aJoints.y)]
           + aWeights.z * uJoints[int(aJoints.z)] + aWeights.w * uJoints[int(aJoints.w)];
#if defined(SKIN_SETS) && SKIN_SETS > 1
    m += aWeights1.x * uJoints[int(aJoints1.x)] + aWeights1.y * uJoints[int(aJoints1.y)]
       + aWeights1.z * uJoints[int(aJoints1.z)] + aWeights1.w * uJoints[int(aJoints1.w)];
#endif
    return m;
}

vec3 skinPoint(vec3 p) {
    return (skinMatrix() * vec4(morphPoint(p), 1.0)).xyz;
}

// Normals go by the cofactor matrix (the inverse transpose times the determinant: GLSL 1.20
// has no inverse()), its sign taken out, as the CPU pose's inverse transpose; normalised.
vec3 skinNormal(vec3 n0) {
    vec3 n = morphNormal(n0);
    mat4 s = skinMatrix();
    vec3 a = s[0].xyz;
    vec3 b = s[1].xyz;
    vec3 c = s[2].xyz;
    vec3 m = mat3(cross(b, c), cross(c, a), cross(a, b)) * n * sign(dot(a, cross(b, c)));
    float l = length(m);
    return l > 0.0 ? m / l : n;
}

// Tangents follow the linear part, normalised; a mirroring matrix flips the handedness.
vec3 skinDirection(vec3 t0) {
    vec3 t = morphTangent(t0);
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
