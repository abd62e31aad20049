// Teaching view: a full-screen quad showing a depth map.
IN vec3 aPosition;
IN vec2 aUv;
OUT vec2 vUv;

void main() {
    vUv = aUv;
    gl_Position = vec4(aPosition.xy, 0.0, 1.0);
}
