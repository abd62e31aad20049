// PBR tier (the seed's formula), linear until glviewOutput:
//   Lo = Ke + E_d(N)*k_d*ao + E_s(R, r)*(k_s*A + B)*ao
//      + sum_i vis_i * Lc_i * (k_d + pi * D*G*F / (4 N.L N.V)) * N.L
// k_d = albedo*(1 - f0)*(1 - metallic), k_s = mix(f0, albedo, metallic), f0 = 0.04.
// The glTF PBR extensions are program permutations (docs/gltf/extensions.md), after the
// Khronos Sample Viewer: KHR_SPECULAR (KHR_materials_specular and _ior) sets f0 = min(ior F0
// * specular colour, 1) * weight and f90 = weight for the dielectric; KHR_SHEEN adds a
// Charlie lobe and scales what lies under it by 1 - max(sheen colour) * E_sheen(N.V);
// KHR_CLEARCOAT adds a GGX lobe of F0 0.04 on its own normal and roughness and scales what
// lies under it by 1 - clearcoat * F_cc(N_cc.V); KHR_IRIDESCENCE mixes the base's reflection
// Fresnel with a thin film's at N.V by the iridescence factor (the diffuse with the film's
// reflectance at normal incidence in place of f0); KHR_ANISOTROPY stretches the base's GGX
// lobe along a tangent-space direction (the Sample Viewer's anisotropic D and V, and its
// bent normal for the environment's lobe).
IN vec3 vEyePos;
#ifdef LOG_DEPTH
#include "logdepth.glsl"
#endif
IN vec2 vUv;
IN vec3 vNormal;
#include "material.glsl"
#if defined(HAS_NORMAL_MAP) || defined(HAS_CC_NORMAL_MAP) || defined(KHR_ANISOTROPY)
#include "normalmap.glsl"
#endif
#if NUM_LIGHTS > 0
uniform vec4 uLightPos[NUM_LIGHTS];   // w = 0: unit direction towards the light; w = 1: position
uniform vec3 uLightColor[NUM_LIGHTS];
#ifdef FALLOFF
#include "falloff.glsl"
#endif
#endif
#if NUM_SHADOWS > 0
#include "shadow.glsl"
#endif
#include "ibl.glsl"
#ifdef KHR_IRIDESCENCE
#include "iridescence.glsl"
#endif
#ifdef KHR_ANISOTROPY
#include "anisotropy.glsl"
#endif
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
// 6 specular colour, 7 transmission, 8 thickness, 9 iridescence, 10 iridescence thickness,
// 11 anisotropy; each with its UV set and transform like the core slots.
uniform mat3 uKhrXf[12];
uniform float uKhrSet[12];
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
#ifdef KHR_IRIDESCENCE
uniform float uIridescence;
uniform float uTermIridescence;        // the --terms layer (0 or 1)
uniform float uIridescenceIor;
uniform vec2 uIridescenceThickness;    // minimum, maximum (nm)
#ifdef HAS_IRIDESCENCE_MAP
uniform sampler2D uIridescenceMap;     // r
#endif
#ifdef HAS_IRIDESCENCE_THICKNESS_MAP
uniform sampler2D uIridescenceThicknessMap;   // g
#endif
#endif
#ifdef KHR_ANISOTROPY
uniform vec3 uAnisotropy;              // cos(rotation), sin(rotation), strength
uniform float uTermAnisotropy;         // the --terms layer (0 or 1)
#ifdef HAS_ANISOTROPY_MAP
uniform sampler2D uAnisotropyMap;      // rg: direction in [-1, 1] as [0, 1]; b: strength
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
// The fragment's material and, once the normal is known, what every lobe shares. main's steps
// pass it along (GLSL 1.20 has no references); a step that changes it returns it or takes it
// inout. Each step computes its values with the same expressions, in the same order, as the
// one main they were split from, so the pictures stay bit-identical.
struct PbrSurface {
    vec3 albedo;      // linear
    float opacity;    // blend: the texture's and the vertex colour's alpha multiplied in
    float metallic;
    float rough;
    float ao;         // 1 where the ambient occlusion term is off
    vec3 emissive;    // linear
    vec3 n;           // the shading normal (normal map applied), on the viewer's side
    vec3 geomN;       // the geometry's: shadows, and the clear coat without its own map
    vec3 v;           // towards the eye
    float nv;
    vec3 kd;          // the diffuse colour (less what transmission takes)
    vec3 ks;          // the specular colour at normal incidence
#ifdef KHR_SPECULAR
    vec3 f90;
#endif
#ifdef KHR_IRIDESCENCE
    float irid;       // the film's weight
    vec3 iridF;       // the film's Fresnel at N.V
#endif
#ifdef KHR_ANISOTROPY
    float aniso;      // the strength (0: the layer off)
    vec3 anisoT;      // the direction the lobe stretches along (eye space)
    vec3 anisoB;      // cross(geomN, anisoT)
#endif
};

