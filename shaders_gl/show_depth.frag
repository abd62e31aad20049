// Teaching view: depth (compare mode off) as grey; near is dark, far is white.
IN vec2 vUv;
uniform sampler2D uDepth;

void main() {
    float d = TEX2D(uDepth, vUv).r;
    FRAG_COLOR = vec4(vec3(d), 1.0);
}
