// Shadow pass: only depth is written. The map's framebuffer has no colour buffer (or colour
// writes are off on the copy path), so the shader writes nothing: no fragment work beyond
// the fixed-function depth test — except for MASK materials, whose cut-out texels cast no
// shadow (the same alpha test as the lit passes).
#ifdef ALPHA_MASK
IN vec2 vUv;
#include "material.glsl"
#ifdef HAS_TEXTURE
uniform sampler2D uDiffuseMap;
#endif
#ifdef HAS_COLOR
IN float vAlpha;
#endif
#endif

void main() {
#ifdef ALPHA_MASK
    float a = uBaseAlpha;
#ifdef HAS_TEXTURE
    a *= TEX2D(uDiffuseMap, SLOT_UV(0)).a;
#endif
#ifdef HAS_COLOR
    a *= vAlpha;
#endif
    glviewAlphaTest(a);
#endif
}
