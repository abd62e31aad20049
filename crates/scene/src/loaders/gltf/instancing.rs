//! `EXT_mesh_gpu_instancing`: a node with the extension draws its mesh once per instance, at
//! the node's world transform times the instance's TRANSLATION, ROTATION and SCALE (each
//! defaulting to identity), as if the instances were child nodes. The scene holds them
//! expanded (one copy of the mesh per instance, written out here before anything reads a
//! vertex), so every CPU step (bounds, `--check`, the reference renderer, picking, edges)
//! and GL 2.1 see every instance; beside the copies it records an [`Instancing`] per node,
//! from which the renderer draws the copies as instances of the first where the context has
//! instanced arrays (GL 3.3, ES 3.0), uploading one copy and a matrix per instance. The
//! instance matrix is made exactly as a child node's (`gltf`'s TRS to an f32 matrix, then
//! f64), so an instanced file and its twin with the instances written out as nodes are the
//! same picture when drawn expanded.
use crate::loaders::gltf::accessor::{read_f32, Buffers};
use glam::{DMat3, DMat4, DVec3, Mat4};
use gltf::accessor::Dimensions as D;
use serde_json::Value;

/// Instances drawn per file at most (each is a copy of its mesh's vertices; the vertex bound
/// of `gltf.rs` applies to them too).
pub(crate) const MAX_INSTANCES: usize = 1 << 20;

const EXT: &str = "EXT_mesh_gpu_instancing";

/// One instance attribute: `n` rows of `dims`, or None when the extension does not name it;
/// and whether it was stored as integers (quantized).
fn attribute(
    doc: &gltf::Document,
    ext: &Value,
    name: &str,
    dims: D,
    buffers: &Buffers,
) -> Result<(Option<Vec<f32>>, bool), String> {
    let Some(i) = ext.get("attributes").and_then(|a| a.get(name)) else {
        return Ok((None, false));
    };
    let acc = i
        .as_u64()
        .and_then(|i| doc.accessors().nth(usize::try_from(i).ok()?))
        .ok_or_else(|| format!("{name} names no accessor"))?;
    let quantized = acc.data_type() != gltf::accessor::DataType::F32;
    Ok((Some(read_f32(&acc, buffers, &[dims])?.1), quantized))
}

/// The instance transforms of `node` (None if it has no instancing extension).
fn transforms(
    doc: &gltf::Document,
    node: &gltf::Node,
    buffers: &Buffers,
) -> Result<Option<Vec<DMat4>>, String> {
    let Some(ext) = node.extension_value(EXT) else {
        return Ok(None);
    };
    let t = attribute(doc, ext, "TRANSLATION", D::Vec3, buffers)?.0;
    let (r, r_quantized) = attribute(doc, ext, "ROTATION", D::Vec4, buffers)?;
    let s = attribute(doc, ext, "SCALE", D::Vec3, buffers)?.0;
    let counts = [
        t.as_ref().map(|v| v.len() / 3),
        r.as_ref().map(|v| v.len() / 4),
        s.as_ref().map(|v| v.len() / 3),
    ];
    let mut known = counts.iter().flatten();
    let Some(&n) = known.next() else {
        return Err("no TRANSLATION, ROTATION or SCALE attribute".into());
    };
    if known.any(|&m| m != n) {
        return Err(format!("attribute counts differ ({counts:?})"));
    }
    let row3 = |v: &Option<Vec<f32>>, k: usize, d: [f32; 3]| {
        v.as_ref()
            .map_or(d, |v| [v[3 * k], v[3 * k + 1], v[3 * k + 2]])
    };
    let mut out = Vec::with_capacity(n.min(MAX_INSTANCES));
    for k in 0..n {
        let rotation = r.as_ref().map_or([0.0, 0.0, 0.0, 1.0], |v| {
            let q = glam::Vec4::from_slice(&v[4 * k..4 * k + 4]);
            // Quantized quaternions are off unit length by their rounding (a scale error of
            // a few percent): normalized. Float ones are used as written, like a node's.
            match r_quantized {
                true => q.try_normalize().unwrap_or(glam::Vec4::W).to_array(),
                false => q.to_array(),
            }
        });
        let trs = gltf::scene::Transform::Decomposed {
            translation: row3(&t, k, [0.0; 3]),
            rotation,
            scale: row3(&s, k, [1.0; 3]),
        };
        out.push(Mat4::from_cols_array_2d(&trs.matrix()).as_dmat4());
    }
    Ok(Some(out))
}