// The base colour, metallic, roughness, occlusion and emission: the factors times their
// maps and the vertex colour; the alpha test's discard on the way.
PbrSurface pbrMaterial() {
    PbrSurface s;
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
    s.opacity = uOpacity * texAlpha;
#else
    s.opacity = uOpacity;
#endif
#ifdef HAS_COLOR
    // Vertex colours are sRGB values that no sampler decodes: always decoded here.
    albedo *= mix(vColor.rgb / 12.92, pow((vColor.rgb + 0.055) / 1.055, vec3(2.4)),
                  step(0.04045, vColor.rgb));
#endif
    s.albedo = albedo;
    s.metallic = uMetallic;
    s.rough = uRoughness;
    float ao = 1.0;
#ifdef HAS_ORM_MAP
    vec3 orm = TEX2D(uOrmMap, SLOT_UV(1)).rgb;
    ao = mix(1.0, orm.r, uOrmAo);
    s.rough *= orm.g;
    s.metallic *= orm.b;
#endif
#ifdef HAS_AO_MAP
    ao *= 1.0 + uOcclusionStrength * (TEX2D(uAoMap, SLOT_UV(3)).r - 1.0);
#endif
    s.ao = mix(1.0, ao, uTermsB.x);
    s.emissive = uEmissive;
#ifdef HAS_EMISSIVE_MAP
    s.emissive *= glviewToLinear(TEX2D(uEmissiveMap, SLOT_UV(4)).rgb);
#endif
    return s;
}

#ifdef KHR_IRIDESCENCE
// KHR_materials_iridescence: the film's weight and its Fresnel at N.V over the base's k_s;
// the diffuse takes what the film reflects at normal incidence in place of f0 (mixed by the
// weight), as glview's k_d takes f0 and not the Fresnel at the view's angle.
void pbrFilm(inout PbrSurface s, float f0max) {
    s.irid = uIridescence * uTermIridescence;
#ifdef HAS_IRIDESCENCE_MAP
    s.irid *= TEX2D(uIridescenceMap, KHR_UV(9)).r;
#endif
    float d = uIridescenceThickness.y;
#ifdef HAS_IRIDESCENCE_THICKNESS_MAP
    d = mix(uIridescenceThickness.x, d, TEX2D(uIridescenceThicknessMap, KHR_UV(10)).g);
#endif
    // A film of no thickness is none (as the Sample Viewer: the formula would tint).
    if (d <= 0.0) s.irid = 0.0;
    s.iridF = glviewIridescence(uIridescenceIor, s.nv, d, s.ks);
    vec3 i0 = glviewIridescence(uIridescenceIor, 1.0, d, s.ks);
    float f0 = mix(f0max, max(max(i0.r, i0.g), i0.b), s.irid);
    s.kd = s.albedo * (1.0 - f0) * (1.0 - s.metallic);
}
#endif

