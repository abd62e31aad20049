//! Light frusta for shadow maps (pure math, no GL): the view-projection a light's depth map
//! is rendered with, fitted to the scene's bounds.
use crate::light::{Light, LightKind};
use crate::scene::Bounds;
use glam::{Mat4, Vec3};

/// How a light's shadow is stored.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum ShadowProjection {
    /// Directional light: orthographic, fitted tightly to the bounds seen from the light.
    Ortho,
    /// Point light at least [`CUBE_BELOW`] radii from the centre: one perspective frustum
    /// aimed at the scene.
    Perspective,
    /// Point light inside the bounding sphere or just outside it: six 90° frusta (+X, −X, +Y, −Y, +Z, −Z), drawn
    /// into a 3×2 atlas of one depth texture. One `sampler2DShadow` serves every dialect,
    /// including GLSL 1.20, which has no cube shadow lookups.
    Cube,
}

impl ShadowProjection {
    /// Its name in `--stats`' shadow pass entry.
    pub(crate) fn name(self) -> &'static str {
        match self {
            ShadowProjection::Ortho => "ortho",
            ShadowProjection::Perspective => "perspective",
            ShadowProjection::Cube => "cube",
        }
    }
}

/// A point light nearer the centre than this many bounding radii gets the six-face atlas. At
/// distance d the single frustum needs a full angle of 2·asin(r/d) (·1.02 padding): just
/// outside the sphere that passes 180° and the projection mirrors, and below ~1.1 r (131°)
/// the map's texels spread so thin towards the edges that six 90° faces resolve more.
pub(crate) const CUBE_BELOW: f32 = 1.1;

/// The atlas faces' view directions, in the order the shader picks them.
pub(crate) const CUBE_DIRECTIONS: [Vec3; 6] = [
    Vec3::X,
    Vec3::NEG_X,
    Vec3::Y,
    Vec3::NEG_Y,
    Vec3::Z,
    Vec3::NEG_Z,
];

/// The six faces' view-projections of a point light at `p`, in the order the shader picks
/// them: face = 2·axis + (negative ? 1 : 0) for the dominant axis of (fragment − light).
pub(crate) fn cube_faces(p: Vec3, bounds: &Bounds) -> [Mat4; 6] {
    let r = bounds.radius();
    let far = ((bounds.center() - p).length() + r) * 1.01;
    // The near plane only has to exclude the light itself; r·1e-3 keeps the depth precision
    // of a 24-bit buffer (far/near ≈ 2·10³) for anything a visible distance away.
    let near = (r * 1e-3).min(far * 1e-3);
    let proj = Mat4::perspective_rh_gl(std::f32::consts::FRAC_PI_2, 1.0, near, far);
    CUBE_DIRECTIONS.map(|d| proj * Mat4::look_at_rh(p, p + d, stable_up(d)))
}

/// Maps a face's texture space [0, 1]² to its tile of the 3×2 atlas.
pub(crate) fn atlas_tile(face: usize) -> Mat4 {
    let (fx, fy) = ((face % 3) as f32, (face / 3) as f32);
    Mat4::from_translation(Vec3::new(fx / 3.0, fy / 2.0, 0.0))
        * Mat4::from_scale(Vec3::new(1.0 / 3.0, 0.5, 1.0))
}

/// An up vector that is never parallel to `dir` (a light shining straight down must not
/// break `look_at`).
pub(crate) fn stable_up(dir: Vec3) -> Vec3 {
    if dir.normalize().dot(Vec3::Y).abs() > 0.99 {
        Vec3::Z
    } else {
        Vec3::Y
    }
}

/// The light's view-projection (to GL clip space) and its kind, or None for a point light
/// inside or just outside the bounding sphere (see `point_inside`).
pub(crate) fn light_view_proj(light: &Light, bounds: &Bounds) -> Option<(Mat4, ShadowProjection)> {
    let c = bounds.center();
    let r = bounds.radius();
    match light.kind {
        LightKind::Directional(d) => {
            let d = d.normalize();
            let eye = c - d * (2.0 * r);
            let view = Mat4::look_at_rh(eye, c, stable_up(d));
            let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
            for p in bounds.corners() {
                let q = view.transform_point3(p);
                lo = lo.min(q);
                hi = hi.max(q);
            }
            // A hair of padding so geometry on the boundary is inside the map, not clamped.
            let pad = (hi - lo).max_element() * 1e-3 + 1e-6;
            let (lo, hi) = (lo - Vec3::splat(pad), hi + Vec3::splat(pad));
            let proj = Mat4::orthographic_rh_gl(lo.x, hi.x, lo.y, hi.y, -hi.z, -lo.z);
            Some((proj * view, ShadowProjection::Ortho))
        }
        LightKind::Point(p) => {
            let to_c = c - p;
            let dist = to_c.length();
            if dist < r * CUBE_BELOW {
                return None;
            }
            let view = Mat4::look_at_rh(p, c, stable_up(to_c));
            let half = (r / dist).asin() * 1.02;
            let near = (dist - r).max(dist * 1e-4);
            let far = dist + r * 1.01;
            let proj = Mat4::perspective_rh_gl(2.0 * half, 1.0, near, far);
            Some((proj * view, ShadowProjection::Perspective))
        }
    }
}