/// One instanced node of a scene: its instances are scene meshes `first + k * per_instance`
/// up to `per_instance` more (instance `k`'s copy of each triangle primitive, in order).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Instancing {
    /// The glTF node and the mesh it instances.
    pub node: usize,
    pub mesh: usize,
    /// Instances the file gives the node (every one is drawn).
    pub count: usize,
    pub first: usize,
    pub per_instance: usize,
    /// Instance `k`'s local (re-centred) coordinates from instance 0's, column-major; empty
    /// when the copies cannot share one mesh (an instance mirrored unlike the first, a
    /// singular transform, no triangles): the renderer then draws the copies as they are.
    pub relative: Vec<Mat4>,
}

impl Instancing {
    /// Whether the renderer may draw the copies as instances of the first.
    pub fn shareable(&self) -> bool {
        self.relative.len() == self.count && self.count > 1 && self.per_instance > 0
    }
}

/// An instanced node as [`expand`] wrote it out: its entries `entry..entry + worlds.len()`
/// of the expanded list, each instance's world transform.
pub(crate) struct Run {
    pub(crate) node: usize,
    pub(crate) mesh: usize,
    pub(crate) entry: usize,
    pub(crate) worlds: Vec<DMat4>,
    /// Each instance's own transform (the node's comes before it in `worlds`).
    pub(crate) locals: Vec<DMat4>,
}

/// The instance transform of entry `e` of [`expand`]'s list, if it is a copy of an
/// instanced node (`runs` in entry order).
pub(crate) fn instance_of(runs: &[Run], e: usize) -> Option<DMat4> {
    let r = &runs[runs.partition_point(|r| r.entry <= e).checked_sub(1)?];
    r.locals.get(e - r.entry).copied()
}

/// The up-axis rotation as a matrix (its columns the rotated axes; exact).
fn up_matrix(up: crate::model::UpAxis) -> DMat4 {
    DMat4::from_mat3(DMat3::from_cols(
        up.rotate(DVec3::X),
        up.rotate(DVec3::Y),
        up.rotate(DVec3::Z),
    ))
}

/// The scene's record of `run`, whose entries' triangle primitives became meshes at
/// `meshes[e]` (None: skipped) for entry `e`: `relative` maps instance 0's local coordinates
/// (file coordinates rotated to +Y up, less `origin`) to instance `k`'s, made in f64.
pub(crate) fn record(
    run: &Run,
    meshes: &[Vec<usize>],
    up: crate::model::UpAxis,
    origin: DVec3,
) -> Instancing {
    let count = run.worlds.len();
    let of = |k: usize| meshes.get(run.entry + k).map_or(&[][..], Vec::as_slice);
    let per_instance = of(0).len();
    let first = of(0).first().copied().unwrap_or(0);
    // Each copy must sit where the layout says (a primitive skipped for one instance only
    // would break it).
    let laid_out = (0..count).all(|k| {
        of(k)
            .iter()
            .enumerate()
            .all(|(j, &m)| m == first + k * per_instance + j)
            && of(k).len() == per_instance
    });
    let mut out = Instancing {
        node: run.node,
        mesh: run.mesh,
        count,
        first,
        per_instance,
        relative: Vec::new(),
    };
    let det0 = run.worlds.first().map_or(0.0, DMat4::determinant);
    let same_hand = run
        .worlds
        .iter()
        .all(|w| w.determinant().is_normal() && (w.determinant() > 0.0) == (det0 > 0.0));
    if !laid_out || !same_hand || per_instance == 0 {
        return out;
    }
    let u = up_matrix(up);
    let (to, from) = (
        DMat4::from_translation(-origin) * u,
        u.transpose() * DMat4::from_translation(origin),
    );
    let inv0 = run.worlds[0].inverse();
    let relative: Vec<Mat4> = run
        .worlds
        .iter()
        .map(|w| (to * *w * inv0 * from).as_mat4())
        .collect();
    if relative.iter().all(Mat4::is_finite) {
        out.relative = relative;
    }
    out
}

