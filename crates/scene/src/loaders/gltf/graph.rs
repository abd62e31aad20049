//! The node hierarchy of a glTF scene, walked without recursion. glTF nodes must form strict
//! trees; a node reached twice is either a cycle (it is its own ancestor) or a node with two
//! parents, and both are refused with the node's index: walking them as written would repeat
//! subtrees without bound (a cycle) or exponentially (a DAG of shared children).
use glam::{DMat4, Mat4};

/// Deeper hierarchies are refused (a valid 10,000-level chain loads).
pub(crate) const MAX_DEPTH: usize = 1 << 16;

const UNSEEN: usize = usize::MAX;
const ROOT: usize = usize::MAX - 1;

/// The mesh instances among `nodes` (from [`nodes`]) as (node index, mesh, world transform).
pub(crate) fn instances<'a>(
    doc: &'a gltf::Document,
    nodes: &[(usize, DMat4)],
) -> Vec<(usize, gltf::Mesh<'a>, DMat4)> {
    let all: Vec<gltf::Node<'a>> = doc.nodes().collect();
    nodes
        .iter()
        .filter_map(|&(i, world)| Some((i, all.get(i)?.mesh()?, world)))
        .collect()
}

/// Every node of `scene` as (node index, world transform), each visited once (meshes,
/// cameras and lights are read from the same walk).
pub(crate) fn nodes<'a>(
    doc: &'a gltf::Document,
    scene: &gltf::Scene<'a>,
) -> Result<Vec<(usize, DMat4)>, String> {
    let nodes: Vec<gltf::Node<'a>> = doc.nodes().collect();
    let mut parent = vec![UNSEEN; nodes.len()];
    let mut stack: Vec<(usize, DMat4, usize)> = Vec::new();
    for r in scene.nodes() {
        let i = r.index();
        if parent[i] != UNSEEN {
            return Err(format!(
                "node {i}: listed twice among the scene's root nodes"
            ));
        }
        parent[i] = ROOT;
        stack.push((i, DMat4::IDENTITY, 1));
    }
    let is_ancestor = |parent: &[usize], a: usize, mut j: usize| loop {
        if j == a {
            return true;
        }
        if j >= parent.len() {
            return false;
        }
        j = parent[j];
    };
    let mut out = Vec::new();
    while let Some((i, up, depth)) = stack.pop() {
        let node = &nodes[i];
        let local = Mat4::from_cols_array_2d(&node.transform().matrix()).as_dmat4();
        let world = up * local;
        out.push((i, world));
        for c in node.children() {
            let ci = c.index();
            if parent[ci] != UNSEEN {
                return Err(if is_ancestor(&parent, ci, i) {
                    format!(
                        "node {ci}: the node graph has a cycle (node {i} lists its ancestor \
                         {ci} as a child)"
                    )
                } else if parent[ci] == ROOT {
                    format!("node {ci}: a scene root is also a child of node {i}")
                } else {
                    format!(
                        "node {ci} has two parents (nodes {} and {i}); glTF nodes must form trees",
                        parent[ci]
                    )
                });
            }
            if depth >= MAX_DEPTH {
                return Err(format!(
                    "node {ci}: the node hierarchy is deeper than {MAX_DEPTH} levels"
                ));
            }
            parent[ci] = i;
            stack.push((ci, world, depth + 1));
        }
    }
    Ok(out)
}
