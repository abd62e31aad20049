// FXAA (Lottes' console variant): the display image's luma edges are found from the four
// diagonal neighbours and the pixel is re-sampled along the edge; where the wide estimate
// leaves the local luma range the narrow one is kept.
IN vec2 vUv;
uniform sampler2D uImage;
uniform vec2 uTexel;   // 1 / size

float glviewLuma(vec3 c) {
    return dot(c, vec3(0.299, 0.587, 0.114));
}

void main() {
    const float REDUCE_MIN = 1.0 / 128.0;
    const float REDUCE_MUL = 1.0 / 8.0;
    const float SPAN_MAX = 8.0;
    vec4 m = TEX2D(uImage, vUv);
    float lNW = glviewLuma(TEX2D(uImage, vUv + vec2(-1.0, -1.0) * uTexel).rgb);
    float lNE = glviewLuma(TEX2D(uImage, vUv + vec2(1.0, -1.0) * uTexel).rgb);
    float lSW = glviewLuma(TEX2D(uImage, vUv + vec2(-1.0, 1.0) * uTexel).rgb);
    float lSE = glviewLuma(TEX2D(uImage, vUv + vec2(1.0, 1.0) * uTexel).rgb);
    float lM = glviewLuma(m.rgb);
    float lMin = min(lM, min(min(lNW, lNE), min(lSW, lSE)));
    float lMax = max(lM, max(max(lNW, lNE), max(lSW, lSE)));
    vec2 dir = vec2(-((lNW + lNE) - (lSW + lSE)), (lNW + lSW) - (lNE + lSE));
    float reduce = max((lNW + lNE + lSW + lSE) * 0.25 * REDUCE_MUL, REDUCE_MIN);
    float rcpMin = 1.0 / (min(abs(dir.x), abs(dir.y)) + reduce);
    dir = clamp(dir * rcpMin, vec2(-SPAN_MAX), vec2(SPAN_MAX)) * uTexel;
    vec4 a = 0.5 * (TEX2D(uImage, vUv + dir * (1.0 / 3.0 - 0.5)) + TEX2D(uImage, vUv + dir * (2.0 / 3.0 - 0.5)));
    vec4 b = a * 0.5 + 0.25 * (TEX2D(uImage, vUv - dir * 0.5) + TEX2D(uImage, vUv + dir * 0.5));
    float lB = glviewLuma(b.rgb);
    FRAG_COLOR = (lB < lMin || lB > lMax) ? a : b;
}
