//! The integration tests, one binary: one build and link instead of one per file, and one
//! process whose in-process GPU fixture (`common::render`) keeps one headless context and
//! program cache for every render that needs no special environment. `tests/leaks.rs` stays
//! a separate binary because it judges its own process's resident memory.
mod analytic;
mod antialiasing;
mod api;
mod bad_input;
mod batch;
mod bloom;
mod cache;
mod common;
mod compare;
mod conformance;
mod culling;
mod fast_parse;
mod fuzz_format_regressions;
mod fuzz_regressions;
mod gltf_alpha;
mod gltf_draw;
mod gltf_extensions;
mod gltf_materials;
mod gltf_sidedness;
mod gpu_vs_reference;
mod hostile_formats;
mod lighting;
mod loading;
mod models_committed;
mod parity;
mod pbr;
mod post_copy;
mod precision;
mod quirky_formats;
mod reference;
mod reference_materials;
mod repro;
mod serve;
mod serve_client;
mod shaders;
mod shadows;
mod stats;
mod stress;
mod terminator;
mod texture_upload;
mod translucency;
mod window;
mod wire_colors;
mod xvfb;
