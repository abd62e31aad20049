// PBR tier (the seed's formula), linear until glviewOutput:
//   Lo = Ke + E_d(N)*k_d*ao + E_s(R, r)*(k_s*A + B)*ao
//      + sum_i vis_i * Lc_i * (k_d + pi * D*G*F / (4 N.L N.V)) * N.L
// k_d = albedo*(1 - f0)*(1 - metallic), k_s = mix(f0, albedo, metallic), f0 = 0.04.
// The glTF PBR extensions are program permutations (docs/gltf/extensions.md), after the
// Khronos Sample Viewer: KHR_SPECULAR (KHR_materials_specular and _ior) sets f0 = min(ior F0
// * specular colour, 1) * weight and f90 = weight for the dielectric; KHR_SHEEN adds a
// Charlie lobe and scales what lies under it by 1 - max(sheen colour) * E_sheen(N.V);
// KHR_CLEARCOAT adds a GGX lobe of F0 0.04 on its own normal and roughness and scales what
// lies under it by 1 - clearcoat * F_cc(N_cc.V).
IN vec3 vEyePos;
#ifdef LOG_DEPTH
#include "logdepth.glsl"
#endif
IN vec2 vUv;
IN vec3 vNormal;
#include "material.glsl"
#if defined(HAS_NORMAL_MAP) || defined(HAS_CC_NORMAL_MAP)
#include "normalmap.glsl"
#endif
#if NUM_LIGHTS > 0
uniform vec4 uLightPos[NUM_LIGHTS];   // w = 0: unit direction towards the light; w = 1: position
uniform vec3 uLightColor[NUM_LIGHTS];
#endif
#if NUM_SHADOWS > 0
#include "shadow.glsl"
#endif
#include "ibl.glsl"
#include "output.glsl"

uniform vec3 uBaseColor;
uniform float uMetallic;
uniform float uRoughness;
uniform vec3 uEmissive;
uniform float uOpacity;
uniform vec4 uTermsA;   // direct diffuse, direct specular, IBL diffuse, IBL specular (0 or 1)
uniform vec3 uTermsB;   // ambient occlusion, shadows, emissive (0 or 1)
#ifdef HAS_ALBEDO_MAP
uniform sampler2D uAlbedoMap;    // sRGB, decoded by the sampler or below
#endif
#ifdef HAS_ORM_MAP
uniform sampler2D uOrmMap;       // g: roughness, b: metallic, r: occlusion where uOrmAo is 1
uniform float uOrmAo;            // 1: an MTL's packed maps; 0: glTF's metallicRoughness
#endif
#ifdef HAS_AO_MAP
uniform sampler2D uAoMap;        // glTF occlusion (r, linear)
uniform float uOcclusionStrength;
#endif
#ifdef HAS_EMISSIVE_MAP
uniform sampler2D uEmissiveMap;  // sRGB
#endif

