//! glTF 2.0 (`.gltf` with its buffers, `.glb`) into the same [`Scene`]: the JSON is parsed by
//! the `gltf` crate, but buffers and images are resolved here under the folder rule every
//! format shares ([`crate::load::uri`]), accessors are read with their sizes checked first
//! ([`crate::loaders::gltf::accessor`]) and the node graph is walked without recursion, refusing cycles
//! ([`crate::loaders::gltf::graph`]). Node transforms are applied in f64 as each primitive is read
//! ([`crate::loaders::gltf::primitive`]) and the scene re-centred like OBJ; lines and points go to
//! [`Scene::wire`]. A missing or broken image is a warning.

pub mod accessor;
pub mod animations;
pub mod buffers;
pub mod cameras;
pub mod draco;
pub mod glb;
pub mod graph;
pub mod instancing;
pub mod khr;
pub mod lights;
pub mod material;
#[cfg(feature = "native")]
pub mod meshopt;
#[cfg(not(feature = "native"))]
pub mod meshopt {
    //! EXT_meshopt_compression needs meshoptimizer (C++), which the browser build has not:
    //! a scene there arrives decoded (the mesh cache's entry).
    pub(crate) fn decode(_: &serde_json::Value, _: &[Vec<u8>]) -> Result<Vec<u8>, String> {
        Err("EXT_meshopt_compression is decoded in native builds only (meshoptimizer)".into())
    }
}
pub mod modes;
pub mod plan;
pub mod pointer;
pub mod primitive;
pub mod quirks;
pub mod scenes;
pub mod slots;
pub mod sources;
pub mod specgloss;
pub mod variants;
use crate::error::{Error, Result};
use crate::load::options::LoadOptions;
use crate::loaders::gltf::accessor::MAX_ELEMENTS;
use crate::loaders::gltf::primitive::{Instance, Primitives, Recorded};
use crate::model::scene::Parts;
use glam::DMat4;
use gltf::mesh::Semantic;
use std::path::Path;
use std::sync::Arc;
use {
    crate::model::material::Texture, crate::model::Bounds, crate::model::Scene,
    crate::model::Warning,
};

/// Extensions whose absence would make glview draw a required extension wrongly are refused;
/// these are the ones it implements.
pub(crate) const SUPPORTED_EXTENSIONS: &[&str] = &[
    "KHR_mesh_quantization",
    "KHR_materials_emissive_strength",
    "EXT_meshopt_compression",
    "KHR_draco_mesh_compression",
    "EXT_texture_webp",
    "EXT_texture_avif",
    "KHR_texture_basisu",
    "EXT_mesh_gpu_instancing",
    "KHR_materials_unlit",
    "KHR_texture_transform",
    "KHR_materials_clearcoat",
    "KHR_materials_sheen",
    "KHR_materials_specular",
    "KHR_materials_ior",
    "KHR_materials_transmission",
    "KHR_materials_volume",
    "KHR_materials_pbrSpecularGlossiness",
    "KHR_materials_iridescence",
    "KHR_materials_anisotropy",
    "KHR_materials_variants",
    "KHR_lights_punctual",
    // Pointers to nodes' translation, rotation, scale and weights; others are warned of
    // (`gltf_pointer`).
    "KHR_animation_pointer",
];

/// Decoded images stop here (bytes of RGBA8); later images are skipped with a warning.
const MAX_TEXTURE_BYTES: usize = 512 << 20;

/// The error for a file that cannot be loaded: gltf's validation errors can span lines; the
/// user gets one.
fn invalid(path: &Path, m: String) -> Error {
    Error::model(path, None, m.replace('\n', "; "))
}

