// Image-based light of the PBR tier, the seed's split sum without explicit-LOD lookups:
// E_d from the irradiance cube; E_s from NUM_SPEC_LEVELS cubes, one per roughness
// (r_i = i / (NUM_SPEC_LEVELS - 1)), the two nearest mixed linearly (every level is sampled
// with a hat weight, so no sampler is indexed by a variable: GLSL 1.20 cannot); BF from the
// lookup table. With IBL_RGBM the cubes are 8-bit RGB*M (range 16) and the table holds A and
// B as 16-bit values split over two 8-bit channels, read with nearest texels and filtered
// here.
#include "brdf.glsl"
uniform mat3 uEnvFromEye;        // eye space -> environment (world) directions
uniform float uIblIntensity;
uniform samplerCube uIrradiance;
uniform sampler2D uBrdfLut;
uniform float uLutSize;
uniform samplerCube uSpecular0;
uniform samplerCube uSpecular1;
#if NUM_SPEC_LEVELS > 2
uniform samplerCube uSpecular2;
#endif
#if NUM_SPEC_LEVELS > 3
uniform samplerCube uSpecular3;
#endif
#if NUM_SPEC_LEVELS > 4
uniform samplerCube uSpecular4;
#endif
#if NUM_SPEC_LEVELS > 5
uniform samplerCube uSpecular5;
#endif
#if NUM_SPEC_LEVELS > 6
uniform samplerCube uSpecular6;
#endif
#if NUM_SPEC_LEVELS > 7
uniform samplerCube uSpecular7;
#endif

vec3 glviewDecode(vec4 t) {
#ifdef IBL_RGBM
    return t.rgb * t.a * 16.0;
#else
    return t.rgb;
#endif
}

vec3 glviewIrradiance(vec3 nEye) {
    return glviewDecode(TEXCUBE(uIrradiance, uEnvFromEye * nEye)) * uIblIntensity;
}

#define GLVIEW_LEVEL(i, s) { float w = 1.0 - abs(lvl - float(i)); if (w > 0.0) c += w * glviewDecode(TEXCUBE(s, d)); }

vec3 glviewSpecular(vec3 rEye, float r) {
    vec3 d = uEnvFromEye * rEye;
    float lvl = clamp(r, 0.0, 1.0) * float(NUM_SPEC_LEVELS - 1);
    vec3 c = vec3(0.0);
    GLVIEW_LEVEL(0, uSpecular0)
    GLVIEW_LEVEL(1, uSpecular1)
#if NUM_SPEC_LEVELS > 2
    GLVIEW_LEVEL(2, uSpecular2)
#endif
#if NUM_SPEC_LEVELS > 3
    GLVIEW_LEVEL(3, uSpecular3)
#endif
#if NUM_SPEC_LEVELS > 4
    GLVIEW_LEVEL(4, uSpecular4)
#endif
#if NUM_SPEC_LEVELS > 5
    GLVIEW_LEVEL(5, uSpecular5)
#endif
#if NUM_SPEC_LEVELS > 6
    GLVIEW_LEVEL(6, uSpecular6)
#endif
#if NUM_SPEC_LEVELS > 7
    GLVIEW_LEVEL(7, uSpecular7)
#endif
    return c * uIblIntensity;
}

#ifdef IBL_RGBM
// The RGBM table is 2·size wide: (A, B) on the left, the sheen albedo on the right.
vec4 glviewLutRaw(vec2 ij) {
    return TEX2D(uBrdfLut, (ij + 0.5) / vec2(2.0 * uLutSize, uLutSize));
}
vec2 glviewLutTexel(vec2 ij) {
    vec4 t = glviewLutRaw(ij);
    return vec2(t.r * 255.0 * 256.0 + t.g * 255.0, t.b * 255.0 * 256.0 + t.a * 255.0) / 65535.0;
}
// The table cell around uv, filtered here since a value's two bytes cannot be blended apart:
// corner texels i0 and i1 (clamped to the table) and the weights f between them.
void glviewLutCell(vec2 uv, out vec2 i0, out vec2 i1, out vec2 f) {
    vec2 p = clamp(uv * uLutSize - 0.5, vec2(0.0), vec2(uLutSize - 1.0));
    i0 = floor(p);
    f = p - i0;
    i1 = min(i0 + 1.0, vec2(uLutSize - 1.0));
}
#endif

// (A, B) with the specular integral = f0 * A + B, at x = N.V, y = roughness.
vec2 glviewBrdf(float nv, float r) {
    vec2 uv = vec2(clamp(nv, 0.0, 1.0), clamp(r, 0.0, 1.0));
#ifdef IBL_RGBM
    vec2 i0, i1, f;
    glviewLutCell(uv, i0, i1, f);
    return mix(mix(glviewLutTexel(i0), glviewLutTexel(vec2(i1.x, i0.y)), f.x),
               mix(glviewLutTexel(vec2(i0.x, i1.y)), glviewLutTexel(i1), f.x), f.y);
#else
    // Texel i holds x = (i + 0.5) / size: the coordinate is the value itself.
    return TEX2D(uBrdfLut, uv).rg;
#endif
}

#ifdef KHR_SHEEN
// The sheen lobe's directional albedo E(N.V, sheen roughness): the table's third value.
float glviewSheenE(float nv, float r) {
    vec2 uv = vec2(clamp(nv, 0.0, 1.0), clamp(r, 0.0, 1.0));
#ifdef IBL_RGBM
    vec2 i0, i1, f;
    glviewLutCell(uv, i0, i1, f);
    vec2 o = vec2(uLutSize, 0.0);
    vec4 t00 = glviewLutRaw(i0 + o);
    vec4 t10 = glviewLutRaw(vec2(i1.x, i0.y) + o);
    vec4 t01 = glviewLutRaw(vec2(i0.x, i1.y) + o);
    vec4 t11 = glviewLutRaw(i1 + o);
    vec4 e = vec4(t00.r, t10.r, t01.r, t11.r) * (255.0 * 256.0)
           + vec4(t00.g, t10.g, t01.g, t11.g) * 255.0;
    e /= 65535.0;
    return mix(mix(e.x, e.y, f.x), mix(e.z, e.w, f.x), f.y);
#else
    return TEX2D(uBrdfLut, uv).b;
#endif
}
#endif
