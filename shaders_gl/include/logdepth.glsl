// Logarithmic depth, the second seed document's (2.10): z_ndc = 2 ln(C w + 1) / ln(C far + 1) - 1,
// i.e. window depth ln(C w + 1) / ln(C far + 1), with w the clip-space w (eye distance along
// the view axis). Relative depth precision is then about the same at every distance.
IN float vClipW;
uniform float uLogDepthC;
uniform float uLogDepthFar;
// glPolygonOffset's factor for a written depth (which the fixed-function offset does not
// reach): the lit surface under edge lines (render/edges.rs) is pushed back by this many
// times its depth slope, fwidth(z) ≥ GL's max slope. 0 otherwise.
uniform float uLogDepthOffset;

void glviewLogDepth() {
    float z = log(uLogDepthC * max(vClipW, 0.0) + 1.0) / log(uLogDepthC * uLogDepthFar + 1.0);
    FRAG_DEPTH = z + uLogDepthOffset * (fwidth(z) + 1.0 / 16777216.0);
}
