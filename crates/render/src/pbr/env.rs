//! Environments as equirectangular linear-radiance images (+Y up; u = 0.5 at −Z, increasing
//! towards +X; v = 0 at +Y), with bilinear lookup and a box-filtered mip chain for filtered
//! importance sampling; and the cube-face directions of GL's cube-map convention.
use crate::error::{Error, Result};
use glam::DVec3;
use std::f64::consts::PI;
use std::path::Path;

#[derive(Clone, Debug)]
pub struct Environment {
    pub(crate) width: usize,
    pub(crate) height: usize,
    /// Linear RGB, row 0 at the top (+Y).
    pub(crate) texels: Vec<[f32; 3]>,
}

/// Files larger than this many texels are box-downscaled after decoding; the prefiltered
/// maps never need more detail than a 2048×1024 image holds.
const MAX_TEXELS: usize = 2048 * 1024;

/// The largest environment file read (a 16k×8k Radiance file is about 512 MiB).
const MAX_FILE_BYTES: u64 = 1 << 30;

impl Environment {
    pub fn uniform(c: [f32; 3]) -> Environment {
        Environment {
            width: 8,
            height: 4,
            texels: vec![c; 32],
        }
    }

    /// The built-in sky: a zenith-to-horizon gradient, a darker ground, and a soft sun, so a
    /// PBR model looks lit without a file.
    pub(crate) fn builtin() -> Environment {
        let (w, h) = (256usize, 128usize);
        let sun = DVec3::new(-0.45, 0.7, 0.55).normalize();
        let mut texels = Vec::with_capacity(w * h);
        for y in 0..h {
            for x in 0..w {
                let d = direction(x as f64 + 0.5, y as f64 + 0.5, w, h);
                let c = if d.y >= 0.0 {
                    let t = d.y.powf(0.5);
                    DVec3::new(0.9, 0.95, 1.0).lerp(DVec3::new(0.25, 0.45, 0.9), t)
                } else {
                    DVec3::new(0.3, 0.27, 0.24) * (1.0 + d.y * 0.5)
                };
                // A sun of ~6° with a smooth edge (no aliasing at 256 × 128).
                let s = ((d.dot(sun) - 0.994) / 0.006).clamp(0.0, 1.0);
                let c = c + DVec3::splat(40.0 * s * s);
                texels.push([c.x as f32, c.y as f32, c.z as f32]);
            }
        }
        Environment {
            width: w,
            height: h,
            texels,
        }
    }

    /// The environment a request names.
    pub fn from_source(source: &super::EnvSource) -> Result<Environment> {
        Ok(match source {
            super::EnvSource::Builtin => Environment::builtin(),
            super::EnvSource::Uniform(c) => Environment::uniform(*c),
            super::EnvSource::File(p) => Environment::load(p)?,
        })
    }

    /// Reads a Radiance HDR (equirectangular) through the `image` crate, from wherever the
    /// scene's files are read (the disk, or the browser's fetched files).
    pub fn load(path: &Path) -> Result<Environment> {
        use glview_scene::load::resources::{current, Kind};
        let err = |m: String| Error::Usage(format!("{}: {m}", path.display()));
        let files = current();
        if !matches!(files.kind(path), Ok(Kind::File(_))) {
            return Err(err("no such environment file".into()));
        }
        let bytes = files
            .read(path, MAX_FILE_BYTES)
            .map_err(|e| err(e.to_string()))?;
        // The content names the format, else the extension (a `#?RGBE` header has no magic
        // the `image` crate knows).
        let mut reader = image::ImageReader::new(std::io::Cursor::new(bytes))
            .with_guessed_format()
            .map_err(|e| err(e.to_string()))?;
        if reader.format().is_none() {
            if let Ok(f) = image::ImageFormat::from_path(path) {
                reader.set_format(f);
            }
        }
        let img = reader
            .decode()
            .map_err(|e| err(format!("not a readable HDR image: {e}")))?
            .to_rgb32f();
        let (w, h) = (img.width() as usize, img.height() as usize);
        if w < 2 || h < 1 {
            return Err(err(format!("{w}x{h} is too small for an environment")));
        }
        let mut texels: Vec<[f32; 3]> = img
            .pixels()
            .map(|p| p.0.map(|v| if v.is_finite() { v.max(0.0) } else { 0.0 }))
            .collect();
        let (mut w, mut h) = (w, h);
        while w * h > MAX_TEXELS && w >= 2 && h >= 2 {
            (texels, w, h) = downsample(&texels, w, h);
        }
        Ok(Environment {
            width: w,
            height: h,
            texels,
        })
    }