/// Loads glTF or GLB bytes as if they were the file `path` (buffers and images are looked up
/// beside it).
pub(crate) fn load_gltf_bytes(path: &Path, bytes: &[u8], opts: &LoadOptions) -> Result<Scene> {
    let bad = |m: String| invalid(path, m);
    let mut warnings = Vec::new();
    let Parsed {
        doc,
        blob,
        pointed,
        images: notes,
    } = parse_document(path, bytes, &mut warnings)?;
    let dir = path.parent().unwrap_or(Path::new("."));
    let buffers = read_buffers(&doc, blob, path, opts, &mut warnings)?;
    let dependencies = crate::loaders::gltf::buffers::external_files(&doc, dir, opts.textures);

    let images = decode_images(&doc, (&buffers.buffers, &notes), path, opts, &mut warnings);
    let mut materials = Vec::new();
    for m in doc.materials() {
        let mut image = |i: usize| images.get(i).cloned().flatten();
        materials.push(crate::loaders::gltf::material::material(
            &doc, &m, &mut image,
        ));
        for message in crate::loaders::gltf::khr::problems(&doc, &m) {
            warnings.push(Warning {
                file: path.to_path_buf(),
                line: None,
                message,
            });
        }
    }
    let default_index = materials.len();
    materials.push(crate::model::material::Material::default());

    let (scene, mut views) = crate::loaders::gltf::scenes::choose(&doc, opts).map_err(bad)?;
    let nodes = crate::loaders::gltf::graph::nodes(&doc, &scene).map_err(bad)?;
    let mut camera_problems = Vec::new();
    views.cameras =
        crate::loaders::gltf::cameras::cameras(&doc, &nodes, opts.up, &mut camera_problems);
    warnings.extend(camera_problems.into_iter().map(|message| Warning {
        file: path.to_path_buf(),
        line: None,
        message,
    }));
    let mut warn = |message| warnings.push(Warning::of(path, message));
    let plan = crate::loaders::gltf::plan::plan(&doc, &nodes, (&buffers, &pointed), &mut warn);
    let instances = crate::loaders::gltf::graph::instances(&doc, &nodes);
    let (instances, mut maps, runs) =
        crate::loaders::gltf::instancing::expand(&doc, instances, &buffers).map_err(bad)?;
    maps.extend(views.check_lines());
    check_instanced_total(&instances, &buffers.draco).map_err(bad)?;
    let mut read = Primitives::default();
    // Where each entry's primitives start in `read.prims`, for the instanced nodes' record.
    let mut prim_start = Vec::with_capacity(instances.len() + 1);
    for (e, (node, mesh, world)) in instances.iter().enumerate() {
        prim_start.push(read.prims.len());
        let instance = Instance::new(*node, *world, opts.up, &buffers, path)
            .with_variant(views.variant)
            .with_moving(plan.moving(*node, mesh.index()))
            .with_instance(crate::loaders::gltf::instancing::instance_of(&runs, e));
        instance
            .read_mesh(mesh, &mut read, &mut warnings)
            .map_err(bad)?;
    }
    prim_start.push(read.prims.len());
    let (lo, hi, origin) = crate::model::extent_and_origin(
        read.prims
            .iter()
            .flat_map(|p| &p.positions)
            .chain(&read.wire_pts)
            .copied(),
    );
    let lights = crate::loaders::gltf::lights::read_into(
        &doc,
        &nodes,
        (opts.up, origin),
        path,
        &mut warnings,
    );
    let sources = std::mem::take(&mut read.sources);
    let (meshes, mut bounds, mesh_of, parts) =
        build_meshes(read.prims, sources, (origin, default_index), opts);
    let wire_parts = std::mem::take(&mut read.wire_sources);
    let mut wire = read.wire;
    for q in &read.wire_pts {
        let l = (*q - origin).as_vec3();
        bounds.include(l);
        wire.positions.push(l.into());
    }
    if meshes.is_empty() && wire.is_empty() {
        return Err(bad("no triangles in the file".into()));
    }
    let entry_meshes: Vec<Vec<usize>> = prim_start
        .windows(2)
        .map(|w| mesh_of[w[0]..w[1]].iter().flatten().copied().collect())
        .collect();
    let instancing = records(&runs, &entry_meshes, &plan, (opts.up, origin));
    let built = crate::motion::rig::Built {
        origin,
        default_material: default_index,
        opts,
        path,
    };
    let motion = rig_of(
        plan,
        (parts, wire_parts),
        (&meshes, &wire, &materials),
        built,
        &mut maps,
    );
    let parts = Parts {
        meshes: meshes.into(),
        materials,
        bounds,
        origin,
        file_bounds: (lo, hi),
        dependencies,
        warnings,
        wire,
        maps,
        instancing,
        views,
        lights,
        motion,
    };
    Ok(Scene::new(Scene::name_of(path), parts))
}

