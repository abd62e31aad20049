//! The ordered pass of the fast path: statements applied in file order exactly as tobj
//! applies them (a new model on `o`/`g` or a material change after faces, materials looked
//! up among the libraries loaded so far), and tobj's `single_index` vertices: one per
//! distinct (v, vt, vn) per model, in order of first use.
use crate::loaders::obj::fast::chunk::{Chunk, EventKind, MISSING};
use crate::loaders::obj::fast::Base;
use std::collections::HashMap;
use std::path::Path;

/// What the loader takes from the repair pass and tobj, as the fast path found it.
pub(crate) struct Parsed {
    pub(crate) models: Vec<tobj::Model>,
    pub(crate) materials: Result<Vec<tobj::Material>, tobj::LoadError>,
    /// Every `usemtl` name with its line.
    pub(crate) usemtl: Vec<(usize, String)>,
    /// Smoothing group per face; empty when the file has no `s` statement.
    pub(crate) face_groups: Vec<u32>,
}

/// The model being filled (tobj's `TmpModels`), with the dedup tables.
struct Models<'a> {
    pos: Pool<'a, 3>,
    tex: Pool<'a, 2>,
    nrm: Pool<'a, 3>,
    done: Vec<tobj::Model>,
    name: String,
    mat_id: Option<usize>,
    mesh: tobj::Mesh,
    faces: usize,
    all_triangles: bool,
    /// Per position index: the first vertex made from it in this model (or `u32::MAX`).
    first: Vec<u32>,
    /// Per vertex of this model: its (v, vt, vn).
    keys: Vec<[u32; 3]>,
    /// Vertices whose position already has a vertex with another vt or vn.
    more: HashMap<[u32; 3], u32>,
}

impl Models<'_> {
    fn corner(&mut self, key: [u32; 3]) {
        let v = key[0] as usize;
        let first = self.first[v];
        let id = if first == u32::MAX {
            let id = self.add(key);
            self.first[v] = id;
            id
        } else if self.keys[first as usize] == key {
            first
        } else if let Some(&id) = self.more.get(&key) {
            id
        } else {
            let id = self.add(key);
            self.more.insert(key, id);
            id
        };
        self.mesh.indices.push(id);
    }

    fn add(&mut self, key: [u32; 3]) -> u32 {
        let [v, vt, vn] = key.map(|i| i as usize);
        let m = &mut self.mesh;
        m.positions.extend_from_slice(self.pos.get(v));
        if vt != MISSING as usize {
            m.texcoords.extend_from_slice(self.tex.get(vt));
        }
        if vn != MISSING as usize {
            m.normals.extend_from_slice(self.nrm.get(vn));
        }
        self.keys.push(key);
        self.keys.len() as u32 - 1
    }

    fn face(&mut self, corners: &[[u32; 3]]) {
        for &c in corners {
            self.corner(c);
        }
        self.mesh.face_arities.push(corners.len() as u32);
        self.all_triangles &= corners.len() == 3;
        self.faces += 1;
    }

    fn pop(&mut self) {
        let mut mesh = std::mem::take(&mut self.mesh);
        // The first model was given room for the whole file.
        for v in [&mut mesh.positions, &mut mesh.normals, &mut mesh.texcoords] {
            if v.capacity() > 2 * v.len() {
                v.shrink_to_fit();
            }
        }
        if mesh.indices.capacity() > 2 * mesh.indices.len() {
            mesh.indices.shrink_to_fit();
        }
        mesh.material_id = self.mat_id;
        if self.all_triangles {
            mesh.face_arities = Vec::new();
        }
        self.done.push(tobj::Model::new(mesh, self.name.clone()));
        for k in self.keys.drain(..) {
            self.first[k[0] as usize] = u32::MAX;
        }
        self.more.clear();
        self.faces = 0;
        self.all_triangles = true;
    }
}

/// tobj's `TmpMaterials`: libraries merged in the order the file names them.
#[derive(Default)]
struct Materials {
    list: Vec<tobj::Material>,
    map: HashMap<String, usize>,
    err: Option<tobj::LoadError>,
}

impl Materials {
    fn merge(&mut self, r: tobj::MTLLoadResult) {
        match r {
            Ok((mut mats, map)) => {
                let offset = self.list.len();
                self.list.append(&mut mats);
                for (k, v) in map {
                    self.map.insert(k, v + offset);
                }
            }
            Err(e) => self.err = Some(e),
        }
    }

