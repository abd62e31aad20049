//! Geometry every loader shares: generated normals and tangents, polygons triangulated, duplicate
//! faces dropped, feature edges, whether a mesh is closed, point-cloud spacing, and a counting
//! sort by small keys.

pub mod buckets;
pub mod closure;
pub mod dedup;
pub mod edges;
pub mod normals;
pub mod prim;
pub mod spacing;
pub mod tangents;
pub mod triangulate;
