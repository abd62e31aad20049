//! `glview export --live`: the lesson page carries glview's renderer (the browser build,
//! `scripts/build_web.sh`), the model's files and the precomputed environment maps, and
//! draws live where the browser can; the turntable's pictures stay as its fallback (not with
//! `--live-only`). Everything is gzipped and base64'd into the page's JSON: the page unpacks
//! it with the browser's `DecompressionStream`, so it still makes no request.
use super::ExportOptions;
use crate::options::Options;
use crate::scene::load::resources::{self, Recording};
use crate::{Error, Result};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Whether the page draws live.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Live {
    /// The turntable's pictures only (the page of before).
    #[default]
    Off,
    /// Live where the browser can, the pictures otherwise.
    Live,
    /// Live only: no pictures (a smaller page; without WebGL it says why and shows nothing).
    Only,
}

/// Where the model's files sit in the page (the teacher's folders are not the page's).
const LESSON: &str = "/lesson";

/// What the page's live script is handed (gzipped, base64): the viewer's options as words,
/// the files by the paths those words name, the maps, the wasm; and the wasm-bindgen glue.
pub(crate) struct Payload {
    pub(crate) data: serde_json::Value,
    pub(crate) glue: String,
    /// Bytes of the wasm, the files (the model's, an environment) and the maps, gzipped
    /// (before base64).
    pub(crate) bytes: [u64; 3],
}

/// The browser build's folder: `web_dir`, else `$GLVIEW_WEB_DIR`, else `web/` beside the
/// executable's folder (`target/web` for `target/debug/glview`).
pub fn web_dir(given: Option<&Path>) -> Result<PathBuf> {
    let dir = given
        .map(Path::to_path_buf)
        .or_else(|| std::env::var_os("GLVIEW_WEB_DIR").map(PathBuf::from))
        .or_else(|| {
            let exe = std::env::current_exe().ok()?;
            Some(exe.parent()?.parent()?.join("web"))
        })
        .unwrap_or_else(|| PathBuf::from("target/web"));
    if dir.join("glview_web_bg.wasm").is_file() && dir.join("no-modules/glview_web.js").is_file() {
        Ok(dir)
    } else {
        Err(Error::Usage(format!(
            "the browser build is not in {} (glview_web_bg.wasm, no-modules/glview_web.js): \
             run `bash scripts/build_web.sh`, or name its folder with --web-dir",
            dir.display()
        )))
    }
}

fn gzip(bytes: &[u8]) -> Vec<u8> {
    let mut e = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::best());
    // Writing to a Vec cannot fail.
    let _ = e.write_all(bytes);
    e.finish().unwrap_or_default()
}

/// The files loading `options`' model reads (the model, its MTL libraries, images, glTF
/// buffers), by their paths under `dir`, the model's folder; and the model as scene bytes
/// where a page can take them instead ([`scene_bytes`]).
fn model_files(
    options: &Options,
    model: &Path,
    renames: &[(&Path, &Path)],
) -> Result<(Files, Prepared)> {
    let before = resources::current();
    let recording = Arc::new(Recording::new(before.clone()));
    resources::set(recording.clone());
    let mut load = crate::session::settings::load_options(options, None);
    // Through the loader itself: a cache hit would read no file.
    load.cache = false;
    let loaded = crate::scene::load::load(model, &load);
    resources::set(before);
    let scene = loaded?;
    Ok((recording.files(), scene_bytes(&load, scene, renames)))
}

/// A model's scene bytes (`cache::to_bytes`: parsed, normals made, levels of detail and
/// clusters built, textures decoded) for a page to read instead of the model's files, so the
/// browser computes none of it; None where the page needs the files: a scene that moves (the
/// mesh cache holds no rig either), one with material variants (`V` loads the file again),
/// load options the cache does not take.
type Prepared = Option<Vec<u8>>;

/// Files by path, with their bytes.
type Files = Vec<(PathBuf, Arc<[u8]>)>;

fn scene_bytes(
    load: &crate::scene::load::options::LoadOptions,
    mut scene: crate::scene::Scene,
    renames: &[(&Path, &Path)],
) -> Prepared {
    if !load.cacheable() || scene.motion.is_some() || !scene.views.variants.is_empty() {
        return None;
    }
    let clusters = crate::scene::lod::clusters::prepare(&mut scene);
    crate::scene::cache::to_bytes((&scene, &clusters), renames).ok()
}

/// Scene bytes are sent where, gzipped, they are at most this many times the model's files
/// gzipped. Measured (gzip -9): the 200k dragon's OBJ 2.22 MB, its scene bytes 5.25 MB
/// (2.4×: normals, levels of detail, clusters); the Avocado's PNGs 8.28 MB, its decoded
/// RGBA8 8.9 MB (1.1×); JPEG-textured models grow far more (DamagedHelmet's 3.7 MB GLB
/// decodes to 84 MB of pixels), and keep their files. docs/web.md has the table.
const SCENE_BYTES_MAX_RATIO: u64 = 3;

