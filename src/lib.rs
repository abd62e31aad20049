//! glview: a legacy-compatible OpenGL model viewer as a library (OBJ/MTL, STL, PLY, glTF):
//! options, loading, rendering on every context, comparisons and the Python/serving API.
//! The command line, the window and the tools are the `glview-cli` crate.
//!
//! Dependencies point one way: `api`/`headless` → `render` → {`scene`, `camera`, `light`,
//! `shader`, `gpu`} → `platform`. Only `gpu` and `platform` contain `unsafe`.
#![deny(unsafe_code)]

pub mod anim_out;
pub mod camera;
pub mod compare;
pub mod error;
pub mod export;
pub mod frame;
pub mod grid;
pub mod image_out;
pub mod keys;
pub mod light;
pub mod metrics;
pub mod options;
pub mod pbr;
pub mod repro;
pub mod shading;

#[allow(unsafe_code)]
pub mod gpu;
#[allow(unsafe_code)]
pub mod platform;
pub mod reference;
pub mod render;
pub mod shader;

pub mod api;
pub mod headless;
pub mod progress;
pub mod session;

pub use error::{Error, Result};
/// The scene crate: the model, its loaders, geometry, levels of detail and motion.
pub use glview_scene as scene;
pub use options::Options;
