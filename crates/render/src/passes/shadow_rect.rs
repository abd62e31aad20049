//! Where a shadow map must be drawn again after casters moved. A playing model redraws its
//! maps every frame, and on llvmpipe a 2,048² map costs more than the frame it shadows; but
//! only the texels under the moved casters' old and new places can change. So a pose marks
//! the box holding both ([`MovedBoxes`]), and the next shadow pass clears and draws every
//! caster again inside that box's rectangle of each light view only ([`rect`]), with the
//! scissor test. Rasterizing a triangle gives the same depth at a texel whatever the
//! scissor, and outside the rectangle only unmoved casters ever drew, so the map equals a
//! full redraw texel for texel (tests/suite/motion_render.rs holds it to a fresh renderer's
//! picture, byte for byte).
use crate::scene::Bounds;
use glam::{Mat4, Vec3, Vec4};
use std::collections::HashMap;

/// Texels added on every side of a rectangle: a texel is drawn when its centre is inside a
/// triangle, so one would do; two absorb float rounding of the corners' projection.
const MARGIN: f32 = 2.0;

/// The rectangle `[x, y, width, height]` of a `face`² view with view-projection `vp` that
/// holds box `b`; None when the box is outside the view. The whole view when a corner lies
/// behind a perspective light (its projection would wrap).
pub(crate) fn rect(vp: &Mat4, b: &Bounds, face: u32) -> Option<[u32; 4]> {
    let all = [0, 0, face, face];
    if b.is_empty() {
        return None;
    }
    let (mut lo, mut hi) = (
        glam::Vec2::splat(f32::INFINITY),
        glam::Vec2::splat(f32::NEG_INFINITY),
    );
    for p in b.corners() {
        let c = *vp * Vec4::from((p, 1.0));
        // NaN compares false: not finite either way.
        if c.w <= 1e-6 || !c.is_finite() {
            return Some(all);
        }
        let t = (c.truncate().truncate() / c.w * 0.5 + 0.5) * face as f32;
        lo = lo.min(t);
        hi = hi.max(t);
    }
    let f = face as f32;
    let (x0, y0) = (
        (lo.x - MARGIN).floor().max(0.0),
        (lo.y - MARGIN).floor().max(0.0),
    );
    let (x1, y1) = ((hi.x + MARGIN).ceil().min(f), (hi.y + MARGIN).ceil().min(f));
    (x1 > x0 && y1 > y0).then_some([x0 as u32, y0 as u32, (x1 - x0) as u32, (y1 - y0) as u32])
}

/// The rectangles of boxes `boxes` in a `face`² view ([`rect`]), without repeats; the whole
/// view alone when one of them is the whole view (each is drawn with every caster).
pub(crate) fn rects(vp: &Mat4, boxes: &[Bounds], face: u32) -> Vec<[u32; 4]> {
    let all = [0, 0, face, face];
    let mut out: Vec<[u32; 4]> = Vec::new();
    for r in boxes.iter().filter_map(|b| rect(vp, b, face)) {
        if r == all {
            return vec![all];
        }
        if !out.contains(&r) {
            out.push(r);
        }
    }
    out
}

/// The box around a sphere.
pub(crate) fn sphere_box(center: Vec3, radius: f32) -> Bounds {
    Bounds {
        min: center - Vec3::splat(radius),
        max: center + Vec3::splat(radius),
    }
}

/// The box each moving draw mesh was last drawn within, so a pose knows where it was (its
/// vertices are already rewritten when the renderer hears of it). A mesh not yet here was
/// never posed: its draw record's bounding sphere holds it.
#[derive(Default)]
pub(crate) struct MovedBoxes(HashMap<usize, Bounds>);

impl MovedBoxes {
    /// Where draw mesh `i` was: its last box, else the box of its sphere.
    pub(crate) fn was(&self, i: usize, sphere: (Vec3, f32)) -> Bounds {
        self.0
            .get(&i)
            .copied()
            .unwrap_or_else(|| sphere_box(sphere.0, sphere.1))
    }

    /// Records where draw mesh `i` is now.
    pub(crate) fn is(&mut self, i: usize, b: Bounds) {
        self.0.insert(i, b);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_box() -> Bounds {
        Bounds {
            min: Vec3::splat(-0.25),
            max: Vec3::splat(0.25),
        }
    }

    #[test]
    fn an_orthographic_view_maps_a_box_to_its_texels_plus_the_margin() {
        // NDC [-1, 1] → texels [0, 100]: the box's ±0.25 → 37.5..62.5, then ±2 texels.
        let r = rect(&Mat4::IDENTITY, &unit_box(), 100).unwrap();
        assert_eq!(r, [35, 35, 30, 30]);
    }

    #[test]
    fn a_box_past_the_edge_is_clamped_and_one_outside_is_nothing() {
        let shift = |x: f32| Mat4::from_translation(Vec3::new(x, 0.0, 0.0));
        let r = rect(&shift(0.9), &unit_box(), 100).unwrap();
        assert_eq!((r[0], r[0] + r[2]), (80, 100));
        assert_eq!(rect(&shift(3.0), &unit_box(), 100), None);
        assert_eq!(rect(&Mat4::IDENTITY, &Bounds::empty(), 100), None);
    }

    #[test]
    fn rectangles_are_drawn_once_and_the_whole_view_alone() {
        let far = Bounds {
            min: Vec3::splat(0.5),
            max: Vec3::splat(0.75),
        };
        let big = Bounds {
            min: Vec3::splat(-2.0),
            max: Vec3::splat(2.0),
        };
        let id = Mat4::IDENTITY;
        assert_eq!(rects(&id, &[unit_box(), far, unit_box()], 100).len(), 2);
        assert_eq!(
            rects(&id, &[unit_box(), big, far], 100),
            vec![[0, 0, 100, 100]]
        );
        assert!(rects(&id, &[], 100).is_empty());
    }

    #[test]
    fn a_corner_behind_a_perspective_light_redraws_the_whole_view() {
        let vp = Mat4::perspective_rh_gl(1.0, 1.0, 0.1, 10.0);
        // The box straddles the light's plane (z from -0.25 to 0.25): w ≤ 0 at its back.
        assert_eq!(rect(&vp, &unit_box(), 64), Some([0, 0, 64, 64]));
        let ahead = Mat4::from_translation(Vec3::new(0.0, 0.0, -3.0));
        let r = rect(&(vp * ahead), &unit_box(), 64).unwrap();
        assert!(r[2] < 64 && r[3] < 64, "{r:?}");
    }

    #[test]
    fn a_mesh_never_posed_was_within_its_sphere_then_where_it_was_recorded() {
        let mut m = MovedBoxes::default();
        let b = m.was(3, (Vec3::ONE, 2.0));
        assert_eq!((b.min, b.max), (Vec3::splat(-1.0), Vec3::splat(3.0)));
        m.is(3, unit_box());
        assert_eq!(m.was(3, (Vec3::ONE, 2.0)).max, Vec3::splat(0.25));
    }
}
