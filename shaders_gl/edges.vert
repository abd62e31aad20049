// Lines over the model (--edges, --wireframe), the lit pass's camera. 1-pixel lines are
// GL_LINES of the positions alone; WIDE lines (--line-width) are a quad per segment,
// widened here in screen space: every corner knows the segment's other end and its side,
// so no geometry shader is needed (GL 2.1, ES 3.0 and core alike). BARYCENTRIC draws the
// triangles themselves (a soup of unshared corners) and passes each corner's barycentric
// coordinate and the triangle's mask of edges to draw.
IN vec3 aPosition;
#ifdef WIDE
IN vec3 aNormal;    // the segment's other end
IN vec2 aUv;        // x: which side of the segment, ±1
uniform vec2 uViewport;   // pixels
uniform float uWidth;     // pixels
#endif
#ifdef BARYCENTRIC
IN vec3 aNormal;    // the corner's barycentric coordinate: (1,0,0), (0,1,0) or (0,0,1)
IN vec2 aUv;        // x: the triangle's edges to draw, bit k the edge opposite corner k
OUT vec3 vBary;
OUT float vMask;
#endif

uniform mat4 uModelView;
uniform mat4 uProjection;
#ifdef LOG_DEPTH
OUT float vClipW;
#endif

void main() {
    gl_Position = uProjection * (uModelView * vec4(aPosition, 1.0));
#ifdef WIDE
    vec4 other = uProjection * (uModelView * vec4(aNormal, 1.0));
    vec2 px = 0.5 * uViewport;
    // An end behind the eye has no screen position: the direction falls back to x.
    vec2 d = other.w > 0.0 && gl_Position.w > 0.0
        ? other.xy / other.w * px - gl_Position.xy / gl_Position.w * px
        : vec2(1.0, 0.0);
    d = length(d) > 0.0 ? normalize(d) : vec2(1.0, 0.0);
    // Half the width across (the side's normal) and past the end (a square cap, so
    // segments meeting at a corner leave no notch), in pixels, back to clip space.
    vec2 offset = (vec2(-d.y, d.x) * aUv.x - d) * (0.5 * uWidth);
    gl_Position.xy += offset / px * gl_Position.w;
#endif
#ifdef BARYCENTRIC
    vBary = aNormal;
    vMask = aUv.x;
#endif
#ifdef LOG_DEPTH
    vClipW = gl_Position.w;
#endif
}
