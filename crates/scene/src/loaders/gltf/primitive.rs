//! One glTF mesh's primitives read under the transform of a node that instances it: positions,
//! normals and tangents transformed in f64 (and turned to the up axis asked for), attributes
//! that are not finite dropped with a warning (normals and tangents are then generated),
//! lines and points set aside for [`Wire`]; then each triangle primitive made a [`crate::Mesh`]
//! once the scene's origin is known.
use crate::geometry::prim::{check_range, Prim};
use crate::loaders::gltf::accessor;
use crate::model::{UpAxis, Warning, Wire};
use crate::motion::pose::{Deform, Placed, Source};
use crate::motion::{Carried, Moving};
use glam::{DMat3, DMat4, DVec3};
use gltf::accessor::Dimensions as D;
use gltf::mesh::{Mode, Semantic};
use std::path::Path;
use std::sync::Arc;

/// What the scene's primitives gave: the triangle primitives, and the lines and points with
/// the positions they index (world coordinates, re-centred later with the triangles).
#[derive(Default)]
pub(crate) struct Primitives {
    pub(crate) prims: Vec<Prim>,
    pub(crate) wire_pts: Vec<DVec3>,
    pub(crate) wire: Wire,
    /// Some wire primitive had no normals: the points are drawn unlit.
    wire_unlit: bool,
    /// The moving primitives' sources (`at`: the index in `prims`).
    pub(crate) sources: Vec<Recorded>,
    /// The moving lines' and points' sources (`at`: their first index in `wire_pts`).
    pub(crate) wire_sources: Vec<Recorded>,
    /// The sources read so far by (mesh, primitive, skin joint count): every node drawing
    /// a mesh (each copy of an instanced node among them) shares one, read, warned about
    /// and charged to the file's morph budget once.
    shared: std::collections::HashMap<(usize, usize, Option<usize>), Arc<Source>>,
}

/// Which primitive a moving source is read for: its mesh and index there, the label its
/// warnings carry, and whether it is lines or points.
struct Which<'l> {
    mesh: usize,
    prim: usize,
    label: &'l str,
    wire: bool,
}

/// A moving primitive as the loader read it: where it went (`at`) and what carries it.
pub(crate) struct Recorded {
    pub(crate) at: usize,
    pub(crate) by: Carried,
}

impl Primitives {
    /// Adds the colours and normals of `n` wire positions about to be added: colours white
    /// where a primitive has none (while some other has them); normals only while every
    /// primitive so far had them (else the points are drawn unlit).
    fn wire_attributes(
        &mut self,
        n: usize,
        colors: Option<Vec<[f32; 3]>>,
        normals: Option<Vec<DVec3>>,
    ) {
        let before = self.wire_pts.len();
        let w = &mut self.wire;
        match colors.filter(|c| c.len() == n) {
            Some(c) => {
                w.colors.resize(before, [1.0; 3]);
                w.colors.extend(c);
            }
            None if !w.colors.is_empty() => w.colors.resize(before + n, [1.0; 3]),
            None => {}
        }
        match normals.filter(|v| v.len() == n) {
            Some(v) if !self.wire_unlit && w.normals.len() == before => w
                .normals
                .extend(v.iter().map(|d| d.normalize_or_zero().as_vec3().to_array())),
            _ => {
                w.normals.clear();
                // None of the later ones count either.
                self.wire_unlit = true;
            }
        }
    }
}

/// A node instancing a mesh: its transform and what follows from it for directions, and where
/// the accessors' bytes are.
pub(crate) struct Instance<'a> {
    node: usize,
    world: DMat4,
    /// The inverse transpose, for normals.
    normal_m: DMat3,
    /// A singular transform (a zero scale) has no normal matrix: normals are generated.
    normal_ok: bool,
    /// A negative determinant: the winding and the bitangent sign flip.
    mirrored: bool,
    up: UpAxis,
    /// The `KHR_materials_variants` variant drawn, if one was chosen.
    variant: Option<usize>,
    /// How the node's mesh moves (skin, morph targets, animation), if it does.
    moving: Option<Moving<'a>>,
    /// An instanced node's copy: the instance's transform (`world` holds it after the
    /// node's), for poses.
    instance: Option<DMat4>,
    buffers: &'a accessor::Buffers,
    /// The glTF file, named by warnings.
    path: &'a Path,
}