#ifdef HAS_COLOR
IN vec4 vColor;
#endif
#ifdef HAS_KHR_MAPS
// The extensions' texture slots (src/scene/material_khr.rs SLOTS order): 0 clearcoat,
// 1 clearcoat roughness, 2 clearcoat normal, 3 sheen colour, 4 sheen roughness, 5 specular,
// 6 specular colour, 7 transmission, 8 thickness; each with its UV set and transform like
// the core slots.
uniform mat3 uKhrXf[9];
uniform float uKhrSet[9];
#define KHR_UV(i) ((uKhrXf[i] * vec3(uKhrSet[i] > 0.5 ? GLVIEW_UV1 : vUv, 1.0)).xy)
#endif
#ifdef KHR_SPECULAR
uniform vec3 uF0;               // ((ior - 1) / (ior + 1))^2 * specularColorFactor
uniform float uSpecularWeight;  // specularFactor
#ifdef HAS_SPECULAR_MAP
uniform sampler2D uSpecularMap;       // a
#endif
#ifdef HAS_SPECULAR_COLOR_MAP
uniform sampler2D uSpecularColorMap;  // sRGB
#endif
#endif
#if defined(KHR_CLEARCOAT) || defined(KHR_SHEEN) || defined(KHR_TRANSMISSION)
uniform vec3 uTermsC;   // clearcoat, sheen, transmission layers (0 or 1)
#endif
#ifdef KHR_TRANSMISSION
// The opaque frame's copy (output values, undone by glviewInverseOutput) with its mip chain
// (uFrameLevels = log2 of its larger side; 0 without glGenerateMipmap: read sharp).
uniform sampler2D uTransmissionFrame;
uniform float uFrameLevels;
uniform float uTransmission;
uniform float uIor;
uniform mat4 uProjection;
#ifdef HAS_TRANSMISSION_MAP
uniform sampler2D uTransmissionMap;    // r
#endif
#ifdef KHR_VOLUME
uniform float uThickness;
uniform vec3 uAttenuationColor;
uniform float uAttenuationDistance;    // 0: infinite
#ifdef HAS_THICKNESS_MAP
uniform sampler2D uThicknessMap;       // g
#endif
#endif
// GLSL 1.20 has no explicit level in fragment shaders: a bias from level 0 is the same here,
// as the copy is read one texel per pixel.
#if __VERSION__ >= 130
#define GLVIEW_TEX2D_LOD(s, uv, l) textureLod(s, uv, l)
#else
#define GLVIEW_TEX2D_LOD(s, uv, l) texture2D(s, uv, l)
#endif
#endif
#ifdef KHR_CLEARCOAT
uniform float uClearcoat;
uniform float uClearcoatRoughness;
#ifdef HAS_CC_MAP
uniform sampler2D uClearcoatMap;       // r
#endif
#ifdef HAS_CC_ROUGH_MAP
uniform sampler2D uClearcoatRoughMap;  // g
#endif
#ifdef HAS_CC_NORMAL_MAP
uniform sampler2D uClearcoatNormalMap;
uniform float uClearcoatNormalScale;
#endif
#endif
#ifdef KHR_SHEEN
uniform vec3 uSheenColor;
uniform float uSheenRoughness;
#ifdef HAS_SHEEN_COLOR_MAP
uniform sampler2D uSheenColorMap;      // sRGB
#endif
#ifdef HAS_SHEEN_ROUGH_MAP
uniform sampler2D uSheenRoughMap;      // a
#endif
#endif

vec3 glviewSafeNormalize(vec3 n) {
    float len = length(n);
    return len > 0.0 ? n / len : vec3(0.0, 0.0, 1.0);
}

vec3 glviewToLinear(vec3 c) {
#ifdef SRGB_DECODE_IN_SHADER
    return mix(c / 12.92, pow((c + 0.055) / 1.055, vec3(2.4)), step(0.04045, c));
#else
    return c;
#endif
}

