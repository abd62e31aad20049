// PBR tier: positions, normals and tangents to eye space.
IN vec3 aPosition;
IN vec3 aNormal;
IN vec2 aUv;
#include "instance.glsl"
#include "skin.glsl"
#ifdef HAS_COLOR
IN vec4 aColor;     // per-vertex colour, sRGB like a base-colour map; alpha (1 if not given)
OUT vec4 vColor;
#endif
#if defined(HAS_NORMAL_MAP) || defined(HAS_CC_NORMAL_MAP) || defined(KHR_ANISOTROPY)
IN vec4 aTangent;
#endif
#ifdef HAS_UV1
IN vec2 aUv1;       // glTF TEXCOORD_1, for slots that name it
OUT vec2 vUv1;
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
OUT vec2 vUv;
OUT vec3 vNormal;
#if defined(HAS_NORMAL_MAP) || defined(HAS_CC_NORMAL_MAP) || defined(KHR_ANISOTROPY)
OUT vec4 vTangent;
#endif

void main() {
    vec4 eye = uModelView * vec4(instancePoint(skinPoint(aPosition)), 1.0);
    vEyePos = eye.xyz;
    vUv = aUv;
#ifdef HAS_UV1
    vUv1 = aUv1;
#endif
#ifdef HAS_COLOR
    vColor = aColor;
#endif
    vNormal = uNormalMatrix * instanceNormal(skinNormal(aNormal));
#if defined(HAS_NORMAL_MAP) || defined(HAS_CC_NORMAL_MAP) || defined(KHR_ANISOTROPY)
    vTangent = vec4(uNormalMatrix * instanceDirection(skinDirection(aTangent.xyz)), skinHanded(aTangent.w));
#endif
    gl_Position = uProjection * eye;
#ifdef POINTS
    gl_PointSize = uPointSize;
#endif
#ifdef LOG_DEPTH
    vClipW = gl_Position.w;
#endif
}
