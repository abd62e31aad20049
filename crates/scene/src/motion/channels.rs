//! What the motion runtime plays: channels (a node's translation, rotation, scale or morph
//! weights over time, or a material factor's), animations of them, and skins. Read from a
//! file by its loader (glTF: `loaders::gltf::animations`).
use crate::motion::materials::MaterialProperty;
use crate::motion::sample::Keys;
use crate::motion::{AnimationInfo, Path};
use glam::DMat4;

/// Joints of one skin.
pub(crate) const MAX_JOINTS: usize = 1 << 16;

/// One channel: a node's translation, rotation, scale or morph weights over time.
#[derive(Clone, Debug)]
pub(crate) struct Channel {
    pub(crate) node: usize,
    pub(crate) path: Path,
    /// Shared with the merged animation that plays every one together ([`crate::motion::together`]).
    pub(crate) keys: std::sync::Arc<Keys>,
}

/// One material factor over time (a KHR_animation_pointer channel).
#[derive(Clone, Debug)]
pub(crate) struct MaterialKeys {
    /// The glTF material (the scene's material of the same index).
    pub(crate) material: usize,
    pub(crate) property: MaterialProperty,
    pub(crate) keys: std::sync::Arc<Keys>,
}

#[derive(Clone, Debug)]
pub(crate) struct Animation {
    pub(crate) info: AnimationInfo,
    pub(crate) channels: Vec<Channel>,
    pub(crate) materials: Vec<MaterialKeys>,
}

/// A skin glview applies: world transforms of `joints` times `inverse_bind` make the
/// joint matrices (the skinned node's own transform is ignored, as glTF asks).
#[derive(Clone, Debug)]
pub(crate) struct Skin {
    pub(crate) joints: Vec<usize>,
    pub(crate) inverse_bind: Vec<DMat4>,
}
