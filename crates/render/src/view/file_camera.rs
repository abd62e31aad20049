//! `--camera`: a file's camera as the camera options that show the same view (yaw, pitch,
//! distance, target, fov, near, ortho), so a picture through it is a picture of options
//! and orbiting from it moves those options like any view (no second camera model).
//!
//! The orbit pivots on the point of the view ray nearest the model's centre. The file's
//! aspect ratio is not the picture's: yfov is kept and the picture's aspect is used, as the
//! glTF Sample Viewer does when a file gives none (when it gives one the Sample Viewer
//! stretches the picture to it; glview never stretches nor letterboxes). An orthographic
//! camera keeps its height 2·ymag the same way. zfar is not used: the far plane is fitted
//! to the model like every view's. The orbit camera has no roll: a file camera's roll
//! about its view direction is dropped (the picture stays upright; `--check` says so).
use crate::error::{Error, Result};
use crate::options::{Camera, Options, Ortho};
use crate::scene::model::views::{pivot_distance, yaw_pitch, Projection};
use crate::scene::Scene;
use glam::DVec3;

/// `args`' camera options with `--camera` replaced by what it stands for (unchanged
/// without it); an unknown camera is an error naming the file and listing its cameras.
pub(crate) fn resolve(args: &Options, scene: &Scene) -> Result<Camera> {
    let mut c = args.camera.clone();
    let Some(query) = c.view.take() else {
        return Ok(c);
    };
    let file = args.load.model.clone().unwrap_or_else(|| "built-in".into());
    let cam = scene
        .views
        .camera(&query)
        .map_err(|e| Error::model(file, None, e))?;
    let eye = DVec3::from_array(cam.eye);
    let forward = DVec3::from_array(cam.forward);
    let centre = scene.origin + scene.bounds.center().as_dvec3();
    let local_eye = scene.to_local(eye);
    let d = pivot_distance(
        local_eye,
        forward.as_vec3(),
        scene.to_local(centre),
        scene.bounds.radius(),
    );
    (c.yaw, c.pitch) = yaw_pitch(forward, DVec3::from_array(cam.up));
    c.distance = Some(d);
    c.target = Some((eye + forward * f64::from(d)).to_array());
    match cam.projection {
        Projection::Perspective { yfov, znear, .. } => {
            c.fov = yfov.to_degrees().clamp(1e-3, 179.0);
            c.near = Some(znear);
            c.ortho = None;
        }
        Projection::Orthographic { ymag, .. } => {
            c.ortho = Some(Ortho::Height(2.0 * ymag));
            c.near = None;
        }
    }
    Ok(c)
}
