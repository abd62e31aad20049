//! The ground grid of `--grid` and the orientation triad of `--axes` as pure math (no GL):
//! where the grid's plane lies, its unit, and the rule that says how much line a pixel
//! shows. The grid pass (`render/grid.rs` with `grid.frag`, which states the same rule in
//! GLSL) and the CPU reference (`reference/grid.rs`) both follow it, so the GPU's lines are
//! checked against a ray-cast plane.
use crate::scene::Bounds;
use glam::{DVec2, DVec3, Mat4, Vec3};

/// The plane y = `height` (the scene's up axis after `--up`), lines every `unit` along X and
/// Z, fading out between half `fade` and `fade` from `centre` (x, z).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridPlane {
    pub height: f64,
    pub centre: DVec2,
    pub unit: f64,
    pub fade: f64,
}

/// How far the grid reaches, in bounding radii: far enough to hold a low light's shadow.
pub const FADE_RADII: f64 = 4.0;
/// The lines' opacity where they are fully drawn.
pub const LINE_ALPHA: f64 = 0.6;

impl GridPlane {
    /// The grid under `bounds`: at their lowest point, centred below them, with a unit of
    /// 1, 2 or 5 × 10^k near half the bounding radius (a few cells across the model).
    pub fn for_bounds(bounds: &Bounds) -> GridPlane {
        let r = f64::from(bounds.radius());
        let c = bounds.center().as_dvec3();
        let height = if bounds.is_empty() {
            0.0
        } else {
            f64::from(bounds.min.y)
        };
        GridPlane {
            height,
            centre: DVec2::new(c.x, c.z),
            unit: nice_unit(0.5 * r),
            fade: FADE_RADII * r,
        }
    }

    /// The overlay's label: `grid 0.5` (model units per cell).
    pub fn label(&self) -> String {
        format!("grid {}", self.unit as f32)
    }

    /// The lines' opacity at world point `p` (on the plane) for a pixel whose footprint
    /// spans `fw` = fwidth(p.xz / unit) (the sum of the absolute changes across one pixel
    /// in x and in y), lines `width` pixels wide. grid.frag computes exactly this.
    pub fn alpha(&self, p: DVec3, fw: DVec2, width: f64) -> f64 {
        let q = DVec2::new(p.x, p.z) / self.unit;
        let fw = fw.max(DVec2::splat(1e-9));
        // Pixels to the nearest line along each axis; the nearer one counts.
        let d = (fract(q - 0.5) - 0.5).abs() / fw;
        let cover = (0.5 * width + 0.5 - d.x.min(d.y)).clamp(0.0, 1.0);
        // Lines closer than a few pixels apart would only make moiré: they fade out.
        let crowd = 1.0 - smoothstep(0.2, 0.45, fw.x.max(fw.y));
        LINE_ALPHA * cover * crowd * self.fade_at(p)
    }

    /// How much of the grid (lines and shadow) is left at `p`: 1 near the model, 0 from
    /// `fade` on.
    pub fn fade_at(&self, p: DVec3) -> f64 {
        let far = (DVec2::new(p.x, p.z) - self.centre).length();
        1.0 - smoothstep(0.5 * self.fade, self.fade, far)
    }

    /// A multiple of the unit on the plane near the centre: the GPU draws relative to it,
    /// so its f32 line rule never works on large coordinates.
    pub fn origin(&self) -> DVec3 {
        let snap = |v: f64| (v / self.unit).round() * self.unit;
        DVec3::new(snap(self.centre.x), self.height, snap(self.centre.y))
    }

    /// The square the grid is drawn on, relative to [`GridPlane::origin`] (corners on the
    /// plane, counter-clockwise from above).
    pub fn corners(&self) -> [Vec3; 4] {
        let o = self.origin();
        let (c, f) = (self.centre, self.fade);
        [(-1.0, 1.0), (1.0, 1.0), (1.0, -1.0), (-1.0, -1.0)]
            .map(|(sx, sz)| DVec3::new(c.x + sx * f - o.x, 0.0, c.y + sz * f - o.z).as_vec3())
    }
}

