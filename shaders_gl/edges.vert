// Lines over the model (--edges, --wireframe): positions only, the lit pass's camera.
IN vec3 aPosition;

uniform mat4 uModelView;
uniform mat4 uProjection;
#ifdef LOG_DEPTH
OUT float vClipW;
#endif

void main() {
    gl_Position = uProjection * (uModelView * vec4(aPosition, 1.0));
#ifdef LOG_DEPTH
    vClipW = gl_Position.w;
#endif
}