/// `instances` (node, mesh, world) with every instanced node replaced by one entry per
/// instance; a `--check` line per instanced node; and the instanced nodes' runs.
#[allow(clippy::type_complexity)]
pub(crate) fn expand<'a>(
    doc: &'a gltf::Document,
    instances: Vec<(usize, gltf::Mesh<'a>, DMat4)>,
    buffers: &Buffers,
) -> Result<(Vec<(usize, gltf::Mesh<'a>, DMat4)>, Vec<String>, Vec<Run>), String> {
    let mut out = Vec::with_capacity(instances.len());
    let mut lines = Vec::new();
    let mut runs = Vec::new();
    let mut asked = 0usize;
    for (i, mesh, world) in instances {
        let node = doc.nodes().nth(i).ok_or("node vanished")?;
        let Some(ms) =
            transforms(doc, &node, buffers).map_err(|e| format!("node {i}: {EXT}: {e}"))?
        else {
            out.push((i, mesh, world));
            continue;
        };
        asked += ms.len();
        lines.push(format!(
            "instances: node {i} draws mesh {} {} times ({EXT})",
            mesh.index(),
            ms.len()
        ));
        if asked > MAX_INSTANCES {
            return Err(format!(
                "node {i}: {EXT}: more than {MAX_INSTANCES} instances in the file"
            ));
        }
        let worlds: Vec<DMat4> = ms.iter().map(|m| world * *m).collect();
        runs.push(Run {
            node: i,
            mesh: mesh.index(),
            entry: out.len(),
            worlds: worlds.clone(),
            locals: ms,
        });
        out.extend(worlds.into_iter().map(|w| (i, mesh.clone(), w)));
    }
    Ok((out, lines, runs))
}

#[cfg(test)]
mod tests {
    use crate::model::UpAxis;
    use glam::{DMat4, DVec3};
    use {crate::loaders::gltf::instancing::record, crate::loaders::gltf::instancing::Run};

    fn run(worlds: Vec<DMat4>) -> Run {
        Run {
            node: 0,
            mesh: 0,
            entry: 0,
            worlds,
            locals: Vec::new(),
        }
    }

    /// Instance k's relative matrix takes the first copy's local points (up axis turned,
    /// origin taken off) to where the loader puts instance k's.
    #[test]
    fn relative_matrices_move_the_first_copy_onto_each_instance() {
        let worlds = vec![
            DMat4::from_scale_rotation_translation(
                DVec3::new(1.0, 2.0, 0.5),
                glam::DQuat::from_rotation_y(0.3),
                DVec3::new(5.0, 0.0, -1.0),
            ),
            DMat4::from_scale_rotation_translation(
                DVec3::new(0.7, 1.0, 1.5),
                glam::DQuat::from_rotation_x(1.1),
                DVec3::new(-2.0, 3.0, 4.0),
            ),
        ];
        let (up, origin) = (UpAxis::PosZ, DVec3::new(10.0, -4.0, 2.0));
        let meshes = vec![vec![3], vec![4]];
        let r = record(&run(worlds.clone()), &meshes, up, origin);
        assert!(r.shareable() && (r.first, r.per_instance) == (3, 1));
        let local = |w: &DMat4, p: DVec3| up.rotate(w.transform_point3(p)) - origin;
        let p = DVec3::new(0.25, -0.5, 1.0);
        let moved = r.relative[1].transform_point3(local(&worlds[0], p).as_vec3());
        let want = local(&worlds[1], p).as_vec3();
        assert!(moved.distance(want) < 1e-5, "{moved} vs {want}");
        assert!(r.relative[0].abs_diff_eq(glam::Mat4::IDENTITY, 1e-6));
    }

    /// Copies that cannot share one mesh are recorded but not shareable: one instance
    /// mirrored unlike the first (its winding was flipped at load), a zero scale, or copies
    /// not where the layout says.
    #[test]
    fn unshareable_copies_are_drawn_as_written_out() {
        let mirrored = DMat4::from_scale(DVec3::new(-1.0, 1.0, 1.0));
        let flat = DMat4::from_scale(DVec3::new(1.0, 0.0, 1.0));
        let (up, o) = (UpAxis::PosY, DVec3::ZERO);
        let laid = vec![vec![0], vec![1]];
        for (worlds, meshes) in [
            (vec![DMat4::IDENTITY, mirrored], laid.clone()),
            (vec![DMat4::IDENTITY, flat], laid),
            (
                vec![DMat4::IDENTITY, DMat4::IDENTITY],
                vec![vec![0], vec![2]],
            ),
        ] {
            let r = record(&run(worlds), &meshes, up, o);
            assert_eq!(r.count, 2);
            assert!(!r.shareable(), "{r:?}");
        }
        let both = record(&run(vec![mirrored, mirrored]), &[vec![0], vec![1]], up, o);
        assert!(both.shareable());
    }
}
