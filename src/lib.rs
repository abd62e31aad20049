//! glview: a legacy-compatible OpenGL OBJ/MTL viewer.
//!
//! Dependencies point one way: `app`/`headless` → `render` → {`scene`, `camera`, `light`,
//! `shader`, `gpu`} → `platform`. Only `gpu` and `platform` contain `unsafe`.
#![deny(unsafe_code)]

pub mod camera;
pub mod cli;
pub mod compare;
pub mod error;
pub mod frame;
pub mod image_out;
pub mod keys;
pub mod light;
pub mod metrics;
pub mod options;
pub mod pbr;
pub mod repro;
pub mod scene;
pub mod shading;

#[allow(unsafe_code)]
pub mod gpu;
#[allow(unsafe_code)]
pub mod platform;
pub mod reference;
pub mod render;
pub mod shader;

pub mod api;
pub mod app;
pub mod batch;
pub mod headless;
pub mod picture;
pub mod run;

pub use error::{Error, Result};
pub use options::Options;
