//! glview in the browser: the scene and render crates compiled to wasm32-unknown-unknown,
//! drawing on a canvas's WebGL 2 context (GLSL ES 3.00, both tiers) or WebGL 1 (GLSL ES 1.00,
//! the legacy tier), through glow. The page (web/page/, plain JS, no bundler) makes a
//! [`Viewer`](web::Viewer) with the options of `glview -o` as words and the canvas, draws,
//! and sends it the window's key names. Built by `scripts/build_web.sh` into `target/web/`.
//! On the host the crate is empty (its dependencies are the browser's).
#[cfg(target_arch = "wasm32")]
pub mod web;
