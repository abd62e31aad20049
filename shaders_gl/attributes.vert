// Attribute pass (library API): eye-space position and normal for the depth, normal and id
// buffers. gl_Position is computed exactly as in lit.vert, so the same pixels are covered.
IN vec3 aPosition;
IN vec3 aNormal;
#include "instance.glsl"
#include "skin.glsl"

uniform mat4 uModelView;
uniform mat4 uProjection;
uniform mat3 uNormalMatrix;

OUT vec3 vEyePos;
OUT vec3 vNormal;

void main() {
    vec4 eye = uModelView * vec4(instancePoint(skinPoint(aPosition)), 1.0);
    vEyePos = eye.xyz;
    vNormal = uNormalMatrix * instanceNormal(skinNormal(aNormal));
    gl_Position = uProjection * eye;
}
