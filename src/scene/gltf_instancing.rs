//! `EXT_mesh_gpu_instancing` by CPU expansion: a node with the extension draws its mesh once
//! per instance, at the node's world transform times the instance's TRANSLATION, ROTATION and
//! SCALE (each defaulting to identity), as if the instances were child nodes. Expanded here,
//! before anything reads a vertex, so every later step (bounds, culling, shadows, the
//! reference renderer, `--stats`) sees every instance on every context. The instance matrix
//! is made exactly as a child node's (`gltf`'s TRS to an f32 matrix, then f64), so an
//! instanced file and its twin with the instances written out as nodes are the same picture.
use super::gltf_accessor::{read_f32, Buffers};
use glam::{DMat4, Mat4};
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

/// `instances` (node, mesh, world) with every instanced node replaced by one entry per
/// instance; and a `--check` line per instanced node.
#[allow(clippy::type_complexity)]
pub(crate) fn expand<'a>(
    doc: &'a gltf::Document,
    instances: Vec<(usize, gltf::Mesh<'a>, DMat4)>,
    buffers: &Buffers,
) -> Result<(Vec<(usize, gltf::Mesh<'a>, DMat4)>, Vec<String>), String> {
    let mut out = Vec::with_capacity(instances.len());
    let mut lines = Vec::new();
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
            "instances: node {i} draws mesh {} {} times ({EXT}, expanded on the CPU)",
            mesh.index(),
            ms.len()
        ));
        if asked > MAX_INSTANCES {
            return Err(format!(
                "node {i}: {EXT}: more than {MAX_INSTANCES} instances in the file"
            ));
        }
        out.extend(ms.into_iter().map(|m| (i, mesh.clone(), world * m)));
    }
    Ok((out, lines))
}
