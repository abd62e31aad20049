//! The built-in scene (the glass holder): the committed output of [`crate::generate`],
//! compiled in so every front end — the command line, Python, the browser build and the
//! renderer's own tests — draws it without a file.
use crate::error::Result;
use crate::{LoadOptions, Scene};
use std::path::Path;

pub const OBJ: &str = include_str!("../../../models/glass_holder.obj");
pub const MTL: &str = include_str!("../../../models/glass_holder.mtl");

/// Loads the built-in scene with these options.
pub fn load(opts: &LoadOptions) -> Result<Scene> {
    crate::loaders::obj::load_embedded(
        Path::new("glass_holder.obj"),
        OBJ.as_bytes(),
        MTL.as_bytes(),
        opts,
    )
}
