//! The window's `C` view: the legacy tier left, PBR right, on one camera. Each pane is
//! framed for its own aspect: the camera the window's whole aspect was fitted to would cut
//! a model off at a half's sides (the half is narrower than the window).
use crate::camera::OrbitCamera;
use crate::frame::{FrameSettings, Shading};
use crate::passes::{FrameStats, Renderer, Target};
use crate::scene::Bounds;
use crate::Result;

/// The tiers of the split view, left to right.
pub const TIERS: [Shading; 2] = [Shading::Phong, Shading::Pbr];

/// `camera` (framed and zoomed for a `full` aspect) for a pane of aspect `pane`: the
/// distance (or orthographic height) scaled by the ratio of the two fits, so a fitted model
/// fits the pane as it fitted the window, and a zoom in or out is kept.
pub fn pane_camera(camera: &OrbitCamera, bounds: &Bounds, full: f32, pane: f32) -> OrbitCamera {
    let mut c = *camera;
    let ratio = c.fit_distance(bounds, pane) / c.fit_distance(bounds, full);
    if ratio.is_finite() && ratio > 0.0 {
        c.distance *= ratio;
    }
    if let Some(h) = &mut c.ortho_height {
        let ratio = OrbitCamera::fit_ortho_height(bounds, pane)
            / OrbitCamera::fit_ortho_height(bounds, full);
        if ratio.is_finite() && ratio > 0.0 {
            *h *= ratio;
        }
    }
    c
}

/// Draws the split view into `target` (`width`×`height`, the window's size times any SSAA
/// factor): each tier in its half, framed for the half. Returns the last pane's stats.
pub fn draw(
    renderer: &mut Renderer,
    settings: &FrameSettings,
    target: &Target,
    width: u32,
    height: u32,
) -> Result<FrameStats> {
    let half = (width / 2).max(1);
    let h = height.max(1);
    let bounds = renderer.scene().bounds;
    let camera = pane_camera(
        &settings.camera,
        &bounds,
        width.max(1) as f32 / h as f32,
        half as f32 / h as f32,
    );
    let mut last = None;
    for (i, shading) in TIERS.into_iter().enumerate() {
        let s = FrameSettings {
            shading,
            camera,
            ..settings.clone()
        };
        let x = i as u32 * half;
        last = Some(renderer.render_viewport(&s, target, [x, 0, half, h])?);
    }
    Ok(last.expect("two panes"))
}
