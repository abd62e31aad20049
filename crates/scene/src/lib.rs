//! glview's scene: the model (meshes, materials, bounds, cameras, lights, motion), loaded from
//! OBJ/MTL, STL, PLY and glTF by a loader per format (`loaders/`), with the geometry every
//! format shares (`geometry/`), levels of detail and clusters (`lod/`), the mesh cache
//! (`cache/`: on disk in native builds, and scene bytes for the browser) and the motion runtime (`motion/`). No GL, no window, no clock:
//! the renderer, the CPU reference renderer, the browser build and the tests share it. Files
//! are read through [`load::resources::Resources`]; threads and the disk cache are the `native` feature's.
// Developer docs: links to private items resolve with --document-private-items.
#![allow(rustdoc::private_intra_doc_links)]
pub mod builtin;
pub mod cache;
pub mod error;
pub mod generate;
pub mod geometry;
pub mod load;
pub mod loaders;
pub mod lod;
pub mod model;
pub mod motion;
pub mod profile;
pub mod report;
pub mod textures;

pub use load::options::{LoadOptions, ProgressFn};
pub use load::{load, load_prepared};
pub use loaders::gltf::instancing::Instancing;
pub use model::material::{Material, Texture};
pub use model::meshes::Meshes;
pub use model::{
    bounding_sphere, terminator_lift, Bounds, Mesh, Scene, UpAxis, Vertex, Warning, Wire,
};
pub use textures::decode_image;
