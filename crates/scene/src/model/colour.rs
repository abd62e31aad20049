//! sRGB transfer functions: the loaders encode linear colours for the legacy tier, the
//! renderer and the reference shade with them.

/// sRGB encoding of a linear value in [0, 1].
pub fn srgb_encode(x: f64) -> f64 {
    let x = x.clamp(0.0, 1.0);
    if x <= 0.0031308 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    }
}

/// sRGB decoding to linear.
pub fn srgb_decode(x: f64) -> f64 {
    if x <= 0.04045 {
        x / 12.92
    } else {
        ((x + 0.055) / 1.055).powf(2.4)
    }
}