/// The bounds a shadow map is fitted to while the grid is on: the model's, and where its
/// box's shadow falls on the plane from each casting light (clipped to the grid's square),
/// so the model's shadow on the grid lies inside the map instead of being cut at its edge.
pub fn shadow_bounds(bounds: &Bounds, lights: &[crate::light::Light]) -> Bounds {
    use crate::light::LightKind;
    let g = GridPlane::for_bounds(bounds);
    let h = g.height as f32;
    let (lo, hi) = (
        g.centre.as_vec2() - g.fade as f32,
        g.centre.as_vec2() + g.fade as f32,
    );
    let mut out = *bounds;
    for l in lights {
        for c in bounds.corners() {
            let p = match l.kind {
                // A light from (nearly) the horizon or below throws no shadow on the floor
                // within reach.
                LightKind::Directional(d) if d.y < -1e-3 => c + d * ((c.y - h) / -d.y),
                LightKind::Point(q) if q.y > c.y => q + (c - q) * ((q.y - h) / (q.y - c.y)),
                _ => continue,
            };
            let xz = glam::Vec2::new(p.x, p.z).clamp(lo, hi);
            out.include(Vec3::new(xz.x, h, xz.y));
        }
    }
    out
}

/// The lines' colour over a background of `background` (display values): light grey over a
/// dark one, dark grey over a light one.
pub fn line_color(background: Vec3) -> [f32; 3] {
    let y = background.dot(Vec3::new(0.2126, 0.7152, 0.0722));
    [if y > 0.5 { 0.15 } else { 0.8 }; 3]
}

/// What the model's shadow leaves of the light on a white diffuse floor with normal `n`:
/// (ambient + Σ visᵢ·Lᵢ·max(n·lᵢ, 0)) / (ambient + Σ Lᵢ·max(n·lᵢ, 0)), with L the lights'
/// luminance; the grid darkens what lies behind it by 1 minus this (grid.frag does the same).
pub fn floor_light(ambient: f64, lights: &[(f64, f64)]) -> f64 {
    let full: f64 = ambient + lights.iter().map(|(k, _)| k).sum::<f64>();
    let lit: f64 = ambient + lights.iter().map(|(k, vis)| k * vis).sum::<f64>();
    if full > 0.0 {
        lit / full
    } else {
        1.0
    }
}

/// Luminance weights (Rec. 709) of the lights' colours in the floor's light.
pub const LUMINANCE: [f64; 3] = [0.2126, 0.7152, 0.0722];

/// The largest 1, 2 or 5 × 10^k at most `x` (x > 0; 1 otherwise).
pub fn nice_unit(x: f64) -> f64 {
    if !(x.is_finite() && x > 0.0) {
        return 1.0;
    }
    let p = 10f64.powf(x.log10().floor());
    let m = x / p;
    // (m is in [1, 10) but for rounding at exact powers.)
    let step = if m >= 5.0 - 1e-9 {
        5.0
    } else if m >= 2.0 - 1e-9 {
        2.0
    } else {
        1.0
    };
    step * p
}

/// GLSL's fract, per component.
fn fract(v: DVec2) -> DVec2 {
    v - v.floor()
}

