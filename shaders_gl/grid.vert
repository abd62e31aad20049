// The ground grid (--grid): a square on the plane, its corners relative to the grid's
// origin (a multiple of the unit near the model, so the line rule works on small numbers
// wherever the model lies). uGridProjection reaches past the square, so the far part of the
// grid is not clipped at the frame's far plane; grid.frag writes the frame's own depth.
IN vec3 aPosition;
uniform mat4 uModelView;        // view · translation to the grid's origin
uniform mat4 uGridProjection;
OUT vec3 vLocal;
OUT vec3 vEyePos;

void main() {
    vec4 eye = uModelView * vec4(aPosition, 1.0);
    vLocal = aPosition;
    vEyePos = eye.xyz;
    gl_Position = uGridProjection * eye;
}
