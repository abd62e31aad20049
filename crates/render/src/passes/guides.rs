//! The guides drawn over the finished frame, after post, in display colour: the orientation
//! triad of `--axes` (key X) and the grid's unit (`--grid`, key Z), composed on the CPU into a
//! small picture (anti-aliased lines, font8x8 labels: the same on every context and in the
//! headless PNG) and blended into the bottom-left corner of the frame's rectangle with the
//! window overlay's program. The triad is the view's rotation of the world axes, seen
//! orthographically: it turns with the camera and never moves with zoom or pan.
use super::{FrameCx, Outcome};
use crate::grid::{triad_direction, GridPlane, AXES};
use crate::image::canvas;
use crate::image::Rgba;
use crate::Result;

/// The triad's square, in pixels of the picture.
pub const TRIAD_PX: f32 = 84.0;
/// Gap between the guides and the frame's edges, in pixels of the picture.
pub(crate) const MARGIN_PX: f32 = 4.0;
/// An axis seen side-on is this share of half the triad's square.
pub const AXIS_SHARE: f32 = 0.72;

/// Where the triad's centre lies in a picture `height` pixels high, drawn at `scale` frame
/// pixels per picture pixel: (x, y) from the top-left corner, in frame pixels.
pub fn triad_centre(height: u32, scale: f32) -> (f32, f32) {
    let half = 0.5 * (TRIAD_PX * scale).round();
    let m = (MARGIN_PX * scale).round();
    (m + half, height as f32 - m - half)
}

/// The guides, run after post (not in [`super::PASSES`], which precede it).
pub(crate) struct Guides;

impl super::Pass for Guides {
    fn name(&self) -> &'static str {
        "guides"
    }
    fn run(&self, cx: &mut FrameCx) -> Result<Outcome> {
        draw(cx)
    }
}

/// Draws the guides the settings ask for, or says why not.
fn draw(cx: &mut FrameCx) -> Result<Outcome> {
    let g = cx.settings.lighting.guides;
    let s = cx.settings;
    if !(g.axes || g.grid) {
        return Ok(Outcome::Skipped("no --axes or --grid".into()));
    }
    if s.show_shadow_map || s.lighting.attribute_view.code() != 0 {
        return Ok(Outcome::Skipped(
            "a teaching view replaces the scene".into(),
        ));
    }
    let label = g
        .grid
        .then(|| GridPlane::for_scene(&cx.scene.scene, g.up).label());
    let img = compose(&s.camera.view(), g, label.as_deref(), s.background);
    let program = cx.program(&key())?;
    let [x, y, w, h] = cx.viewport;
    let m = (MARGIN_PX * g.scale).round() as u32;
    let (iw, ih) = (
        img.width.min(w.saturating_sub(m)),
        img.height.min(h.saturating_sub(m)),
    );
    let gpu = cx.gpu;
    let rect = [x + m, y + m, iw, ih];
    super::overlay::blend_image(gpu, &program, cx.res.quad(gpu)?, &img, cx.target.fbo, rect)?;
    cx.stats.draw_calls += 1;
    let [x, y, w, h] = cx.viewport;
    cx.gpu.viewport(x, y, w, h);
    let what = match (g.axes, label) {
        (true, Some(l)) => format!("guides(axes, {l})"),
        (true, None) => "guides(axes)".into(),
        (false, Some(l)) => format!("guides({l})"),
        (false, None) => unreachable!("returned above"),
    };
    Ok(Outcome::Ran(what))
}

pub(crate) fn key() -> crate::shader::cache::ProgramKey {
    super::overlay::key()
}

