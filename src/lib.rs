//! glview: a legacy-compatible OpenGL model viewer as a library (OBJ/MTL, STL, PLY, glTF):
//! options, loading, rendering on every context, comparisons and the Python/serving API.
//! The command line, the window and the tools are the `glview-cli` crate.
//!
//! This is the native library: contexts (EGL and OSMesa on Linux, WGL on Windows), files,
//! threads and the clock, around the renderer (`glview-render`, re-exported below) and the
//! scene (`glview-scene`).
//! Dependencies point one way: `api`/`headless`/`session` → the renderer → the scene;
//! `platform` makes the contexts the renderer draws in. Only the renderer's `gpu` and
//! `platform` contain `unsafe`.
#![deny(unsafe_code)]

pub mod anim_out;
pub mod compare;
pub mod export;
mod ibl_cache;
pub mod image_out;
pub mod metrics;
pub mod repro;

#[allow(unsafe_code)]
pub mod platform;
pub mod reference;

pub mod api;
pub mod headless;
pub mod progress;
pub mod session;

pub use glview_render::passes as render;
/// The renderer and the view model (`glview-render`), under the paths they had before the
/// crate split.
pub use glview_render::{
    camera, clock, error, frame, gpu, grid, image, keys, light, options, pbr, shader, shading,
    stereo, view,
};
pub use glview_render::{Error, Options, Result};
/// The scene crate: the model, its loaders, geometry, levels of detail and motion.
pub use glview_scene as scene;

/// What the native library gives the renderer once, before its first frame: the clock its
/// `--stats` milliseconds are in and the disk cache of precomputed environment maps.
/// [`headless::Headless::new`] and [`session::Session::new`] call it; a front end that makes
/// its own context (the cli's window) calls it before drawing.
pub fn native_hooks() {
    static START: std::sync::OnceLock<std::time::Instant> = std::sync::OnceLock::new();
    // Every session and context calls this; the hooks are given once.
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        START.get_or_init(std::time::Instant::now);
        clock::set(|| START.get().map_or(0.0, |s| s.elapsed().as_secs_f64() * 1e3));
        pbr::store::set_store(std::sync::Arc::new(ibl_cache::DiskMaps));
    });
}
