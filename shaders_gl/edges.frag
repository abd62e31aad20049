// Lines over the model: one flat colour (RGBM-encoded on the CPU when the frame is). The
// surface was drawn with a polygon offset, so a line on it passes the LEQUAL depth test.
uniform vec4 uColor;
#ifdef LOG_DEPTH
#include "logdepth.glsl"
#endif
#ifdef BARYCENTRIC
IN vec3 vBary;
IN float vMask;
uniform float uWidth;     // pixels
#endif

void main() {
#ifdef LOG_DEPTH
    // The surface's offset is in its own written depth (uLogDepthOffset).
    glviewLogDepth();
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