#ifdef KHR_ANISOTROPY
// KHR_materials_anisotropy (the Sample Viewer's getAnisotropyInfo): the texture's direction
// (or the tangent's) turned by the rotation, in the tangent frame of the geometry's normal;
// the strength is the factor times the texture's blue.
void pbrAnisotropy(inout PbrSurface s) {
    vec2 dir = vec2(1.0, 0.0);
    float strength = uAnisotropy.z * uTermAnisotropy;
#ifdef HAS_ANISOTROPY_MAP
    vec3 a = TEX2D(uAnisotropyMap, KHR_UV(11)).rgb;
    dir = a.rg * 2.0 - 1.0;
    strength *= a.b;
#endif
    dir = mat2(uAnisotropy.x, uAnisotropy.y, -uAnisotropy.y, uAnisotropy.x) * dir;
    float dl = length(dir);
    dir = dl > 0.0 ? dir / dl : vec2(1.0, 0.0);
    // The tangent frame as glviewTangentToEye builds it (flipped on back faces).
    float side = gl_FrontFacing ? 1.0 : -1.0;
    vec3 tv = vTangent.xyz * side;
    vec3 t = tv - s.geomN * dot(s.geomN, tv);
    float tl = length(t);
    if (tl <= 0.0) strength = 0.0;
    t = tl > 0.0 ? t / tl : vec3(1.0, 0.0, 0.0);
    vec3 b = cross(s.geomN, t) * (vTangent.w < 0.0 ? -side : side);
    s.anisoT = t * dir.x + b * dir.y;
    s.anisoB = cross(s.geomN, s.anisoT);
    s.aniso = clamp(strength, 0.0, 1.0);
}
#endif

// The view direction and the base layer's diffuse and specular colours (KHR_SPECULAR: its
// dielectric F0 and F90).
void pbrView(inout PbrSurface s) {
    s.v = normalize(-vEyePos);
    s.nv = max(dot(s.n, s.v), 1e-4);
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
    float f0max = max(max(f0d.r, f0d.g), f0d.b);
    s.kd = s.albedo * (1.0 - f0max) * (1.0 - s.metallic);
    s.ks = mix(f0d, s.albedo, s.metallic);
    s.f90 = vec3(mix(specW, 1.0, s.metallic));
#else
    float f0max = 0.04;
    s.kd = s.albedo * (1.0 - 0.04) * (1.0 - s.metallic);
    s.ks = mix(vec3(0.04), s.albedo, s.metallic);
#endif
#ifdef KHR_IRIDESCENCE
    pbrFilm(s, f0max);
#endif
#ifdef KHR_ANISOTROPY
    pbrAnisotropy(s);
#endif
}

// The base layer's Fresnel at the angle whose cosine is vh.
vec3 pbrFresnel(PbrSurface s, float vh) {
#ifdef KHR_SPECULAR
    return glviewF_Schlick90(s.ks, s.f90, vh);
#else
    return glviewF_Schlick(s.ks, vh);
#endif
}

// The split sum's specular colour k_s A + F90 B (F90 is 1 without KHR_SPECULAR).
vec3 pbrSplitSum(PbrSurface s, vec2 bf) {
#ifdef KHR_SPECULAR
    return s.ks * bf.x + s.f90 * bf.y;
#else
    return s.ks * bf.x + bf.y;
#endif
}

// Image-based light (the seed's split sum): the irradiance's diffuse and the prefiltered
// cube's specular, occluded.
vec3 pbrIbl(PbrSurface s) {
    vec2 bf = glviewBrdf(s.nv, s.rough);
    vec3 r = reflect(-s.v, s.n);
#ifdef KHR_ANISOTROPY
    // The Sample Viewer's getIBLRadianceAnisotropy: the isotropic lobe about the bent normal.
    if (s.aniso > 0.0)
        r = reflect(-s.v, glviewAnisoBentNormal(s.n, s.v, s.anisoB, s.aniso, s.rough));
#endif
#ifdef DOMINANT_DIRECTION
    // Filament's dominant direction: rough lobes lean towards the normal.
    float a = s.rough * s.rough;
    r = normalize(mix(r, s.n, a * a));
#endif
    vec3 spec = pbrSplitSum(s, bf);
#ifdef KHR_IRIDESCENCE
    // The film's Fresnel is the same for every direction of the lobe: it scales A + B.
    spec = mix(spec, s.iridF * (bf.x + bf.y), s.irid);
#endif
#ifdef MULTISCATTER
    // Energy lost to single scattering is added back (Fdez-Aguera 2019).
    spec *= 1.0 + s.ks * (1.0 / max(bf.x + bf.y, 1e-4) - 1.0);
#endif
    return s.ao * (uTermsA.z * glviewIrradiance(s.n) * s.kd
        + uTermsA.w * glviewSpecular(r, s.rough) * spec);
}

