//! A scene's meshes, which a mesh cache hit may leave in the entry until something needs
//! them. A hit whose large meshes have whole-mesh levels of detail reads, for each such mesh,
//! only a compact copy of those levels (their vertices and remapped indices: a few MB of an
//! 85 MB entry) and leaves the full arrays, and the groups' levels, in the entry's second
//! section (see `crate::cache`, native builds). The renderer draws a first view from the compact copies
//! (`Meshes::first_view`, which never reads); anything else that touches the meshes (the
//! `Deref` to `Vec<Mesh>`: a CPU user, a draw that needs more than a whole level, a clone)
//! reads them then, once. So a `Meshes` is never read empty: either its meshes are here, or
//! they are read before the first look. That read is checked against the section's own hash;
//! if it fails the model is read again (the same meshes: loading is deterministic), and only
//! if that fails too (the model deleted or changed since the hit) does the access panic,
//! saying why (a warning said why the entry failed): there is nothing right to return.
use crate::model::Mesh;
use crate::model::Vertex;
use std::sync::{Mutex, OnceLock};

/// Meshes, here or still in a cache entry (read on first use; see the module docs).
pub struct Meshes {
    full: OnceLock<Full>,
    /// Until `full` is filled: how to read it.
    rest: Mutex<Option<Box<dyn Rest>>>,
    /// Per mesh, what a first view draws (`Meshes::first_view`); empty when all were here.
    first: Vec<First>,
}

/// Every mesh and, for those that came compact, their levels' indices (the mesh cache's
/// `Lod::indices`, read with the full arrays).
pub(crate) struct Full {
    pub(crate) meshes: Vec<Mesh>,
    pub(crate) levels: Vec<Option<Vec<u32>>>,
    /// Bytes of the entry read for them (0: they were here, or the model was read again).
    pub(crate) bytes: u64,
}

/// One mesh of a first view: whole, or only its whole-mesh levels.
#[cfg_attr(not(feature = "native"), allow(dead_code))]
pub(crate) enum First {
    Whole(Mesh),
    Compact(Compact),
}

/// What a first view draws of one mesh, and what the renderer needs of it.
pub enum FirstView<'a> {
    /// All of the mesh (it came whole, or it has been read).
    Whole(&'a Mesh),
    /// Only its whole-mesh levels; the rest is read when a draw or a CPU user needs it.
    Compact(&'a Compact),
}

/// A mesh's whole-mesh levels of detail over the vertices they use: same vertex values,
/// same triangles in the same order as the full mesh's, so a level draws the same pixels
/// from either. Also what the renderer would otherwise compute from the full arrays.
#[derive(Clone, Debug, Default)]
pub struct Compact {
    pub material: usize,
    pub has_uv: bool,
    /// The full mesh's triangle and vertex counts.
    pub triangles: usize,
    pub(crate) vertex_count: usize,
    pub vertices: Vec<Vertex>,
    /// The whole levels' triangles, indexing `vertices`, in the order of the full index
    /// buffer from triangle `first` on.
    pub indices: Vec<u32>,
    pub first: u32,
    pub colors: Vec<[f32; 3]>,
    pub color_alpha: Vec<f32>,
    pub uv1: Vec<[f32; 2]>,
    /// The full mesh's bounding sphere ([`crate::model::bounding_sphere`]) and terminator lift.
    pub center: [f32; 3],
    pub radius: f32,
    pub terminator_lift: f32,
}

/// Reads the full meshes when first needed: the entry's second section, or (when that
/// fails its hash) the model again.
pub(crate) trait Rest: Send {
    /// The full meshes, given the first section's (`Some` for the meshes that came whole),
    /// and the levels' indices of those that came compact.
    fn read(self: Box<Self>, first: Vec<Option<Mesh>>) -> Result<Full, String>;
}

impl Meshes {
    #[cfg_attr(not(feature = "native"), allow(dead_code))]
    /// Meshes whose full arrays are still to be read by `rest`: `first` holds each mesh's
    /// first-view part (whole, or its compact copy).
    pub(crate) fn deferred(first: Vec<First>, rest: Box<dyn Rest>) -> Meshes {
        Meshes {
            full: OnceLock::new(),
            rest: Mutex::new(Some(rest)),
            first,
        }
    }

    /// Whether every mesh's arrays are here (nothing left to read).
    pub fn is_read(&self) -> bool {
        self.full.get().is_some()
    }

    /// Mesh `i` as a first view draws it, without reading anything: whole where its arrays
    /// are here, else its compact copy.
    pub fn first_view(&self, i: usize) -> Option<FirstView<'_>> {
        if let Some(f) = self.full.get() {
            return f.meshes.get(i).map(FirstView::Whole);
        }
        Some(match self.first.get(i)? {
            First::Compact(c) => FirstView::Compact(c),
            First::Whole(m) => FirstView::Whole(m),
        })
    }

    /// The number of meshes, without reading any.
    pub fn count(&self) -> usize {
        match self.full.get() {
            Some(f) => f.meshes.len(),
            None => self.first.len(),
        }
    }

    /// Triangles and vertices of every mesh, without reading any.
    pub(crate) fn counts(&self) -> (usize, usize) {
        (0..self.count())
            .filter_map(|i| self.first_view(i))
            .fold((0, 0), |(t, v), m| match m {
                FirstView::Whole(m) => (t + m.triangle_count(), v + m.vertices.len()),
                FirstView::Compact(c) => (t + c.triangles, v + c.vertex_count),
            })
    }

    /// Bytes of a cache entry read after the first view for these meshes (0: none yet).
    pub fn bytes_read_later(&self) -> u64 {
        self.full.get().map_or(0, |f| f.bytes)
    }

    /// The levels' indices of mesh `i` when it came compact (read now with the full arrays
    /// if they are not here yet), else None (its levels came with its clusters).
    pub fn levels_read(&self, i: usize) -> Option<&[u32]> {
        self.full().levels.get(i)?.as_deref()
    }

    /// Gives `clusters` (a mesh cache hit's, for these meshes) the levels' indices left in
    /// the entry with the full arrays (reading them now): clusters as a cold load makes them.
    pub fn complete(&self, clusters: &mut [Option<crate::lod::clusters::Clusters>]) {
        for (i, c) in clusters.iter_mut().enumerate() {
            if let (Some(c), Some(l)) = (c, self.levels_read(i)) {
                if c.lod.indices.is_empty() {
                    c.lod.indices = l.to_vec();
                }
            }
        }
    }

    /// The meshes, read if they are still in the entry.
    pub fn into_vec(self) -> Vec<Mesh> {
        self.full();
        self.full.into_inner().map(|f| f.meshes).unwrap_or_default()
    }

    fn full(&self) -> &Full {
        self.full.get_or_init(|| {
            let rest = self.rest.lock().unwrap_or_else(|e| e.into_inner()).take();
            let first = self
                .first
                .iter()
                .map(|f| match f {
                    First::Whole(m) => Some(m.clone()),
                    First::Compact(_) => None,
                })
                .collect();
            let read = match rest {
                Some(rest) => rest.read(first),
                // `get_or_init` runs this once; a panic in an earlier read took it.
                None => Err("the mesh cache entry's meshes failed to read before".into()),
            };
            match read {
                Ok(full) => full,
                // The entry failed its second section's hash and the model could not be
                // read again either (deleted since the hit validated it): nothing can stand
                // in for the meshes. The one panic of a lazy scene; see the module docs.
                Err(e) => panic!("{e}"),
            }
        })
    }
}