void main() {
#ifdef POINTS
    // Round points: the sprite's square less what lies outside its inscribed disk.
    vec2 pc = gl_PointCoord - vec2(0.5);
    if (dot(pc, pc) > 0.25) discard;
#endif
    vec3 albedo = uBaseColor;
    float texAlpha = 1.0;
#ifdef HAS_ALBEDO_MAP
    vec4 base = TEX2D(uAlbedoMap, SLOT_UV(0));
    albedo *= glviewToLinear(base.rgb);
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
    // Vertex colours are sRGB values that no sampler decodes: always decoded here.
    albedo *= mix(vColor.rgb / 12.92, pow((vColor.rgb + 0.055) / 1.055, vec3(2.4)),
                  step(0.04045, vColor.rgb));
#endif
    float metallic = uMetallic;
    float rough = uRoughness;
    float ao = 1.0;
#ifdef HAS_ORM_MAP
    vec3 orm = TEX2D(uOrmMap, SLOT_UV(1)).rgb;
    ao = mix(1.0, orm.r, uOrmAo);
    rough *= orm.g;
    metallic *= orm.b;
#endif
#ifdef HAS_AO_MAP
    ao *= 1.0 + uOcclusionStrength * (TEX2D(uAoMap, SLOT_UV(3)).r - 1.0);
#endif
    ao = mix(1.0, ao, uTermsB.x);
    vec3 emissive = uEmissive;
#ifdef HAS_EMISSIVE_MAP
    emissive *= glviewToLinear(TEX2D(uEmissiveMap, SLOT_UV(4)).rgb);
#endif
#ifdef UNLIT
    // KHR_materials_unlit: the base colour is the colour, through the same output step.
    FRAG_COLOR = glviewOutputRgba(albedo, opacity);
#else
    vec3 n = glviewSafeNormalize(vNormal);
    if (!gl_FrontFacing) n = -n;
    vec3 geomN = n;
#ifdef HAS_NORMAL_MAP
    n = glviewNormalMap(n, gl_FrontFacing);
#endif
#ifndef SHOW_ATTRIBUTE
#define SHOW_ATTRIBUTE 0
#endif
#if SHOW_ATTRIBUTE == 1
    FRAG_COLOR = vec4(n * 0.5 + 0.5, 1.0);
    return;
#elif SHOW_ATTRIBUTE == 2
    FRAG_COLOR = vec4(fract(vUv), 0.0, 1.0);
    return;
#elif SHOW_ATTRIBUTE == 3
    FRAG_COLOR = vec4(vec3(clamp(rough, 0.0, 1.0)), 1.0);
    return;
#elif SHOW_ATTRIBUTE == 4
    FRAG_COLOR = vec4(vec3(clamp(metallic, 0.0, 1.0)), 1.0);
    return;
#endif
    vec3 v = normalize(-vEyePos);
    float nv = max(dot(n, v), 1e-4);
#ifdef KHR_SPECULAR
    vec3 f0d = uF0;
    float specW = uSpecularWeight;
#ifdef HAS_SPECULAR_COLOR_MAP
    f0d *= glviewToLinear(TEX2D(uSpecularColorMap, KHR_UV(6)).rgb);
#endif
#ifdef HAS_SPECULAR_MAP
    specW *= TEX2D(uSpecularMap, KHR_UV(5)).a;
#endif
    f0d = min(f0d, vec3(1.0)) * specW;
    vec3 kd = albedo * (1.0 - max(max(f0d.r, f0d.g), f0d.b)) * (1.0 - metallic);
    vec3 ks = mix(f0d, albedo, metallic);
    vec3 f90 = vec3(mix(specW, 1.0, metallic));
#else
    vec3 kd = albedo * (1.0 - 0.04) * (1.0 - metallic);
    vec3 ks = mix(vec3(0.04), albedo, metallic);
#endif
    vec3 color = uTermsB.z * emissive;
#ifdef KHR_TRANSMISSION
    // KHR_materials_transmission (the Sample Viewer's getIBLVolumeRefraction): the diffuse
    // share becomes the light from behind, read from the opaque frame where the ray leaves
    // (here when thin-walled; refracted through the thickness with KHR_materials_volume),
    // blurred by the roughness scaled by the ior.
    float trans = uTransmission * uTermsC.z;
#ifdef HAS_TRANSMISSION_MAP
    trans *= TEX2D(uTransmissionMap, KHR_UV(7)).r;
#endif
    vec3 exitPos = vEyePos;
#ifdef KHR_VOLUME
    float thick = uThickness;
#ifdef HAS_THICKNESS_MAP
    thick *= TEX2D(uThicknessMap, KHR_UV(8)).g;
#endif
    exitPos += glviewSafeNormalize(refract(-v, n, 1.0 / uIor)) * thick;
    // Beer-Lambert: after a distance d the light keeps attenuationColor^(d / distance)
    // (the light from behind and each light through the surface alike).
    vec3 attenuation = vec3(1.0);
    if (uAttenuationDistance > 0.0)
        attenuation = pow(max(uAttenuationColor, vec3(1e-6)), vec3(thick / uAttenuationDistance));
#endif
    vec4 exitClip = uProjection * vec4(exitPos, 1.0);
    vec2 frameUv = exitClip.xy / exitClip.w * 0.5 + 0.5;
    float frameLod = uFrameLevels * rough * clamp(uIor * 2.0 - 2.0, 0.0, 1.0);
    // The lights' transmission lobe's roughness: the same ior scaling (the same for each light).
    float transRough = rough * clamp(uIor * 2.0 - 2.0, 0.0, 1.0);
    vec3 behind = glviewInverseOutput(GLVIEW_TEX2D_LOD(uTransmissionFrame, frameUv, frameLod).rgb);
#ifdef KHR_VOLUME
    behind *= attenuation;
#endif
    kd *= 1.0 - trans;
#endif

    // Image-based light (the seed's split sum).
    vec2 bf = glviewBrdf(nv, rough);
    vec3 r = reflect(-v, n);
#ifdef DOMINANT_DIRECTION
    // Filament's dominant direction: rough lobes lean towards the normal.
    float a = rough * rough;
    r = normalize(mix(r, n, a * a));
#endif
#ifdef KHR_SPECULAR
    vec3 spec = ks * bf.x + f90 * bf.y;
#else
    vec3 spec = ks * bf.x + bf.y;
#endif
#ifdef MULTISCATTER
    // Energy lost to single scattering is added back (Fdez-Aguera 2019).
    spec *= 1.0 + ks * (1.0 / max(bf.x + bf.y, 1e-4) - 1.0);
#endif
    color += ao * (uTermsA.z * glviewIrradiance(n) * kd + uTermsA.w * glviewSpecular(r, rough) * spec);
#ifdef KHR_TRANSMISSION
    // What the specular lobe does not reflect passes: (1 - (k_s A + F90 B)) of the light
    // behind, tinted by the base colour, for the dielectric share.
#ifdef KHR_SPECULAR
    vec3 passes = 1.0 - (ks * bf.x + f90 * bf.y);
#else
    vec3 passes = 1.0 - (ks * bf.x + bf.y);
#endif
    color += trans * (1.0 - metallic) * passes * albedo * behind;
#endif
#ifdef KHR_SHEEN
    vec3 sheenColor = uSheenColor * uTermsC.y;
#ifdef HAS_SHEEN_COLOR_MAP
    sheenColor *= glviewToLinear(TEX2D(uSheenColorMap, KHR_UV(3)).rgb);
#endif
    float sheenRough = uSheenRoughness;
#ifdef HAS_SHEEN_ROUGH_MAP
    sheenRough *= TEX2D(uSheenRoughMap, KHR_UV(4)).a;
#endif
    float sheenE = glviewSheenE(nv, sheenRough);
    // The sheen's light: the irradiance times its albedo (exact in a uniform environment).
    // The Charlie lobe is wide and leans to the horizon: against the reference on the
    // built-in sky the irradiance cube is nearer than the specular cube at the sheen
    // roughness along R (pixels > 8/255 at sheen roughness 0.1/0.4/1: 5/18/0.3 % against
    // 9/39/40 %; docs/gltf/extensions.md).
    vec3 fSheen = ao * uTermsA.w * glviewIrradiance(n) * sheenColor * sheenE;
    float sheenScale = 1.0 - max(max(sheenColor.r, sheenColor.g), sheenColor.b) * sheenE;
#endif
#ifdef KHR_CLEARCOAT
    float cc = uClearcoat * uTermsC.x;
#ifdef HAS_CC_MAP
    cc *= TEX2D(uClearcoatMap, KHR_UV(0)).r;
#endif
    float ccRough = uClearcoatRoughness;
#ifdef HAS_CC_ROUGH_MAP
    ccRough *= TEX2D(uClearcoatRoughMap, KHR_UV(1)).g;
#endif
    ccRough = clamp(ccRough, 0.0, 1.0);
    // Without its own map the coat follows the geometry, not the base's normal map.
    vec3 ccN = geomN;
#ifdef HAS_CC_NORMAL_MAP
    vec3 ccM = TEX2D(uClearcoatNormalMap, KHR_UV(2)).rgb * 2.0 - 1.0;
    ccM.xy *= uClearcoatNormalScale;
    ccN = glviewTangentToEye(geomN, gl_FrontFacing, ccM);
#endif
    float ccNv = max(dot(ccN, v), 1e-4);
    vec2 ccBf = glviewBrdf(ccNv, ccRough);
    vec3 fCoat = vec3(ao * uTermsA.w * (0.04 * ccBf.x + ccBf.y))
        * glviewSpecular(reflect(-v, ccN), ccRough);
    float ccF = glviewF_Schlick(vec3(0.04), ccNv).x;
#endif

#if NUM_LIGHTS > 0
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
        vec3 l = uLightPos[i].xyz;
        if (uLightPos[i].w != 0.0) {
            vec3 d = uLightPos[i].xyz - vEyePos;
            float len = length(d);
            l = len > 0.0 ? d / len : vec3(0.0);
        }
        float nl = dot(n, l);
        float shadow = mix(1.0, vis[i], uTermsB.y);
#ifdef KHR_TRANSMISSION
        {
            // The light through the surface (the Sample Viewer's punctual BTDF): the light's
            // direction from where the ray leaves, mirrored to the viewer's side, in a GGX
            // lobe of the roughness scaled by the ior; no cosine and no shadow map (the
            // surface would shadow itself), as there.
            vec3 lt = l;
            if (uLightPos[i].w != 0.0) lt = glviewSafeNormalize(uLightPos[i].xyz - exitPos);
            vec3 lm = glviewSafeNormalize(lt - 2.0 * n * dot(lt, n));
            vec3 ht = glviewSafeNormalize(lm + v);
            float nlm = max(dot(n, lm), 1e-4);
#ifdef KHR_SPECULAR
            vec3 ft = glviewF_Schlick90(ks, f90, dot(v, ht));
#else
            vec3 ft = glviewF_Schlick(ks, dot(v, ht));
#endif
            vec3 bt = (1.0 - ft) * albedo * glviewD_GGX(max(dot(n, ht), 0.0), transRough)
                * glviewG_Smith(nv, nlm, transRough) / (4.0 * nv * nlm);
#ifdef KHR_VOLUME
            bt *= attenuation;
#endif
            color += trans * (1.0 - metallic) * uTermsA.x * uLightColor[i] * GLVIEW_PI * bt;
        }
#endif
        if (nl > 0.0) {
            vec3 h = glviewSafeNormalize(l + v);
#ifdef KHR_SPECULAR
            vec3 f = glviewF_Schlick90(ks, f90, dot(v, h));
#else
            vec3 f = glviewF_Schlick(ks, dot(v, h));
#endif
            vec3 fs = glviewD_GGX(max(dot(n, h), 0.0), rough) * glviewG_Smith(nv, nl, rough) * f
                / (4.0 * nv * nl);
            color += shadow * uLightColor[i] * (uTermsA.x * kd + uTermsA.y * GLVIEW_PI * fs) * nl;
#ifdef KHR_SHEEN
            float sh = glviewD_Charlie(max(dot(n, h), 0.0), sheenRough) * glviewV_Neubelt(nv, nl);
            fSheen += shadow * uLightColor[i] * (uTermsA.y * GLVIEW_PI * sh * nl) * sheenColor;
#endif
        }
#ifdef KHR_CLEARCOAT
        float ccNl = dot(ccN, l);
        if (ccNl > 0.0) {
            vec3 hc = glviewSafeNormalize(l + v);
            float fc = glviewF_Schlick(vec3(0.04), dot(v, hc)).x;
            float sc = glviewD_GGX(max(dot(ccN, hc), 0.0), ccRough)
                * glviewG_Smith(ccNv, ccNl, ccRough) * fc / (4.0 * ccNv * ccNl);
            fCoat += shadow * uLightColor[i] * (uTermsA.y * GLVIEW_PI * sc * ccNl);
        }
#endif
    }
#endif
#ifdef KHR_SHEEN
    color = color * sheenScale + fSheen;
#endif
#ifdef KHR_CLEARCOAT
    color = color * (1.0 - cc * ccF) + cc * fCoat;
#endif
    FRAG_COLOR = glviewOutputRgba(color, opacity);
#endif
#ifdef LOG_DEPTH
    glviewLogDepth();
#endif
}