impl<'a> Instance<'a> {
    pub(crate) fn new(
        node: usize,
        world: DMat4,
        up: UpAxis,
        buffers: &'a accessor::Buffers,
        path: &'a Path,
    ) -> Self {
        let normal_m = DMat3::from_mat4(world).inverse().transpose();
        Instance {
            node,
            world,
            normal_m,
            normal_ok: normal_m.is_finite(),
            mirrored: world.determinant() < 0.0,
            up,
            variant: None,
            moving: None,
            instance: None,
            buffers,
            path,
        }
    }

    /// The same instance, its primitives taking `variant`'s materials where they map it.
    pub(crate) fn with_variant(self, variant: Option<usize>) -> Self {
        Instance { variant, ..self }
    }

    /// The same instance, its primitives read as moving ones (posed now in the static
    /// pose, their sources kept for other poses).
    pub(crate) fn with_moving(self, moving: Option<Moving<'a>>) -> Self {
        Instance { moving, ..self }
    }

    /// The same instance as a copy of an instanced node, `instance` its transform after the
    /// node's (None: a plain node).
    pub(crate) fn with_instance(self, instance: Option<DMat4>) -> Self {
        Instance { instance, ..self }
    }

    fn warn(&self, warnings: &mut Vec<Warning>, message: String) {
        warnings.push(Warning {
            file: self.path.to_path_buf(),
            line: None,
            message,
        })
    }

    /// Reads every primitive of `mesh` into `out`; a primitive without positions is skipped
    /// with a warning. An error is a message for the file as a whole.
    pub(crate) fn read_mesh(
        &self,
        mesh: &gltf::Mesh,
        out: &mut Primitives,
        warnings: &mut Vec<Warning>,
    ) -> Result<(), String> {
        for (pi, p) in mesh.primitives().enumerate() {
            let where_ = || format!("mesh {} primitive {pi}", mesh.index());
            let Some(pos_acc) = p.get(&Semantic::Positions) else {
                self.warn(warnings, format!("{}: no POSITION: skipped", where_()));
                continue;
            };
            let positions = self.positions(&pos_acc, &where_)?;
            let n = positions.len() as u32;
            let corners: Vec<u32> = match p.indices() {
                Some(a) => accessor::read_indices(&a, self.buffers)?,
                None => (0..n).collect(),
            };
            if let Some(k) = corners.iter().position(|&k| k >= n) {
                return Err(format!(
                    "{}: index {} (element {k}) out of range ({n} vertices)",
                    where_(),
                    corners[k]
                ));
            }
            let (indices, segments) =
                crate::loaders::gltf::modes::split(p.mode(), &corners, self.mirrored);
            if matches!(p.mode(), Mode::Points) || !segments.is_empty() {
                let base = out.wire_pts.len() as u32;
                // Points take their COLOR_0 and NORMAL (lit where every point has one).
                let colors = self.colors(&p)?.0;
                // A moving node's lines and points are posed as its triangles are (skinned,
                // morphed, carried by the node), in the static pose too.
                let (positions, normals) = match self.moving {
                    Some(m) => {
                        let which = Which {
                            mesh: mesh.index(),
                            prim: pi,
                            label: &where_(),
                            wire: true,
                        };
                        let (q, n, _) = self.posed(&p, m, which, out, warnings)?;
                        (q, n)
                    }
                    None => (positions, self.normals(&p, &where_, warnings)?),
                };
                out.wire_attributes(positions.len(), colors, normals);
                out.wire_pts.extend(&positions);
                if p.mode() == Mode::Points {
                    out.wire.points.extend(corners.iter().map(|i| base + i));
                }
                out.wire
                    .segments
                    .extend(segments.iter().map(|s| [base + s[0], base + s[1]]));
                continue;
            }
            let (positions, normals, tangents) = match self.moving {
                Some(m) => {
                    let which = Which {
                        mesh: mesh.index(),
                        prim: pi,
                        label: &where_(),
                        wire: false,
                    };
                    self.posed(&p, m, which, out, warnings)?
                }
                None => (
                    positions,
                    self.normals(&p, &where_, warnings)?,
                    self.tangents(&p, &where_, warnings)?,
                ),
            };
            let uvs = self.uv_set(&p, 0, warnings)?;
            let uv1 = self.uv_set(&p, 1, warnings)?;
            let (colors, alphas) = self.colors(&p)?;
            out.prims.push(Prim {
                positions,
                normals,
                uvs,
                uv1,
                tangents,
                colors,
                alphas,
                indices,
                material: self
                    .variant
                    .and_then(|v| crate::loaders::gltf::variants::material(&p, v))
                    .or(p.material().index()),
                name: mesh.name().unwrap_or("mesh").to_string(),
            });
        }
        Ok(())
    }

