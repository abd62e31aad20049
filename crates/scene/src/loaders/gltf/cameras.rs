//! glTF cameras as the drawn scene places them: each node with a `camera` gives a
//! [`FileCamera`] at its world transform, in the coordinates the meshes are in (after
//! `--up`, before re-centring on [`crate::model::Scene::origin`]). A camera looks down its node's
//! -Z with +Y up; the node's scale does not change the view (the direction is normalised),
//! as the specification asks. A camera with values no projection can be made of (a zero
//! or non-finite field of view, magnification or near plane) is skipped with a warning.
use crate::model::views::{FileCamera, Projection};
use crate::model::UpAxis;
use glam::{DMat4, DVec3, DVec4};

/// The cameras among `nodes` (index, world transform), ordered by camera then node index;
/// a warning for each camera that cannot be used.
pub(crate) fn cameras(
    doc: &gltf::Document,
    nodes: &[(usize, DMat4)],
    up: UpAxis,
    warnings: &mut Vec<String>,
) -> Vec<FileCamera> {
    let all: Vec<gltf::Node> = doc.nodes().collect();
    let mut found: Vec<(usize, usize, DMat4)> = nodes
        .iter()
        .filter_map(|&(i, world)| Some((all.get(i)?.camera()?.index(), i, world)))
        .collect();
    found.sort_by_key(|&(c, n, _)| (c, n));
    let mut out = Vec::new();
    for (ci, ni, world) in found {
        let (Some(camera), Some(node)) = (doc.cameras().nth(ci), all.get(ni)) else {
            continue;
        };
        let projection = match projection(&camera) {
            Ok(p) => p,
            Err(e) => {
                warnings.push(format!("camera {ci} (node {ni}): {e}; not offered"));
                continue;
            }
        };
        let rotate = |v: DVec4| up.rotate((world * v).truncate());
        let eye = rotate(DVec4::W);
        let forward = rotate(DVec4::new(0.0, 0.0, -1.0, 0.0)).normalize_or_zero();
        let up_dir = rotate(DVec4::Y).normalize_or_zero();
        if !eye.is_finite() || forward == DVec3::ZERO || up_dir == DVec3::ZERO {
            warnings.push(format!(
                "camera {ci} (node {ni}): its node's transform has no view direction (a zero \
                 scale); not offered"
            ));
            continue;
        }
        let name = camera
            .name()
            .or(node.name())
            .map_or_else(|| format!("camera {ci}"), str::to_string);
        out.push(FileCamera {
            name,
            node_name: node.name().map(str::to_string),
            eye: eye.to_array(),
            forward: forward.to_array(),
            up: up_dir.to_array(),
            projection,
        });
    }
    out
}

/// The camera's projection, its values checked.
fn projection(camera: &gltf::Camera) -> Result<Projection, String> {
    let positive = |what: &str, v: f32| {
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(format!("{what} {v} is not a positive number"))
        }
    };
    Ok(match camera.projection() {
        gltf::camera::Projection::Perspective(p) => {
            let yfov = positive("yfov", p.yfov())?;
            if yfov >= std::f32::consts::PI {
                return Err(format!("yfov {yfov} is not below π"));
            }
            Projection::Perspective {
                yfov,
                aspect_ratio: p.aspect_ratio().filter(|a| a.is_finite() && *a > 0.0),
                znear: positive("znear", p.znear())?,
                zfar: p.zfar().filter(|f| f.is_finite() && *f > p.znear()),
            }
        }
        gltf::camera::Projection::Orthographic(o) => {
            // Negative magnifications mirror the picture; glview's views do not.
            Projection::Orthographic {
                xmag: positive("xmag", o.xmag().abs())?,
                ymag: positive("ymag", o.ymag().abs())?,
                znear: o.znear(),
                zfar: o.zfar(),
            }
        }
    })
}
