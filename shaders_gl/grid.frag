// The ground grid (--grid): lines every uUnit along X and Z, antialiased by their distance
// in pixels (the offset to the nearest line over fwidth, which GLSL 1.20 and ES 3.00 fragment
// shaders both have), fading out away from the model, and the file's two floor axes through
// its origin in the triad's colours; the rule of GridPlane::lines (src/grid.rs), which the
// CPU reference ray-casts. Where the model shadows the plane, what
// lies behind it darkens by the share of light the shadow takes from a white diffuse floor
// (the lights' luminance times N.L, ambient included), so the grid receives the shadow
// without hiding the background. One blended draw: C = L·a + C_dst·(1 − s)(1 − a).
IN vec3 vLocal;
IN vec3 vEyePos;
uniform float uUnit;
uniform vec2 uCentre;        // the fade's centre, relative to the origin (x, z)
uniform float uFade;         // the lines are gone this far from the centre
uniform float uWidth;        // line width in pixels
uniform float uLineAlpha;
uniform vec3 uLineColor;     // in the frame's values
uniform vec2 uAxisAt;        // the file's origin (x, z) relative to the grid's origin
uniform vec3 uAxisColorX;    // the file axis along X, and along Z (the frame's values)
uniform vec3 uAxisColorZ;
uniform float uAxisAlpha;
uniform vec3 uDepthRange;    // near, far of the frame's projection; z = 1: orthographic
#include "output.glsl"
#ifdef LOG_DEPTH
uniform float uLogDepthC;
uniform float uLogDepthFar;
#endif
#if NUM_SHADOWS > 0
uniform vec4 uLightPos[NUM_LIGHTS];
uniform vec3 uLightColor[NUM_LIGHTS];
uniform float uAmbient;      // luminance of the ambient light
uniform vec3 uNormal;        // the plane's normal in eye space, towards the camera's side
uniform float uLitSide;      // 1: the camera sees the side the lights fall on
#include "shadow.glsl"

float visibility(int i) {
    if (i == 0) return shadowVisibility(uShadowMap0, 0, SHADOW_CUBE0, vEyePos, uNormal);
#if NUM_SHADOWS > 1
    if (i == 1) return shadowVisibility(uShadowMap1, 1, SHADOW_CUBE1, vEyePos, uNormal);
#endif
#if NUM_SHADOWS > 2
    if (i == 2) return shadowVisibility(uShadowMap2, 2, SHADOW_CUBE2, vEyePos, uNormal);
#endif
#if NUM_SHADOWS > 3
    if (i == 3) return shadowVisibility(uShadowMap3, 3, SHADOW_CUBE3, vEyePos, uNormal);
#endif
    return 1.0;
}
#endif

// src over dst, each (colour, opacity) with straight alpha.
vec4 over(vec4 src, vec4 dst) {
    float a = src.a + dst.a * (1.0 - src.a);
    return a > 0.0 ? vec4((src.rgb * src.a + dst.rgb * dst.a * (1.0 - src.a)) / a, a) : vec4(0.0);
}

// The depth the frame's projection gives this point (its own clip space reaches further).
float frameDepth() {
    float w = -vEyePos.z;
#ifdef LOG_DEPTH
    return log(uLogDepthC * max(w, 0.0) + 1.0) / log(uLogDepthC * uLogDepthFar + 1.0);
#else
    float n = uDepthRange.x;
    float f = uDepthRange.y;
    if (uDepthRange.z > 0.5) return (w - n) / (f - n);
    return ((f + n) / (f - n) - 2.0 * f * n / ((f - n) * w)) * 0.5 + 0.5;
#endif
}

void main() {
    vec2 q = vLocal.xz / uUnit;
    vec2 fw = max(fwidth(q), vec2(1e-9));
    vec2 d = abs(fract(q - 0.5) - 0.5) / fw;
    float cover = clamp(0.5 * uWidth + 0.5 - min(d.x, d.y), 0.0, 1.0);
    float crowd = 1.0 - smoothstep(0.2, 0.45, max(fw.x, fw.y));
    float fade = 1.0 - smoothstep(0.5 * uFade, uFade, length(vLocal.xz - uCentre));
    vec4 line = vec4(uLineColor, uLineAlpha * cover * crowd * fade);
    vec2 qa = (vLocal.xz - uAxisAt) / uUnit;
    float ax = uAxisAlpha * clamp(0.75 * uWidth + 0.5 - abs(qa.y) / fw.y, 0.0, 1.0) * fade;
    float az = uAxisAlpha * clamp(0.75 * uWidth + 0.5 - abs(qa.x) / fw.x, 0.0, 1.0) * fade;
    line = over(vec4(uAxisColorZ, az), over(vec4(uAxisColorX, ax), line));
    float a = line.a;
    float s = 0.0;
#if NUM_SHADOWS > 0
    if (uLitSide > 0.5) {
        float full = uAmbient;
        float lit = uAmbient;
        for (int i = 0; i < NUM_LIGHTS; ++i) {
            vec4 lp = uLightPos[i];
            vec3 l = lp.w == 0.0 ? lp.xyz : normalize(lp.xyz - vEyePos);
            float k = dot(uLightColor[i], vec3(0.2126, 0.7152, 0.0722)) * max(dot(uNormal, l), 0.0);
            full += k;
            lit += k * visibility(i);
        }
        s = full > 0.0 ? (1.0 - lit / full) * fade : 0.0;
    }
#endif
    float alpha = 1.0 - (1.0 - s) * (1.0 - a);
    if (alpha <= 0.0) discard;
    // Blended by the fixed function, or on the RGBM frame in output.glsl over a copy of it.
    FRAG_COLOR = glviewOutputRgba(line.rgb * (a / alpha), alpha);
    FRAG_DEPTH = clamp(frameDepth(), 0.0, 1.0);
}
