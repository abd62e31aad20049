//! Regression tests for the `stl`, `ply` and `gltf` fuzz targets (fuzz/README.md, "Format
//! targets"): each input goes through the target's own code (`run_format` of fuzz/src/lib.rs,
//! included here), which panics on a broken scene invariant or an error that does not name the
//! file in one line. Cases marked "review" were found by reading the loaders while the fuzzers
//! ran; the others are the fuzzers' findings, minimised.
use crate::fuzz_regressions::fuzz_support::run_format;

fn ok(name: &str, data: &[u8]) -> glview::scene::Scene {
    run_format(name, data).unwrap_or_else(|e| panic!("{name}: expected a scene: {e}"))
}

fn err(name: &str, data: &[u8], expect: &str) {
    match run_format(name, data) {
        Ok(s) => panic!(
            "{name}: expected an error, got {} triangles",
            s.triangle_count()
        ),
        Err(e) => assert!(e.to_string().contains(expect), "{name}: {e}"),
    }
}

fn tri_gltf(node: &str, extra_attr: &str, bin: &[u8]) -> Vec<u8> {
    format!(
        r#"{{"asset": {{"version": "2.0"}}, "scenes": [{{"nodes": [0]}}], "nodes": [{node}],
      "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0{extra_attr}}}}}]}}],
      "buffers": [{{"uri": "data:;base64,{}", "byteLength": {}}}],
      "bufferViews": [{{"buffer": 0, "byteLength": 36}}],
      "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                      "min": [0, 0, 0], "max": [1, 1, 0]}}]}}"#,
        crate::gltf_materials::b64(bin),
        bin.len()
    )
    .into_bytes()
}

fn triangle(scale: f32) -> Vec<u8> {
    [0f32, 0., 0., 1., 0., 0., 0., 1., 0.]
        .iter()
        .flat_map(|x| (x * scale).to_le_bytes())
        .collect()
}

/// Review: a node scale times a position beyond f32 range was infinite after rounding.
#[test]
fn gltf_positions_beyond_f32_after_the_node_transform_are_refused() {
    let g = tri_gltf(
        r#"{"mesh": 0, "scale": [1e30, 1e30, 1e30]}"#,
        "",
        &triangle(1e30),
    );
    err("fuzz.gltf", &g, "beyond 32-bit float range");
}

/// Review: a zero scale has no normal matrix; the file's normals would have become NaN.
#[test]
fn gltf_normals_under_a_singular_transform_are_generated() {
    let g = tri_gltf(
        r#"{"mesh": 0, "scale": [1, 1, 0]}"#,
        r#", "NORMAL": 0"#,
        &triangle(1.0),
    );
    let s = ok("fuzz.gltf", &g);
    assert_eq!(s.triangle_count(), 1);
}

/// Review: two vertex elements gave more positions than colours.
#[test]
fn ply_with_two_vertex_elements_keeps_the_invariants() {
    let ply = b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n\
                element vertex 1\nproperty float x\nproperty float y\nproperty float z\n\
                element face 1\nproperty list uchar int vertex_indices\nend_header\n\
                0 0 0 1 2 3\n1 0 0 1 2 3\n0 1 0 1 2 3\n5 5 5\n3 0 1 2\n";
    ok("fuzz.ply", ply);
}

/// Review: an ASCII STL facet may list up to 1024 vertices (a fan), no more.
#[test]
fn stl_facet_with_too_many_vertices_is_refused() {
    let mut s = String::from("solid x\nfacet normal 0 0 1\nouter loop\n");
    for i in 0..1100 {
        s += &format!("vertex {i} {} 0\n", i % 2);
    }
    err(
        "fuzz.stl",
        s.as_bytes(),
        "facet 1 has more than 1024 vertices",
    );
}

/// Finding G1 (gltf target, first minute): a GLB whose header states a length below its own
/// 12 bytes made the gltf crate subtract with overflow (a panic wherever overflow checks are
/// on, as in tests; release builds wrapped and refused it). The smallest equivalent input.
#[test]
fn glb_length_below_the_header_is_refused() {
    let mut glb = b"glTF".to_vec();
    glb.extend(2u32.to_le_bytes());
    glb.extend(4u32.to_le_bytes());
    glb.extend(b"JSON{}");
    err("fuzz.glb", &glb, "GLB header shorter than 12 bytes");
}

/// Finding G2 (gltf target): a POSITION attribute naming an accessor that does not exist
/// panicked inside gltf-json's validator, which indexes the accessors before checking the
/// index. The smallest equivalent input.
#[test]
fn position_accessor_out_of_range_is_refused() {
    let g = br#"{"asset": {"version": "2.0"}, "meshes": [{"primitives": [{"attributes": {"POSITION": 1}}]}]}"#;
    err(
        "fuzz.gltf",
        g,
        "mesh 0 primitive 0: accessor 1 does not exist",
    );
}

/// Finding G3 (gltf target, second run, ~30 s): an image with a `bufferView` but no
/// `mimeType`, or with neither `uri` nor `bufferView`, made the crate's `Image::source`
/// unwrap `None`. Images are now read from the JSON; both are warnings and the model loads.
#[test]
fn images_without_mime_type_or_source_are_warnings() {
    for (image, expect) in [
        (
            r#"{"bufferView": 0}"#,
            "image 0: not an image in a known format",
        ),
        ("{}", "image 0: neither a uri nor a bufferView"),
    ] {
        let g = String::from_utf8(tri_gltf(r#"{"mesh": 0}"#, "", &triangle(1.0)))
            .unwrap()
            .replace(
                "\"meshes\"",
                &format!(
                    "\"images\": [{image}], \"textures\": [{{\"source\": 0}}], \"materials\": \
                     [{{\"pbrMetallicRoughness\": {{\"baseColorTexture\": {{\"index\": 0}}}}}}], \
                     \"meshes\""
                ),
            )
            .replace("\"POSITION\": 0}", "\"POSITION\": 0}, \"material\": 0");
        let s = ok("fuzz.gltf", g.as_bytes());
        assert!(
            s.warnings.iter().any(|w| w.message.contains(expect)),
            "{expect:?} not in {:?}",
            s.warnings
        );
    }
}