/// The bytes of every buffer, of the views EXT_meshopt_compression decoded, and of the
/// accessors Draco streams filled.
fn read_buffers(
    doc: &gltf::Document,
    blob: Option<Vec<u8>>,
    path: &Path,
    opts: &LoadOptions,
    warnings: &mut Vec<Warning>,
) -> Result<accessor::Buffers> {
    let bad = |m: String| invalid(path, m);
    let dir = path.parent().unwrap_or(Path::new("."));
    let mut warn = |m| warnings.push(Warning::of(path, m));
    let buffers = crate::loaders::gltf::buffers::buffers(
        doc,
        blob,
        (dir, opts.textures.allow_outside_paths),
        &mut warn,
    )
    .map_err(bad)?;
    let views = crate::loaders::gltf::buffers::decoded_views(doc, &buffers).map_err(bad)?;
    let (draco, miscounted) =
        crate::loaders::gltf::draco::decode_all(doc, &buffers).map_err(bad)?;
    warnings.extend(miscounted.map(|m| Warning::of(path, m)));
    Ok(accessor::Buffers {
        buffers,
        views,
        draco,
    })
}

/// The scene's record of each instanced node's `runs` (its copies are the meshes
/// `entry_meshes` of its entries). An animated node's copies move apart from any relative
/// matrices recorded now: they are drawn as they are, not as instances of the first (a
/// node merely morphed by its static weights keeps them: its copies never move).
fn records(
    runs: &[crate::loaders::gltf::instancing::Run],
    entry_meshes: &[Vec<usize>],
    plan: &crate::motion::Plan,
    (up, origin): (crate::model::UpAxis, glam::DVec3),
) -> Vec<crate::loaders::gltf::instancing::Instancing> {
    runs.iter()
        .map(|r| crate::loaders::gltf::instancing::record(r, entry_meshes, up, origin))
        .map(|mut r| {
            if plan.animated(r.node) {
                r.relative.clear();
            }
            r
        })
        .collect()
}

/// The scene's rig (None: nothing can move) over `meshes` and the lines and points, its
/// `--check` lines added to `maps`.
fn rig_of(
    plan: crate::motion::Plan,
    (parts, wires): (Vec<crate::motion::Part>, Vec<Recorded>),
    drawn: (
        &[crate::model::Mesh],
        &crate::model::Wire,
        &[crate::model::material::Material],
    ),
    built: crate::motion::rig::Built,
    maps: &mut Vec<String>,
) -> Option<Arc<crate::motion::Rig>> {
    if plan.is_empty() {
        return None;
    }
    let wires = wires
        .into_iter()
        .map(|r| crate::motion::WirePart {
            first: r.at,
            by: r.by,
        })
        .collect();
    let rig = crate::motion::Rig::new(plan, (parts, wires), drawn, built);
    maps.extend(rig.check_lines());
    Some(Arc::new(rig))
}

/// The triangle primitives made meshes re-centred on `origin` (None where a primitive has
/// too few indices), their bounds, and the moving ones' parts.
#[allow(clippy::type_complexity)]
fn build_meshes(
    prims: Vec<crate::geometry::prim::Prim>,
    sources: Vec<Recorded>,
    (origin, default_index): (glam::DVec3, usize),
    opts: &LoadOptions,
) -> (
    Vec<crate::model::Mesh>,
    Bounds,
    Vec<Option<usize>>,
    Vec<crate::motion::Part>,
) {
    let mut bounds = Bounds::empty();
    let mut meshes = Vec::new();
    // The scene mesh each primitive became (None: too few indices).
    let mut mesh_of = Vec::with_capacity(prims.len());
    let mut sources = sources.into_iter().peekable();
    let mut parts = Vec::new();
    for (pi, p) in prims.into_iter().enumerate() {
        if p.indices.len() < 3 {
            mesh_of.push(None);
            continue;
        }
        while sources.peek().is_some_and(|s| s.at < pi) {
            sources.next();
        }
        if let Some(r) = sources.next_if(|s| s.at == pi) {
            parts.push(crate::motion::Part {
                mesh: meshes.len(),
                by: r.by,
                prim: p.clone(),
            });
        }
        mesh_of.push(Some(meshes.len()));
        let mesh = p.into_mesh(origin, default_index, opts);
        for v in &mesh.vertices {
            bounds.include(v.position.into());
        }
        meshes.push(mesh);
    }
    (meshes, bounds, mesh_of, parts)
}

/// A parsed document, the GLB's binary chunk, the KHR_animation_pointer channels that
/// animate materials (taken out of the document: [`crate::loaders::gltf::pointer`]) and the images
/// the quirk repairs added in place of missing ones ([`crate::loaders::gltf::quirks`]).
struct Parsed {
    doc: gltf::Document,
    blob: Option<Vec<u8>>,
    pointed: Vec<crate::loaders::gltf::pointer::MaterialChannel>,
    images: ImageNotes,
}