/// The guides' picture (rows top first, straight alpha, transparent elsewhere): the triad in
/// a square at the left, the grid's label along the bottom (right of the triad if any).
pub(crate) fn compose(
    view: &glam::Mat4,
    g: crate::frame::Guides,
    label: Option<&str>,
    background: glam::Vec3,
) -> Rgba {
    let (axes, k) = (g.axes, g.scale.max(1.0));
    let side = if axes {
        (TRIAD_PX * k).round() as u32
    } else {
        0
    };
    let glyph = k.round().max(1.0) as u32;
    let label_w = label.map_or(0, |l| (l.chars().count() as u32 + 1) * 8 * glyph + 2);
    let width = (side + label_w).max(1);
    let height = side.max(if label.is_some() { 10 * glyph } else { 1 });
    let mut img = Rgba {
        width,
        height,
        data: vec![0; (width * height * 4) as usize],
    };
    if axes {
        let half = 0.5 * side as f32;
        let len = AXIS_SHARE * half - 9.0 * k;
        let mut order: Vec<(f32, usize)> = AXES
            .iter()
            .enumerate()
            .map(|(i, (a, _, _))| (triad_direction(view, g.up, *a).2, i))
            .collect();
        // Far axes first: the one towards the viewer is drawn over the others.
        order.sort_by(|a, b| a.0.total_cmp(&b.0));
        for (_, i) in order {
            let (axis, rgb, name) = AXES[i];
            let (dx, dy, _) = triad_direction(view, g.up, axis);
            let end = (half + dx * len, half + dy * len);
            segment(&mut img, (half, half), end, 2.0 * k, rgb);
            // The letter just past the tip, outwards from the centre (beside the centre
            // when the axis points at the viewer).
            let shown = dx.hypot(dy);
            let (ux, uy) = if shown > 1e-3 {
                (dx / shown, dy / shown)
            } else {
                (0.7, -0.7)
            };
            let (lx, ly) = (end.0 + ux * 8.0 * k, end.1 + uy * 8.0 * k);
            let g = (8 * glyph) as f32;
            letter(
                &mut img,
                (lx - 0.5 * g).round() as i32,
                (ly - 0.5 * g).round() as i32,
                &name.to_string(),
                rgb,
                glyph,
            );
        }
    }
    if let Some(l) = label {
        let grey = crate::grid::line_color(background).map(|c| (c * 255.0).round() as u8);
        let y = height as i32 - 9 * glyph as i32;
        letter(&mut img, side as i32 + 4, y, l, grey, glyph);
    }
    img
}

/// An anti-aliased segment `width` pixels wide with round ends, blended over `img`.
fn segment(img: &mut Rgba, a: (f32, f32), b: (f32, f32), width: f32, rgb: [u8; 3]) {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let len2 = (dx * dx + dy * dy).max(1e-12);
    for y in 0..img.height {
        for x in 0..img.width {
            let (px, py) = (x as f32 + 0.5, y as f32 + 0.5);
            let t = (((px - a.0) * dx + (py - a.1) * dy) / len2).clamp(0.0, 1.0);
            let d = (px - a.0 - t * dx).hypot(py - a.1 - t * dy);
            let cover = (0.5 * width + 0.5 - d).clamp(0.0, 1.0);
            if cover > 0.0 {
                over(img, x, y, rgb, cover);
            }
        }
    }
}

/// Text at (x, y) (top-left of its first glyph) with a dark shadow one glyph pixel down and
/// right, so it reads over any background.
fn letter(img: &mut Rgba, x: i32, y: i32, text: &str, rgb: [u8; 3], glyph: u32) {
    for (off, colour) in [(glyph as i32, [16u8; 3]), (0, rgb)] {
        let (w, h) = ((text.chars().count() as u32 * 8 + 1) * glyph, 9 * glyph);
        // The font writes colour only; a scratch picture marks which pixels it wrote.
        let mut scratch = Rgba {
            width: w,
            height: h,
            data: [1u8, 2, 3, 0].repeat((w * h) as usize),
        };
        canvas::text_scaled(&mut scratch, 0, 0, text, [255; 3], glyph);
        for sy in 0..h {
            for sx in 0..w {
                let (tx, ty) = (x + off + sx as i32, y + off + sy as i32);
                let inside =
                    tx >= 0 && ty >= 0 && (tx as u32) < img.width && (ty as u32) < img.height;
                if inside && scratch.pixel(sx, sy)[..3] == [255; 3] {
                    over(img, tx as u32, ty as u32, colour, 1.0);
                }
            }
        }
    }
}

/// Blends `rgb` at coverage `a` over pixel (x, y) (straight alpha).
fn over(img: &mut Rgba, x: u32, y: u32, rgb: [u8; 3], a: f32) {
    let o = ((y * img.width + x) * 4) as usize;
    let px = &mut img.data[o..o + 4];
    let da = f32::from(px[3]) / 255.0;
    let out = a + da * (1.0 - a);
    for c in 0..3 {
        let v = (f32::from(rgb[c]) * a + f32::from(px[c]) * da * (1.0 - a)) / out.max(1e-6);
        px[c] = v.round().clamp(0.0, 255.0) as u8;
    }
    px[3] = (out * 255.0).round() as u8;
}
