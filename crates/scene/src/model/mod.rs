//! The model's parts beside its meshes: materials (and their KHR extensions), texture slots,
//! the meshes a cache hit may leave in its entry, the views a file offers (cameras, scenes,
//! variants) and `--xray`.

pub mod colour;
pub mod lights;
pub mod material;
pub mod material_khr;
pub mod meshes;
pub mod scene;
pub mod texture_slot;
pub mod views;
pub mod xray;

use glam::{DVec3, Vec3};
pub use scene::{Parts, Scene};

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
    /// COLOR_0 is encoded at load (the colour rule, [`crate::model::material::ColourRule`]). Kept beside [`Vertex`] so the vertex layout stays the same.
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

/// The bounding sphere (centre of the box, farthest vertex) the renderer culls a mesh with;
/// the mesh cache stores it for meshes it keeps compact ([`crate::model::meshes::Compact`]).
pub fn bounding_sphere(vertices: &[Vertex]) -> (Vec3, f32) {
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
pub fn terminator_lift(m: &Mesh) -> f64 {
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
    pub fn triangle_count(&self) -> usize {
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
    pub fn empty() -> Self {
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
    pub fn around(points: impl IntoIterator<Item = Vec3>) -> Self {
        let mut b = Bounds::empty();
        for p in points {
            b.include(p);
        }
        b
    }
    /// The smallest box holding both.
    pub fn union(&self, other: &Bounds) -> Bounds {
        Bounds {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }
    pub fn is_empty(&self) -> bool {
        self.min.x > self.max.x
    }
    pub fn center(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }
    /// Radius of the sphere around [`Bounds::center`] that holds the box; never zero, so a
    /// single point or a flat model still gets a usable camera.
    pub fn radius(&self) -> f32 {
        let r = (self.max - self.min).length() * 0.5;
        if r.is_finite() && r > 0.0 {
            r
        } else {
            1.0
        }
    }
    pub fn corners(&self) -> [Vec3; 8] {
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

/// Line segments and points from `l` and `p` statements, glTF `LINES` and `POINTS`, and
/// point clouds (a PLY or OBJ with vertices and no faces), drawn as lines and points.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Wire {
    /// Positions relative to [`Scene::origin`].
    pub positions: Vec<[f32; 3]>,
    pub segments: Vec<[u32; 2]>,
    pub points: Vec<u32>,
    /// Per-position colours (display-encoded, as PLY's), or empty.
    pub colors: Vec<[f32; 3]>,
    /// Per-position unit normals (a cloud's), or empty: points are then drawn unlit.
    pub normals: Vec<[f32; 3]>,
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
    /// most 2,048 points ([`crate::geometry::spacing::mean_nearest`]); None below two distinct points.
    pub fn spacing(&self) -> Option<f64> {
        if self.points.len() == self.positions.len() {
            // A cloud: every position is a point, read in place.
            return crate::geometry::spacing::mean_nearest(&self.positions);
        }
        let pts: Vec<[f32; 3]> = self
            .points
            .iter()
            .filter_map(|&i| self.positions.get(i as usize).copied())
            .collect();
        crate::geometry::spacing::mean_nearest(&pts)
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

// A word in options and in JSON (the options' own trait is the renderer's: `OptionValue`).
impl serde::Serialize for UpAxis {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

impl<'de> serde::Deserialize<'de> for UpAxis {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        let s = <String as serde::Deserialize>::deserialize(d)?;
        s.parse().map_err(serde::de::Error::custom)
    }
}

impl UpAxis {
    /// The proper rotation (no mirroring) taking this axis to +Y; exact (only swaps and
    /// sign changes).
    pub fn rotate(self, p: DVec3) -> DVec3 {
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
