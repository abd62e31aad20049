// SSAA in the window: each pixel is the mean of its k x k block of the large frame (an exact
// box filter, the GPU twin of bench::metrics::downsample); taps at texel centres, nearest.
IN vec2 vUv;
uniform sampler2D uImage;
uniform vec2 uTexel;   // 1 / the large frame's size
uniform int uK;

void main() {
    float k = float(uK);
    vec2 corner = vUv - 0.5 * k * uTexel;
    vec4 sum = vec4(0.0);
    for (int j = 0; j < 4; ++j) {
        if (j >= uK) break;
        for (int i = 0; i < 4; ++i) {
            if (i >= uK) break;
            sum += TEX2D(uImage, corner + (vec2(float(i), float(j)) + 0.5) * uTexel);
        }
    }
    FRAG_COLOR = sum / (k * k);
}
