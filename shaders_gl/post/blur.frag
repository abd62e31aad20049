// Bloom, one axis of the separable Gaussian: taps at whole texels (nearest filtering), weights
// normalised on the CPU; texels beyond the edge read the edge (clamp).
IN vec2 vUv;
uniform sampler2D uImage;
uniform vec2 uStep;            // one texel along the blur axis
uniform float uWeights[33];    // centre first
uniform int uRadius;

void main() {
    vec3 c = TEX2D(uImage, vUv).rgb * uWeights[0];
    for (int i = 1; i <= 32; ++i) {
        if (i > uRadius) break;
        float fi = float(i);
        c += (TEX2D(uImage, vUv + uStep * fi).rgb + TEX2D(uImage, vUv - uStep * fi).rgb) * uWeights[i];
    }
    FRAG_COLOR = vec4(c, 1.0);
}