/// What the parse says of the file's images: placeholders the quirk repairs added for
/// textures without an image (absent, without a warning of their own), and AVIF images
/// with the image their texture falls back to where they do not decode.
#[derive(Default)]
struct ImageNotes {
    placeholders: Vec<usize>,
    fallbacks: Vec<(usize, usize)>,
}

/// The parsed document ([`Parsed`]), after the checks the `gltf` crate skips or does too
/// late: required extensions (refused unless supported; unsupported used ones are a
/// warning) and attribute accessor indices (its validator would panic); real exporters'
/// quirks are repaired with a warning each ([`crate::loaders::gltf::quirks`]).
fn parse_document(path: &Path, bytes: &[u8], warnings: &mut Vec<Warning>) -> Result<Parsed> {
    let bad = |m: String| invalid(path, m);
    let mut warn = |m: String| warnings.push(Warning::of(path, m));
    let (text, blob) = if bytes.starts_with(b"glTF") {
        let glb = crate::loaders::gltf::glb::split(bytes, &mut warn)
            .map_err(|e| bad(format!("not a valid glTF file: {e}")))?;
        (glb.json, glb.bin)
    } else {
        (bytes, None)
    };
    let mut found = crate::loaders::gltf::quirks::Found::default();
    let (mut json, pointed) = json_of(text, &mut found, &mut warn)
        .map_err(|e| bad(format!("not a valid glTF file: {e}")))?;
    if let Some(v) = &json.asset.min_version {
        check_min_version(v).map_err(bad)?;
    }
    for x in &json.extensions_required {
        if !SUPPORTED_EXTENSIONS.contains(&x.as_str()) {
            return Err(bad(format!(
                "requires glTF extension {x}, which glview does not support"
            )));
        }
    }
    for x in &json.extensions_used {
        if !SUPPORTED_EXTENSIONS.contains(&x.as_str()) {
            warn(format!("uses glTF extension {x}, which glview ignores"));
        }
    }
    // The crate's validator indexes the accessors with the POSITION index before it has
    // checked that index (a panic, found by the gltf fuzz target).
    for (mi, m) in json.meshes.iter().enumerate() {
        for (pi, p) in m.primitives.iter().enumerate() {
            if let Some(a) = p
                .attributes
                .values()
                .find(|a| a.value() >= json.accessors.len())
            {
                return Err(bad(format!(
                    "mesh {mi} primitive {pi}: accessor {} does not exist",
                    a.value()
                )));
            }
        }
    }
    // Checked above; the crate's validator refuses any it does not know itself.
    json.extensions_required.clear();
    let (fallbacks, no_avif) =
        prefer_extension_sources(&mut json, crate::textures::avif::available());
    if let Some(m) = no_avif {
        warn(m);
    }
    crate::loaders::gltf::quirks::tolerate(&mut json, &mut found);
    validate(&mut json, &mut found).map_err(|e| bad(format!("not a valid glTF file: {e}")))?;
    for w in found.warnings() {
        warn(w);
    }
    Ok(Parsed {
        doc: gltf::Document::from_json_without_validation(json),
        blob: blob.map(<[u8]>::to_vec),
        pointed,
        images: ImageNotes {
            placeholders: found.placeholders,
            fallbacks,
        },
    })
}

/// The JSON `text` as the crate's document, and the material pointer channels taken out
/// of it. Read straight into the crate's types unless it names KHR_animation_pointer or
/// those types refuse it; then read as a JSON value first, the pointer channels rewritten
/// ([`crate::loaders::gltf::pointer`]) and the quirks the types cannot hold repaired, which costs a
/// second parse only for those files.
fn json_of(
    text: &[u8],
    found: &mut crate::loaders::gltf::quirks::Found,
    warn: &mut dyn FnMut(String),
) -> std::result::Result<
    (
        gltf::json::Root,
        Vec<crate::loaders::gltf::pointer::MaterialChannel>,
    ),
    String,
> {
    let pointers = crate::loaders::gltf::pointer::mentions(text);
    let direct = if pointers {
        None
    } else {
        match serde_json::from_slice(text) {
            Ok(json) => return Ok((json, Vec::new())),
            Err(e) => Some(e.to_string()),
        }
    };
    let first_error = |e: serde_json::Error| direct.clone().unwrap_or_else(|| e.to_string());
    let mut value: serde_json::Value = serde_json::from_slice(text).map_err(first_error)?;
    let (materials, dropped) = if pointers {
        crate::loaders::gltf::pointer::rewrite(&mut value)
    } else {
        Default::default()
    };
    for d in &dropped {
        warn(d.message());
    }
    crate::loaders::gltf::quirks::tolerate_value(&mut value, found);
    let json = serde_json::from_value(value).map_err(first_error)?;
    Ok((json, materials))
}

