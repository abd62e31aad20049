//! Scene data: meshes, materials and bounds, loaded from OBJ/MTL. No GL, no windowing, so the
//! GPU renderer, the CPU reference renderer and the tests share it.
pub(crate) mod buckets;
pub mod cache;
pub(crate) mod closure;
pub mod clusters;
pub(crate) mod dedup;
pub(crate) mod edges;
pub mod fast;
pub(crate) mod finish;
pub mod formats;
pub mod generate;
pub(crate) mod gltf;
pub(crate) mod gltf_accessor;
pub(crate) mod gltf_buffers;
pub(crate) mod gltf_cameras;
pub(crate) mod gltf_draco;
pub(crate) mod gltf_glb;
pub(crate) mod gltf_graph;
pub(crate) mod gltf_instancing;
pub(crate) mod gltf_khr;
pub(crate) mod gltf_lights;
pub(crate) mod gltf_material;
pub(crate) mod gltf_meshopt;
pub(crate) mod gltf_modes;
pub(crate) mod gltf_pointer;
pub(crate) mod gltf_primitive;
pub(crate) mod gltf_quirks;
pub(crate) mod gltf_scenes;
pub(crate) mod gltf_specgloss;
pub(crate) mod gltf_variants;
pub mod load;
pub(crate) mod lod;
pub mod material;
pub mod material_khr;
pub(crate) mod material_report;
pub mod meshes;
pub mod motion;
pub(crate) mod mtl;
pub(crate) mod mtl_mapping;
pub mod normals;
pub mod obj;
pub(crate) mod ply;
pub mod profile;
pub(crate) mod quirks;
pub mod reorder;
pub(crate) mod repair;
pub mod report;
pub(crate) mod spacing;
pub(crate) mod stl;
pub(crate) mod tangents;
pub(crate) mod texture;
pub(crate) mod texture_avif;
pub(crate) mod texture_ktx2;
pub(crate) mod texture_path;
pub mod texture_slot;
pub(crate) mod tokens;
pub(crate) mod triangulate;
pub(crate) mod uri;
pub mod views;
pub(crate) mod xray;

use glam::{DVec3, Vec3};
pub use gltf_instancing::Instancing;
pub use load::{load, load_prepared, LoadOptions, ProgressFn};
pub use material::{Material, Texture};
pub use meshes::Meshes;

/// One interleaved vertex as uploaded to the vertex buffer.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Vertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    pub uv: [f32; 2],
}

/// A triangle mesh with one material. Positions are relative to [`Scene::origin`].
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    pub name: String,
    pub vertices: Vec<Vertex>,
    pub indices: Vec<u32>,
    pub material: usize,
    pub has_uv: bool,
    /// Whether some or all normals were generated rather than read from the file.
    pub generated_normals: usize,
    /// Per-vertex colours (`v x y z r g b`), multiplying the diffuse colour; empty when the
    /// file has none. Display (sRGB-encoded) values whatever the format: glTF's linear
    /// COLOR_0 is encoded at load (the colour rule, [`material::ColourRule`]). Kept beside [`Vertex`] so the vertex layout stays the same.
    pub colors: Vec<[f32; 3]>,
    /// The alpha of those colours (glTF COLOR_0 as VEC4), one per vertex, multiplying the base
    /// colour's alpha (MASK and BLEND); empty when the file has none or every one is 1.
    pub color_alpha: Vec<f32>,
    /// Second UV set (glTF TEXCOORD_1), one per vertex; empty when the file has none.
    pub uv1: Vec<[f32; 2]>,
    /// Tangents as the file supplies them (glTF TANGENT: xyz, w = bitangent sign), one per
    /// vertex; empty when absent (MikkTSpace ones are generated at upload where needed).
    pub tangents: Vec<[f32; 4]>,
}

