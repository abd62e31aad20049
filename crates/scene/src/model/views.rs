//! What a file offers to be seen through and picked from, beside its geometry: its cameras
//! (placed by their nodes), its scenes and its material variants (glTF's cameras, scenes and
//! `KHR_materials_variants`; other formats have none). Which scene and variant were drawn is
//! kept too. Selection by `N|NAME` ([`pick`]) is shared by `--camera`, `--scene` and
//! `--variant`, so an unknown name is the same one-line error listing what the file has.
//! Format-neutral and serde, so the mesh cache keeps it with the scene.
use glam::{DVec3, Vec3};
use serde::{Deserialize, Serialize};

/// A camera of the file as placed in the drawn scene.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FileCamera {
    /// The camera's name, else its node's, else `camera N`.
    pub name: String,
    /// Its node's name, which `--camera` also accepts.
    pub node_name: Option<String>,
    /// The eye in the file's coordinates after `--up` (those [`crate::model::Scene::origin`] is in).
    pub eye: [f64; 3],
    /// Unit view direction (the node's -Z) and up (its +Y), in the same frame.
    pub forward: [f64; 3],
    pub up: [f64; 3],
    pub projection: Projection,
}

/// A glTF camera's projection (the specification's fields; angles in radians).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum Projection {
    Perspective {
        yfov: f32,
        aspect_ratio: Option<f32>,
        znear: f32,
        zfar: Option<f32>,
    },
    Orthographic {
        xmag: f32,
        ymag: f32,
        znear: f32,
        zfar: f32,
    },
}

/// The file's cameras, scenes and variants, and which scene and variant were drawn.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Views {
    /// The drawn scene's camera nodes, ordered by camera index then node index (a file
    /// whose cameras each have one node numbers them as its `cameras` array does).
    pub cameras: Vec<FileCamera>,
    /// Every scene's name (`scene N` when unnamed).
    pub scenes: Vec<String>,
    pub scene: usize,
    /// `KHR_materials_variants` names, in the file's order.
    pub variants: Vec<String>,
    pub variant: Option<usize>,
}

/// The index `query` selects among `names`: a number is an index, anything else a name
/// (exact, then ignoring case). The error names the kind and lists what there is.
pub fn pick(kind: &str, names: &[&str], query: &str) -> Result<usize, String> {
    let q = query.trim();
    let found = match q.parse::<usize>() {
        Ok(i) => (i < names.len()).then_some(i),
        Err(_) => names
            .iter()
            .position(|n| *n == q)
            .or_else(|| names.iter().position(|n| n.eq_ignore_ascii_case(q))),
    };
    found.ok_or_else(|| {
        if names.is_empty() {
            return format!("no {kind} {q:?}: the file has no {kind}s");
        }
        let list: Vec<String> = names
            .iter()
            .enumerate()
            .map(|(i, n)| format!("{i} {n:?}"))
            .collect();
        format!("no {kind} {q:?}: the file has {}", list.join(", "))
    })
}

impl Views {
    /// The camera `query` (index, camera name or node name) selects.
    pub fn camera(&self, query: &str) -> Result<&FileCamera, String> {
        self.camera_index(query).map(|i| &self.cameras[i])
    }

    /// The index of the camera `query` (index, camera name or node name) selects.
    pub fn camera_index(&self, query: &str) -> Result<usize, String> {
        let names: Vec<&str> = self.cameras.iter().map(|c| c.name.as_str()).collect();
        let by_node = self.cameras.iter().position(|c| {
            c.node_name.as_deref() == Some(query.trim()) && !names.contains(&query.trim())
        });
        match (pick("camera", &names, query), by_node) {
            (Ok(i), _) | (Err(_), Some(i)) => Ok(i),
            (Err(e), None) => Err(e),
        }
    }

    /// `--check` lines: one per camera, the scenes and the variants (none for a file that
    /// has none of them). The loader adds them to the scene's `--check` lines after the
    /// instance counts; the file's lights (KHR_lights_punctual) add theirs beside them.
    pub(crate) fn check_lines(&self) -> Vec<String> {
        let mut out = Vec::new();
        for (i, c) in self.cameras.iter().enumerate() {
            let what = match c.projection {
                Projection::Perspective {
                    yfov, aspect_ratio, ..
                } => format!(
                    "perspective, yfov {:.2}°, aspect {}",
                    yfov.to_degrees(),
                    aspect_ratio.map_or("of the picture".into(), |a| format!("{a:.4}"))
                ),
                Projection::Orthographic { xmag, ymag, .. } => {
                    format!("orthographic, xmag {xmag} ymag {ymag}")
                }
            };
            let e = c.eye;
            let roll = roll_deg(DVec3::from(c.forward), DVec3::from(c.up));
            let roll = if roll > 0.01 {
                format!(", rolled {roll:.2}° (shown upright)")
            } else {
                String::new()
            };
            out.push(format!(
                "camera {i} {:?}: {what}, eye {:.4},{:.4},{:.4}{roll} (--camera {i})",
                c.name, e[0], e[1], e[2]
            ));
        }
        if self.scenes.len() > 1 {
            out.push(format!(
                "scenes: {} (drawn: {} {:?}; --scene N|NAME)",
                list(&self.scenes),
                self.scene,
                self.scenes.get(self.scene).map_or("", String::as_str)
            ));
        }
        if !self.variants.is_empty() {
            let drawn = self
                .variant
                .and_then(|v| self.variants.get(v))
                .map_or("none (the default materials)".into(), |n| format!("{n:?}"));
            out.push(format!(
                "variants: {} (drawn: {drawn}; --variant N|NAME)",
                list(&self.variants)
            ));
        }
        out
    }
}

