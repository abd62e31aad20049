// Stereo: each output pixel from the two eyes' pictures (display values, one texel each,
// nearest): the anaglyph's matrices, or the eye and texel the layout puts there. Drawn over
// the output rectangle only, so the stencil buffer stays the translucency's.
IN vec2 vUv;
uniform sampler2D uLeft;
uniform sampler2D uRight;
uniform vec2 uEyeSize;   // each eye's picture, in pixels
uniform vec2 uOrigin;    // the output rectangle's lower-left corner in the target
uniform vec2 uOutSize;   // the output rectangle's size
uniform vec2 uParity;    // the rectangle's top-left pixel on the screen (column, row) mod 2
uniform int uMode;       // 0 anaglyph, 1 side by side, 2 over-under, 3 rows, 4 columns, 5 checkerboard
uniform mat3 uMatLeft;
uniform mat3 uMatRight;

vec4 texel(sampler2D eye, vec2 p) {
    return TEX2D(eye, (p + 0.5) / uEyeSize);
}

// 1.0 where an interlaced mode shows the left eye at column `c`, row `r` (from the top).
float leftAt(float c, float r) {
    float n = uMode == 3 ? r : (uMode == 4 ? c : c + r);
    return 1.0 - mod(n, 2.0);
}

void main() {
    vec2 p = floor(gl_FragCoord.xy - uOrigin);
    if (uMode == 0) {
        vec4 l = texel(uLeft, p);
        vec4 r = texel(uRight, p);
        vec3 c = clamp(uMatLeft * l.rgb + uMatRight * r.rgb, 0.0, 1.0);
        FRAG_COLOR = vec4(c, max(l.a, r.a));
    } else if (uMode == 1) {
        FRAG_COLOR = p.x < uEyeSize.x ? texel(uLeft, p) : texel(uRight, p - vec2(uEyeSize.x, 0.0));
    } else if (uMode == 2) {
        // Left eye on top (GL counts rows from the bottom).
        FRAG_COLOR = p.y >= uEyeSize.y ? texel(uLeft, p - vec2(0.0, uEyeSize.y)) : texel(uRight, p);
    } else {
        float row = uOutSize.y - 1.0 - p.y + uParity.y;
        float left = leftAt(p.x + uParity.x, row);
        FRAG_COLOR = left > 0.5 ? texel(uLeft, p) : texel(uRight, p);
    }
}
