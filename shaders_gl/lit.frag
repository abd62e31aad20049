// Legacy tier: colour = Ke + Ka*ambient + sum of visibility * (Kd*Lc*diffuse + Ks*Lc*spec),
// clamped; a texture multiplies Ka and Kd, an emissive map Ke, a normal map bends the normal
// (not with Gouraud). Back faces use the flipped normal (FRONT_ONLY: the draw culls them, so
// none arrive). UNLIT: Kd times the texture.
// The products of uniforms (Ka*ambient, Kd*Lc, Ks*Lc and the term switches) are formed once
// per draw on the CPU (lit.rs, `set_material_terms`): llvmpipe would form them per fragment.
IN vec3 vEyePos;
#ifdef LOG_DEPTH
#include "logdepth.glsl"
#endif
#if defined(HAS_TEXTURE) || defined(HAS_EMISSIVE_MAP) || defined(HAS_NORMAL_MAP)
IN vec2 vUv;
#endif
#ifdef HAS_COLOR
IN vec4 vColor;
#endif
IN vec3 vNormal;
#if NUM_LIGHTS > 0
#ifdef GOURAUD
IN vec4 vFactors[NUM_LIGHTS];
uniform vec4 uLightPos[NUM_LIGHTS];
vec3 safeNormalize(vec3 n) {
    float len2 = dot(n, n);
    return len2 > 0.0 ? n * inversesqrt(len2) : vec3(0.0, 0.0, 1.0);
}
#else
#include "lighting.glsl"
#ifdef FALLOFF
#include "falloff.glsl"
#endif
#endif
uniform vec3 uLightDiffuse[NUM_LIGHTS];    // Kd * light colour (0 with the diffuse term off)
uniform vec3 uLightSpecular[NUM_LIGHTS];   // Ks * light colour (0 with the specular term off)
#endif
#if NUM_SHADOWS > 0
#include "shadow.glsl"
#endif
#include "output.glsl"
#include "material.glsl"
#ifdef HAS_NORMAL_MAP
#include "normalmap.glsl"
#endif
#ifdef HAS_EMISSIVE_MAP
uniform sampler2D uEmissiveMap;
#endif

uniform vec3 uKd;            // UNLIT's colour
uniform vec3 uKe;
uniform vec3 uAmbientTerm;   // Ka * ambient (0 with the ambient term off)
uniform float uOpacity;
#ifdef HAS_TEXTURE
uniform sampler2D uDiffuseMap;
#endif

void main() {
#ifdef POINTS
    // Round points: the sprite's square less what lies outside its inscribed disk.
    vec2 pc = gl_PointCoord - vec2(0.5);
    if (dot(pc, pc) > 0.25) discard;
#endif
    vec3 tex = vec3(1.0);
    float texAlpha = 1.0;
#ifdef HAS_TEXTURE
    vec4 base = TEX2D(uDiffuseMap, SLOT_UV(0));
    tex = base.rgb;
    texAlpha = base.a;
#endif
#ifdef HAS_COLOR
    texAlpha *= vColor.a;   // glTF: COLOR_0's alpha multiplies the base colour's
#endif
    glviewAlphaTest(uBaseAlpha * texAlpha);
#if ALPHA_MODE == 2
    float opacity = uOpacity * texAlpha;
#else
    float opacity = uOpacity;
#endif
#ifdef HAS_COLOR
    tex *= vColor.rgb;
#endif
#ifdef UNLIT
    FRAG_COLOR = glviewOutputRgba(uKd * tex, opacity);
#else
    vec3 emissive = uKe;
#ifdef HAS_EMISSIVE_MAP
    emissive *= TEX2D(uEmissiveMap, SLOT_UV(4)).rgb;
#endif
    vec3 color = emissive + uAmbientTerm * tex;
#if NUM_LIGHTS > 0
    vec3 n = safeNormalize(vNormal);
#ifndef FRONT_ONLY
    if (!gl_FrontFacing) n = -n;
#endif
    vec3 geomN = n;   // shadow lookups are offset along the surface's own normal
#ifdef HAS_NORMAL_MAP
    n = glviewNormalMap(n, gl_FrontFacing);
#endif
    vec3 v = normalize(-vEyePos);
    float vis[NUM_LIGHTS];
    for (int i = 0; i < NUM_LIGHTS; ++i) vis[i] = 1.0;
#if NUM_SHADOWS > 0
    vis[0] = shadowVisibility(uShadowMap0, 0, SHADOW_CUBE0, vEyePos, geomN);
#endif
#if NUM_SHADOWS > 1
    vis[1] = shadowVisibility(uShadowMap1, 1, SHADOW_CUBE1, vEyePos, geomN);
#endif
#if NUM_SHADOWS > 2
    vis[2] = shadowVisibility(uShadowMap2, 2, SHADOW_CUBE2, vEyePos, geomN);
#endif
#if NUM_SHADOWS > 3
    vis[3] = shadowVisibility(uShadowMap3, 3, SHADOW_CUBE3, vEyePos, geomN);
#endif
    for (int i = 0; i < NUM_LIGHTS; ++i) {
#ifdef GOURAUD
#ifdef FRONT_ONLY
        vec2 f = vFactors[i].xy;
#else
        vec2 f = gl_FrontFacing ? vFactors[i].xy : vFactors[i].zw;
#endif
#else
        vec2 f = lightFactors(toLight(uLightPos[i], vEyePos), n, v);
#ifdef FALLOFF
        f *= glviewFalloff(i, vEyePos);   // Gouraud's factors have it per vertex
#endif
#endif
        color += vis[i] * (uLightDiffuse[i] * tex * f.x + uLightSpecular[i] * f.y);
    }
#endif
    FRAG_COLOR = glviewOutputRgba(color, opacity);
#endif
#ifdef LOG_DEPTH
    glviewLogDepth();
#endif
}
