//! Translucent surfaces, as the second seed document draws them (`--translucency nearest`,
//! the command line's default): opaque meshes first; then the translucent ones into depth
//! only (colour writes off); then the translucent ones again with depth test EQUAL, no depth
//! writes and blending: only the nearest translucent fragment of each pixel passes, whatever
//! the triangle order, and blends over what lies behind it — the background (colour or
//! environment, drawn first, as in the sorted mode) included, as glTF's BLEND says.
//! `--translucency nearest-masked` is the seed's globe frame: the opaque and translucent
//! draws write 1 into the stencil buffer, the frame is cleared to black and the background
//! drawn last, only where the stencil is not 1, so it never shows through a translucent
//! surface. Both translucent passes draw with the very same program, buffers and state apart
//! from the colour mask, so their depths are bit-identical by construction (no `invariant`
//! needed; the EQUAL pass drawing every pixel the depth pass covered is tested).
//! `--translucency sorted` keeps the legacy order (meshes back to front by centre, back faces
//! then front faces).
use super::background::{self, masked};
use super::units::BEHIND_UNIT;
use super::FrameCx;
use crate::frame::{BlendFormula, TranslucencyMode};
use crate::gpu::program::Program;
use crate::gpu::state::{Blend, Cull, DepthFunc, RenderState, Stencil, StencilFunc};
use crate::scene::Material;
use crate::Result;

/// Whether this frame draws translucency the nearest-layer way.
fn nearest(cx: &FrameCx) -> bool {
    cx.settings.lighting.translucency.mode != TranslucencyMode::Sorted
        && cx.scene.meshes.iter().any(|m| m.translucent)
}

/// Draws mesh `i` (its program bound) once per state. On the RGBM frame (bloom without float
/// render targets) fixed-function blending cannot decode the frame, so each blended draw
/// reads a fresh copy of the frame and blends in the shader instead: exact where a draw
/// covers each pixel once (the nearest layer; a convex mesh's front or back faces).
pub(crate) fn draw_states(
    cx: &mut FrameCx,
    i: usize,
    program: &Program,
    states: &[RenderState],
) -> Result<()> {
    for state in states {
        if !(cx.rgbm && state.blend != Blend::Off) {
            super::cull::draw(cx, i, state)?;
            continue;
        }
        let [x, y, w, h] = cx.viewport;
        cx.bind_target();
        cx.res
            .post
            .behind(cx.gpu, w, h)?
            .copy_region_from_framebuffer(BEHIND_UNIT, x, y);
        cx.rgbm_blend = if state.blend == Blend::Additive {
            2.0
        } else {
            1.0
        };
        cx.set_rgbm_blend(program);
        let off = RenderState {
            blend: Blend::Off,
            ..*state
        };
        super::cull::draw(cx, i, &off)?;
        cx.rgbm_blend = 0.0;
        cx.set_rgbm_blend(program);
    }
    Ok(())
}

/// The opacity a mesh is drawn with: `--opacity` overrides translucent materials.
pub(crate) fn opacity(cx: &FrameCx, m: &Material, translucent: bool) -> f32 {
    match cx.settings.lighting.translucency.opacity {
        Some(a) if translucent => a,
        _ => m.draw_opacity(),
    }
}

/// Clears the frame for the lit passes: black when the background comes last (masked),
/// else the background colour (unless the background pass already drew the environment).
pub(crate) fn clear(cx: &mut FrameCx) {
    if masked(cx) {
        cx.clear(Some([0.0; 3]));
    } else if !cx.res.background_drawn {
        cx.clear(Some(cx.settings.background.to_array()));
    }
}

fn blend(cx: &FrameCx) -> Blend {
    match cx.settings.lighting.translucency.blend {
        BlendFormula::Alpha => Blend::Alpha,
        BlendFormula::Add => Blend::Additive,
    }
}

const MARK: Stencil = Stencil {
    func: StencilFunc::Always,
    reference: 1,
    write: true,
};

/// A tier's mesh drawing: the meshes, and the render states of each draw by translucency.
pub(crate) type DrawFn<'a> =
    dyn FnMut(&mut FrameCx, &[usize], &dyn Fn(bool) -> Vec<RenderState>) -> Result<()> + 'a;

/// Draws the visible meshes (`order`, translucent ones from `first` on) with the tier's
/// `draw`, in the frame's translucency mode, then the masked background.
pub(crate) fn draw_frame(
    cx: &mut FrameCx,
    order: &[usize],
    first: usize,
    draw: &mut DrawFn,
) -> Result<()> {
    if !nearest(cx) {
        // Legacy: opaque, then translucent meshes back to front, each back faces first.
        let b = blend(cx);
        return draw(cx, order, &|translucent| {
            if translucent {
                [Cull::Front, Cull::Back]
                    .map(|cull| RenderState {
                        blend: b,
                        depth_write: false,
                        cull,
                        ..Default::default()
                    })
                    .to_vec()
            } else {
                vec![RenderState::default()]
            }
        });
    }
    let masked = masked(cx);
    let mark = masked.then_some(MARK);
    let (opaque, glass) = order.split_at(first);
    let opaque_state = RenderState {
        stencil: mark,
        ..Default::default()
    };
    draw(cx, opaque, &|_| vec![opaque_state])?;
    if !glass.is_empty() {
        // 1. the nearest translucent depth
        draw(cx, glass, &|_| {
            vec![RenderState {
                color_write: false,
                ..Default::default()
            }]
        })?;
        // 2. its colour, blended, where the depth is exactly that depth
        let b = blend(cx);
        draw(cx, glass, &|_| {
            vec![RenderState {
                depth: Some(DepthFunc::Equal),
                depth_write: false,
                blend: b,
                stencil: mark,
                ..Default::default()
            }]
        })?;
    }
    if masked {
        background::fill_unmarked(cx)?;
    }
    cx.stats.pass_log.push(format!(
        "translucent: nearest layer of {} mesh(es), depth then colour (EQUAL), {}",
        glass.len(),
        if masked {
            "background masked by the stencil"
        } else {
            "over the background"
        }
    ));
    Ok(())
}