fn list(names: &[String]) -> String {
    let items: Vec<String> = names
        .iter()
        .enumerate()
        .map(|(i, n)| format!("{i} {n:?}"))
        .collect();
    items.join(", ")
}

/// The orbit camera's angles looking along `forward` (unit): yaw and pitch in degrees, as
/// `glview_render::camera::OrbitCamera` places its eye at target + distance · (cos p sin y, sin p,
/// cos p cos y), so its view direction is minus that. Looking straight down or up the
/// direction has no yaw: it is taken from `up`, whose horizontal part is the orbit's
/// −sin p · (sin y, cos y), so a plan view keeps the file's orientation.
pub fn yaw_pitch(forward: DVec3, up: DVec3) -> (f32, f32) {
    let d = -forward.normalize_or(DVec3::NEG_Z);
    let pitch = d.y.clamp(-1.0, 1.0).asin();
    let yaw = if d.x.hypot(d.z) > 1e-9 {
        d.x.atan2(d.z)
    } else {
        let s = -pitch.sin().signum();
        (s * up.x).atan2(s * up.z)
    };
    (yaw.to_degrees() as f32, pitch.to_degrees() as f32)
}

/// How far (degrees) the file camera's `up` turns about its view from the orbit camera's
/// at the same angles: the roll an orbit view cannot show.
pub(crate) fn roll_deg(forward: DVec3, up: DVec3) -> f64 {
    let (y, p) = yaw_pitch(forward, up);
    let (y, p) = (f64::from(y).to_radians(), f64::from(p).to_radians());
    let orbit_up = DVec3::new(-p.sin() * y.sin(), p.cos(), -p.sin() * y.cos());
    orbit_up.angle_between(up.normalize_or_zero()).to_degrees()
}

/// The distance from `eye` along `forward` to the point nearest `centre` on the view
/// ray: the orbit's pivot. A centre behind the camera pivots at `fallback` instead.
pub fn pivot_distance(eye: Vec3, forward: Vec3, centre: Vec3, fallback: f32) -> f32 {
    let d = (centre - eye).dot(forward);
    if d.is_finite() && d > fallback * 1e-3 {
        d
    } else {
        fallback
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pick_takes_indices_then_names_and_lists_the_file() {
        let names = ["Front", "Top"];
        assert_eq!(pick("camera", &names, "1"), Ok(1));
        assert_eq!(pick("camera", &names, "top"), Ok(1));
        assert_eq!(pick("camera", &names, "Front"), Ok(0));
        let e = pick("camera", &names, "Side").unwrap_err();
        assert_eq!(e, r#"no camera "Side": the file has 0 "Front", 1 "Top""#);
        assert!(pick("camera", &names, "2").is_err());
        assert_eq!(
            pick("variant", &[], "red").unwrap_err(),
            r#"no variant "red": the file has no variants"#
        );
    }

    /// The angles give back the direction: the orbit's eye lies behind the camera.
    #[test]
    fn yaw_pitch_inverts_the_orbit_direction() {
        for (y, p) in [
            (30.0f64, 25.0f64),
            (-120.0, -40.0),
            (0.0, 89.0),
            (179.0, 0.0),
        ] {
            let (yr, pr) = (y.to_radians(), p.to_radians());
            let dir = DVec3::new(pr.cos() * yr.sin(), pr.sin(), pr.cos() * yr.cos());
            let up = DVec3::new(-pr.sin() * yr.sin(), pr.cos(), -pr.sin() * yr.cos());
            let (yaw, pitch) = yaw_pitch(-dir, up);
            assert!((f64::from(yaw) - y).abs() < 1e-4, "{y} {p}: {yaw}");
            assert!((f64::from(pitch) - p).abs() < 1e-4, "{y} {p}: {pitch}");
            assert!(roll_deg(-dir, up) < 1e-3);
        }
    }

    /// Straight down or up, the yaw comes from the camera's up: a plan view whose top is
    /// +X (or -X from below) stays so, with no roll.
    #[test]
    fn plan_views_take_their_yaw_from_up() {
        for (forward, up) in [(DVec3::NEG_Y, DVec3::X), (DVec3::Y, DVec3::NEG_X)] {
            assert!(roll_deg(forward, up) < 1e-3, "{forward} {up}");
        }
        // A camera rolled 30° about its view direction reports it.
        let r = roll_deg(DVec3::NEG_Z, DVec3::new(0.5, 3f64.sqrt() / 2.0, 0.0));
        assert!((r - 30.0).abs() < 1e-3, "{r}");
    }
}
