// Depth in [0, 1) packed into an RGBA8 texel and back (SHADOW_PACKED: shadow maps without
// depth textures, WebGL 1 without WEBGL_depth_texture). Channel k holds the k-th base-255
// digit: fract(d * 255^k) less the part the next channel holds, so each channel is an exact
// multiple of 1/255 before the 8-bit store rounds it and the digits come back whole; the
// last channel keeps what float precision leaves (about 2^-24 of error, as a 24-bit depth
// buffer). A texel cleared to white unpacks to just over 1: nothing nearer than the far
// plane, lit.
vec4 glviewPackDepth(float d) {
    // 1 - 2^-24: a depth of exactly 1 would pack as 0 (fract(1) = 0), the nearest of all.
    d = clamp(d, 0.0, 0.99999994);
    vec4 e = fract(d * vec4(1.0, 255.0, 65025.0, 16581375.0));
    return e - e.yzww * vec4(1.0 / 255.0, 1.0 / 255.0, 1.0 / 255.0, 0.0);
}

float glviewUnpackDepth(vec4 e) {
    return dot(e, vec4(1.0, 1.0 / 255.0, 1.0 / 65025.0, 1.0 / 16581375.0));
}
