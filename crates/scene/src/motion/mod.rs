//! What moves in a glTF scene: skins, morph targets and animations, read by the loader into
//! a [`Rig`] that poses the scene's meshes at any moment on the CPU. A pose is the loader's
//! own path with other node transforms and morph weights: the still at a moment, a frame of
//! an animated picture and a frame played in the window are made by the same code, so they
//! are the same picture. No GL.
//!
//! Reading and checking: `read` (animations, skins) and `source` (a moving primitive's
//! streams); sampling a channel: `sample`; node transforms and vertices: `pose`.
pub mod channels;
pub mod gpu;
pub(crate) mod materials;
pub(crate) mod pose;
pub(crate) mod rig;
pub(crate) mod sample;
#[cfg(test)]
mod tests;
pub(crate) mod together;

pub(crate) use rig::{Carried, Moving, Part, Plan, WirePart};

use crate::error::Result;
use std::sync::OnceLock;
use {crate::model::Bounds, crate::model::Scene};

/// A moment of one of the file's animations.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Moment {
    /// Index into [`Scene::animations`].
    pub animation: usize,
    /// Seconds from the animation's start (each channel holds its first and last keys
    /// outside its own key times).
    pub seconds: f64,
}

/// One of the file's animations, as `--check` lists it.
#[derive(Clone, Debug, PartialEq)]
pub struct AnimationInfo {
    pub name: String,
    /// The last key time of any of its channels, in seconds.
    pub duration: f64,
    pub channels: usize,
    /// Not one of the file's: every animation of it on one clock (`--animation all`), the
    /// last entry of [`Scene::animations`] where the file has two or more.
    pub together: bool,
    /// The animation played where none is named: every one together where they drive
    /// different nodes (as the glTF Sample Viewer plays them), else the first.
    pub default: bool,
}

/// What a channel moves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Path {
    Translation,
    Rotation,
    Scale,
    Weights,
}

/// The file's skins, morph targets and animations, and the meshes they pose.
#[derive(Debug)]
pub struct Rig {
    animations: Vec<AnimationInfo>,
    /// The scene meshes a pose rewrites (sorted).
    meshes: Vec<usize>,
    /// By animation: the parts it moves (sorted indices into `parts`).
    reached: Vec<Vec<usize>>,
    /// By animation: whether it moves any of `wires`.
    wire_reached: Vec<bool>,
    plan: Plan,
    parts: Vec<Part>,
    wires: Vec<rig::WirePart>,
    /// What the loader re-centred and built the meshes with.
    origin: glam::DVec3,
    up: crate::model::UpAxis,
    default_material: usize,
    creases: crate::geometry::normals::Creases,
    path: std::path::PathBuf,
    /// Bounds of the static pose (the loaded scene's), and of what never moves.
    static_bounds: Bounds,
    still_bounds: Bounds,
    /// Per animation: the bounds of every moment of it (sampled), computed on first use.
    framing: Vec<OnceLock<Bounds>>,
    /// The materials KHR_animation_pointer channels animate.
    materials: materials::Materials,
}

impl Rig {
    /// The indices of the scene meshes a pose rewrites: they have no clusters (their
    /// triangles move) and are uploaded again after each pose.
    pub fn meshes(&self) -> &[usize] {
        &self.meshes
    }

    /// `--check`'s lines: skins (joints), morph targets and animations (channels, duration).
    pub(crate) fn check_lines(&self) -> Vec<String> {
        let mut out = self.plan.check_lines();
        for (i, a) in self.animations.iter().enumerate() {
            out.push(if a.together {
                format!(
                    "animation {i} \"all\": the file's animations together, {} channels, \
                     {:.3} s (--animation all)",
                    a.channels, a.duration
                )
            } else {
                format!(
                    "animation {i} \"{}\": {} channels, {:.3} s",
                    a.name, a.channels, a.duration
                )
            });
        }
        out.extend(self.plan.together_lines());
        out
    }
}

impl Scene {
    /// The file's animations (empty: nothing to play).
    pub fn animations(&self) -> &[AnimationInfo] {
        self.motion.as_deref().map_or(&[], |r| &r.animations)
    }

    /// Whether a pose rewrites mesh `i` (its triangles move: it never gets clusters, and the
    /// renderer draws it whole).
    pub fn mesh_moves(&self, i: usize) -> bool {
        self.motion
            .as_ref()
            .is_some_and(|r| r.meshes.binary_search(&i).is_ok())
    }

    /// Poses the meshes, lines and points at `moment` (None: the static pose, as loaded)
    /// and returns the indices of the meshes whose vertices were rewritten (their vertex
    /// count may change: generated normals are generated again). From one moment to another, a mesh that
    /// neither moment's animation moves is left as it is, and not returned (it would be
    /// rewritten with the same vertices). The bounds become the animation's framing
    /// bounds (the same for every moment of it: a camera fitted to them does not follow
    /// the motion), or the static pose's. Without a rig nothing changes.
    pub fn pose(&mut self, moment: Option<Moment>) -> Result<Vec<usize>> {
        self.pose_except(moment, &[])
    }

    /// As [`Scene::pose`], but the meshes `gpu` (sorted: skinned on the GPU, see
    /// [`gpu`]) are neither posed nor returned: they keep the vertices they had.
    pub fn pose_except(&mut self, moment: Option<Moment>, gpu: &[usize]) -> Result<Vec<usize>> {
        let Some(rig) = self.motion.clone() else {
            return Ok(Vec::new());
        };
        if let Some(m) = moment {
            if m.animation >= rig.animations.len() || !m.seconds.is_finite() {
                return Err(crate::error::Error::model(
                    &rig.path,
                    None,
                    format!(
                        "no moment {:.3} s of animation {} (the file has {})",
                        m.seconds,
                        m.animation,
                        rig.animations.len()
                    ),
                ));
            }
        }
        let wires = rig.placed_wires((self.posed, moment))?;
        let changed = rig.pose_into((self.posed, moment), gpu, &mut self.meshes)?;
        rig.pose_materials(moment, &mut self.materials);
        if let Some(placed) = wires {
            rig.write_wires(placed, &mut self.wire);
        }
        self.bounds = match moment {
            None => rig.static_bounds,
            Some(m) => rig.framing(m.animation),
        };
        self.posed = moment;
        Ok(changed)
    }
}
