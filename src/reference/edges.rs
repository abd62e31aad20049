//! The edges of `--edges` / `--wireframe` in the reference: the same segments as the GPU's
//! (`scene::edges`), projected with the camera in f64. A pixel is an edge pixel when a
//! projected segment passes within half a pixel of its centre, measured along the segment's
//! minor axis (one pixel per column of an x-major segment, as GL's diamond-exit rule draws a
//! 1-pixel line), and the segment's point there is not hidden: the first opaque surface on
//! the ray towards it is not nearer than it (by 10⁻⁶ of the near–far range, for the faces
//! the edge itself bounds). Segments are binned into 16-pixel tiles, so a wireframe of a scan
//! costs what its lines cover. Wider lines (`--line-width`) cover the pixels whose centre
//! lies within half the width of the segment, or of its ends (the GPU's square caps are
//! taken as round here: they differ in a corner pixel or two).
use super::{material, Context};
use crate::scene::geometry::edges::{self, EdgeSet};
use glam::{DVec2, DVec3, DVec4};

const TILE: u32 = 16;

/// A segment in world space and in pixels (x right, y down, pixel centres at +0.5).
struct Segment {
    a: DVec3,
    b: DVec3,
    pa: DVec2,
    pb: DVec2,
    /// Clip w at the ends (perspective: screen and world parameters differ).
    wa: f64,
    wb: f64,
}

/// The frame's segments, binned by tile.
pub(crate) struct ScreenEdges {
    segments: Vec<Segment>,
    tiles: Vec<Vec<u32>>,
    tiles_x: u32,
    pub(crate) color: DVec3,
    /// Line width in pixels.
    width: f64,
}

impl ScreenEdges {
    pub(crate) fn new(ctx: &Context, set: EdgeSet, color: DVec3, width: f64) -> ScreenEdges {
        let (w, h) = ctx.size;
        let tiles_x = w.div_ceil(TILE);
        let tiles_y = h.div_ceil(TILE);
        let mut out = ScreenEdges {
            segments: Vec::new(),
            tiles: vec![Vec::new(); (tiles_x * tiles_y) as usize],
            tiles_x,
            color,
            width,
        };
        let m = ctx.view.forward;
        let to_px = |c: DVec4| {
            DVec2::new(
                (c.x / c.w + 1.0) * 0.5 * f64::from(w),
                (1.0 - c.y / c.w) * 0.5 * f64::from(h),
            )
        };
        for mesh in &ctx.scene.meshes {
            let lines = edges::extract(mesh, set);
            let p = |c: u32| DVec3::from(lines.positions[c as usize].map(f64::from));
            for s in &lines.segments {
                let (mut a, mut b) = (p(s[0]), p(s[1]));
                let (mut ca, mut cb) = (m * a.extend(1.0), m * b.extend(1.0));
                // Clip at the near plane (z = −w), as GL does.
                let (da, db) = (ca.z + ca.w, cb.z + cb.w);
                if da < 0.0 && db < 0.0 {
                    continue;
                }
                if da < 0.0 || db < 0.0 {
                    let t = da / (da - db);
                    let (cm, pm) = (ca + (cb - ca) * t, a + (b - a) * t);
                    if da < 0.0 {
                        (ca, a) = (cm, pm);
                    } else {
                        (cb, b) = (cm, pm);
                    }
                }
                let seg = Segment {
                    a,
                    b,
                    pa: to_px(ca),
                    pb: to_px(cb),
                    wa: ca.w,
                    wb: cb.w,
                };
                let lo = seg.pa.min(seg.pb) - (1.0 + width / 2.0);
                let hi = seg.pa.max(seg.pb) + (1.0 + width / 2.0);
                if hi.x < 0.0 || hi.y < 0.0 || lo.x > f64::from(w) || lo.y > f64::from(h) {
                    continue;
                }
                let i = out.segments.len() as u32;
                let tile = |v: f64, n: u32| ((v.max(0.0) as u32) / TILE).min(n - 1);
                // A long segment's box covers many tiles it misses: fine for the few long
                // lines of feature edges, and a wireframe's lines are short.
                for ty in tile(lo.y, tiles_y)..=tile(hi.y, tiles_y) {
                    for tx in tile(lo.x, tiles_x)..=tile(hi.x, tiles_x) {
                        out.tiles[(ty * tiles_x + tx) as usize].push(i);
                    }
                }
                out.segments.push(seg);
            }
        }
        out
    }

    /// Whether pixel (x, y) (top row 0) shows an edge.
    pub(crate) fn covers(&self, ctx: &Context, x: u32, y: u32) -> bool {
        let c = DVec2::new(f64::from(x) + 0.5, f64::from(y) + 0.5);
        let tile = &self.tiles[((y / TILE) * self.tiles_x + x / TILE) as usize];
        tile.iter().any(|&i| {
            let s = &self.segments[i as usize];
            let d = s.pb - s.pa;
            if self.width > 1.0 {
                let len2 = d.length_squared();
                let u = if len2 > 0.0 {
                    ((c - s.pa).dot(d) / len2).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                if (s.pa + d * u - c).length() > self.width / 2.0 {
                    return false;
                }
                let t = u * s.wa / ((1.0 - u) * s.wb + u * s.wa);
                return visible(ctx, s.a + (s.b - s.a) * t);
            }
            // Along the major axis: the parameter at the centre's column (row), then the
            // distance along the minor axis.
            let (major, minor) = if d.x.abs() >= d.y.abs() {
                (0, 1)
            } else {
                (1, 0)
            };
            if d[major] == 0.0 {
                return false;
            }
            let u = (c[major] - s.pa[major]) / d[major];
            if !(0.0..=1.0).contains(&u) {
                return false;
            }
            if (s.pa[minor] + u * d[minor] - c[minor]).abs() > 0.5 {
                return false;
            }
            // Screen parameter u → the segment's parameter in world space.
            let t = u * s.wa / ((1.0 - u) * s.wb + u * s.wa);
            visible(ctx, s.a + (s.b - s.a) * t)
        })
    }
}

/// Whether no opaque surface lies in front of world point `p`.
fn visible(ctx: &Context, p: DVec3) -> bool {
    let c = ctx.view.forward * p.extend(1.0);
    let (o, d) = ctx.view.ray_ndc(c.x / c.w, c.y / c.w);
    let tp = (p - o).dot(d) / d.length_squared();
    ctx.opaque
        .closest_where(o, d, 0.0, (tp - 1e-6).max(0.0), |h| {
            material::drawn(ctx, h, d)
        })
        .is_none()
}
