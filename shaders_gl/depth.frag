// Shadow pass: only depth is written (colour writes are off or there is no colour buffer).
void main() {
    FRAG_COLOR = vec4(1.0);
}
