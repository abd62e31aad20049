// The window overlay: a picture composed on the CPU, rows top-down.
IN vec2 vUv;
uniform sampler2D uImage;

void main() {
    FRAG_COLOR = TEX2D(uImage, vec2(vUv.x, 1.0 - vUv.y));
}
