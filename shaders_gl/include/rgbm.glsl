// RGBM in 8 bits per channel for the linear frame where there are no float render targets:
// value = rgb * m * 8 (range [0, 8]); m is rounded up to the next 1/255 so rgb <= 1 keeps the
// most precision (relative step ~1/255 of the largest channel, absolute 1.2e-4 below 8/255).
// The CPU twin is render::post::rgbm_encode.
const float GLVIEW_RGBM_RANGE = 8.0;

vec4 glviewRgbmEncode(vec3 c) {
    c = clamp(c / GLVIEW_RGBM_RANGE, 0.0, 1.0);
    float m = max(max(c.r, c.g), max(c.b, 1e-6));
    m = ceil(m * 255.0) / 255.0;
    return vec4(c / m, m);
}

vec3 glviewRgbmDecode(vec4 t) {
    return t.rgb * t.a * GLVIEW_RGBM_RANGE;
}
