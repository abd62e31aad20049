// Background: a full-screen quad at the far plane; the direction through each pixel comes from
// the inverse projection.
IN vec3 aPosition;
uniform mat4 uInvProjection;
OUT vec3 vEyeDir;

void main() {
    vec4 p = uInvProjection * vec4(aPosition.xy, 1.0, 1.0);
    vEyeDir = p.xyz / p.w;
    gl_Position = vec4(aPosition.xy, 1.0, 1.0);
}