    /// A moving primitive's attributes in the static pose (skinned by its skin's joints or
    /// carried by the node, morphed by the static weights); its source is recorded in `out`
    /// for the next `prims` entry, or (`wire`: lines or points) for the next wire position.
    fn posed(
        &self,
        p: &gltf::Primitive,
        m: Moving,
        which: Which,
        out: &mut Primitives,
        warnings: &mut Vec<Warning>,
    ) -> Result<Placed, String> {
        let Which {
            mesh,
            prim,
            label,
            wire,
        } = which;
        let joints = m.skin.map(|s| s.1.len());
        let src = match out.shared.get(&(mesh, prim, joints)) {
            Some(src) => src.clone(),
            None => {
                let mut warn = |message| self.warn(warnings, message);
                let read = crate::loaders::gltf::sources::read(
                    p,
                    self.buffers,
                    (joints, m.morph_budget),
                    label,
                    &mut warn,
                )?;
                let read = Arc::new(read);
                out.shared.insert((mesh, prim, joints), read.clone());
                read
            }
        };
        let deform = match m.skin {
            Some((_, joints)) if !src.sets.is_empty() => Deform::Skin(joints),
            _ => Deform::Node(self.world),
        };
        let placed = src.place(&deform, m.weights, self.up, false);
        check_range(&placed.0).map_err(|e| format!("{label}: node {}: {e}", self.node))?;
        let skin = m.skin.map(|s| s.0).filter(|_| !src.sets.is_empty());
        let (list, at) = match wire {
            true => (&mut out.wire_sources, out.wire_pts.len()),
            false => (&mut out.sources, out.prims.len()),
        };
        list.push(Recorded {
            at,
            by: Carried {
                node: self.node,
                skin,
                instance: self.instance,
                src,
            },
        });
        Ok(placed)
    }

    /// The POSITION accessor's points in world coordinates; an error if one is not finite, or
    /// is beyond f32 after the transform (it would become infinite when rounded after
    /// re-centring).
    fn positions(
        &self,
        pos_acc: &gltf::Accessor,
        where_: &dyn Fn() -> String,
    ) -> Result<Vec<DVec3>, String> {
        let (_, raw) = accessor::read_f32(pos_acc, self.buffers, &[D::Vec3])?;
        if let Some(k) = raw.iter().position(|x| !x.is_finite()) {
            return Err(format!(
                "accessor {} (POSITION of {}): element {} is not finite",
                pos_acc.index(),
                where_(),
                k / 3
            ));
        }
        let positions: Vec<DVec3> = raw
            .chunks_exact(3)
            .map(|q| {
                self.up.rotate(
                    self.world
                        .transform_point3(glam::Vec3::from_slice(q).as_dvec3()),
                )
            })
            .collect();
        if positions
            .iter()
            .any(|q| !q.is_finite() || q.abs().max_element() > f64::from(f32::MAX))
        {
            return Err(format!(
                "{}: node {} transforms positions beyond 32-bit float range",
                where_(),
                self.node
            ));
        }
        Ok(positions)
    }

