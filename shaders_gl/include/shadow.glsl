// Hardware depth comparison (sampler2DShadow) with percentage-closer filtering: PCF_TAPS
// compared lookups on a regular grid around the projected point, averaged; each lookup is
// itself bilinearly filtered where the driver supports LINEAR on depth textures.
// Light i's matrices start at uShadowMatrix[i * SHADOW_STRIDE]: one for a directional or an
// outside point light, six (a 3x2 atlas of 90-degree faces) for a point light inside the scene.
uniform mat4 uShadowMatrix[NUM_SHADOWS * SHADOW_STRIDE]; // eye space -> map texture space
uniform vec2 uShadowTexel[NUM_SHADOWS];                   // 1 / texture size
uniform float uShadowNormalOffset[NUM_SHADOWS];           // eye-space distance along the normal
uniform float uShadowBias;                                // constant bias in [0,1] depth units
#if SHADOW_STRIDE > 1
uniform mat3 uEyeToWorld;
#endif
#ifdef SHADOW_PACKED
// No depth textures: the map is RGBA8 holding packed depth, compared here as ES 2.0's are.
#include "packdepth.glsl"
#ifndef SHADOW_COMPARE_IN_SHADER
#define SHADOW_COMPARE_IN_SHADER 1
#endif
#undef SHADOW_SAMPLER
#define SHADOW_SAMPLER sampler2D
#define SHADOW_DEPTH(map, uv) glviewUnpackDepth(TEX2D(map, uv))
#else
#define SHADOW_DEPTH(map, uv) TEX2D(map, uv).r
#endif
#ifndef SHADOW_SAMPLER
#define SHADOW_SAMPLER sampler2DShadow
#endif

#ifdef CONST_INDEX_ONLY
// GLSL ES 1.00 (WebGL 1, Appendix A) indexes uniform arrays in a fragment shader by constants
// and loop indices only: light i's entries are picked by a loop over the lights.
vec4 glviewShadowLightPos(int i) {
    vec4 r = vec4(0.0);
    for (int k = 0; k < NUM_SHADOWS; ++k) {
        if (k == i) r = uLightPos[k];
    }
    return r;
}
float glviewShadowNormalOffset(int i) {
    float r = 0.0;
    for (int k = 0; k < NUM_SHADOWS; ++k) {
        if (k == i) r = uShadowNormalOffset[k];
    }
    return r;
}
vec2 glviewShadowTexel(int i) {
    vec2 r = vec2(0.0);
    for (int k = 0; k < NUM_SHADOWS; ++k) {
        if (k == i) r = uShadowTexel[k];
    }
    return r;
}
mat4 glviewShadowMatrix(int m) {
    mat4 r = mat4(0.0);
    for (int k = 0; k < NUM_SHADOWS * SHADOW_STRIDE; ++k) {
        if (k == m) r = uShadowMatrix[k];
    }
    return r;
}
#define SHADOW_LIGHT_POS(i) glviewShadowLightPos(i)
#define SHADOW_NORMAL_OFFSET(i) glviewShadowNormalOffset(i)
#define SHADOW_TEXEL(i) glviewShadowTexel(i)
#define SHADOW_MATRIX(m) glviewShadowMatrix(m)
#else
#define SHADOW_LIGHT_POS(i) uLightPos[i]
#define SHADOW_NORMAL_OFFSET(i) uShadowNormalOffset[i]
#define SHADOW_TEXEL(i) uShadowTexel[i]
#define SHADOW_MATRIX(m) uShadowMatrix[m]
#endif

#ifdef SHADOW_COMPARE_IN_SHADER
// No shadow samplers (GLSL ES 1.00): what a LINEAR, LEQUAL-comparing depth sampler returns,
// from four NEAREST lookups of the depth texture compared here and weighted bilinearly.
float glviewShadowTap(SHADOW_SAMPLER map, vec3 c, vec2 texel) {
    vec2 t = c.xy / texel - 0.5;
    vec2 f = fract(t);
    vec2 b = (floor(t) + 0.5) * texel;
    float a00 = step(c.z, SHADOW_DEPTH(map, b));
    float a10 = step(c.z, SHADOW_DEPTH(map, b + vec2(texel.x, 0.0)));
    float a01 = step(c.z, SHADOW_DEPTH(map, b + vec2(0.0, texel.y)));
    float a11 = step(c.z, SHADOW_DEPTH(map, b + texel));
    return mix(mix(a00, a10, f.x), mix(a01, a11, f.x), f.y);
}
#define SHADOW_TAP(map, c, texel) glviewShadowTap(map, c, texel)
#else
#define SHADOW_TAP(map, c, texel) SHADOW2D(map, c)
#endif

