//! The one router from a model file to a [`Scene`]: the mesh cache first, then the loader
//! of the file's format (by its name: OBJ, STL, PLY, glTF, the first three optionally
//! gzipped). Each format's loader sits beside the others (`obj`, `formats` for STL and PLY,
//! `gltf`) and none dispatches to another; what every loader is asked is [`LoadOptions`].

pub mod finish;
pub mod options;
pub mod resources;
pub mod uri;
use crate::error::{Error, Result};
use crate::loaders::formats::{self, format_of, Format, MAX_STREAM};
use crate::model::Scene;
pub use options::{LoadOptions, ProgressFn};
use std::io::Read;
use std::path::Path;

/// Reads a file, refusing what is not a regular file (directories, devices, FIFOs would hang).
pub(crate) fn read_regular_file(path: &Path) -> Result<Vec<u8>> {
    let files = resources::current();
    match files.kind(path).map_err(|e| Error::io(path, e))? {
        resources::Kind::Dir => Err(Error::model(path, None, "is a directory, not an OBJ file")),
        resources::Kind::Other => Err(Error::model(path, None, "is not a regular file")),
        resources::Kind::File(_) => files.read(path, u64::MAX).map_err(|e| Error::io(path, e)),
    }
}

/// Loads a model file: OBJ (with its MTL libraries and diffuse textures), STL, PLY or glTF,
/// the first three optionally gzipped (`.gz`); the format comes from the file name. Large
/// files of every format go through the mesh cache, whose hit reads only the entry. Large
/// meshes come back reordered when the cache took part (see [`load_prepared`]).
pub fn load(path: &Path, opts: &LoadOptions) -> Result<Scene> {
    load_prepared(path, opts).map(|(scene, _)| scene)
}

/// As [`load`], with the meshes' clusters and their levels of detail when the mesh cache took
/// part: a hit stores them and a miss builds them ([`crate::lod::clusters::prepare`], which
/// reorders the indices) to write the entry; otherwise None, and the caller prepares the
/// scene itself.
pub fn load_prepared(
    path: &Path,
    opts: &LoadOptions,
) -> Result<(Scene, Option<Vec<Option<crate::lod::clusters::Clusters>>>)> {
    crate::profile::begin(0);
    let size = match resources::current().kind(path) {
        Ok(resources::Kind::File(n)) => n,
        _ => 0,
    };
    // Looked up whatever the size (a miss is one failed open): a small file with large
    // images has an entry too. Native builds only: the cache is a folder on disk.
    let cached = cfg!(feature = "native") && opts.cache && opts.cacheable();
    #[cfg(feature = "native")]
    if cached {
        if let Some((scene, clusters)) = crate::cache::lookup(path, opts.textures) {
            log::debug!("{}: loaded from the mesh cache", path.display());
            crate::profile::set_bytes(size);
            crate::profile::end(true);
            return Ok((scene, Some(clusters)));
        }
    }
    let mut content = None;
    let scene = load_uncached(path, opts, &mut content)?;
    // The entry holds everything a format gives (colours, both UV sets, tangents, lines,
    // points, decoded textures), so every format is cached.
    // A scene that moves is not cached: the entry holds meshes, not the rig that poses them.
    #[cfg(not(feature = "native"))]
    {
        let _ = (cached, size, content);
        Ok((scene, None))
    }
    #[cfg(feature = "native")]
    cache_entry(path, opts, (size, content), scene)
}

/// Writes the mesh cache's entry of a scene just loaded where it is worth one, and returns
/// the scene with the clusters built for it.
#[cfg(feature = "native")]
fn cache_entry(
    path: &Path,
    opts: &LoadOptions,
    (size, content): (u64, Option<Vec<u8>>),
    mut scene: Scene,
) -> Result<(Scene, Option<Vec<Option<crate::lod::clusters::Clusters>>>)> {
    let cached = opts.cache && opts.cacheable();
    if !(cached && scene.motion.is_none() && crate::cache::worth_an_entry(size, &scene)) {
        return Ok((scene, None));
    }
    // The levels of detail are built here, once, for the entry and for this picture alike
    // (a picture that would draw them builds them anyway: the renderer's `build_levels`,
    // so the cache never changes a picture); only writing the entry is left to another
    // thread, which `cache::wait_for_writes` (the CLI's exit, the next lookup) waits for.
    let clusters = crate::lod::clusters::prepare(&mut scene);
    if clusters.iter().flatten().next().is_none() {
        crate::cache::put(path, content.as_deref(), opts.textures, (&scene, &clusters));
    } else {
        let (path, textures) = (path.to_path_buf(), opts.textures);
        let (copy, levels) = (scene.clone(), clusters.clone());
        crate::cache::put_later(move || {
            crate::cache::put(&path, content.as_deref(), textures, (&copy, &levels));
        });
    }
    Ok((scene, Some(clusters)))
}

/// [`load`] without the cache; `obj_bytes` receives a plain OBJ's bytes (for the entry's
/// content hash: other formats are not hashed, so their entries never pass a verified hit).
fn load_uncached(
    path: &Path,
    opts: &LoadOptions,
    obj_bytes: &mut Option<Vec<u8>>,
) -> Result<Scene> {
    let (format, gz) = formats::format_of(path);
    let bytes = read_regular_file(path)?;
    crate::profile::set_bytes(bytes.len() as u64);
    crate::profile::mark(crate::profile::Stage::Read);
    if gz || format != Format::Obj {
        return load_bytes(path, &bytes, opts);
    }
    let scene = crate::loaders::obj::load_bytes(path, &bytes, opts)?;
    *obj_bytes = Some(bytes);
    Ok(scene)
}

/// Loads model bytes as if they were the file `path`: the format from its name, gzipped
/// when it ends in `.gz` (the fuzz targets and [`load`] come through here).
pub fn load_bytes(path: &Path, bytes: &[u8], opts: &LoadOptions) -> Result<Scene> {
    let (format, gz) = format_of(path);
    // Streams stop at MAX_STREAM inflated bytes: more than the element limits need, and it
    // bounds the time a bomb of text the parsers skip (STL junk tokens) can take.
    let gz_reader =
        || std::io::BufReader::new(flate2::read::GzDecoder::new(bytes).take(MAX_STREAM));
    match (format, gz) {
        (Format::Gltf, false) => crate::loaders::gltf::load_gltf_bytes(path, bytes, opts),
        (Format::Gltf, true) => Err(Error::model(path, None, "gzipped glTF is not supported")),
        (Format::Stl, false) => formats::load_stl(path, bytes, Some(bytes.len() as u64), opts),
        (Format::Stl, true) => formats::load_stl(path, gz_reader(), None, opts),
        (Format::Ply, false) => formats::load_ply(path, bytes, Some(bytes.len() as u64), opts),
        (Format::Ply, true) => formats::load_ply(path, gz_reader(), None, opts),
        (Format::Obj, false) => crate::loaders::obj::load_bytes(path, bytes, opts),
        (Format::Obj, true) => {
            crate::loaders::obj::load_bytes(path, &formats::gunzip(path, bytes)?, opts)
        }
    }
}
