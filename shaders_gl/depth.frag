// Shadow pass: only depth is written. The map's framebuffer has no colour buffer (or colour
// writes are off on the copy path), so the shader writes nothing: no fragment work beyond
// the fixed-function depth test — except for MASK materials, whose cut-out texels cast no
// shadow (the same alpha test as the lit passes), and for packed depth (no depth textures),
// where the colour is the depth.
#ifdef SHADOW_PACKED
#include "packdepth.glsl"
// The polygon offset (slope factor, units), added here rather than by the rasteriser:
// whether gl_FragCoord.z includes glPolygonOffset's differs between drivers (llvmpipe's
// does). The offset depth is also the depth tested, as a depth map's is, so the nearest
// caster after the offset wins, not before (where a steep wall meets a floor the two
// differ). The slope is GL's max(|dz/dx|, |dz/dy|); a unit is 2^-24, a 24-bit depth step.
// Without a writable depth (ES 2.0 without EXT_frag_depth) the rasteriser's offset is used
// as the driver gives it.
uniform vec2 uPolygonOffset;
#endif
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
#ifdef SHADOW_PACKED
    float z = gl_FragCoord.z;
#ifdef HAS_FRAG_DEPTH
    float slope = max(abs(dFdx(z)), abs(dFdy(z)));
    z = clamp(z + uPolygonOffset.x * slope + uPolygonOffset.y * 5.96e-8, 0.0, 1.0);
    FRAG_DEPTH = z;
#endif
    FRAG_COLOR = glviewPackDepth(z);
#endif
}
