// Bloom, downsampling: one bilinear tap at the centre of each 2x2 block is their exact mean.
IN vec2 vUv;
uniform sampler2D uImage;

void main() {
    FRAG_COLOR = vec4(TEX2D(uImage, vUv).rgb, 1.0);
}
