//! One loader per format, side by side: `obj/` (with MTL), `stl`, `ply` (their shared building
//! in `formats`), `gltf/`; `load::load` picks one by the file's name.

pub mod formats;
pub mod gltf;
pub mod obj;
pub mod ply;
pub mod stl;
pub mod tokens;
