//! A triangle primitive before it is a mesh: world coordinates in f64 and its attributes,
//! each None where absent or unusable; made a [`Mesh`] re-centred, with attributes of another
//! length dropped and normals generated where the file gave none. The glTF loader builds
//! them; the motion runtime makes a posed primitive's mesh again with the same code, so a
//! moment's mesh is the loader's to the bit.
use crate::load::options::LoadOptions;
use crate::model::{Mesh, Vertex};
use crate::motion::pose::Placed;
use glam::DVec3;

/// A triangle primitive as read: world coordinates (f64, not yet re-centred) and its
/// attributes, each None if absent or unusable.
#[derive(Clone, Debug)]
pub(crate) struct Prim {
    pub(crate) positions: Vec<DVec3>,
    pub(crate) normals: Option<Vec<DVec3>>,
    pub(crate) uvs: Option<Vec<[f32; 2]>>,
    pub(crate) uv1: Option<Vec<[f32; 2]>>,
    pub(crate) tangents: Option<Vec<[f32; 4]>>,
    pub(crate) colors: Option<Vec<[f32; 3]>>,
    /// COLOR_0's alpha where it is a VEC4.
    pub(crate) alphas: Option<Vec<f32>>,
    pub(crate) indices: Vec<u32>,
    pub(crate) material: Option<usize>,
    pub(crate) name: String,
}

/// An error if a placed position is not finite or beyond f32 (it would become infinite when
/// rounded after re-centring).
pub(crate) fn check_range(positions: &[DVec3]) -> Result<(), String> {
    if positions
        .iter()
        .any(|q| !q.is_finite() || q.abs().max_element() > f64::from(f32::MAX))
    {
        return Err("the pose places positions beyond 32-bit float range".into());
    }
    Ok(())
}

impl Prim {
    /// The same primitive with other positions, normals and tangents (a pose's).
    pub(crate) fn with_geometry(&self, (positions, normals, tangents): Placed) -> Prim {
        Prim {
            positions,
            normals,
            tangents,
            uvs: self.uvs.clone(),
            uv1: self.uv1.clone(),
            colors: self.colors.clone(),
            alphas: self.alphas.clone(),
            indices: self.indices.clone(),
            material: self.material,
            name: self.name.clone(),
        }
    }

    /// Writes a pose's positions, normals and tangents into `mesh`, the mesh this
    /// primitive became ([`Prim::into_mesh`]): the same mesh `into_mesh` of the posed
    /// primitive makes. In place when the mesh has the layout the file's normals give (one
    /// vertex per position, the file's indices) and the pose keeps them: the streams a
    /// pose does not move (UVs, colours, indices) are then neither copied nor rebuilt.
    /// Where normals are generated, now or in the mesh's last pose (its vertices split at
    /// creases), the mesh is made anew. Either way it keeps its material, which a pose
    /// does not change (an object's `--xray` material stays).
    pub(crate) fn pose_into(
        &self,
        (positions, normals, tangents): Placed,
        mesh: &mut Mesh,
        (origin, default_material): (DVec3, usize),
        opts: &LoadOptions,
    ) {
        let count = positions.len();
        // Only the file-normals path leaves a vertex with its file normal (generating
        // marks every vertex generated), and it never reorders the indices.
        let same_layout = mesh.vertices.len() == count
            && mesh.generated_normals < count
            && mesh.indices == self.indices;
        let normals = match normals {
            Some(n) if same_layout && n.len() == count => n,
            normals => {
                // The material is the scene's (`--xray` of an object gives it its own).
                let material = mesh.material;
                *mesh = self
                    .with_geometry((positions, normals, tangents))
                    .into_mesh(origin, default_material, opts);
                mesh.material = material;
                return;
            }
        };
        for ((v, p), n) in mesh.vertices.iter_mut().zip(&positions).zip(&normals) {
            v.position = (*p - origin).as_vec3().into();
            v.normal = n.as_vec3().into();
        }
        mesh.tangents = tangents.filter(|t| t.len() == count).unwrap_or_default();
        mesh.finish_normals(true, None, opts.creases);
    }

    /// The mesh, re-centred on `origin`: attributes of another length than the positions are
    /// dropped, a material index past the file's materials becomes `default_material`, and
    /// normals are generated where the file gave none.
    pub(crate) fn into_mesh(
        self,
        origin: DVec3,
        default_material: usize,
        opts: &LoadOptions,
    ) -> Mesh {
        let p = self;
        let count = p.positions.len();
        let has_n = p.normals.as_ref().is_some_and(|v| v.len() == count);
        let has_uv = p.uvs.as_ref().is_some_and(|v| v.len() == count);
        let vertices: Vec<Vertex> = (0..count)
            .map(|i| Vertex {
                position: (p.positions[i] - origin).as_vec3().into(),
                normal: match &p.normals {
                    Some(v) if has_n => v[i].as_vec3().into(),
                    _ => [0.0; 3],
                },
                // glTF's UV origin is the image's top-left, as textures are uploaded.
                uv: match &p.uvs {
                    Some(v) if has_uv => v[i],
                    _ => [0.0; 2],
                },
            })
            .collect();
        let colors: Vec<[f32; 3]> = p.colors.filter(|c| c.len() == count).unwrap_or_default();
        // An alpha of 1 everywhere changes nothing: no stream for it.
        let color_alpha = p
            .alphas
            .filter(|a| !colors.is_empty() && a.len() == count && a.iter().any(|&x| x != 1.0))
            .unwrap_or_default();
        let mut mesh = Mesh {
            name: p.name,
            vertices,
            indices: p.indices,
            material: p
                .material
                .filter(|&m| m < default_material)
                .unwrap_or(default_material),
            has_uv,
            generated_normals: 0,
            colors,
            color_alpha,
            uv1: p.uv1.filter(|c| c.len() == count).unwrap_or_default(),
            // Tangents go with the file's normals: generated normals get generated tangents.
            tangents: p
                .tangents
                .filter(|c| c.len() == count && has_n)
                .unwrap_or_default(),
        };
        mesh.finish_normals(has_n, None, opts.creases);
        mesh
    }
}
