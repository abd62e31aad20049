// Shadow pass: only depth is written. The map's framebuffer has no colour buffer (or colour
// writes are off on the copy path), so the shader writes nothing: no fragment work beyond
// the fixed-function depth test.
void main() {
}
