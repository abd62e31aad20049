// KHR_materials_anisotropy's lobe (the f64 twin is src/pbr/anisotropy.rs), the Khronos Sample
// Viewer's: the anisotropic GGX distribution (Burley 2012) and height-correlated Smith
// visibility (Heitz 2014) with alpha_t = mix(alpha, 1, strength^2) along the anisotropy
// direction t and alpha_b = alpha (at least 0.001) across it, along b = cross(N_geom, t);
// for the environment, the Sample Viewer's bent normal (the prefiltered isotropic lobe
// turned towards the direction the stretched lobe reflects).

float glviewD_GGXAniso(float nh, float th, float bh, float at, float ab) {
    float a2 = at * ab;
    vec3 f = vec3(ab * th, at * bh, a2 * nh);
    float w2 = a2 / dot(f, f);
    return a2 * w2 * w2 / GLVIEW_PI;
}

float glviewV_GGXAniso(float nl, float nv, float bv, float tv, float tl, float bl,
                       float at, float ab) {
    float gv = nl * length(vec3(at * tv, ab * bv, nv));
    float gl = nv * length(vec3(at * tl, ab * bl, nl));
    return clamp(0.5 / (gv + gl), 0.0, 1.0);
}

// D * V (the specular BRDF without its Fresnel) for light l, half vector h, N.V nv.
float glviewSpecAniso(vec3 n, float nv, vec3 v, vec3 l, vec3 h, vec3 t, vec3 b, float r,
                      float strength) {
    float a = max(r, GLVIEW_MIN_ROUGHNESS);
    float alpha = a * a;
    float at = mix(alpha, 1.0, strength * strength);
    float ab = clamp(alpha, 0.001, 1.0);
    float nl = clamp(dot(n, l), 0.0, 1.0);
    float nh = clamp(dot(n, h), 0.001, 1.0);
    return glviewV_GGXAniso(nl, nv, dot(b, v), dot(t, v), dot(t, l), dot(b, l), at, ab)
        * glviewD_GGXAniso(nh, dot(t, h), dot(b, h), at, ab);
}

// The Sample Viewer's bent normal for the environment's lobe: the normal of the plane holding
// b and facing v, mixed back to n by (1 - strength (1 - r))^4.
vec3 glviewAnisoBentNormal(vec3 n, vec3 v, vec3 b, float strength, float r) {
    vec3 an = cross(cross(b, v), b);
    float bend = 1.0 - strength * (1.0 - r);
    vec3 bent = mix(an, n, bend * bend * bend * bend);
    float len = length(bent);
    return len > 0.0 ? bent / len : n;
}
