// Shadow pass: depth from the light only; MASK materials also pass their UVs for the cutout.
IN vec3 aPosition;
#include "instance.glsl"
#include "skin.glsl"
uniform mat4 uLightMvp;
#ifdef ALPHA_MASK
IN vec2 aUv;
OUT vec2 vUv;
#ifdef HAS_UV1
IN vec2 aUv1;
OUT vec2 vUv1;
#endif
#ifdef HAS_COLOR
IN vec4 aColor;     // its alpha multiplies the base colour's (glTF COLOR_0)
OUT float vAlpha;
#endif
#endif

void main() {
#ifdef ALPHA_MASK
    vUv = aUv;
#ifdef HAS_UV1
    vUv1 = aUv1;
#endif
#ifdef HAS_COLOR
    vAlpha = aColor.a;
#endif
#endif
    gl_Position = uLightMvp * vec4(instancePoint(skinPoint(aPosition)), 1.0);
}