#ifdef KHR_TRANSMISSION
// KHR_materials_transmission (the Sample Viewer's getIBLVolumeRefraction): the diffuse share
// becomes the light from behind, read from the opaque frame where the ray leaves (here when
// thin-walled; refracted through the thickness with KHR_materials_volume), blurred by the
// roughness scaled by the ior.
struct PbrTransmission {
    float weight;        // the share of the dielectric's diffuse that is transmitted
    vec3 exitPos;        // where the ray leaves the volume (eye space)
    float rough;         // the lights' transmission lobe's: the roughness scaled by the ior
    vec3 behind;         // the light from behind, attenuated
#ifdef KHR_VOLUME
    vec3 attenuation;    // Beer-Lambert through the thickness
#endif
};

PbrTransmission pbrTransmission(PbrSurface s) {
    PbrTransmission t;
    t.weight = uTransmission * uTermsC.z;
#ifdef HAS_TRANSMISSION_MAP
    t.weight *= TEX2D(uTransmissionMap, KHR_UV(7)).r;
#endif
    t.exitPos = vEyePos;
#ifdef KHR_VOLUME
    float thick = uThickness;
#ifdef HAS_THICKNESS_MAP
    thick *= TEX2D(uThicknessMap, KHR_UV(8)).g;
#endif
    t.exitPos += glviewSafeNormalize(refract(-s.v, s.n, 1.0 / uIor)) * thick;
    // Beer-Lambert: after a distance d the light keeps attenuationColor^(d / distance)
    // (the light from behind and each light through the surface alike).
    t.attenuation = vec3(1.0);
    if (uAttenuationDistance > 0.0)
        t.attenuation = pow(max(uAttenuationColor, vec3(1e-6)), vec3(thick / uAttenuationDistance));
#endif
    vec4 exitClip = uProjection * vec4(t.exitPos, 1.0);
    vec2 frameUv = exitClip.xy / exitClip.w * 0.5 + 0.5;
    float frameLod = uFrameLevels * s.rough * clamp(uIor * 2.0 - 2.0, 0.0, 1.0);
    // The lights' transmission lobe's roughness: the same ior scaling (the same for each light).
    t.rough = s.rough * clamp(uIor * 2.0 - 2.0, 0.0, 1.0);
    t.behind = glviewInverseOutput(GLVIEW_TEX2D_LOD(uTransmissionFrame, frameUv, frameLod).rgb);
#ifdef KHR_VOLUME
    t.behind *= t.attenuation;
#endif
    return t;
}

// What the specular lobe does not reflect passes: (1 - (k_s A + F90 B)) of the light behind,
// tinted by the base colour, for the dielectric share.
vec3 pbrIblTransmitted(PbrSurface s, PbrTransmission t) {
    vec2 bf = glviewBrdf(s.nv, s.rough);
    vec3 passes = 1.0 - pbrSplitSum(s, bf);
    return t.weight * (1.0 - s.metallic) * passes * s.albedo * t.behind;
}

