// Tangent-space normal mapping (both tiers): the map's normal, its xy scaled by the material's
// normal scale, in the frame of the interpolated tangent (Gram-Schmidt against n) and
// bitangent cross(n, t) * w, the glTF convention. Needs vTangent, and for the material's
// own map (HAS_NORMAL_MAP) uNormalMap and SLOT_UV; the clearcoat's map (PBR tier) goes
// through glviewTangentToEye with its own sample.
IN vec4 vTangent;

// `m`: the map's normal in [-1, 1], xy already scaled.
vec3 glviewTangentToEye(vec3 n, bool front, vec3 m) {
    // A back face is lit with the flipped normal; tangent and bitangent flip with it (as
    // the glTF Sample Viewer does), so the map's relief reads the same from both sides.
    float side = front ? 1.0 : -1.0;
    vec3 tv = vTangent.xyz * side;
    vec3 t = tv - n * dot(n, tv);
    float tl = length(t);
    if (tl <= 0.0) return n;
    t /= tl;
    vec3 b = cross(n, t) * (vTangent.w < 0.0 ? -side : side);
    vec3 r = t * m.x + b * m.y + n * m.z;
    float len = length(r);
    return len > 0.0 ? r / len : n;
}

#ifdef HAS_NORMAL_MAP
uniform sampler2D uNormalMap;
uniform float uNormalScale;

vec3 glviewNormalMap(vec3 n, bool front) {
    vec3 m = TEX2D(uNormalMap, SLOT_UV(2)).rgb * 2.0 - 1.0;
    m.xy *= uNormalScale;
    return glviewTangentToEye(n, front, m);
}
#endif
