// Attribute pass: uMode 0 writes (object id, material id, depth along the view axis, 1);
// uMode 1 the eye-space normal facing the camera. The target is RGBA32F, so ids up to 2^24
// and depths are exact floats, not 8-bit colours.
IN vec3 vEyePos;
IN vec3 vNormal;

uniform vec2 uIds;
uniform float uMode;

void main() {
    if (uMode < 0.5) {
        FRAG_COLOR = vec4(uIds.x, uIds.y, -vEyePos.z, 1.0);
    } else {
        vec3 n = normalize(vNormal);
        FRAG_COLOR = vec4(gl_FrontFacing ? n : -n, 1.0);
    }
}