/// The page's names for `options`' files (the teacher's folders are not the page's): the
/// model under `/lesson/`, an `--env` HDR under `/environment/`. What [`scene`]'s files
/// are called, and what a view's options name when a page draws them.
pub fn page_paths(options: &Options) -> Options {
    let mut o = options.clone();
    if let Some(model) = &options.load.model {
        o.load.model = Some(Path::new(LESSON).join(model.file_name().unwrap_or_default()));
    }
    if let Some(env) = &options.pbr.env {
        o.pbr.env = Some(Path::new("/environment").join(env.file_name().unwrap_or_default()));
    }
    o
}

/// What a page that draws `options` needs beside the renderer, as JSON: the options as
/// words (with [`page_paths`]), the files those name (the model's, read as the loader reads
/// them, and an environment's) and the precomputed maps, each gzipped and base64'd; and the
/// gzipped bytes of the files and of the maps. An error when the model's files reach outside
/// its folder.
pub fn scene(options: &Options) -> Result<(serde_json::Value, [u64; 2])> {
    let read = |p: &Path| std::fs::read(p).map_err(|e| Error::io(p, e));
    let paged = page_paths(options);
    let mut files = Vec::new();
    let mut model_bytes = None;
    if let (Some(model), Some(page_model)) = (&options.load.model, &paged.load.model) {
        let model = std::path::absolute(model).map_err(|e| Error::io(model, e))?;
        let folder = model.parent().unwrap_or(Path::new("/")).to_path_buf();
        // The loader reads some files by their resolved path (a glTF's buffers, under a
        // folder reached through a link): both spellings of the folder are the model's.
        let resolved = std::fs::canonicalize(&folder).unwrap_or_else(|_| folder.clone());
        let lesson = page_model.parent().unwrap_or(Path::new(LESSON));
        // The scene bytes name the model's folder as the page does.
        let renames = [(folder.as_path(), lesson), (resolved.as_path(), lesson)];
        let (read_files, prepared) = model_files(options, &model, &renames)?;
        model_bytes = prepared;
        for (path, bytes) in read_files {
            let rel = path
                .strip_prefix(&folder)
                .or_else(|_| path.strip_prefix(&resolved));
            let rel = rel.map_err(|_| {
                Error::Usage(format!(
                    "--live: {} reads {}, outside its folder: a page holds the model's folder only",
                    model.display(),
                    path.display()
                ))
            })?;
            files.push((lesson.join(rel), bytes));
        }
    }
    let model_files = files.len();
    if let (Some(env), Some(page_env)) = (&options.pbr.env, &paged.pbr.env) {
        files.push((page_env.clone(), read(env)?.into()));
    }
    // The native maps (read from the disk store, else computed as a native picture would),
    // so the page computes none: the PBR tier's ~5 s in the browser.
    let request = crate::view::settings::env_request(options)?;
    let (maps, _) = crate::render::ibl::load_or_compute(&request)?;
    let maps = gzip(&crate::pbr::store::bytes::encode_half(&maps));
    let b64 = super::page::base64;
    let mut zipped: Vec<(&PathBuf, Vec<u8>)> = files.iter().map(|(p, b)| (p, gzip(b))).collect();
    let of_model: u64 = zipped[..model_files]
        .iter()
        .map(|(_, z)| z.len() as u64)
        .sum();
    // The scene's bytes in place of the model's files, where they are not much larger.
    let prepared = model_bytes
        .map(|b| gzip(&b))
        .filter(|z| (z.len() as u64) <= of_model.saturating_mul(SCENE_BYTES_MAX_RATIO));
    if prepared.is_some() {
        zipped.drain(..model_files);
    }
    let mut bytes = [0, maps.len() as u64];
    let files: Vec<serde_json::Value> = zipped
        .iter()
        .map(|(p, z)| {
            bytes[0] += z.len() as u64;
            serde_json::json!({ "path": p.to_string_lossy().replace('\\', "/"), "gz": b64(z) })
        })
        .collect();
    let mut data = serde_json::json!({
        "words": paged.to_words(),
        "files": files,
        "maps": b64(&maps),
    });
    if let Some(z) = prepared {
        bytes[0] += z.len() as u64;
        data["prepared"] = b64(&z).into();
    }
    Ok((data, bytes))
}

/// The payload of `opts`' page; an error when the browser build is missing or the model's
/// files reach outside its folder.
pub(crate) fn payload(opts: &ExportOptions) -> Result<Payload> {
    let dir = web_dir(opts.web_dir.as_deref())?;
    let read = |p: PathBuf| std::fs::read(&p).map_err(|e| Error::io(&p, e));
    let wasm = gzip(&read(dir.join("glview_web_bg.wasm"))?);
    let glue = String::from_utf8_lossy(&read(dir.join("no-modules/glview_web.js"))?).into_owned();
    let (mut data, [files, maps]) = scene(&opts.options)?;
    data["wasm"] = super::page::base64(&wasm).into();
    data["only"] = (opts.live == Live::Only).into();
    data["slowFrameMs"] = SLOW_FRAME_MS.into();
    Ok(Payload {
        data,
        glue,
        bytes: [wasm.len() as u64, files, maps],
    })
}

/// A live page whose frames take longer than this (the median of the first few, after the
/// first) shows the turntable instead: below 10 frames a second a drag lags the hand
/// visibly, and the pictures turn at once. docs/web.md has the measurement.
pub(crate) const SLOW_FRAME_MS: f64 = 100.0;
