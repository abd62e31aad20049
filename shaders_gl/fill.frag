// The background colour over the pixels nothing was drawn into (stencil-masked); RGBM-encoded
// on the CPU when the frame is (bloom without float render targets).
uniform vec4 uColor;

void main() {
    FRAG_COLOR = uColor;
}