/// Texture extensions naming an image format glview decodes, in the order it prefers them.
const IMAGE_EXTENSIONS: &[&str] = &["KHR_texture_basisu", "EXT_texture_avif", "EXT_texture_webp"];
const AVIF: &str = "EXT_texture_avif";

/// A texture's image from the first extension in [`IMAGE_EXTENSIONS`] it has, in place of its
/// own `source`, as the extensions ask of a reader that supports them (the own `source` is
/// the fallback for readers that do not, and may be absent when the extension is required).
/// An extension `source` that names no image is ignored: the texture's own is used. AVIF
/// only where it can be decoded (`avif`); else the texture keeps its own source, which the
/// returned warning says. Also returned: each AVIF image chosen with its texture's own
/// image, used where the AVIF image does not decode.
fn prefer_extension_sources(
    json: &mut gltf::json::Root,
    avif: bool,
) -> (Vec<(usize, usize)>, Option<String>) {
    let images = json.images.len();
    let mut fallbacks = Vec::new();
    let mut skipped = 0;
    for t in &mut json.textures {
        let others = t.extensions.as_ref().map(|e| &e.others);
        let source = IMAGE_EXTENSIONS.iter().find_map(|x| {
            let i = others?.get(*x)?.get("source")?.as_u64()?;
            let i = u32::try_from(i).ok().filter(|&i| (i as usize) < images)?;
            if *x == AVIF && !avif {
                skipped += 1;
                return None;
            }
            Some((i, *x))
        });
        if let Some((i, x)) = source {
            let own = t.source.value();
            if x == AVIF && own < images && own != i as usize {
                fallbacks.push((i as usize, own));
            }
            t.source = gltf::json::Index::new(i);
        }
    }
    let warning = (skipped > 0).then(|| {
        format!(
            "{AVIF}: {skipped} texture(s) have AVIF images, which need libdav1d (Debian: \
             libdav1d6), not found here; their fallback images are drawn"
        )
    });
    (fallbacks, warning)
}

/// The crate's validation (every index in range: its accessors would panic otherwise), less
/// one rule it adds to the specification (an accessor without a `bufferView` is valid:
/// zeros, which sparse values or an extension such as KHR_draco_mesh_compression replace,
/// where the crate demands one unless the accessor is sparse) and with real exporters'
/// quirks repaired ([`crate::loaders::gltf::quirks::repair`]); what is left is refused.
fn validate(
    json: &mut gltf::json::Root,
    found: &mut crate::loaders::gltf::quirks::Found,
) -> std::result::Result<(), gltf::Error> {
    use crate::loaders::gltf::quirks::{repair, Repair};
    use gltf::json::validation::{Error as E, Validate};
    // A repair can reveal what it hid (a child past the nodes behind a missing scene); each
    // round fixes at least one error, and a file has only so many.
    for _ in 0..8 {
        let mut errors = Vec::new();
        json.validate(json, gltf::json::Path::new, &mut |path, error| {
            let path = path();
            let p = path.as_str();
            let view_missing = matches!(error, E::Missing)
                && p.starts_with("accessors[")
                && p.ends_with("].bufferView");
            if !view_missing {
                errors.push((path, error));
            }
        });
        let mut fixed = false;
        let mut left = Vec::new();
        for (path, error) in errors {
            match repair(json, path.as_str(), &error, found) {
                Some(Repair::Fixed) => fixed = true,
                Some(Repair::Ignored) => {}
                None => left.push((path, error)),
            }
        }
        if !left.is_empty() {
            return Err(gltf::Error::Validation(left));
        }
        if !fixed {
            return Ok(());
        }
    }
    Ok(())
}

/// `asset.minVersion` ("major.minor"): a file that needs a later glTF than 2.0 is refused, as
/// the specification asks of a 2.0 reader (it may rely on what 2.0 does not define).
fn check_min_version(v: &str) -> std::result::Result<(), String> {
    let parsed = v
        .split_once('.')
        .and_then(|(a, b)| Some((a.parse::<u32>().ok()?, b.parse::<u32>().ok()?)));
    match parsed {
        Some(needed) if needed <= (2, 0) => Ok(()),
        Some(_) => Err(format!(
            "needs glTF {v} (asset.minVersion), this reader supports 2.0"
        )),
        None => Err(format!(
            "asset.minVersion \"{v}\" is not a version (major.minor)"
        )),
    }
}

