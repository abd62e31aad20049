//! glTF extensions decoded by the loader: `EXT_meshopt_compression` (vertex and index views
//! encoded with meshoptimizer, the view's own buffer a placeholder) loads the same triangles as
//! the plain file; an unknown required extension is named.
use crate::common::*;
use crate::gltf_materials::b64;
use glview::scene::{load, LoadOptions};

#[test]
fn meshopt_compressed_views_decode_to_the_plain_geometry() {
    let pos: [[f32; 3]; 4] = [[0., 0., 0.], [2., 0., 0.], [2., 1., 0.], [0., 1., 0.]];
    let idx: [u32; 6] = [0, 1, 2, 0, 2, 3];
    let v = meshopt::encode_vertex_buffer(&pos).unwrap();
    let i = meshopt::encode_index_buffer(&idx, pos.len()).unwrap();
    let mut packed = v.clone();
    packed.extend(&i);
    let json = format!(
        r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}],
      "extensionsUsed": ["EXT_meshopt_compression"], "extensionsRequired": ["EXT_meshopt_compression"],
      "nodes": [{{"mesh": 0}}],
      "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}, "indices": 1}}]}}],
      "buffers": [{{"uri": "data:application/octet-stream;base64,{}", "byteLength": {}}},
                  {{"byteLength": 72, "extensions": {{"EXT_meshopt_compression": {{"fallback": true}}}}}}],
      "bufferViews": [
        {{"buffer": 1, "byteLength": 48, "byteStride": 12, "extensions": {{"EXT_meshopt_compression":
          {{"buffer": 0, "byteLength": {}, "byteStride": 12, "count": 4, "mode": "ATTRIBUTES"}}}}}},
        {{"buffer": 1, "byteOffset": 48, "byteLength": 24, "extensions": {{"EXT_meshopt_compression":
          {{"buffer": 0, "byteOffset": {}, "byteLength": {}, "byteStride": 4, "count": 6, "mode": "TRIANGLES"}}}}}}],
      "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [2, 1, 0]}},
                    {{"bufferView": 1, "componentType": 5125, "count": 6, "type": "SCALAR"}}]}}"#,
        b64(&packed),
        packed.len(),
        v.len(),
        v.len(),
        i.len()
    );
    let p = out_dir("gltf-extensions").join("meshopt.gltf");
    std::fs::write(&p, &json).unwrap();
    let s = load(&p, &LoadOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.triangle_count(), 2);
    assert_eq!(
        s.file_bounds,
        (glam::DVec3::ZERO, glam::DVec3::new(2.0, 1.0, 0.0))
    );
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    // Corrupt compressed bytes: a clean error naming the view.
    let bad = json.replace(&b64(&packed), &b64(&vec![0xA0; packed.len()]));
    let p = out_dir("gltf-extensions").join("meshopt-bad.gltf");
    std::fs::write(&p, bad).unwrap();
    let e = load(&p, &LoadOptions::default()).unwrap_err().to_string();
    assert!(
        e.contains("meshopt-bad.gltf: buffer view 0: cannot decode"),
        "{e}"
    );
}