#if NUM_LIGHTS > 0
// Light i through the surface (the Sample Viewer's punctual BTDF): the light's direction
// from where the ray leaves, mirrored to the viewer's side, in a GGX lobe of the roughness
// scaled by the ior; no cosine and no shadow map (the surface would shadow itself), as there.
// The light's uniforms come as values: GLSL ES 1.00 (Appendix A) indexes uniform arrays by
// loop indices only, and a parameter is not one.
vec3 pbrTransmittedLight(vec4 lightPos, vec3 lightColor, vec3 l, PbrSurface s,
                         PbrTransmission t) {
    vec3 lt = l;
    if (lightPos.w != 0.0) lt = glviewSafeNormalize(lightPos.xyz - t.exitPos);
    vec3 lm = glviewSafeNormalize(lt - 2.0 * s.n * dot(lt, s.n));
    vec3 ht = glviewSafeNormalize(lm + s.v);
    float nlm = max(dot(s.n, lm), 1e-4);
    vec3 ft = pbrFresnel(s, dot(s.v, ht));
    vec3 bt = (1.0 - ft) * s.albedo * glviewD_GGX(max(dot(s.n, ht), 0.0), t.rough)
        * glviewG_Smith(s.nv, nlm, t.rough) / (4.0 * s.nv * nlm);
#ifdef KHR_VOLUME
    bt *= t.attenuation;
#endif
    return t.weight * (1.0 - s.metallic) * uTermsA.x * lightColor * GLVIEW_PI * bt;
}
#endif
#endif

#ifdef KHR_SHEEN
// KHR_materials_sheen's Charlie lobe: what it reflects is added over the base, which is
// scaled by 1 - max(sheen colour) * E_sheen(N.V).
struct PbrSheen {
    vec3 color;
    float rough;
    float albedo;    // E_sheen(N.V)
};

PbrSheen pbrSheen(PbrSurface s) {
    PbrSheen sh;
    sh.color = uSheenColor * uTermsC.y;
#ifdef HAS_SHEEN_COLOR_MAP
    sh.color *= glviewToLinear(TEX2D(uSheenColorMap, KHR_UV(3)).rgb);
#endif
    sh.rough = uSheenRoughness;
#ifdef HAS_SHEEN_ROUGH_MAP
    sh.rough *= TEX2D(uSheenRoughMap, KHR_UV(4)).a;
#endif
    sh.albedo = glviewSheenE(s.nv, sh.rough);
    return sh;
}

// The sheen's light from the environment: the irradiance times its albedo (exact in a
// uniform environment). The Charlie lobe is wide and leans to the horizon: against the
// reference on the built-in sky the irradiance cube is nearer than the specular cube at the
// sheen roughness along R (pixels > 8/255 at sheen roughness 0.1/0.4/1: 5/18/0.3 % against
// 9/39/40 %; docs/gltf/extensions.md).
vec3 pbrSheenIbl(PbrSurface s, PbrSheen sh) {
    return s.ao * uTermsA.w * glviewIrradiance(s.n) * sh.color * sh.albedo;
}

// The sheen lobe's light from light l (unit direction towards it), shadowed.
void pbrAddSheenLight(vec3 l, float shadow, vec3 lightColor, PbrSurface s, PbrSheen sh,
                      inout vec3 fSheen) {
    float nl = dot(s.n, l);
    if (nl > 0.0) {
        vec3 h = glviewSafeNormalize(l + s.v);
        float d = glviewD_Charlie(max(dot(s.n, h), 0.0), sh.rough) * glviewV_Neubelt(s.nv, nl);
        fSheen += shadow * lightColor * (uTermsA.y * GLVIEW_PI * d * nl) * sh.color;
    }
}
#endif

#ifdef KHR_CLEARCOAT
// KHR_materials_clearcoat: a GGX lobe of F0 0.04 on its own normal and roughness over the
// base, which is scaled by 1 - clearcoat * F_cc(N_cc.V).
struct PbrCoat {
    float weight;
    float rough;
    vec3 n;
    float nv;
    float fresnel;   // F_cc(N_cc.V)
};

PbrCoat pbrCoat(PbrSurface s) {
    PbrCoat c;
    c.weight = uClearcoat * uTermsC.x;
#ifdef HAS_CC_MAP
    c.weight *= TEX2D(uClearcoatMap, KHR_UV(0)).r;
#endif
    c.rough = uClearcoatRoughness;
#ifdef HAS_CC_ROUGH_MAP
    c.rough *= TEX2D(uClearcoatRoughMap, KHR_UV(1)).g;
#endif
    c.rough = clamp(c.rough, 0.0, 1.0);
    // Without its own map the coat follows the geometry, not the base's normal map.
    c.n = s.geomN;
#ifdef HAS_CC_NORMAL_MAP
    vec3 ccM = TEX2D(uClearcoatNormalMap, KHR_UV(2)).rgb * 2.0 - 1.0;
    ccM.xy *= uClearcoatNormalScale;
    c.n = glviewTangentToEye(s.geomN, gl_FrontFacing, ccM);
#endif
    c.nv = max(dot(c.n, s.v), 1e-4);
    c.fresnel = glviewF_Schlick(vec3(0.04), c.nv).x;
    return c;
}