/// An image file's bytes (PNG, JPEG, WebP, BMP, TGA, GIF, HDR, KTX2, AVIF) decoded as a
/// texture is, within the same bounds (refused before decoding when too large, downscaled
/// past the texture budget): width, height and RGBA8 pixels, top row first. For tools and
/// the fuzz targets; a model's textures are decoded by its loader.
pub fn decode_image(bytes: &[u8]) -> std::result::Result<(u32, u32, Vec<u8>), String> {
    let t = texture::decode_bytes(
        bytes,
        std::path::PathBuf::from("<bytes>"),
        0,
        material::TextureOptions::default(),
    )?;
    Ok((t.width, t.height, t.rgba))
}

/// The bounding sphere (centre of the box, farthest vertex) the renderer culls a mesh with;
/// the mesh cache stores it for meshes it keeps compact ([`meshes::Compact`]).
pub(crate) fn bounding_sphere(vertices: &[Vertex]) -> (Vec3, f32) {
    let center = Bounds::around(vertices.iter().map(|v| Vec3::from(v.position))).center();
    let radius = vertices
        .iter()
        .map(|v| (Vec3::from(v.position) - center).length())
        .fold(0.0f32, f32::max);
    (center, radius)
}

/// The shadow-terminator lift of a mesh: a quarter of its mean edge length (f64, local
/// units). The GPU (`shadow.glsl`) and the reference raise shadow lookups by it where the
/// shading normal faces a light that the facet itself faces away from.
pub(crate) fn terminator_lift(m: &Mesh) -> f64 {
    use rayon::prelude::*;
    let p = |i: u32| glam::DVec3::from(m.vertices[i as usize].position.map(f64::from));
    // In parallel slices of 64k triangles: 20 ms of a cached 2M-triangle picture's ~190 on
    // one thread. A mesh of one slice sums in the same order as before.
    let (sum, n) = m
        .indices
        .par_chunks(3 << 16)
        .map(|slice| {
            slice.chunks_exact(3).fold((0.0, 0usize), |(s, n), t| {
                let (a, b, c) = (p(t[0]), p(t[1]), p(t[2]));
                (s + a.distance(b) + b.distance(c) + c.distance(a), n + 3)
            })
        })
        .reduce(|| (0.0, 0), |(s, n), (t, k)| (s + t, n + k));
    if n == 0 {
        0.0
    } else {
        0.25 * sum / n as f64
    }
}

impl Mesh {
    pub(crate) fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }
}

/// The bounding box (lo, hi) of `points` in file coordinates and the centre every loader
/// re-centres its positions on in f64 before rounding to f32 (the origin when there are no
/// points).
pub(crate) fn extent_and_origin(points: impl IntoIterator<Item = DVec3>) -> (DVec3, DVec3, DVec3) {
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for p in points {
        lo = lo.min(p);
        hi = hi.max(p);
    }
    let origin = if lo.x <= hi.x {
        (lo + hi) * 0.5
    } else {
        DVec3::ZERO
    };
    (lo, hi, origin)
}

/// Axis-aligned bounds.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Bounds {
    pub min: Vec3,
    pub max: Vec3,
}

impl Bounds {
    pub(crate) fn empty() -> Self {
        Bounds {
            min: Vec3::splat(f32::INFINITY),
            max: Vec3::splat(f32::NEG_INFINITY),
        }
    }
    pub fn include(&mut self, p: Vec3) {
        self.min = self.min.min(p);
        self.max = self.max.max(p);
    }
    /// The box around `points` (empty without any).
    pub(crate) fn around(points: impl IntoIterator<Item = Vec3>) -> Self {
        let mut b = Bounds::empty();
        for p in points {
            b.include(p);
        }
        b
    }
    /// The smallest box holding both.
    pub(crate) fn union(&self, other: &Bounds) -> Bounds {
        Bounds {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }
    pub(crate) fn is_empty(&self) -> bool {
        self.min.x > self.max.x
    }
    pub fn center(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }
    /// Radius of the sphere around [`Bounds::center`] that holds the box; never zero, so a
    /// single point or a flat model still gets a usable camera.
    pub(crate) fn radius(&self) -> f32 {
        let r = (self.max - self.min).length() * 0.5;
        if r.is_finite() && r > 0.0 {
            r
        } else {
            1.0
        }
    }
    pub(crate) fn corners(&self) -> [Vec3; 8] {
        let (a, b) = (self.min, self.max);
        [
            Vec3::new(a.x, a.y, a.z),
            Vec3::new(b.x, a.y, a.z),
            Vec3::new(a.x, b.y, a.z),
            Vec3::new(b.x, b.y, a.z),
            Vec3::new(a.x, a.y, b.z),
            Vec3::new(b.x, a.y, b.z),
            Vec3::new(a.x, b.y, b.z),
            Vec3::new(b.x, b.y, b.z),
        ]
    }
}

/// A problem the loader worked around; printed as one warning line each.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Warning {
    pub file: std::path::PathBuf,
    pub line: Option<usize>,
    pub message: String,
}

