// Legacy tier: positions to eye space; with GOURAUD the lighting factors are evaluated here,
// per vertex, for the front and the flipped (back-face) normal.
IN vec3 aPosition;
IN vec3 aNormal;
IN vec2 aUv;
#include "instance.glsl"
#include "skin.glsl"
#ifdef HAS_COLOR
IN vec4 aColor;     // per-vertex colour: multiplies Ka and Kd like a texture; alpha
OUT vec4 vColor;    // (1 if not given) multiplies the base colour's alpha
#endif
#ifdef HAS_UV1
IN vec2 aUv1;       // glTF TEXCOORD_1, for slots that name it
OUT vec2 vUv1;
#endif
#ifdef HAS_NORMAL_MAP
IN vec4 aTangent;
OUT vec4 vTangent;
#endif

uniform mat4 uModelView;
uniform mat4 uProjection;
uniform mat3 uNormalMatrix;
#ifdef POINTS
uniform float uPointSize;   // diameter in pixels (GL 2.1 and core need PROGRAM_POINT_SIZE on)
#endif

OUT vec3 vEyePos;
#ifdef LOG_DEPTH
OUT float vClipW;   // for the logarithmic depth written per fragment
#endif
#if defined(HAS_TEXTURE) || defined(HAS_EMISSIVE_MAP) || defined(HAS_NORMAL_MAP)
OUT vec2 vUv;
#endif
OUT vec3 vNormal;   // also used by Gouraud: the shadow lookup is offset along it
#ifdef GOURAUD
#if NUM_LIGHTS > 0
#include "lighting.glsl"
#ifdef FALLOFF
#include "falloff.glsl"
#endif
OUT vec4 vFactors[NUM_LIGHTS];   // xy: front face, zw: back face (times the falloff)
#endif
#endif

void main() {
    vec4 eye = uModelView * vec4(instancePoint(skinPoint(aPosition)), 1.0);
    vEyePos = eye.xyz;
#if defined(HAS_TEXTURE) || defined(HAS_EMISSIVE_MAP) || defined(HAS_NORMAL_MAP)
    vUv = aUv;
#endif
#ifdef HAS_UV1
    vUv1 = aUv1;
#endif
#ifdef HAS_NORMAL_MAP
    vTangent = vec4(uNormalMatrix * instanceDirection(skinDirection(aTangent.xyz)), skinHanded(aTangent.w));
#endif
#ifdef HAS_COLOR
    vColor = aColor;
#endif
    vec3 n = uNormalMatrix * instanceNormal(skinNormal(aNormal));
#ifdef GOURAUD
#if NUM_LIGHTS > 0
    n = safeNormalize(n);
    vec3 v = normalize(-eye.xyz);
    for (int i = 0; i < NUM_LIGHTS; ++i) {
        vec3 l = toLight(uLightPos[i], eye.xyz);
        vFactors[i] = vec4(lightFactors(l, n, v), lightFactors(l, -n, v));
#ifdef FALLOFF
        vFactors[i] *= glviewFalloff(i, eye.xyz);
#endif
    }
#endif
#endif
    vNormal = n;
    gl_Position = uProjection * eye;
#ifdef POINTS
    gl_PointSize = uPointSize;
#endif
#ifdef LOG_DEPTH
    vClipW = gl_Position.w;
#endif
}