    fn finish(self) -> Result<Vec<tobj::Material>, tobj::LoadError> {
        match self.err {
            Some(e) if self.list.is_empty() => Err(e),
            _ => Ok(self.list),
        }
    }
}

/// Elements of one kind (`N` numbers each) as the chunks hold them, without copying them
/// into one array: element `i` is found in the chunk that holds it, the last chunk hit first
/// (a model mostly uses elements in file order).
struct Pool<'a, const N: usize> {
    parts: Vec<&'a [f64]>,
    /// First element index of each part, and the total at the end.
    starts: Vec<usize>,
    last: usize,
}

impl<'a, const N: usize> Pool<'a, N> {
    fn new(parts: Vec<&'a [f64]>) -> Self {
        let mut starts = vec![0];
        for p in &parts {
            starts.push(starts[starts.len() - 1] + p.len() / N);
        }
        Pool {
            parts,
            starts,
            last: 0,
        }
    }

    fn len(&self) -> usize {
        self.starts[self.starts.len() - 1]
    }

    #[inline]
    fn get(&mut self, i: usize) -> &'a [f64] {
        let mut k = self.last;
        if !(self.starts[k]..self.starts[k + 1]).contains(&i) {
            k = self.starts.partition_point(|&s| s <= i) - 1;
            self.last = k;
        }
        let j = (i - self.starts[k]) * N;
        &self.parts[k][j..j + N]
    }
}

pub(crate) fn build(
    chunks: Vec<Chunk>,
    bases: &[Base],
    mtl: &mut dyn FnMut(&Path) -> tobj::MTLLoadResult,
) -> Parsed {
    let pos = Pool::<3>::new(chunks.iter().map(|c| c.pos.as_slice()).collect());
    let tex = Pool::<2>::new(chunks.iter().map(|c| c.tex.as_slice()).collect());
    let nrm = Pool::<3>::new(chunks.iter().map(|c| c.nrm.as_slice()).collect());
    let total = bases.last().map_or(0, |b| b.faces);
    let corners: usize = chunks.iter().map(|c| c.corners.len()).sum();
    let room = |n: usize, k: usize| Vec::with_capacity(n.min(corners) * k);
    let nv = pos.len();
    let mesh = tobj::Mesh {
        positions: room(pos.len(), 3),
        normals: room(nrm.len(), 3),
        texcoords: room(tex.len(), 2),
        indices: Vec::with_capacity(corners),
        ..tobj::Mesh::default()
    };
    let mut m = Models {
        pos,
        tex,
        nrm,
        done: Vec::new(),
        name: "unnamed_object".into(),
        mat_id: None,
        mesh,
        faces: 0,
        all_triangles: true,
        first: vec![u32::MAX; nv],
        keys: Vec::with_capacity(nv.min(corners)),
        more: HashMap::new(),
    };
    let mut mats = Materials::default();
    let mut usemtl = Vec::new();
    let mut groups = Vec::with_capacity(total);
    let (mut group, mut has_groups) = (0u32, false);
    for (c, base) in chunks.iter().zip(bases) {
        let mut events = c.events.iter().peekable();
        let mut at = 0;
        for f in 0..=c.arity.len() {
            while let Some(e) = events.next_if(|e| e.face == f) {
                match &e.kind {
                    EventKind::Name(n) => {
                        if m.faces > 0 {
                            m.pop();
                        }
                        m.name.clone_from(n);
                    }
                    EventKind::UseMtl(name, key) => {
                        usemtl.push((base.lines + e.line + 1, name.clone()));
                        let new = mats.map.get(key).copied();
                        if m.mat_id != new && m.faces > 0 {
                            m.pop();
                        }
                        m.mat_id = new;
                    }
                    EventKind::MtlLib(p) => mats.merge(mtl(Path::new(p))),
                    EventKind::Smooth(g) => (group, has_groups) = (*g, true),
                }
            }
            if let Some(&n) = c.arity.get(f) {
                m.face(&c.corners[at..at + n as usize]);
                at += n as usize;
                groups.push(group);
            }
        }
    }
    m.pop();
    if !has_groups {
        groups = Vec::new();
    }
    Parsed {
        models: m.done,
        materials: mats.finish(),
        usemtl,
        face_groups: groups,
    }
}
