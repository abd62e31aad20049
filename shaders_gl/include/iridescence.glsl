// KHR_materials_iridescence's thin film (the f64 twin is src/pbr/iridescence.rs): the Fresnel
// of a film of index n2 and thickness d nm over a base of reflectance f0, seen at cos1 from
// air (Belcour & Barla 2017 as the Khronos Sample Viewer evaluates it: Schlick's Fresnel at
// both interfaces, the base's ior from its F0, the first two orders of the Airy sum against
// Gaussian fits of the XYZ sensitivities, in linear Rec. 709).

vec3 glviewIorToF0(vec3 nt, float ni) {
    vec3 d = (nt - vec3(ni)) / (nt + vec3(ni));
    return d * d;
}

vec3 glviewSchlick1(vec3 f0, float c) {
    float x = clamp(1.0 - c, 0.0, 1.0);
    float x2 = x * x;
    return f0 + (vec3(1.0) - f0) * (x2 * x2 * x);
}

// The film's spectral response to optical path difference opd (nm) with phase shift `shift`
// (amplitudes normalised by the fits' integral of Y; X has a second lobe).
vec3 glviewFilmSensitivity(float opd, vec3 shift) {
    float phase = 6.28318530718e-9 * opd;
    vec3 amp = vec3(0.8465900023, 1.0002218936, 1.0011224857);
    vec3 pos = vec3(1.6810e6, 1.7953e6, 2.2084e6);
    vec3 var = vec3(4.3278e9, 9.3046e9, 6.6121e9);
    vec3 xyz = amp * cos(pos * phase + shift) * exp(-phase * phase * var);
    xyz.x += 0.1538683065 * cos(2.2399e6 * phase + shift.x) * exp(-4.5282e9 * phase * phase);
    return mat3(3.2404542, -0.9692660, 0.0556434,
                -1.5371385, 1.8760108, -0.2040259,
                -0.4985314, 0.0415560, 1.0572252) * xyz;
}

vec3 glviewIridescence(float filmIor, float cos1, float d, vec3 baseF0) {
    // The film fades into air as it thins to nothing.
    float n2 = mix(1.0, filmIor, smoothstep(0.0, 0.03, d));
    float cos2Sq = 1.0 - (1.0 - cos1 * cos1) / (n2 * n2);
    if (cos2Sq < 0.0) return vec3(1.0);   // total internal reflection
    float cos2 = sqrt(cos2Sq);
    float r12 = glviewSchlick1(glviewIorToF0(vec3(n2), 1.0), cos1).x;
    float t121 = 1.0 - r12;
    float phi21 = n2 < 1.0 ? 0.0 : GLVIEW_PI;
    vec3 sf0 = sqrt(clamp(baseF0, 0.0, 0.9999));
    vec3 baseIor = (vec3(1.0) + sf0) / (vec3(1.0) - sf0);
    vec3 r23 = glviewSchlick1(glviewIorToF0(baseIor, n2), cos2);
    vec3 phi = vec3(phi21) + GLVIEW_PI * (vec3(1.0) - step(vec3(n2), baseIor));
    float opd = 2.0 * n2 * d * cos2;
    vec3 r123 = clamp(r12 * r23, 1e-5, 0.9999);
    vec3 rs = t121 * t121 * r23 / (vec3(1.0) - r123);
    vec3 cm = (rs - vec3(t121)) * sqrt(r123);
    vec3 i = vec3(r12) + rs + cm * 2.0 * glviewFilmSensitivity(opd, phi);
    cm *= sqrt(r123);
    i += cm * 2.0 * glviewFilmSensitivity(2.0 * opd, 2.0 * phi);
    return max(i, vec3(0.0));
}
