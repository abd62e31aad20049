// Shadow pass: depth from the light only.
IN vec3 aPosition;
uniform mat4 uLightMvp;

void main() {
    gl_Position = uLightMvp * vec4(aPosition, 1.0);
}