impl From<Vec<Mesh>> for Meshes {
    fn from(meshes: Vec<Mesh>) -> Meshes {
        let (levels, bytes) = (Vec::new(), 0);
        Meshes {
            full: OnceLock::from(Full {
                meshes,
                levels,
                bytes,
            }),
            rest: Mutex::new(None),
            first: Vec::new(),
        }
    }
}

impl Default for Meshes {
    fn default() -> Meshes {
        Meshes::from(Vec::new())
    }
}

/// A clone reads the meshes (it is a scene to change or keep, never a first view).
impl Clone for Meshes {
    fn clone(&self) -> Meshes {
        Meshes::from(self.full().meshes.clone())
    }
}

impl std::fmt::Debug for Meshes {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.full.get() {
            Some(full) => full.meshes.fmt(f),
            None => write!(f, "Meshes({} in the mesh cache entry)", self.first.len()),
        }
    }
}

impl std::ops::Deref for Meshes {
    type Target = Vec<Mesh>;
    /// Reads the meshes when they are still in the entry.
    fn deref(&self) -> &Vec<Mesh> {
        &self.full().meshes
    }
}

impl std::ops::DerefMut for Meshes {
    fn deref_mut(&mut self) -> &mut Vec<Mesh> {
        self.full();
        // The levels stay: a change of material (`--xray`) keeps them; one of the indices
        // needs new clusters anyway, which bring their own.
        &mut self.full.get_mut().expect("filled by full() above").meshes
    }
}

impl IntoIterator for Meshes {
    type Item = Mesh;
    type IntoIter = std::vec::IntoIter<Mesh>;
    fn into_iter(self) -> Self::IntoIter {
        self.into_vec().into_iter()
    }
}

impl<'a> IntoIterator for &'a Meshes {
    type Item = &'a Mesh;
    type IntoIter = std::slice::Iter<'a, Mesh>;
    fn into_iter(self) -> Self::IntoIter {
        self.iter()
    }
}

impl<'a> IntoIterator for &'a mut Meshes {
    type Item = &'a mut Mesh;
    type IntoIter = std::slice::IterMut<'a, Mesh>;
    fn into_iter(self) -> Self::IntoIter {
        self.iter_mut()
    }
}
