// Lines over the model: one flat colour (RGBM-encoded on the CPU when the frame is). The
// surface was drawn with a polygon offset, so a line on it passes the LEQUAL depth test.
uniform vec4 uColor;
#ifdef LOG_DEPTH
#include "logdepth.glsl"
uniform float uLineDepthBias;
#endif
#ifdef BARYCENTRIC
IN vec3 vBary;
IN float vMask;
uniform float uWidth;     // pixels
#endif

void main() {
#ifdef LOG_DEPTH
    // A written gl_FragDepth drops the surface's polygon offset: the line comes forward
    // by a constant instead.
    glviewLogDepth();
    gl_FragDepth = max(gl_FragDepth - uLineDepthBias, 0.0);
#endif
#ifdef BARYCENTRIC
    // Distance to each edge in pixels: the coordinate over its change per pixel. Edges the
    // mask leaves out are far away. (No bit operations in GLSL 1.20: floor and mod.)
    float m = floor(vMask + 0.5);
    vec3 on = vec3(mod(m, 2.0), mod(floor(m / 2.0), 2.0), floor(m / 4.0));
    vec3 d = vBary / max(fwidth(vBary), vec3(1e-6));
    d = mix(vec3(1e6), d, on);
    float dist = min(min(d.x, d.y), d.z);
    if (dist > 0.5 * uWidth) {
        discard;
    }
#endif
    FRAG_COLOR = uColor;
}