    /// Bilinear radiance in direction `d` (unit).
    pub fn sample(&self, d: DVec3) -> DVec3 {
        sample_level(&self.texels, self.width, self.height, d)
    }

    /// The mip chain (level 0 = self), each level a 2×2 box filter of the one before.
    pub(crate) fn mips(&self) -> Vec<(Vec<[f32; 3]>, usize, usize)> {
        let mut levels = vec![(self.texels.clone(), self.width, self.height)];
        while let Some((t, w, h)) = levels.last() {
            if *w < 2 || *h < 2 {
                break;
            }
            let next = downsample(t, *w, *h);
            levels.push(next);
        }
        levels
    }
}

/// Direction of equirect position (x, y) in pixels of a w×h image.
pub(crate) fn direction(x: f64, y: f64, w: usize, h: usize) -> DVec3 {
    let phi = (x / w as f64 - 0.5) * 2.0 * PI;
    let theta = y / h as f64 * PI;
    DVec3::new(
        theta.sin() * phi.sin(),
        theta.cos(),
        -theta.sin() * phi.cos(),
    )
}

/// Bilinear lookup of direction `d` in one w×h level (wrapping in u, clamped in v).
pub(crate) fn sample_level(t: &[[f32; 3]], w: usize, h: usize, d: DVec3) -> DVec3 {
    let u = 0.5 + d.x.atan2(-d.z) / (2.0 * PI);
    let v = d.y.clamp(-1.0, 1.0).acos() / PI;
    let x = u * w as f64 - 0.5;
    let y = (v * h as f64 - 0.5).clamp(0.0, (h - 1) as f64);
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    // Columns x0 and x0 + 1 wrapped, rows y0 and y0 + 1 clamped: one integer remainder per
    // lookup, not one per tap (the Monte Carlo references call this millions of times).
    let i0 = (x0 as i64).rem_euclid(w as i64) as usize;
    let i1 = if i0 + 1 == w { 0 } else { i0 + 1 };
    let (r0, r1) = (
        (y0 as usize).min(h - 1) * w,
        ((y0 + 1.0) as usize).min(h - 1) * w,
    );
    let at = |k: usize| {
        let p = t[k];
        DVec3::new(f64::from(p[0]), f64::from(p[1]), f64::from(p[2]))
    };
    let top = at(r0 + i0).lerp(at(r0 + i1), fx);
    let bottom = at(r1 + i0).lerp(at(r1 + i1), fx);
    top.lerp(bottom, fy)
}

fn downsample(t: &[[f32; 3]], w: usize, h: usize) -> (Vec<[f32; 3]>, usize, usize) {
    let (nw, nh) = ((w / 2).max(1), (h / 2).max(1));
    let mut out = Vec::with_capacity(nw * nh);
    for y in 0..nh {
        for x in 0..nw {
            let mut s = [0f32; 3];
            for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                let p = t[(2 * y + dy).min(h - 1) * w + (2 * x + dx).min(w - 1)];
                for c in 0..3 {
                    s[c] += p[c] * 0.25;
                }
            }
            out.push(s);
        }
    }
    (out, nw, nh)
}

