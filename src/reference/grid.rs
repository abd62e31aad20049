//! The ground grid in the reference: the plane of [`GridPlane`] ray-cast per pixel, its lines
//! by the rule the GPU's grid.frag follows, with fwidth taken from the plane points of the
//! neighbouring pixel centres as the rasterizer pairs them (2×2 quads: the right or left
//! neighbour, the one above or below in window rows), and its shadow by exact shadow rays
//! from the plane point. Blended as the GPU blends it: over every surface (after the
//! translucent layers), where the plane is not behind the opaque surface.
use super::Context;
use crate::grid::{floor_light, line_color, GridPlane, LUMINANCE};
use glam::{DVec2, DVec3};

pub(crate) struct RefGrid {
    plane: GridPlane,
    color: DVec3,
    width: f64,
    /// The camera is above the plane: the shadowed side is in sight.
    above: bool,
}

impl RefGrid {
    pub(crate) fn new(ctx: &Context) -> Option<RefGrid> {
        let s = ctx.settings;
        if !s.lighting.guides.grid {
            return None;
        }
        let plane = GridPlane::for_scene(ctx.scene, s.lighting.guides.up);
        Some(RefGrid {
            plane,
            color: DVec3::from(line_color(s.background).map(f64::from)),
            width: f64::from(s.lighting.guides.scale),
            above: ctx.view.eye.y >= plane.height,
        })
    }

    /// The plane point on the ray (o, d) and its ray parameter, wherever it lies.
    fn hit(&self, o: DVec3, d: DVec3) -> Option<(DVec3, f64)> {
        let t = (self.plane.height - o.y) / d.y;
        t.is_finite().then(|| (o + t * d, t))
    }

    /// The plane point seen through pixel (x, y) (any pixel index, even outside the picture).
    fn at(&self, ctx: &Context, x: i64, y: i64) -> Option<DVec3> {
        let (w, h) = ctx.size;
        let nx = 2.0 * (x as f64 + 0.5) / f64::from(w) - 1.0;
        let ny = 1.0 - 2.0 * (y as f64 + 0.5) / f64::from(h);
        let (o, d) = ctx.view.ray_ndc(nx, ny);
        self.hit(o, d).map(|(p, _)| p)
    }

    /// The colour and opacity of the lines and the darkening of what lies behind at pixel
    /// (x, y) when the plane is seen there in front of `t_opaque`, or None.
    pub(crate) fn cover(
        &self,
        ctx: &Context,
        x: u32,
        y: u32,
        t_opaque: Option<f64>,
    ) -> Option<(DVec3, f64, f64)> {
        let (o, d) = ctx.view.ray(x, y, ctx.size.0, ctx.size.1);
        let (p, t) = self.hit(o, d)?;
        // Clipped at the near plane (t = 0); the GPU's grid reaches past the far plane.
        if t < 0.0 || t_opaque.is_some_and(|to| t > to) {
            return None;
        }
        let (x, y) = (i64::from(x), i64::from(y));
        // Window rows go up: row y's quad partner is below it in the picture when its
        // window row is even.
        let wy = i64::from(ctx.size.1) - 1 - y;
        let dx = if x % 2 == 0 { 1 } else { -1 };
        let dy = if wy % 2 == 0 { -1 } else { 1 };
        let q = |p: DVec3| DVec2::new(p.x, p.z) / self.plane.unit;
        let (px, py) = (self.at(ctx, x + dx, y)?, self.at(ctx, x, y + dy)?);
        let fw = (q(px) - q(p)).abs() + (q(py) - q(p)).abs();
        let (line, a) = self.plane.lines(p, fw, self.width, self.color);
        let s = if self.above && ctx.shadows {
            (1.0 - self.floor(ctx, p)) * self.plane.fade_at(p)
        } else {
            0.0
        };
        Some((line, a, s))
    }

    /// [`floor_light`] at plane point `p`, by shadow rays.
    fn floor(&self, ctx: &Context, p: DVec3) -> f64 {
        let s = ctx.settings;
        if s.shading == crate::frame::Shading::Pbr && !s.lighting.pbr_terms.shadows {
            return 1.0;
        }
        let lum = DVec3::from(LUMINANCE);
        let lights: Vec<(f64, f64)> = s
            .lights
            .iter()
            .enumerate()
            .map(|(i, l)| {
                let to = crate::shading::to_light(l, p);
                let k = l.color.as_dvec3().dot(lum) * to.y.max(0.0);
                let casts = i < usize::from(s.lighting.shadow_casters);
                let up = DVec3::Y;
                let lit = !casts || super::surface::light_visible(ctx, p, up, up, 0.0, l);
                (k, if lit { 1.0 } else { 0.0 })
            })
            .collect();
        floor_light(s.lighting.ambient.dot(lum), &lights)
    }

    /// `color` with the grid blended over it: C = L·a + C·(1 − s)(1 − a).
    pub(crate) fn blend(&self, color: DVec3, (line, a, s): (DVec3, f64, f64)) -> DVec3 {
        line * a + color * (1.0 - s) * (1.0 - a)
    }
}
