//! What the glTF loader reads for motion before it reads the meshes: the drawn scene's node
//! graph, skins, animations and animated materials, made the motion runtime's [`Plan`]
//! (which holds no `gltf` types).
use crate::model::material::Factors;
use crate::motion::pose::Graph;
use crate::motion::rig::{Plan, Read};
use glam::DMat4;

/// Reads the graph of the drawn scene (`nodes`: the walk's order), the skins and the
/// animations; problems are warnings.
pub(crate) fn plan(
    doc: &gltf::Document,
    nodes: &[(usize, DMat4)],
    (buffers, pointed): (
        &crate::loaders::gltf::accessor::Buffers,
        &[crate::loaders::gltf::pointer::MaterialChannel],
    ),
    warn: &mut dyn FnMut(String),
) -> Plan {
    let count = doc.nodes().len();
    let mut graph = Graph {
        order: nodes.iter().map(|n| n.0).collect(),
        parent: vec![None; count],
        local: vec![DMat4::IDENTITY; count],
        rest: vec![([0.0; 3], [0.0, 0.0, 0.0, 1.0], [1.0; 3]); count],
        weights: vec![Vec::new(); count],
    };
    let mut in_scene = vec![false; count];
    let mut instanced = vec![false; count];
    let mut skin_of = vec![None; count];
    let all: Vec<gltf::Node> = doc.nodes().collect();
    for &(i, _) in nodes {
        let n = &all[i];
        in_scene[i] = true;
        instanced[i] = n.extension_value("EXT_mesh_gpu_instancing").is_some();
        skin_of[i] = n.skin().map(|s| s.index());
        graph.local[i] = glam::Mat4::from_cols_array_2d(&n.transform().matrix()).as_dmat4();
        graph.rest[i] = n.transform().decomposed();
        graph.weights[i] = n
            .weights()
            .or_else(|| n.mesh().and_then(|m| m.weights()))
            .map(<[f32]>::to_vec)
            .unwrap_or_default();
        for c in n.children() {
            graph.parent[c.index()] = Some(i);
        }
    }
    let animations = crate::motion::together::with_merged(
        crate::loaders::gltf::animations::animations(doc, (buffers, pointed), &in_scene, warn),
    );
    let skins = crate::loaders::gltf::animations::skins(doc, buffers, &in_scene, warn);
    let targets = doc
        .meshes()
        .map(|m| {
            m.primitives()
                .map(|p| p.morph_targets().len())
                .max()
                .unwrap_or(0)
        })
        .collect();
    let mut material_factors: Vec<(usize, Factors)> = Vec::new();
    for k in animations.iter().flat_map(|a| &a.materials) {
        if !material_factors.iter().any(|f| f.0 == k.material) {
            if let Some(m) = doc.materials().nth(k.material) {
                material_factors.push((k.material, crate::loaders::gltf::material::factors_of(&m)));
            }
        }
    }
    Plan::new(Read {
        graph,
        instanced,
        skin_of,
        names: doc.nodes().map(|n| n.name().map(str::to_string)).collect(),
        skins,
        animations,
        targets,
        material_factors,
    })
}
