//! glview's renderer: a frame is a list of passes (`passes/`: shadow, background, the Phong
//! and PBR tiers, translucency, edges, post-processing) over glow, on every GL glview
//! draws with (GL 2.1, GL ES 3.0, GL 3.3; WebGL 1 and 2 in the browser); `gpu/` is the one
//! layer with `unsafe` and GL objects (RAII), `shader/` assembles one body per stage for each
//! GLSL dialect, `pbr/` computes the image-based light, `frame/` is what a frame is drawn
//! with. Beside it, the view model every front end shares: `options` (one typed value per
//! picture), `keys`, the orbit `camera`, `light`s, and `view` (a view's state and the frame
//! settings its options describe). No window, no context, no file, no clock: the native
//! library and the browser build give it a `glow::Context`, bytes and the time.
// Developer docs: links to private items resolve with --document-private-items.
#![allow(rustdoc::private_intra_doc_links)]
#![deny(unsafe_code)]

pub mod camera;
pub mod clock;
pub mod error;
pub mod frame;
#[allow(unsafe_code)]
pub mod gpu;
pub mod grid;
pub mod image;
pub mod keys;
pub mod light;
pub mod options;
pub mod passes;
pub mod pbr;
pub mod shader;
pub mod shading;
pub mod stereo;
pub mod view;

pub use error::{Error, Result};
pub use glview_scene as scene;
pub use options::Options;
