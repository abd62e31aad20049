//! Teaching views of the PBR tier's precomputed maps, composed on the CPU from the data (so
//! they look the same on every context): a cube as an unfolded cross (+Y above, −Y below,
//! then −X, +Z, +X, −Z across), the BRDF table as an image, each through the output step and
//! labelled with its name and value range.
use super::precompute::{Cube, IblData, Lut};
use super::OutputParams;
use crate::image::canvas;
use crate::image::Rgba;

fn range(values: impl Iterator<Item = f32>) -> (f32, f32) {
    values.fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    })
}

/// The cube as a 4×3 cross of `face`-sized tiles, labelled.
pub(crate) fn cube_cross(c: &Cube, name: &str, out: &OutputParams) -> Rgba {
    let n = c.size;
    let tile = n.max(64);
    let mut img = canvas::blank(4 * tile, 3 * tile + canvas::STRIP, [24, 24, 28]);
    // (face, column, row) with GL's face order +X, −X, +Y, −Y, +Z, −Z.
    for (face, col, row) in [
        (2, 1, 0),
        (1, 0, 1),
        (4, 1, 1),
        (0, 2, 1),
        (5, 3, 1),
        (3, 1, 2),
    ] {
        for y in 0..tile {
            for x in 0..tile {
                // Faces are stored with t = 0 first; the cross shows each face as seen from
                // inside the cube, which is that same layout for the GL convention.
                let (sx, sy) = ((x * n / tile).min(n - 1), (y * n / tile).min(n - 1));
                let t = c.faces[face][(sy * n + sx) as usize];
                let v = out.apply([t[0].into(), t[1].into(), t[2].into()]);
                let o =
                    (((canvas::STRIP + row * tile + y) * img.width + col * tile + x) * 4) as usize;
                for (k, c) in v.iter().enumerate() {
                    img.data[o + k] = (c * 255.0).round() as u8;
                }
            }
        }
    }
    let (lo, hi) = range(c.faces.iter().flatten().flat_map(|t| t.iter().copied()));
    let label = format!("{name} {n}x{n} per face, radiance {lo:.3}..{hi:.3}");
    canvas::paste(&mut img, &canvas::strip(4 * tile, &label), 0, 0);
    img
}

/// The BRDF table: A in red, B in green; x = N·V, y = roughness (0 at the top).
pub(crate) fn lut_image(l: &Lut) -> Rgba {
    let n = l.size;
    let scale = (256 / n.max(1)).max(1);
    let side = n * scale;
    let mut img = canvas::blank(side.max(320), side + canvas::STRIP, [24, 24, 28]);
    for y in 0..side {
        for x in 0..side {
            let t = l.texels[((y / scale) * n + x / scale) as usize];
            let o = (((canvas::STRIP + y) * img.width + x) * 4) as usize;
            img.data[o] = (t[0].clamp(0.0, 1.0) * 255.0).round() as u8;
            img.data[o + 1] = (t[1].clamp(0.0, 1.0) * 255.0).round() as u8;
            img.data[o + 2] = 0;
        }
    }
    let (lo, hi) = range(l.texels.iter().flat_map(|t| t.iter().copied()));
    let label = format!("BRDF table {n}x{n} (A red, B green) {lo:.3}..{hi:.3}");
    let strip = canvas::strip(img.width, &label);
    canvas::paste(&mut img, &strip, 0, 0);
    img
}

/// The view `what` names: `irradiance`, `specular` (level `level`) or `lut`.
pub fn view(d: &IblData, what: &str, level: u32, out: &OutputParams) -> Option<Rgba> {
    Some(match what {
        "irradiance" => cube_cross(&d.irradiance, "irradiance E_d", out),
        "specular" => {
            let i = (level as usize).min(d.specular.len().saturating_sub(1));
            let r = d.settings.level_roughness(i as u32);
            cube_cross(
                &d.specular[i],
                &format!("specular E_s level {i} (r {r:.2})"),
                out,
            )
        }
        "lut" => lut_image(&d.lut),
        _ => return None,
    })
}
