// The PBR tier's BRDF: GGX D (alpha = r^2), Smith-Schlick G (k = r^2 / 2), Schlick F.
// The f64 twin is src/pbr/brdf.rs.
const float GLVIEW_PI = 3.14159265358979;
const float GLVIEW_MIN_ROUGHNESS = 0.02;

float glviewD_GGX(float nh, float r) {
    float a = max(r, GLVIEW_MIN_ROUGHNESS);
    float a2 = a * a * a * a;
    float d = nh * nh * (a2 - 1.0) + 1.0;
    return a2 / (GLVIEW_PI * d * d);
}

float glviewG_Smith(float nv, float nl, float r) {
    float a = max(r, GLVIEW_MIN_ROUGHNESS);
    float k = a * a * 0.5;
    return (nv / (nv * (1.0 - k) + k)) * (nl / (nl * (1.0 - k) + k));
}

vec3 glviewF_Schlick(vec3 f0, float vh) {
    float f = 1.0 - clamp(vh, 0.0, 1.0);
    float f2 = f * f;
    return f0 + (1.0 - f0) * (f2 * f2 * f);
}

// Schlick's Fresnel with a reflectance at grazing incidence other than 1 (KHR_materials_specular
// weights the dielectric's f0 and f90 alike).
vec3 glviewF_Schlick90(vec3 f0, vec3 f90, float vh) {
    float f = 1.0 - clamp(vh, 0.0, 1.0);
    float f2 = f * f;
    return f0 + (f90 - f0) * (f2 * f2 * f);
}

#ifdef KHR_SHEEN
// KHR_materials_sheen: Charlie distribution (Estevez & Kulla 2017, alpha = r^2) and the
// Neubelt-Pettineo visibility; twin of src/pbr/sheen.rs.
float glviewD_Charlie(float nh, float r) {
    float a = max(r, 0.07);
    float inv = 1.0 / (a * a);
    float sin2 = max(1.0 - nh * nh, 0.0);
    return (2.0 + inv) * pow(sin2, inv * 0.5) / (2.0 * GLVIEW_PI);
}

float glviewV_Neubelt(float nv, float nl) {
    return 1.0 / max(4.0 * (nl + nv - nl * nv), 1e-8);
}
#endif
