//! The ground grid of `--grid` and the orientation triad of `--axes` as pure math (no GL):
//! where the grid's plane lies, its unit, and the rule that says how much line a pixel
//! shows. The grid pass (`render/grid.rs` with `grid.frag`, which states the same rule in
//! GLSL) and the CPU reference (`reference/grid.rs`) both follow it, so the GPU's lines are
//! checked against a ray-cast plane.
use crate::scene::{Bounds, UpAxis};
use glam::{DVec2, DVec3, Mat4, Vec3};

/// The plane y = `height` (the scene's up axis after `--up`), lines every `unit` along X and
/// Z from the file's origin (so they lie at the file's round coordinates), fading out between
/// half `fade` and `fade` from `centre` (x, z); the file's two axes that lie on the floor
/// drawn through its origin in the triad's colours (as f3d draws them).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridPlane {
    pub height: f64,
    pub(crate) centre: DVec2,
    pub unit: f64,
    pub(crate) fade: f64,
    /// Where the file's origin lies on the plane (x, z of the scene's coordinates, which
    /// are the file's re-centred and turned by `--up`).
    pub(crate) file_origin: DVec2,
    /// The colours of the file axes along the scene's X and along its Z (display values).
    pub(crate) axis_colors: [DVec3; 2],
}

/// How far the grid reaches, in bounding radii: far enough to hold a low light's shadow.
pub(crate) const FADE_RADII: f64 = 4.0;
/// The grid lines' opacity where they are fully drawn.
pub(crate) const LINE_ALPHA: f64 = 0.6;
/// The axis lines' opacity; they are half again as wide as the grid's.
pub(crate) const AXIS_ALPHA: f64 = 0.9;

impl GridPlane {
    /// The grid under `bounds` of a scene whose file origin lies at `origin` below zero
    /// (`Scene::origin`), read with `up`: at the bounds' lowest point, centred below them,
    /// with a unit of 1, 2 or 5 × 10^k near half the bounding radius (a few cells across).
    pub(crate) fn new(bounds: &Bounds, origin: DVec3, up: UpAxis) -> GridPlane {
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
            file_origin: DVec2::new(-origin.x, -origin.z),
            axis_colors: [Vec3::X, Vec3::Z].map(|d| floor_axis_color(up, d)),
        }
    }

    /// [`GridPlane::new`] for a loaded scene.
    pub fn for_scene(scene: &crate::scene::Scene, up: UpAxis) -> GridPlane {
        GridPlane::new(&scene.bounds, scene.origin, up)
    }

    /// The overlay's label: `grid 0.5` (model units per cell).
    pub(crate) fn label(&self) -> String {
        format!("grid {}", self.unit as f32)
    }

    /// The lines at point `p` of the plane, seen through a pixel whose footprint spans
    /// `fw` = fwidth(q) for q = p.xz / unit (the sum of the absolute changes across one
    /// pixel in x and in y), lines `width` pixels wide over the grid colour `grid`: their
    /// colour and opacity. grid.frag computes exactly this.
    pub fn lines(&self, p: DVec3, fw: DVec2, width: f64, grid: DVec3) -> (DVec3, f64) {
        let q = (DVec2::new(p.x, p.z) - self.file_origin) / self.unit;
        let fw = fw.max(DVec2::splat(1e-9));
        let fade = self.fade_at(p);
        // Pixels to the nearest line along each axis; the nearer one counts.
        let d = (fract(q - 0.5) - 0.5).abs() / fw;
        let cover = (0.5 * width + 0.5 - d.x.min(d.y)).clamp(0.0, 1.0);
        // Lines closer than a few pixels apart would only make moiré: they fade out.
        let crowd = 1.0 - smoothstep(0.2, 0.45, fw.x.max(fw.y));
        let a = LINE_ALPHA * cover * crowd * fade;
        // The axis along X lies at q.y = 0, the one along Z at q.x = 0.
        let axis = |dist: f64| AXIS_ALPHA * (0.75 * width + 0.5 - dist).clamp(0.0, 1.0) * fade;
        let (ax, az) = (axis(q.y.abs() / fw.y), axis(q.x.abs() / fw.x));
        let (c, a) = over((self.axis_colors[0], ax), (grid, a));
        over((self.axis_colors[1], az), (c, a))
    }

    /// How much of the grid (lines and shadow) is left at `p`: 1 near the model, 0 from
    /// `fade` on.
    pub fn fade_at(&self, p: DVec3) -> f64 {
        let far = (DVec2::new(p.x, p.z) - self.centre).length();
        1.0 - smoothstep(0.5 * self.fade, self.fade, far)
    }

    /// A point of the lines' lattice on the plane near the centre: the GPU draws relative to
    /// it, so its f32 line rule never works on large coordinates.
    pub(crate) fn origin(&self) -> DVec3 {
        let k = ((self.centre - self.file_origin) / self.unit).round();
        let o = self.file_origin + k * self.unit;
        DVec3::new(o.x, self.height, o.y)
    }

    /// The square the grid is drawn on, relative to [`GridPlane::origin`] (corners on the
    /// plane, counter-clockwise from above).
    pub(crate) fn corners(&self) -> [Vec3; 4] {
        let o = self.origin();
        let (c, f) = (self.centre, self.fade);
        [(-1.0, 1.0), (1.0, 1.0), (1.0, -1.0), (-1.0, -1.0)]
            .map(|(sx, sz)| DVec3::new(c.x + sx * f - o.x, 0.0, c.y + sz * f - o.z).as_vec3())
    }
}