/// GLSL's smoothstep.
pub fn smoothstep(e0: f64, e1: f64, x: f64) -> f64 {
    let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// The axes of the triad, in the order drawn labels read: X red, Y green, Z blue.
pub const AXES: [(Vec3, [u8; 3], char); 3] = [
    (Vec3::X, [230, 57, 57], 'X'),
    (Vec3::Y, [64, 200, 64], 'Y'),
    (Vec3::Z, [72, 120, 255], 'Z'),
];

/// Where world axis `axis` points in the triad: the view's rotation applied to it, as
/// (right, down) in the picture, of length at most 1 (shorter as it turns towards or away
/// from the viewer), and its depth towards the viewer (for drawing order).
pub fn triad_direction(view: &Mat4, axis: Vec3) -> (f32, f32, f32) {
    let v = view.transform_vector3(axis);
    (v.x, -v.y, v.z)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn units_are_one_two_five() {
        for (x, u) in [
            (1.0, 1.0),
            (1.9, 1.0),
            (2.0, 2.0),
            (4.99, 2.0),
            (5.0, 5.0),
            (9.9, 5.0),
            (10.0, 10.0),
            (0.034, 0.02),
            (730.0, 500.0),
        ] {
            assert!((nice_unit(x) - u).abs() < 1e-12 * u, "{x}: {}", nice_unit(x));
        }
        assert_eq!(nice_unit(0.0), 1.0);
        assert_eq!(nice_unit(f64::NAN), 1.0);
    }

    #[test]
    fn plane_at_the_lowest_point_and_lines_on_multiples() {
        let b = Bounds {
            min: Vec3::new(-1.0, -0.5, -1.0),
            max: Vec3::new(1.0, 1.5, 1.0),
        };
        let g = GridPlane::for_bounds(&b);
        assert_eq!(g.height, -0.5);
        assert_eq!(g.unit, 0.5); // radius √3 ≈ 1.73: half is 0.87
        assert_eq!(g.label(), "grid 0.5");
        let fw = DVec2::splat(0.01); // 100 pixels per cell
        let on = g.alpha(DVec3::new(0.5, -0.5, 0.23), fw, 1.0);
        let half = g.alpha(DVec3::new(0.5 + 0.005 * 0.5, -0.5, 0.23), fw, 1.0);
        let off = g.alpha(DVec3::new(0.75, -0.5, 0.23), fw, 1.0);
        assert_eq!(on, LINE_ALPHA);
        assert!((half - 0.5 * LINE_ALPHA).abs() < 1e-9, "{half}");
        assert_eq!(off, 0.0);
        // Faded out far away; crowded lines vanish.
        assert_eq!(g.alpha(DVec3::new(0.0, -0.5, 10.0), fw, 1.0), 0.0);
        assert_eq!(g.alpha(DVec3::new(0.5, -0.5, 0.0), DVec2::splat(0.5), 1.0), 0.0);
    }

    #[test]
    fn shadow_bounds_hold_the_shadow_on_the_floor() {
        let b = Bounds {
            min: Vec3::new(-1.0, 0.0, -1.0),
            max: Vec3::new(1.0, 2.0, 1.0),
        };
        let sun = crate::light::Light {
            kind: crate::light::LightKind::Directional(Vec3::new(1.0, -1.0, 0.0)),
            color: Vec3::ONE,
        };
        let s = shadow_bounds(&b, &[sun]);
        // The top corners' shadow lies 2 further along +x.
        assert_eq!(s.max.x, 3.0);
        assert_eq!((s.min, s.max.y, s.max.z), (b.min, b.max.y, b.max.z));
        let below = crate::light::Light {
            kind: crate::light::LightKind::Directional(Vec3::Y),
            color: Vec3::ONE,
        };
        assert_eq!(shadow_bounds(&b, &[below]), b);
    }

    #[test]
    fn triad_follows_the_view() {
        let mut c = crate::camera::OrbitCamera::fit(
            &Bounds {
                min: Vec3::splat(-1.0),
                max: Vec3::splat(1.0),
            },
            45.0,
            1.0,
        );
        let (x, y, _) = triad_direction(&c.view(), Vec3::X);
        assert!((x - 1.0).abs() < 1e-6 && y.abs() < 1e-6);
        let (_, y, _) = triad_direction(&c.view(), Vec3::Y);
        assert!((y + 1.0).abs() < 1e-6, "Y points up the picture");
        // Yaw 90°: the eye on +X; X points at the viewer, Z to the left.
        c.yaw_deg = 90.0;
        let (x, y, z) = triad_direction(&c.view(), Vec3::X);
        assert!(x.hypot(y) < 1e-6 && z > 0.99);
        let (x, _, _) = triad_direction(&c.view(), Vec3::Z);
        assert!((x + 1.0).abs() < 1e-6);
    }
}
