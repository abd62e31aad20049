// Teaching view: depth (compare mode off) as grey; near is dark, far is white. Perspective maps
// (point lights) are linearised with the projection's A, B (z_ndc = (A z + B) / -z), or their
// depth would crowd against white.
IN vec2 vUv;
uniform sampler2D uDepth;
uniform float uPerspective;   // 1: linearise
uniform vec2 uAB;
uniform vec2 uNearFar;

#ifdef SHADOW_PACKED
#include "packdepth.glsl"
#endif

void main() {
#ifdef SHADOW_PACKED
    float d = min(glviewUnpackDepth(TEX2D(uDepth, vUv)), 1.0);
#else
    float d = TEX2D(uDepth, vUv).r;
#endif
    if (uPerspective > 0.5) {
        float dist = uAB.y / (2.0 * d - 1.0 + uAB.x);
        d = clamp((dist - uNearFar.x) / (uNearFar.y - uNearFar.x), 0.0, 1.0);
    }
    FRAG_COLOR = vec4(vec3(d), 1.0);
}