impl Warning {
    /// A warning about the whole file (no line).
    pub(crate) fn of(file: &std::path::Path, message: String) -> Warning {
        Warning {
            file: file.to_path_buf(),
            line: None,
            message,
        }
    }
}

impl std::fmt::Display for Warning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.file.display())?;
        if let Some(l) = self.line {
            write!(f, ":{l}")?;
        }
        write!(f, ": {}", self.message)
    }
}

/// A loaded model, re-centred: vertex positions are relative to `origin` (the bounding-box
/// centre in file coordinates, kept in f64) so that far-from-origin models keep f32 precision.
#[derive(Clone, Debug)]
pub struct Scene {
    pub name: String,
    /// Here, or (after a mesh cache hit) partly still in the entry until first used.
    pub meshes: Meshes,
    pub materials: Vec<Material>,
    /// Bounds in local (re-centred) coordinates.
    pub bounds: Bounds,
    /// Where local (0,0,0) is in the file's coordinates.
    pub origin: DVec3,
    /// Bounds in the file's coordinates, exactly (f64): (min, max).
    pub file_bounds: (DVec3, DVec3),
    /// Other files the scene was built from (MTL libraries, textures): the mesh cache
    /// checks them too.
    pub dependencies: Vec<std::path::PathBuf>,
    pub warnings: Vec<Warning>,
    /// Lines (`l`) and points (`p`), in local coordinates; not triangles.
    pub wire: Wire,
    /// For `--check`: every texture statement of the MTL and what happens to it.
    pub(crate) maps: Vec<String>,
    /// glTF `EXT_mesh_gpu_instancing` nodes, whose instances `meshes` holds written out
    /// ([`Instancing`]); empty for other formats. The mesh cache keeps it.
    pub instancing: Vec<Instancing>,
    /// The file's cameras, scenes and material variants (glTF's; empty for other formats).
    pub views: views::Views,
    /// The lights the file places (glTF KHR_lights_punctual), in file coordinates; they
    /// replace the default light kit ([`crate::light::LightOpt::File`]).
    pub lights: Vec<crate::light::FileLight>,
    /// glTF skins, morph targets and animations (None: nothing moves); shared by the
    /// scene's clones, which pose their own meshes.
    pub motion: Option<std::sync::Arc<motion::Rig>>,
    /// The moment [`Scene::pose`] posed the meshes at (None: the static pose, as loaded).
    pub posed: Option<motion::Moment>,
}

/// Line segments and points from `l` and `p` statements, glTF `LINES` and `POINTS`, and
/// point clouds (a PLY or OBJ with vertices and no faces), drawn as lines and points.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Wire {
    /// Positions relative to [`Scene::origin`].
    pub positions: Vec<[f32; 3]>,
    pub segments: Vec<[u32; 2]>,
    pub points: Vec<u32>,
    /// Per-position colours (display-encoded, as PLY's), or empty.
    pub(crate) colors: Vec<[f32; 3]>,
    /// Per-position unit normals (a cloud's), or empty: points are then drawn unlit.
    pub(crate) normals: Vec<[f32; 3]>,
}

impl Wire {
    pub fn is_empty(&self) -> bool {
        self.segments.is_empty() && self.points.is_empty()
    }

    /// Every position is a point and there are no lines: a point cloud.
    pub(crate) fn is_cloud(&self) -> bool {
        self.segments.is_empty() && !self.points.is_empty()
    }