// The coat's light from the environment (the split sum on its own normal and roughness).
vec3 pbrCoatIbl(PbrSurface s, PbrCoat c) {
    vec2 ccBf = glviewBrdf(c.nv, c.rough);
    return vec3(s.ao * uTermsA.w * (0.04 * ccBf.x + ccBf.y))
        * glviewSpecular(reflect(-s.v, c.n), c.rough);
}

// The coat's light from light l (unit direction towards it), shadowed.
void pbrAddCoatLight(vec3 l, float shadow, vec3 lightColor, PbrSurface s, PbrCoat c,
                     inout vec3 fCoat) {
    float ccNl = dot(c.n, l);
    if (ccNl > 0.0) {
        vec3 hc = glviewSafeNormalize(l + s.v);
        float fc = glviewF_Schlick(vec3(0.04), dot(s.v, hc)).x;
        float sc = glviewD_GGX(max(dot(c.n, hc), 0.0), c.rough)
            * glviewG_Smith(c.nv, ccNl, c.rough) * fc / (4.0 * c.nv * ccNl);
        fCoat += shadow * lightColor * (uTermsA.y * GLVIEW_PI * sc * ccNl);
    }
}
#endif

#if NUM_LIGHTS > 0
// The unit direction from the fragment towards the light at lightPos (uLightPos[i], given by
// value for ES 1.00's indexing rule; 0 when the fragment is at the light).
vec3 pbrToLight(vec4 lightPos) {
    vec3 l = lightPos.xyz;
    if (lightPos.w != 0.0) {
        vec3 d = lightPos.xyz - vEyePos;
        float len = length(d);
        l = len > 0.0 ? d / len : vec3(0.0);
    }
    return l;
}

// The base layer's light from light l (unit direction towards it), shadowed: Lambert's
// diffuse and the GGX specular.
void pbrAddDirectLight(vec3 l, float shadow, vec3 lightColor, PbrSurface s,
                       inout vec3 color) {
    float nl = dot(s.n, l);
    if (nl > 0.0) {
        vec3 h = glviewSafeNormalize(l + s.v);
        vec3 f = pbrFresnel(s, dot(s.v, h));
#ifdef KHR_IRIDESCENCE
        f = mix(f, s.iridF, s.irid);
#endif
        vec3 fs = glviewD_GGX(max(dot(s.n, h), 0.0), s.rough) * glviewG_Smith(s.nv, nl, s.rough)
            * f / (4.0 * s.nv * nl);
#ifdef KHR_ANISOTROPY
        // The Sample Viewer's BRDF_specularGGXAnisotropy (its V holds the 1 / (4 N.L N.V)).
        if (s.aniso > 0.0)
            fs = glviewSpecAniso(s.n, s.nv, s.v, l, h, s.anisoT, s.anisoB, s.rough, s.aniso) * f;
#endif
        color += shadow * lightColor * (uTermsA.x * s.kd + uTermsA.y * GLVIEW_PI * fs) * nl;
    }
}
#endif

