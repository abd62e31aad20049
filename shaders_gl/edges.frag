// Lines over the model: one flat colour (RGBM-encoded on the CPU when the frame is). The
// surface was drawn with a polygon offset, so a line on it passes the LEQUAL depth test.
uniform vec4 uColor;
#ifdef LOG_DEPTH
#include "logdepth.glsl"
uniform float uLineDepthBias;
#endif

void main() {
#ifdef LOG_DEPTH
    // A written gl_FragDepth drops the surface's polygon offset: the line comes forward
    // by a constant instead.
    glviewLogDepth();
    gl_FragDepth = max(gl_FragDepth - uLineDepthBias, 0.0);
#endif
    FRAG_COLOR = uColor;
}