    /// COLOR_0 in display values, and its alpha where it is a VEC4; None if absent.
    #[allow(clippy::type_complexity)]
    fn colors(
        &self,
        p: &gltf::Primitive,
    ) -> Result<(Option<Vec<[f32; 3]>>, Option<Vec<f32>>), String> {
        let Some(a) = p.get(&Semantic::Colors(0)) else {
            return Ok((None, None));
        };
        let (d, v) = accessor::read_f32(&a, self.buffers, &[D::Vec3, D::Vec4])?;
        // COLOR_0 is linear; `Mesh::colors` holds display values (as PLY's and OBJ's):
        // encoded once here, decoded again by the PBR tier. Its alpha (a weight, not a
        // colour) stays linear.
        let enc = crate::model::material::srgb_encode_hdr;
        let alphas = (d == 4).then(|| v.chunks_exact(4).map(|q| q[3]).collect());
        let rgb = v
            .chunks_exact(d)
            .map(|q| [enc(q[0]), enc(q[1]), enc(q[2])])
            .collect();
        Ok((Some(rgb), alphas))
    }

    /// The NORMAL accessor's directions under the normal matrix; None (normals generated) if
    /// absent, if the transform has no normal matrix, or (with a warning) if one is not finite.
    fn normals(
        &self,
        p: &gltf::Primitive,
        where_: &dyn Fn() -> String,
        warnings: &mut Vec<Warning>,
    ) -> Result<Option<Vec<DVec3>>, String> {
        let Some(a) = p.get(&Semantic::Normals).filter(|_| self.normal_ok) else {
            return Ok(None);
        };
        let (_, v) = accessor::read_f32(&a, self.buffers, &[D::Vec3])?;
        if let Some(k) = v.iter().position(|x| !x.is_finite()) {
            self.warn(
                warnings,
                format!(
                    "accessor {} (NORMAL of {}): element {} is not finite; \
                     normals generated",
                    a.index(),
                    where_(),
                    k / 3
                ),
            );
            return Ok(None);
        }
        Ok(Some(
            v.chunks_exact(3)
                .map(|q| {
                    self.up
                        .rotate(self.normal_m * glam::Vec3::from_slice(q).as_dvec3())
                })
                .collect(),
        ))
    }

    /// The TEXCOORD_`set` accessor; None if absent or (with a warning) if one is not finite.
    fn uv_set(
        &self,
        p: &gltf::Primitive,
        set: u32,
        warnings: &mut Vec<Warning>,
    ) -> Result<Option<Vec<[f32; 2]>>, String> {
        let Some(a) = p.get(&Semantic::TexCoords(set)) else {
            return Ok(None);
        };
        let (_, v) = accessor::read_f32(&a, self.buffers, &[D::Vec2])?;
        if v.iter().all(|x| x.is_finite()) {
            Ok(Some(v.chunks_exact(2).map(|q| [q[0], q[1]]).collect()))
        } else {
            self.warn(
                warnings,
                format!(
                    "accessor {}: a TEXCOORD_{set} is not finite: unused",
                    a.index()
                ),
            );
            Ok(None)
        }
    }

    /// The TANGENT accessor under the node's transform; None (tangents generated) if absent,
    /// if the transform has no normal matrix, or (with a warning) if one is not finite.
    fn tangents(
        &self,
        p: &gltf::Primitive,
        where_: &dyn Fn() -> String,
        warnings: &mut Vec<Warning>,
    ) -> Result<Option<Vec<[f32; 4]>>, String> {
        let Some(a) = p.get(&Semantic::Tangents).filter(|_| self.normal_ok) else {
            return Ok(None);
        };
        let (_, v) = accessor::read_f32(&a, self.buffers, &[D::Vec4])?;
        if !v.iter().all(|x| x.is_finite()) {
            self.warn(
                warnings,
                format!(
                    "accessor {} (TANGENT of {}): not finite; tangents generated",
                    a.index(),
                    where_()
                ),
            );
            return Ok(None);
        }
        // Supplied tangents follow the node's linear part like any direction in the
        // surface; a mirroring transform reverses cross(N, T), so the bitangent sign flips
        // with it.
        let m3 = DMat3::from_mat4(self.world);
        let flip = if self.mirrored { -1.0 } else { 1.0 };
        Ok(Some(
            v.chunks_exact(4)
                .map(|q| {
                    let t = self.up.rotate(m3 * glam::Vec3::from_slice(q).as_dvec3());
                    let t = t.normalize_or_zero().as_vec3();
                    let w = if q[3] < 0.0 { -flip } else { flip };
                    [t.x, t.y, t.z, w as f32]
                })
                .collect(),
        ))
    }
}