    /// The mean distance from a point to its nearest distinct neighbour, over a sample of at
    /// most 2,048 points ([`spacing::mean_nearest`]); None below two distinct points.
    pub(crate) fn spacing(&self) -> Option<f64> {
        if self.points.len() == self.positions.len() {
            // A cloud: every position is a point, read in place.
            return spacing::mean_nearest(&self.positions);
        }
        let pts: Vec<[f32; 3]> = self
            .points
            .iter()
            .filter_map(|&i| self.positions.get(i as usize).copied())
            .collect();
        spacing::mean_nearest(&pts)
    }
}

/// Which file axis points up; the model is rotated at load so it becomes +Y.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum UpAxis {
    #[default]
    PosY,
    NegY,
    PosX,
    NegX,
    PosZ,
    NegZ,
}

impl std::str::FromStr for UpAxis {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        Ok(match s.to_ascii_uppercase().as_str() {
            "+Y" | "Y" => UpAxis::PosY,
            "-Y" => UpAxis::NegY,
            "+X" | "X" => UpAxis::PosX,
            "-X" => UpAxis::NegX,
            "+Z" | "Z" => UpAxis::PosZ,
            "-Z" => UpAxis::NegZ,
            _ => {
                return Err(format!(
                    "up axis must be one of +Y -Y +X -X +Z -Z, not {s:?}"
                ))
            }
        })
    }
}

impl std::fmt::Display for UpAxis {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            UpAxis::PosY => "+Y",
            UpAxis::NegY => "-Y",
            UpAxis::PosX => "+X",
            UpAxis::NegX => "-X",
            UpAxis::PosZ => "+Z",
            UpAxis::NegZ => "-Z",
        })
    }
}

crate::word_value!(UpAxis, "an axis: +Y, -Y, +X, -X, +Z or -Z");

impl UpAxis {
    /// The proper rotation (no mirroring) taking this axis to +Y; exact (only swaps and
    /// sign changes).
    pub(crate) fn rotate(self, p: DVec3) -> DVec3 {
        match self {
            UpAxis::PosY => p,
            UpAxis::NegY => DVec3::new(p.x, -p.y, -p.z),
            UpAxis::PosX => DVec3::new(-p.y, p.x, p.z),
            UpAxis::NegX => DVec3::new(p.y, -p.x, p.z),
            UpAxis::PosZ => DVec3::new(p.x, p.z, -p.y),
            UpAxis::NegZ => DVec3::new(p.x, -p.z, p.y),
        }
    }
}

impl Scene {
    /// A model file's scene name: its file name without the extension.
    pub(crate) fn name_of(path: &std::path::Path) -> String {
        path.file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "model".into())
    }

    /// A scene built in code (tests, generators): local coordinates are file coordinates.
    pub fn from_meshes(name: &str, meshes: Vec<Mesh>, materials: Vec<Material>) -> Scene {
        let bounds = Bounds::around(
            meshes
                .iter()
                .flat_map(|m| &m.vertices)
                .map(|v| Vec3::from(v.position)),
        );
        Scene {
            name: name.into(),
            meshes: meshes.into(),
            materials,
            bounds,
            origin: DVec3::ZERO,
            file_bounds: (bounds.min.as_dvec3(), bounds.max.as_dvec3()),
            dependencies: Vec::new(),
            warnings: Vec::new(),
            wire: Wire::default(),
            maps: Vec::new(),
            instancing: Vec::new(),
            views: Default::default(),
            lights: Vec::new(),
            motion: None,
            posed: None,
        }
    }

    /// Counted without reading meshes still in a cache entry.
    pub fn triangle_count(&self) -> usize {
        self.meshes.counts().0
    }
    pub fn vertex_count(&self) -> usize {
        self.meshes.counts().1
    }
    /// Converts a point in file coordinates to local coordinates, in f64 before rounding.
    pub fn to_local(&self, p: DVec3) -> Vec3 {
        (p - self.origin).as_vec3()
    }
}