/// Whether a point light is inside the bounding sphere or within [`CUBE_BELOW`] radii of its
/// centre (a single frustum cannot see all of the scene from there, or only badly).
/// The tests' statement of the rule `light_view_proj` applies inline.
#[cfg(test)]
fn point_inside(light: &Light, bounds: &Bounds) -> bool {
    matches!(light.kind, LightKind::Point(p) if (bounds.center() - p).length() < bounds.radius() * CUBE_BELOW)
}

/// Maps clip space [-1, 1]³ to texture space [0, 1]³.
pub(crate) fn bias_matrix() -> Mat4 {
    Mat4::from_translation(Vec3::splat(0.5)) * Mat4::from_scale(Vec3::splat(0.5))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bounds() -> Bounds {
        Bounds {
            min: Vec3::new(-3.0, 0.0, -3.0),
            max: Vec3::new(3.0, 2.0, 3.0),
        }
    }

    fn inside_clip(m: Mat4, p: Vec3) -> bool {
        let q = m.project_point3(p);
        q.abs().max_element() <= 1.0 + 1e-5
    }

    #[test]
    fn directional_frustum_holds_every_corner_tightly() {
        for dir in [
            Vec3::NEG_Y,
            Vec3::new(0.3, -1.0, 0.2),
            Vec3::X,
            Vec3::new(0.0, 1.0, 0.0),
        ] {
            let l = Light::new(LightKind::Directional(dir), Vec3::ONE);
            let (m, kind) = light_view_proj(&l, &bounds()).unwrap();
            assert_eq!(kind, ShadowProjection::Ortho);
            assert!(m.is_finite(), "{dir}");
            let mut max = 0.0f32;
            for c in bounds().corners() {
                assert!(inside_clip(m, c), "{dir} {c}");
                max = max.max(m.project_point3(c).truncate().abs().max_element());
            }
            // Tight: some corner touches the frustum's edge.
            assert!(max > 0.99, "{dir}: {max}");
        }
    }

    #[test]
    fn point_light_outside_sees_the_whole_scene() {
        let l = Light::new(LightKind::Point(Vec3::new(4.0, 8.0, 3.0)), Vec3::ONE);
        let (m, kind) = light_view_proj(&l, &bounds()).unwrap();
        assert_eq!(kind, ShadowProjection::Perspective);
        for c in bounds().corners() {
            assert!(inside_clip(m, c), "{c}");
        }
        // Straight above: the up vector must not be parallel to the view direction.
        let above = Light::new(LightKind::Point(Vec3::new(0.0, 20.0, 0.0)), Vec3::ONE);
        assert!(light_view_proj(&above, &bounds()).unwrap().0.is_finite());
    }

    #[test]
    fn cube_faces_cover_every_direction() {
        let p = Vec3::new(0.2, 1.0, -0.3);
        let faces = cube_faces(p, &bounds());
        for (i, d) in CUBE_DIRECTIONS.iter().enumerate() {
            // A point along the face's axis (slightly off it) projects into that face.
            let q = faces[i].project_point3(p + *d * 2.0 + d.any_orthonormal_vector() * 0.5);
            assert!(q.abs().max_element() <= 1.0, "face {i}: {q}");
            assert!(faces[i].is_finite());
        }
        assert_eq!(
            atlas_tile(4).transform_point3(Vec3::ZERO),
            Vec3::new(1.0 / 3.0, 0.5, 0.0)
        );
    }

    #[test]
    fn point_light_inside_has_no_single_frustum() {
        let l = Light::new(LightKind::Point(Vec3::new(0.0, 1.0, 0.0)), Vec3::ONE);
        assert!(light_view_proj(&l, &bounds()).is_none());
        assert!(point_inside(&l, &bounds()));
    }

    #[test]
    fn point_light_just_outside_uses_six_faces_and_single_frusta_stay_below_180() {
        let b = bounds();
        let (c, r) = (b.center(), b.radius());
        let dir = Vec3::new(0.6, 0.7, 0.4).normalize();
        let light = |k: f32| Light::new(LightKind::Point(c + dir * r * k), Vec3::ONE);
        // Just outside the sphere a single frustum would need more than 180°.
        for k in [1.0002, 1.01, 1.05, 1.099] {
            assert!(light_view_proj(&light(k), &b).is_none(), "{k}");
            assert!(point_inside(&light(k), &b), "{k}");
        }
        for k in [1.101, 1.3, 3.0] {
            let (m, kind) = light_view_proj(&light(k), &b).unwrap();
            assert_eq!(kind, ShadowProjection::Perspective);
            assert!(!point_inside(&light(k), &b));
            let full = 2.0 * (1.0 / k).asin().to_degrees() * 1.02;
            assert!(full < 180.0, "{k}: {full}°");
            for corner in b.corners() {
                assert!(inside_clip(m, corner), "{k}: {corner}");
            }
        }
    }
}
