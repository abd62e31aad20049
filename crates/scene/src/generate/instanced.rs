//! A glTF file of one cube drawn `n` times through `EXT_mesh_gpu_instancing`, and its twin with
//! the same instances written out as child nodes (same buffer, same TRS values): the
//! instancing test's and `glview bench --instancing`'s pair. Instances sit on a square grid,
//! each turned about its own axis and scaled unevenly (positive scales), so normals need the
//! inverse transpose.
use serde_json::{json, Value};

/// The two documents and the buffer both name (`uri`).
pub struct InstancedGltf {
    pub instanced: String,
    pub twin: String,
    pub bin: Vec<u8>,
    pub uri: &'static str,
}

/// The cube: 24 corners (a normal per face), 12 triangles, 16-bit indices.
fn cube() -> (Vec<[f32; 3]>, Vec<[f32; 3]>, Vec<u16>) {
    let (mut p, mut n, mut idx) = (Vec::new(), Vec::new(), Vec::new());
    for axis in 0..3 {
        for sign in [1.0f32, -1.0] {
            let mut normal = [0.0; 3];
            normal[axis] = sign;
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            let base = p.len() as u16;
            for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                let mut q = [0.0f32; 3];
                q[axis] = 0.5 * sign;
                q[u] = 0.5 * a;
                q[v] = 0.5 * b * sign;
                p.push(q);
                n.push(normal);
            }
            idx.extend([0, 1, 2, 0, 2, 3].map(|i| base + i));
        }
    }
    (p, n, idx)
}

/// Instance `k`'s translation, rotation (a unit quaternion) and scale, on a grid of `side`.
fn trs(k: usize, side: usize) -> ([f32; 3], [f32; 4], [f32; 3]) {
    let (x, z) = ((k % side) as f32, (k / side) as f32);
    let c = (side as f32 - 1.0) * 0.5;
    let t = [1.5 * (x - c), 0.25 * ((k % 7) as f32), 1.5 * (z - c)];
    let angle = 0.37 * k as f32;
    let axis = glam::Vec3::new(1.0, 2.0 + (k % 3) as f32, 0.5).normalize();
    let q = glam::Quat::from_axis_angle(axis, angle).to_array();
    let s = [0.6 + 0.1 * (k % 3) as f32, 0.8, 1.0 + 0.05 * (k % 5) as f32];
    (t, q, s)
}

fn accessor(view: usize, count: usize, ty: &str, component: u32) -> Value {
    json!({"bufferView": view, "componentType": component, "count": count, "type": ty})
}

/// `n` instances of the cube (at least one).
pub fn instanced_gltf(n: usize) -> InstancedGltf {
    let n = n.max(1);
    let side = (n as f64).sqrt().ceil() as usize;
    let (p, normals, idx) = cube();
    let inst: Vec<_> = (0..n).map(|k| trs(k, side)).collect();
    let mut bin = Vec::new();
    let mut views = Vec::new();
    let mut push = |bytes: &[u8], bin: &mut Vec<u8>| {
        views.push(json!({"buffer": 0, "byteOffset": bin.len(), "byteLength": bytes.len()}));
        bin.extend_from_slice(bytes);
        // Every view starts 4-byte aligned.
        bin.resize(bin.len().next_multiple_of(4), 0);
    };
    push(bytemuck::cast_slice(&p), &mut bin);
    push(bytemuck::cast_slice(&normals), &mut bin);
    push(bytemuck::cast_slice(&idx), &mut bin);
    let t: Vec<[f32; 3]> = inst.iter().map(|i| i.0).collect();
    let r: Vec<[f32; 4]> = inst.iter().map(|i| i.1).collect();
    let s: Vec<[f32; 3]> = inst.iter().map(|i| i.2).collect();
    push(bytemuck::cast_slice(&t), &mut bin);
    push(bytemuck::cast_slice(&r), &mut bin);
    push(bytemuck::cast_slice(&s), &mut bin);
    let uri = "instances.bin";
    let mut pos = accessor(0, p.len(), "VEC3", 5126);
    pos["min"] = json!([-0.5, -0.5, -0.5]);
    pos["max"] = json!([0.5, 0.5, 0.5]);
    let base = json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2}]}],
        "accessors": [
            pos,
            accessor(1, normals.len(), "VEC3", 5126),
            accessor(2, idx.len(), "SCALAR", 5123),
            accessor(3, n, "VEC3", 5126),
            accessor(4, n, "VEC4", 5126),
            accessor(5, n, "VEC3", 5126),
        ],
        "bufferViews": views,
        "buffers": [{"uri": uri, "byteLength": bin.len()}],
    });
    let mut instanced = base.clone();
    instanced["extensionsUsed"] = json!(["EXT_mesh_gpu_instancing"]);
    instanced["nodes"] = json!([{"mesh": 0, "extensions": {"EXT_mesh_gpu_instancing":
        {"attributes": {"TRANSLATION": 3, "ROTATION": 4, "SCALE": 5}}}}]);
    let mut twin = base;
    let mut nodes = vec![json!({"children": (1..=n).collect::<Vec<_>>()})];
    nodes.extend(
        inst.iter()
            .map(|(t, r, s)| json!({"mesh": 0, "translation": t, "rotation": r, "scale": s})),
    );
    twin["nodes"] = Value::Array(nodes);
    InstancedGltf {
        instanced: instanced.to_string(),
        twin: twin.to_string(),
        bin,
        uri,
    }
}