void main() {
#ifdef POINTS
    // Round points: the sprite's square less what lies outside its inscribed disk.
    vec2 pc = gl_PointCoord - vec2(0.5);
    if (dot(pc, pc) > 0.25) discard;
#endif
    PbrSurface s = pbrMaterial();
#ifdef UNLIT
    // KHR_materials_unlit: the base colour is the colour, through the same output step.
    FRAG_COLOR = glviewOutputRgba(s.albedo, s.opacity);
#else
    s.n = glviewSafeNormalize(vNormal);
    if (!gl_FrontFacing) s.n = -s.n;
    s.geomN = s.n;
#ifdef HAS_NORMAL_MAP
    s.n = glviewNormalMap(s.n, gl_FrontFacing);
#endif
#ifndef SHOW_ATTRIBUTE
#define SHOW_ATTRIBUTE 0
#endif
#if SHOW_ATTRIBUTE == 1
    FRAG_COLOR = vec4(s.n * 0.5 + 0.5, 1.0);
    return;
#elif SHOW_ATTRIBUTE == 2
    FRAG_COLOR = vec4(fract(vUv), 0.0, 1.0);
    return;
#elif SHOW_ATTRIBUTE == 3
    FRAG_COLOR = vec4(vec3(clamp(s.rough, 0.0, 1.0)), 1.0);
    return;
#elif SHOW_ATTRIBUTE == 4
    FRAG_COLOR = vec4(vec3(clamp(s.metallic, 0.0, 1.0)), 1.0);
    return;
#endif
    pbrView(s);
    vec3 color = uTermsB.z * s.emissive;
#ifdef KHR_TRANSMISSION
    PbrTransmission t = pbrTransmission(s);
    s.kd *= 1.0 - t.weight;
#endif
    color += pbrIbl(s);
#ifdef KHR_TRANSMISSION
    color += pbrIblTransmitted(s, t);
#endif
#ifdef KHR_SHEEN
    PbrSheen sheen = pbrSheen(s);
    vec3 fSheen = pbrSheenIbl(s, sheen);
    float sheenScale = 1.0 - max(max(sheen.color.r, sheen.color.g), sheen.color.b) * sheen.albedo;
#endif
#ifdef KHR_CLEARCOAT
    PbrCoat coat = pbrCoat(s);
    vec3 fCoat = pbrCoatIbl(s, coat);
#endif

#if NUM_LIGHTS > 0
    float vis[NUM_LIGHTS];
    for (int i = 0; i < NUM_LIGHTS; ++i) vis[i] = 1.0;
#if NUM_SHADOWS > 0
    vis[0] = shadowVisibility(uShadowMap0, 0, SHADOW_CUBE0, vEyePos, s.geomN);
#endif
#if NUM_SHADOWS > 1
    vis[1] = shadowVisibility(uShadowMap1, 1, SHADOW_CUBE1, vEyePos, s.geomN);
#endif
#if NUM_SHADOWS > 2
    vis[2] = shadowVisibility(uShadowMap2, 2, SHADOW_CUBE2, vEyePos, s.geomN);
#endif
#if NUM_SHADOWS > 3
    vis[3] = shadowVisibility(uShadowMap3, 3, SHADOW_CUBE3, vEyePos, s.geomN);
#endif
    for (int i = 0; i < NUM_LIGHTS; ++i) {
        vec3 l = pbrToLight(uLightPos[i]);
        float shadow = mix(1.0, vis[i], uTermsB.y);
#ifdef FALLOFF
        float fall = glviewFalloff(i, vEyePos);
        shadow *= fall;
#else
        float fall = 1.0;
#endif
#ifdef KHR_TRANSMISSION
        color += fall * pbrTransmittedLight(uLightPos[i], uLightColor[i], l, s, t);
#endif
        pbrAddDirectLight(l, shadow, uLightColor[i], s, color);
#ifdef KHR_SHEEN
        pbrAddSheenLight(l, shadow, uLightColor[i], s, sheen, fSheen);
#endif
#ifdef KHR_CLEARCOAT
        pbrAddCoatLight(l, shadow, uLightColor[i], s, coat, fCoat);
#endif
    }
#endif
#ifdef KHR_SHEEN
    color = color * sheenScale + fSheen;
#endif
#ifdef KHR_CLEARCOAT
    color = color * (1.0 - coat.weight * coat.fresnel) + coat.weight * fCoat;
#endif
    FRAG_COLOR = glviewOutputRgba(color, s.opacity);
#endif
#ifdef LOG_DEPTH
    glviewLogDepth();
#endif
}
