// Legacy tier: colour = Ke + Ka*ambient + sum of visibility * (Kd*Lc*diffuse + Ks*Lc*spec),
// clamped; a texture multiplies Ka and Kd. Back faces use the flipped normal.
IN vec3 vEyePos;
#ifdef LOG_DEPTH
#include "logdepth.glsl"
#endif
IN vec2 vUv;
#ifdef HAS_COLOR
IN vec3 vColor;
#endif
IN vec3 vNormal;
#if NUM_LIGHTS > 0
#ifdef GOURAUD
IN vec4 vFactors[NUM_LIGHTS];
uniform vec4 uLightPos[NUM_LIGHTS];
uniform vec3 uLightColor[NUM_LIGHTS];
vec3 safeNormalize(vec3 n) {
    float len = length(n);
    return len > 0.0 ? n / len : vec3(0.0, 0.0, 1.0);
}
#else
#include "lighting.glsl"
#endif
#endif
#if NUM_SHADOWS > 0
#include "shadow.glsl"
#endif
#include "output.glsl"

uniform vec3 uKa;
uniform vec3 uKd;
uniform vec3 uKs;
uniform vec3 uKe;
uniform float uOpacity;
uniform vec3 uAmbient;
uniform vec3 uTerms;   // ambient, diffuse, specular switches (0 or 1)
#ifdef HAS_TEXTURE
uniform sampler2D uDiffuseMap;
#endif

void main() {
    vec3 tex = vec3(1.0);
#ifdef HAS_TEXTURE
    tex = TEX2D(uDiffuseMap, vUv).rgb;
#endif
#ifdef HAS_COLOR
    tex *= vColor;
#endif
    vec3 color = uKe + uTerms.x * uKa * tex * uAmbient;
#if NUM_LIGHTS > 0
    vec3 n = safeNormalize(vNormal);
    if (!gl_FrontFacing) n = -n;
    vec3 v = normalize(-vEyePos);
    float vis[NUM_LIGHTS];
    for (int i = 0; i < NUM_LIGHTS; ++i) vis[i] = 1.0;
#if NUM_SHADOWS > 0
    vis[0] = shadowVisibility(uShadowMap0, 0, SHADOW_CUBE0, vEyePos, n);
#endif
#if NUM_SHADOWS > 1
    vis[1] = shadowVisibility(uShadowMap1, 1, SHADOW_CUBE1, vEyePos, n);
#endif
#if NUM_SHADOWS > 2
    vis[2] = shadowVisibility(uShadowMap2, 2, SHADOW_CUBE2, vEyePos, n);
#endif
#if NUM_SHADOWS > 3
    vis[3] = shadowVisibility(uShadowMap3, 3, SHADOW_CUBE3, vEyePos, n);
#endif
    for (int i = 0; i < NUM_LIGHTS; ++i) {
#ifdef GOURAUD
        vec2 f = gl_FrontFacing ? vFactors[i].xy : vFactors[i].zw;
#else
        vec2 f = lightFactors(toLight(uLightPos[i], vEyePos), n, v);
#endif
        color += vis[i] * uLightColor[i] * (uTerms.y * uKd * tex * f.x + uTerms.z * uKs * f.y);
    }
#endif
    FRAG_COLOR = glviewOutputRgba(color, uOpacity);
#ifdef LOG_DEPTH
    glviewLogDepth();
#endif
}