/// Direction through texel (x, y) of cube face `face` (GL order +X, −X, +Y, −Y, +Z, −Z; row 0
/// is the first row uploaded, t = 0), for a face of `size` texels.
pub(crate) fn cube_direction(face: usize, x: f64, y: f64, size: usize) -> DVec3 {
    let s = (x + 0.5) / size as f64 * 2.0 - 1.0;
    let t = (y + 0.5) / size as f64 * 2.0 - 1.0;
    let d = match face {
        0 => DVec3::new(1.0, -t, -s),
        1 => DVec3::new(-1.0, -t, s),
        2 => DVec3::new(s, 1.0, t),
        3 => DVec3::new(s, -1.0, -t),
        4 => DVec3::new(s, -t, 1.0),
        _ => DVec3::new(-s, -t, -1.0),
    };
    d.normalize()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The lookup is the textbook one, tap by tap (each tap's column wrapped, its row
    /// clamped), to the bit: on a noisy 7×5 level (odd sizes, so the wrap and clamp edges
    /// are hit) over a spiral of directions and the poles and seam.
    #[test]
    fn lookup_is_each_tap_wrapped_and_clamped() {
        let (w, h) = (7usize, 5usize);
        let t: Vec<[f32; 3]> = (0..w * h)
            .map(|k| {
                let k = k as f32;
                [(k * 0.37).sin(), (k * 1.3).cos() + 2.0, k]
            })
            .collect();
        let textbook = |d: DVec3| {
            let u = 0.5 + d.x.atan2(-d.z) / (2.0 * PI);
            let v = d.y.clamp(-1.0, 1.0).acos() / PI;
            let x = u * w as f64 - 0.5;
            let y = (v * h as f64 - 0.5).clamp(0.0, (h - 1) as f64);
            let (x0, y0) = (x.floor(), y.floor());
            let at = |i: f64, j: f64| {
                let p = t[(j as usize).min(h - 1) * w + (i as i64).rem_euclid(w as i64) as usize];
                DVec3::new(f64::from(p[0]), f64::from(p[1]), f64::from(p[2]))
            };
            let top = at(x0, y0).lerp(at(x0 + 1.0, y0), x - x0);
            let bottom = at(x0, y0 + 1.0).lerp(at(x0 + 1.0, y0 + 1.0), x - x0);
            top.lerp(bottom, y - y0)
        };
        let mut dirs: Vec<DVec3> = (0..2000)
            .map(|k| {
                let z = 1.0 - 2.0 * (k as f64 + 0.5) / 2000.0;
                let a = k as f64 * 2.399_963;
                let r = (1.0 - z * z).sqrt();
                DVec3::new(r * a.cos(), z, r * a.sin())
            })
            .collect();
        dirs.extend([
            DVec3::Y,
            -DVec3::Y,
            DVec3::Z,
            -DVec3::Z,
            DVec3::X,
            -DVec3::X,
        ]);
        for d in dirs {
            assert_eq!(sample_level(&t, w, h, d), textbook(d), "{d}");
        }
    }

    #[test]
    fn equirect_round_trip() {
        let (w, h) = (64, 32);
        // A texel centre's direction samples back that texel exactly.
        let mut t = vec![[0f32; 3]; w * h];
        t[10 * w + 20] = [1.0, 2.0, 3.0];
        let d = direction(20.5, 10.5, w, h);
        let c = sample_level(&t, w, h, d);
        assert!((c - DVec3::new(1.0, 2.0, 3.0)).length() < 1e-9, "{c}");
    }

    #[test]
    fn cube_faces_point_outwards() {
        for (f, axis) in [
            DVec3::X,
            -DVec3::X,
            DVec3::Y,
            -DVec3::Y,
            DVec3::Z,
            -DVec3::Z,
        ]
        .into_iter()
        .enumerate()
        {
            assert!((cube_direction(f, 7.5, 7.5, 16) - axis).length() < 0.05);
        }
    }
}