/// The bounds a shadow map is fitted to while the grid is on: the model's, and where its
/// box's shadow falls on the plane from each casting light (clipped to the grid's square),
/// so the model's shadow on the grid lies inside the map instead of being cut at its edge.
pub(crate) fn shadow_bounds(bounds: &Bounds, lights: &[crate::light::Light]) -> Bounds {
    use crate::light::LightKind;
    // (Where the lines lie does not matter here: no origin or up needed.)
    let g = GridPlane::new(bounds, glam::DVec3::ZERO, UpAxis::PosY);
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
    let y = background.dot(Vec3::from(LUMINANCE.map(|k| k as f32)));
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

/// `src` over `dst`, each (colour, opacity) with straight alpha.
pub(crate) fn over(src: (DVec3, f64), dst: (DVec3, f64)) -> (DVec3, f64) {
    let a = src.1 + dst.1 * (1.0 - src.1);
    if a <= 0.0 {
        return (DVec3::ZERO, 0.0);
    }
    ((src.0 * src.1 + dst.0 * dst.1 * (1.0 - src.1)) / a, a)
}

/// The triad colour of the file axis that `--up` turns onto the scene's direction `d` (X or
/// Z: the floor's axes).
pub(crate) fn floor_axis_color(up: UpAxis, d: Vec3) -> DVec3 {
    let (_, rgb, _) = AXES
        .iter()
        .find(|(a, _, _)| up.rotate(a.as_dvec3()).as_vec3().dot(d).abs() > 0.5)
        .copied()
        .unwrap_or(AXES[0]);
    DVec3::from(rgb.map(|c| f64::from(c) / 255.0))
}

/// The largest 1, 2 or 5 × 10^k at most `x` (x > 0; 1 otherwise).
pub(crate) fn nice_unit(x: f64) -> f64 {
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
pub(crate) fn smoothstep(e0: f64, e1: f64, x: f64) -> f64 {
    let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// The axes of the triad, in the order drawn labels read: X red, Y green, Z blue.
pub const AXES: [(Vec3, [u8; 3], char); 3] = [
    (Vec3::X, [230, 57, 57], 'X'),
    (Vec3::Y, [64, 200, 64], 'Y'),
    (Vec3::Z, [72, 120, 255], 'Z'),
];

/// Where the file's axis `axis` points in the triad: turned by `--up` into the scene and by
/// the view's rotation, as (right, down) in the picture, of length at most 1 (shorter as it
/// turns towards or away from the viewer), and its depth towards the viewer (drawing order).
pub fn triad_direction(view: &Mat4, up: UpAxis, axis: Vec3) -> (f32, f32, f32) {
    let v = view.transform_vector3(up.rotate(axis.as_dvec3()).as_vec3());
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
            assert!(
                (nice_unit(x) - u).abs() < 1e-12 * u,
                "{x}: {}",
                nice_unit(x)
            );
        }
        assert_eq!(nice_unit(0.0), 1.0);
        assert_eq!(nice_unit(f64::NAN), 1.0);
    }

    #[test]
    fn plane_at_the_lowest_point_and_lines_on_the_files_multiples() {
        let b = Bounds {
            min: Vec3::new(-1.0, -0.5, -1.0),
            max: Vec3::new(1.0, 1.5, 1.0),
        };
        // The file's origin lies at (-0.1, *, 0.2) of the scene's coordinates.
        let g = GridPlane::new(&b, DVec3::new(0.1, 7.0, -0.2), UpAxis::PosY);
        assert_eq!(g.height, -0.5);
        assert_eq!(g.unit, 0.5); // radius √3 ≈ 1.73: half is 0.87
        assert_eq!(g.label(), "grid 0.5");
        let grey = DVec3::splat(0.8);
        let fw = DVec2::splat(0.01); // 100 pixels per cell
        let at = |x: f64, z: f64| g.lines(DVec3::new(x, -0.5, z), fw, 1.0, grey);
        let on = at(0.4, 0.33);
        let half = at(0.4 + 0.005 * 0.5, 0.33);
        let off = at(0.65, 0.33);
        assert_eq!(on, (grey, LINE_ALPHA));
        assert!((half.1 - 0.5 * LINE_ALPHA).abs() < 1e-9, "{half:?}");
        assert_eq!(off.1, 0.0);
        // The file's X axis (red) at z = 0.2, its Z axis (blue) at x = -0.1.
        let red = floor_axis_color(UpAxis::PosY, Vec3::X);
        // (over a grid line: the axis lies on one)
        assert_eq!(at(0.65, 0.2), over((red, AXIS_ALPHA), (grey, LINE_ALPHA)));
        let blue = floor_axis_color(UpAxis::PosY, Vec3::Z);
        assert_eq!(at(-0.1, 0.33), over((blue, AXIS_ALPHA), (grey, LINE_ALPHA)));
        // Faded out far away; crowded lines vanish.
        assert_eq!(at(0.4, 10.0).1, 0.0);
        // (Away from the axes, which are single lines: they never crowd.)
        assert_eq!(
            g.lines(DVec3::new(0.4, -0.5, 0.7), DVec2::splat(0.5), 1.0, grey)
                .1,
            0.0
        );
        // The lattice point the GPU draws from is one of the lines' crossings.
        let o = g.origin();
        assert!(
            ((o.x + 0.1) / 0.5).fract().abs() < 1e-12 && ((o.z - 0.2) / 0.5).fract().abs() < 1e-12
        );
        // Z up: the file's X and Y lie on the floor (Y along the scene's Z, green).
        let green = DVec3::from(AXES[1].1.map(|c| f64::from(c) / 255.0));
        assert_eq!(floor_axis_color(UpAxis::PosZ, Vec3::Z), green);
    }

    #[test]
    fn shadow_bounds_hold_the_shadow_on_the_floor() {
        let b = Bounds {
            min: Vec3::new(-1.0, 0.0, -1.0),
            max: Vec3::new(1.0, 2.0, 1.0),
        };
        let sun = crate::light::Light::new(
            crate::light::LightKind::Directional(Vec3::new(1.0, -1.0, 0.0)),
            Vec3::ONE,
        );
        let s = shadow_bounds(&b, &[sun]);
        // The top corners' shadow lies 2 further along +x.
        assert_eq!(s.max.x, 3.0);
        assert_eq!((s.min, s.max.y, s.max.z), (b.min, b.max.y, b.max.z));
        let below =
            crate::light::Light::new(crate::light::LightKind::Directional(Vec3::Y), Vec3::ONE);
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
        let y_up = UpAxis::PosY;
        let (x, y, _) = triad_direction(&c.view(), y_up, Vec3::X);
        assert!((x - 1.0).abs() < 1e-6 && y.abs() < 1e-6);
        let (_, y, _) = triad_direction(&c.view(), y_up, Vec3::Y);
        assert!((y + 1.0).abs() < 1e-6, "Y points up the picture");
        // A Z-up file: its Z points up the picture.
        let (_, y, _) = triad_direction(&c.view(), UpAxis::PosZ, Vec3::Z);
        assert!((y + 1.0).abs() < 1e-6, "Z up");
        // Yaw 90°: the eye on +X; X points at the viewer, Z to the left.
        c.yaw_deg = 90.0;
        let (x, y, z) = triad_direction(&c.view(), y_up, Vec3::X);
        assert!(x.hypot(y) < 1e-6 && z > 0.99);
        let (x, _, _) = triad_direction(&c.view(), y_up, Vec3::Z);
        assert!((x + 1.0).abs() < 1e-6);
    }
}
