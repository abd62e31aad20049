//! A glTF file's buffers and images, resolved under the one URI rule of [`crate::load::uri`]
//! (`data:`, percent-encoding, relative inside the model's folder). A buffer must hold its
//! `byteLength`; its bytes are read up to that length only. Images are decoded with the bounds
//! of [`crate::textures`]; one that is missing or broken is reported to the caller, who warns.
use crate::load::uri::{self, Resolved};
use crate::model::material::Texture;
use crate::model::material::TextureOptions;
use std::path::{Path, PathBuf};

/// Largest buffer glview reads (a `byteLength` beyond it is refused before reading).
pub(crate) const MAX_BUFFER_BYTES: usize = 1 << 31;

fn read_prefix(path: &Path, len: usize) -> Result<Vec<u8>, String> {
    let files = crate::load::resources::current();
    match files.kind(path).map_err(|e| e.to_string())? {
        // A file shorter than `len` is read whole: the caller says so.
        crate::load::resources::Kind::File(_) => {
            files.read(path, len as u64).map_err(|e| e.to_string())
        }
        _ => Err("not a regular file".into()),
    }
}

/// Every buffer's bytes, at most `byteLength` long. `blob` is the GLB binary chunk. A buffer
/// with fewer bytes than its `byteLength` (an exporter that wrote the length before it
/// trimmed the data) is read as the bytes there, as three.js reads it, with a warning in
/// `warn`; an accessor reaching past them is refused where it is read.
pub(crate) fn buffers(
    doc: &gltf::Document,
    blob: Option<Vec<u8>>,
    (dir, allow_outside): (&Path, bool),
    warn: &mut dyn FnMut(String),
) -> Result<Vec<Vec<u8>>, String> {
    let mut blob = blob;
    let mut out = Vec::new();
    for b in doc.buffers() {
        let (i, len) = (b.index(), b.length());
        let what = |e: String| match b.source() {
            gltf::buffer::Source::Uri(u) if !u.starts_with("data:") => {
                format!("buffer {i} ({u:?}): {e}")
            }
            _ => format!("buffer {i}: {e}"),
        };
        if len > MAX_BUFFER_BYTES {
            return Err(what(format!(
                "byteLength {len} is more than glview reads ({MAX_BUFFER_BYTES})"
            )));
        }
        let fallback = b
            .extension_value("EXT_meshopt_compression")
            .and_then(|e| e.get("fallback")?.as_bool())
            .unwrap_or(false);
        if fallback && matches!(b.source(), gltf::buffer::Source::Bin) {
            // A placeholder for views decoded from another buffer: never read.
            out.push(Vec::new());
            continue;
        }
        let mut data = match b.source() {
            gltf::buffer::Source::Bin => blob
                .take()
                .ok_or_else(|| what("refers to the GLB binary chunk, which is missing".into()))?,
            gltf::buffer::Source::Uri(u) => {
                match uri::resolve(u, dir, allow_outside).map_err(what)? {
                    Resolved::Data(d) => d,
                    Resolved::File(p) => read_prefix(&p, len).map_err(what)?,
                }
            }
        };
        if data.len() < len {
            warn(what(format!(
                "byteLength is {len} but only {} bytes are there; read as those bytes, as \
                 three.js reads them",
                data.len()
            )));
        }
        data.truncate(len);
        out.push(data);
    }
    Ok(out)
}

/// The bytes of every buffer view compressed with `EXT_meshopt_compression`, decoded.
pub(crate) fn decoded_views(
    doc: &gltf::Document,
    buffers: &[Vec<u8>],
) -> Result<Vec<Option<Vec<u8>>>, String> {
    doc.views()
        .map(|v| {
            v.extension_value("EXT_meshopt_compression")
                .map(|e| {
                    crate::loaders::gltf::meshopt::decode(e, buffers)
                        .map_err(|m| format!("buffer view {}: {m}", v.index()))
                })
                .transpose()
        })
        .collect()
}

/// Decodes image `index`, or says why not (for a warning). Read from the JSON: the crate's
/// `Image::source` unwraps a missing `mimeType` or `uri` (found by the gltf fuzz target).
pub(crate) fn image(
    doc: &gltf::Document,
    index: usize,
    buffers: &[Vec<u8>],
    path: &Path,
    opts: TextureOptions,
) -> Result<Texture, String> {
    let img = doc
        .as_json()
        .images
        .get(index)
        .ok_or_else(|| format!("image {index} does not exist"))?;
    let dir = path.parent().unwrap_or(Path::new("."));
    if let Some(v) = &img.buffer_view {
        let view = doc
            .views()
            .nth(v.value())
            .ok_or_else(|| format!("buffer view {} does not exist", v.value()))?;
        let data = buffers
            .get(view.buffer().index())
            .and_then(|d| d.get(view.offset()..view.offset().checked_add(view.length())?))
            .ok_or_else(|| format!("buffer view {} lies outside its buffer", view.index()))?;
        return crate::textures::decode_bytes(data, path.to_path_buf(), index, opts);
    }
    let u = img.uri.as_deref().ok_or("neither a uri nor a bufferView")?;
    match uri::resolve(u, dir, opts.allow_outside_paths)? {
        Resolved::Data(d) => crate::textures::decode_bytes(&d, path.to_path_buf(), index, opts),
        Resolved::File(p) => crate::textures::decode(p, opts),
    }
}

/// The files outside the glTF file that its buffers and images name (not `data:` URIs, not
/// the GLB's own chunk): the mesh cache checks them as it checks an OBJ's MTL and textures.
pub(crate) fn external_files(
    doc: &gltf::Document,
    dir: &Path,
    opts: TextureOptions,
) -> Vec<PathBuf> {
    let json = doc.as_json();
    let buffer_uris = json.buffers.iter().filter_map(|b| b.uri.as_deref());
    let image_uris = json.images.iter().filter_map(|i| i.uri.as_deref());
    buffer_uris
        .chain(image_uris)
        .filter(|u| !u.get(..5).is_some_and(|p| p.eq_ignore_ascii_case("data:")))
        .filter_map(|u| match uri::resolve(u, dir, opts.allow_outside_paths) {
            Ok(Resolved::File(p)) => Some(p),
            _ => None,
        })
        .collect()
}

/// How an image is named in a warning: its URI when it has a (non-data) one.
pub(crate) fn image_label(doc: &gltf::Document, index: usize) -> String {
    match doc
        .as_json()
        .images
        .get(index)
        .and_then(|i| i.uri.as_deref())
    {
        Some(uri) if !uri.starts_with("data:") => format!("image {index} ({uri:?})"),
        _ => format!("image {index}"),
    }
}