// tile: the part of the texture this lookup may read (x0, y0, x1, y1); clamp: keep taps
// inside it (atlas faces) instead of treating points outside as lit (single maps, whose
// frustum holds the whole scene).
float shadowLookup(SHADOW_SAMPLER map, vec4 c, vec2 texel, vec4 tile, bool clampToTile) {
    if (c.w <= 0.0) return 1.0;
    vec3 q = c.xyz / c.w;
    if (!clampToTile && (q.x < 0.0 || q.x > 1.0 || q.y < 0.0 || q.y > 1.0)) return 1.0;
    if (q.z > 1.0) return 1.0;
    q.z -= uShadowBias;
    vec2 lo = tile.xy + 0.5 * texel;
    vec2 hi = tile.zw - 0.5 * texel;
#if PCF_TAPS == 1
    return SHADOW_TAP(map, vec3(clamp(q.xy, lo, hi), q.z), texel);
#else
#if PCF_TAPS == 4
    const int N = 2;
#elif PCF_TAPS == 9
    const int N = 3;
#else
    const int N = 4;
#endif
    float sum = 0.0;
    float start = -0.5 * float(N - 1);
    for (int i = 0; i < N; ++i) {
        for (int j = 0; j < N; ++j) {
            vec2 o = vec2(start + float(i), start + float(j)) * texel;
            sum += SHADOW_TAP(map, vec3(clamp(q.xy + o, lo, hi), q.z), texel);
        }
    }
    return sum / float(N * N);
#endif
}

uniform float uTerminatorLift;  // per mesh: a quarter of its mean edge length (eye space)

// The shadow terminator of coarse smooth meshes: where the shading normal n turns towards
// light i but the facet itself faces away, the facet lies in the shadow of its own lit
// neighbours and shows as a dark triangle inside the lit side. There the lookup rises along n
// by uTerminatorLift, to about the smooth surface the normals describe (the idea of Chiang,
// Li and Burley's terminator offset, with a per-mesh height since GLSL 1.20 has no access to
// the triangle's corners). The facet's plane comes from the position's derivatives. The CPU
// reference applies the same rule to its shadow rays (src/reference/surface.rs).
vec3 terminatorLift(int i, vec3 p, vec3 n) {
    vec3 ng = cross(dFdx(p), dFdy(p));
    float len = length(ng);
    if (len <= 0.0) return p;
    ng /= len;
    if (dot(ng, n) < 0.0) ng = -ng;
    vec4 lp = SHADOW_LIGHT_POS(i);
    vec3 l = lp.w == 0.0 ? lp.xyz : normalize(lp.xyz - p);
    return (dot(n, l) > 0.0 && dot(ng, l) <= 0.0) ? p + n * uTerminatorLift : p;
}

// Visibility of light i at eye-space point p with unit normal n; cube > 0.5 for an atlas.
float shadowVisibility(SHADOW_SAMPLER map, int i, float cube, vec3 p, vec3 n) {
    p = terminatorLift(i, p, n);
    // Normal offset: look the shadow up a little off the surface, which removes acne on
    // slopes without the large depth bias that would detach shadows from their casters.
    vec4 ps = vec4(p + n * SHADOW_NORMAL_OFFSET(i), 1.0);
    int m = i * SHADOW_STRIDE;
    vec4 tile = vec4(0.0, 0.0, 1.0, 1.0);
#if SHADOW_STRIDE > 1
    if (cube > 0.5) {
        // The face is the dominant axis of the world-space direction from the light.
        vec3 d = uEyeToWorld * (ps.xyz - SHADOW_LIGHT_POS(i).xyz);
        vec3 a = abs(d);
        float f;
        if (a.x >= a.y && a.x >= a.z) {
            f = d.x >= 0.0 ? 0.0 : 1.0;
        } else if (a.y >= a.z) {
            f = d.y >= 0.0 ? 2.0 : 3.0;
        } else {
            f = d.z >= 0.0 ? 4.0 : 5.0;
        }
        m += int(f);
        float fx = mod(f, 3.0);
        float fy = floor(f / 3.0);
        tile = vec4(fx / 3.0, fy / 2.0, (fx + 1.0) / 3.0, (fy + 1.0) / 2.0);
    }
#endif
    return shadowLookup(map, SHADOW_MATRIX(m) * ps, SHADOW_TEXEL(i), tile, cube > 0.5);
}

#if NUM_SHADOWS > 0
uniform SHADOW_SAMPLER uShadowMap0;
#endif
#if NUM_SHADOWS > 1
uniform SHADOW_SAMPLER uShadowMap1;
#endif
#if NUM_SHADOWS > 2
uniform SHADOW_SAMPLER uShadowMap2;
#endif
#if NUM_SHADOWS > 3
uniform SHADOW_SAMPLER uShadowMap3;
#endif
