// The explicit output step: everything before it is linear and unclamped. Without TONEMAP
// (the legacy tier) it is the fixed-function clamp; with it: exposure, tone mapping
// (1 ACES fit, 2 Reinhard, 3 Khronos PBR Neutral, 0 clamp) and sRGB encoding. The CPU twin is
// OutputParams::apply in src/pbr/mod.rs.
#ifdef LINEAR_OUTPUT
// An offscreen frame: linear and unclamped; the composite pass applies the output step.
vec3 glviewOutput(vec3 c) {
    return c;
}
#elif defined(TONEMAP)
uniform float uExposure;   // 2^EV

vec3 glviewSrgb(vec3 c) {
    c = clamp(c, 0.0, 1.0);
    vec3 lo = 12.92 * c;
    vec3 hi = 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055;
    return vec3(c.r <= 0.0031308 ? lo.r : hi.r,
                c.g <= 0.0031308 ? lo.g : hi.g,
                c.b <= 0.0031308 ? lo.b : hi.b);
}

vec3 glviewTonemap(vec3 c) {
#if TONEMAP == 1
    c = max(c, 0.0) * 0.6;
    return clamp((c * (2.51 * c + 0.03)) / (c * (2.43 * c + 0.59) + 0.14), 0.0, 1.0);
#elif TONEMAP == 2
    c = max(c, 0.0);
    return c / (1.0 + c);
#elif TONEMAP == 3
    const float start = 0.8 - 0.04;
    const float desat = 0.15;
    float x = min(c.r, min(c.g, c.b));
    float offset = x < 0.08 ? x - 6.25 * x * x : 0.04;
    c -= offset;
    float peak = max(c.r, max(c.g, c.b));
    if (peak < start) return clamp(c, 0.0, 1.0);
    const float d = 1.0 - start;
    float newPeak = 1.0 - d * d / (peak + d - start);
    c *= newPeak / peak;
    float g = 1.0 - 1.0 / (desat * (peak - newPeak) + 1.0);
    return clamp(mix(c, vec3(newPeak), g), 0.0, 1.0);
#else
    return clamp(c, 0.0, 1.0);
#endif
}

vec3 glviewOutput(vec3 linear) {
    return glviewSrgb(glviewTonemap(linear * uExposure));
}

#ifdef KHR_TRANSMISSION
// The output step undone, for the opaque frame's copy transmission reads: sRGB decoded, the
// tone curve inverted (exact for none, Reinhard and the ACES fit below their clamp; for
// Khronos PBR Neutral exact below its shoulder, where it is the identity less a small
// offset, and without the shoulder's desaturation above), the exposure divided out. A copy
// holds at most 1: what was clipped there is read as at most 4 (unbounded, a clipped
// highlight behind the glass became a glowing blob).
vec3 glviewInverseOutput(vec3 s) {
    vec3 y = mix(s / 12.92, pow((s + 0.055) / 1.055, vec3(2.4)), step(0.04045, s));
#if TONEMAP == 1
    y = min(y, vec3(0.999));
    vec3 a = 2.43 * y - 2.51;
    vec3 b = 0.59 * y - 0.03;
    vec3 c = 0.14 * y;
    vec3 x = (-b - sqrt(max(b * b - 4.0 * a * c, 0.0))) / (2.0 * a);
    y = max(x, 0.0) / 0.6;
#elif TONEMAP == 2
    y = min(y, vec3(0.999));
    y = y / (1.0 - y);
#elif TONEMAP == 3
    const float start = 0.8 - 0.04;
    const float d = 1.0 - start;
    float peak = max(y.r, max(y.g, y.b));
    if (peak >= start) {
        float p = min(peak, 0.999);
        y *= (d * d / (1.0 - p) - d + start) / max(peak, 1e-6);
    }
    float m = min(y.r, min(y.g, y.b));
    // offset(x) = x - 6.25 x^2 below 0.08 (the curve's min channel is 6.25 x^2), else 0.04
    float x = m < 0.04 ? sqrt(max(m, 0.0) / 6.25) : m + 0.04;
    y += x < 0.08 ? x - 6.25 * x * x : 0.04;
#endif
    return min(y, vec3(4.0)) / uExposure;
}
#endif
#else
vec3 glviewOutput(vec3 c) {
    return clamp(c, 0.0, 1.0);
}
#endif

// What a lit fragment writes: the output colour and its opacity; with FRAME_RGBM (bloom where
// there are no float render targets: the linear frame in the 8-bit default framebuffer) the
// alpha channel holds the RGBM multiplier instead, see rgbm.glsl.
#ifdef FRAME_RGBM
#include "rgbm.glsl"
// RGBM cannot be blended by the fixed function: translucent surfaces (nearest layer: one
// per pixel) read what lies behind them from a copy of the frame and blend here.
uniform float uRgbmBlend;     // 0 opaque, 1 alpha (C = a*src + (1 - a)*dst), 2 additive
uniform sampler2D uBehind;
uniform vec4 uBehindRect;     // the frame's rectangle in window pixels: x, y, w, h
vec4 glviewOutputRgba(vec3 c, float a) {
    vec3 o = glviewOutput(c);
    if (uRgbmBlend > 0.5) {
        vec3 d = glviewRgbmDecode(TEX2D(uBehind, (gl_FragCoord.xy - uBehindRect.xy) / uBehindRect.zw));
        o = a * o + (uRgbmBlend > 1.5 ? 1.0 : 1.0 - a) * d;
    }
    return glviewRgbmEncode(o);
}
#else
vec4 glviewOutputRgba(vec3 c, float a) {
    return vec4(glviewOutput(c), a);
}
#endif