/// Meshes can be instanced by many nodes: the total is bounded before anything is read.
/// An accessor a Draco stream filled counts what the stream decoded (`draco`).
fn check_instanced_total(
    instances: &[(usize, gltf::Mesh, DMat4)],
    draco: &crate::loaders::gltf::draco::Decoded,
) -> std::result::Result<(), String> {
    let count = |a: gltf::Accessor| match draco.get(&a.index()) {
        Some(d) => d.len() / (a.data_type().size() * a.dimensions().multiplicity()),
        None => a.count(),
    };
    let mut total = 0usize;
    for (node, mesh, _) in instances {
        for p in mesh.primitives() {
            let n = p.get(&Semantic::Positions).map_or(0, count);
            let k = p.indices().map_or(0, count);
            total = total.saturating_add(n.max(k / 3));
            if total > MAX_ELEMENTS {
                return Err(format!(
                    "node {node}: the scene instances more than {MAX_ELEMENTS} vertices; \
                     refused before reading them"
                ));
            }
        }
    }
    Ok(())
}

/// Every image a material uses, decoded in parallel (a few at a time, so the texture budget is
/// checked between batches and at most one batch overshoots it); a missing, broken or
/// over-budget image is a warning and None. The placeholders the quirk repairs added for
/// textures without an image are None without a warning of their own; an AVIF image that
/// does not decode is its texture's fallback image, with a warning ([`ImageNotes`]).
fn decode_images(
    doc: &gltf::Document,
    (buffers, notes): (&[Vec<u8>], &ImageNotes),
    path: &Path,
    opts: &LoadOptions,
    warnings: &mut Vec<Warning>,
) -> Vec<Option<Arc<Texture>>> {
    use rayon::prelude::*;
    let mut used = vec![false; doc.images().len()];
    for m in doc.materials() {
        let pbr = m.pbr_metallic_roughness();
        let slots = [
            pbr.base_color_texture().map(|t| t.texture()),
            pbr.metallic_roughness_texture().map(|t| t.texture()),
            m.normal_texture().map(|t| t.texture()),
            m.occlusion_texture().map(|t| t.texture()),
            m.emissive_texture().map(|t| t.texture()),
        ];
        let extensions = crate::loaders::gltf::khr::used_images(doc, &m);
        for i in slots
            .into_iter()
            .flatten()
            .map(|t| t.source().index())
            .chain(extensions)
        {
            if let Some(u) = used.get_mut(i) {
                *u = true;
            }
        }
    }
    let wanted: Vec<usize> = (0..used.len())
        .filter(|&i| used[i] && !notes.placeholders.contains(&i))
        .collect();
    let mut out: Vec<Option<Arc<Texture>>> = vec![None; used.len()];
    let mut texture_bytes = 0usize;
    for batch in wanted.chunks(rayon::current_num_threads().max(1)) {
        let decoded: Vec<(usize, std::result::Result<Texture, String>)> = if texture_bytes
            > MAX_TEXTURE_BYTES
        {
            batch
                .iter()
                .map(|&i| {
                    let e = format!("over the {} MiB texture budget", MAX_TEXTURE_BYTES >> 20);
                    (i, Err(e))
                })
                .collect()
        } else {
            batch
                .par_iter()
                .map(|&i| {
                    (
                        i,
                        crate::loaders::gltf::buffers::image(doc, i, buffers, path, opts.textures),
                    )
                })
                .collect()
        };
        for (i, t) in decoded {
            let label = crate::loaders::gltf::buffers::image_label(doc, i);
            match t {
                Ok(t) => {
                    texture_bytes += t.rgba.len();
                    out[i] = Some(Arc::new(t));
                }
                Err(e) => {
                    let fallback = notes.fallbacks.iter().find(|f| f.0 == i).map(|f| f.1);
                    let decoded = fallback.map(|j| {
                        (
                            j,
                            crate::loaders::gltf::buffers::image(
                                doc,
                                j,
                                buffers,
                                path,
                                opts.textures,
                            ),
                        )
                    });
                    let message = match decoded {
                        Some((j, Ok(t))) => {
                            texture_bytes += t.rgba.len();
                            out[i] = Some(Arc::new(t));
                            format!("{label}: {e}; its texture's fallback image {j} is drawn")
                        }
                        _ => format!("{label}: {e}; materials using it render without it"),
                    };
                    warnings.push(Warning::of(path, message));
                }
            }
        }
    }
    out
}
