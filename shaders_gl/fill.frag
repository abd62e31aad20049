// The background colour over the pixels nothing was drawn into (stencil-masked).
uniform vec3 uColor;

void main() {
    FRAG_COLOR = vec4(uColor, 1.0);
}
