//! Colour textures' mipmaps are built on the CPU (glGenerateMipmap costs 110–190 ms of shader
//! compilation on llvmpipe): the chain must be the driver's own, level by level, so pictures
//! do not change. Read back with glGetTexImage on a desktop context.
use glview::gpu::texture::{MipSource, Texture2d, TextureFormat};
use glview::headless::Headless;
use glview::platform::{Backend, GlRequest};

/// A deterministic image with smooth ramps, hard edges and noise, alpha varying too.
fn pattern(w: u32, h: u32) -> Vec<u8> {
    let mut seed = 0x9e37_79b9u32;
    (0..w * h)
        .flat_map(|i| {
            let (x, y) = (i % w, i / w);
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            [
                (x * 255 / w.max(2)) as u8,
                if (x / 3 + y / 5) % 2 == 0 { 30 } else { 220 },
                (seed & 0xff) as u8,
                (128 + (y * 127 / h.max(2))) as u8,
            ]
        })
        .collect()
}

#[test]
fn cpu_mipmaps_equal_the_drivers() {
    let hl = Headless::new(Backend::Egl, GlRequest::Core, 8, 8).expect("EGL context");
    assert!(
        hl.gpu.caps.generate_mipmap,
        "a 3.3 context has glGenerateMipmap"
    );
    for format in [TextureFormat::Rgba8, TextureFormat::Srgb8A8] {
        for (w, h) in [(64, 64), (256, 32), (100, 60), (7, 5)] {
            let img = pattern(w, h);
            let make = |source| {
                Texture2d::from_rgba_with(&hl.gpu, format, w, h, &img, source).expect("texture")
            };
            let (cpu, driver) = (make(MipSource::Cpu), make(MipSource::Driver));
            let levels = 32 - w.max(h).leading_zeros();
            let mut worst = 0u8;
            for level in 0..levels {
                let (a, b) = (
                    cpu.read_level(level).expect("desktop GL"),
                    driver.read_level(level).expect("desktop GL"),
                );
                assert_eq!((a.0, a.1), (b.0, b.1));
                let d = a.2.iter().zip(&b.2).map(|(p, q)| p.abs_diff(*q)).max();
                let d = d.unwrap_or(0);
                worst = worst.max(d);
                // llvmpipe's blit filters in 8-bit fixed point and rounds its own way: one
                // step either way is rounding, more would be a different filter.
                // Power-of-two 8-bit chains are llvmpipe's exactly (its blit averages rows
                // then columns in 8-bit fixed point, rounding half up, as `mipmaps` does).
                // Odd sizes weigh taps in fixed point (one step); sRGB levels are encoded
                // with the exact curve here and an approximation there (one step a level,
                // two where a level is filtered from an already different one).
                let allowed = match (format, w.is_power_of_two() && h.is_power_of_two()) {
                    (TextureFormat::Rgba8, true) => 0,
                    (TextureFormat::Rgba8, false) => 1,
                    _ => 2,
                };
                assert!(
                    d <= allowed,
                    "{format:?} {w}x{h} level {level}: differs by {d}/255 (allowed {allowed})"
                );
            }
            eprintln!("{format:?} {w}x{h}: {levels} levels, worst {worst}/255");
        }
    }
    hl.gpu.check_error("texture readback").unwrap();
}

/// Setting a texture's parameters mid-frame (a material's sampler on its first use) binds it
/// for the call only: the active unit keeps the texture a pass bound there. The shadow map
/// on unit 1 was once replaced by the first material texture uploaded in the lit pass, and
/// the window's first Phong frame lost its shadows.
#[test]
fn parameter_changes_keep_the_units_binding() {
    use glow::HasContext;
    let hl = Headless::new(Backend::Egl, GlRequest::Core, 8, 8).expect("EGL context");
    let img = pattern(4, 4);
    let kept = Texture2d::from_rgba(&hl.gpu, 4, 4, &img).expect("texture");
    kept.bind(1);
    // SAFETY: a binding query on the current context.
    let bound = || unsafe { hl.gpu.gl.get_parameter_texture(glow::TEXTURE_BINDING_2D) };
    let before = bound();
    assert!(before.is_some());
    let other = Texture2d::from_rgba(&hl.gpu, 4, 4, &img).expect("texture");
    assert_eq!(bound(), before, "creating a texture");
    other.set_sampler(
        [glow::CLAMP_TO_EDGE, glow::MIRRORED_REPEAT],
        glow::NEAREST,
        glow::NEAREST,
    );
    assert_eq!(bound(), before, "set_sampler");
    other.set_filter(false);
    assert_eq!(bound(), before, "set_filter");
    other.set_compare(false);
    assert_eq!(bound(), before, "set_compare");
}
