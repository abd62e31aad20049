//! Large meshes drawn in parts: triangles reordered for locality, cut into clusters with bounds
//! and normal cones, and simplified into levels of detail chosen by screen-space error.

pub mod clusters;
pub mod levels;
pub mod reorder;
#[cfg(feature = "native")]
pub mod simplify;
