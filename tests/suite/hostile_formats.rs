//! Hostile STL, PLY and glTF files (issue 20), each run as its own `glview --check` process
//! under a 4 GiB address-space limit and a 60 s deadline, with its peak resident memory
//! measured by `/usr/bin/time`: exit code 1, one line `error: FILE...` saying what is wrong,
//! peak ≤ 1.5 GB. The few that are survivable (a missing or corrupt image, a non-finite STL
//! facet) load with one warning naming where the problem is.
use crate::bad_input::run_with_deadline;
use crate::common::*;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

const PEAK_LIMIT_KB: u64 = 1_500_000;

/// (exit code, stdout, stderr, peak RSS in KB) of `glview --check FILE` under the limits.
fn check(file: &Path) -> (Option<i32>, String, String, u64) {
    let rss = file.with_extension("rss");
    let script = format!(
        "ulimit -v 4194304; exec /usr/bin/time -o '{}' -f %M '{}' --check '{}'",
        rss.display(),
        bin(),
        file.display()
    );
    let o = run_with_deadline(
        Command::new("sh").args(["-c", &script]),
        Duration::from_secs(60),
    )
    .unwrap_or_else(|| panic!("{}: killed after 60 s", file.display()));
    let peak = std::fs::read_to_string(&rss)
        .ok()
        .and_then(|s| s.lines().last()?.trim().parse().ok())
        .unwrap_or_else(|| panic!("{}: no peak RSS measured", file.display()));
    let text = |b: &[u8]| String::from_utf8_lossy(b).into_owned();
    (o.status.code(), text(&o.stdout), text(&o.stderr), peak)
}

/// Refused: exit 1, one line naming the file and containing `expect`, within the memory bound.
fn refused(file: &Path, expect: &str) -> u64 {
    let (code, _, err, peak) = check(file);
    let name = file.file_name().unwrap().to_string_lossy();
    assert_eq!(code, Some(1), "{name}: {err}");
    let lines: Vec<&str> = err.lines().collect();
    assert_eq!(lines.len(), 1, "{name}: expected one line:\n{err}");
    assert!(
        lines[0].starts_with(&format!("error: {}", file.display())),
        "{name}: {err}"
    );
    assert!(lines[0].contains(expect), "{name}: {expect:?} not in {err}");
    assert!(peak <= PEAK_LIMIT_KB, "{name}: peak RSS {peak} KB");
    eprintln!("{name}: refused, peak RSS {peak} KB");
    peak
}

/// Loads (exit 0) with a warning containing `expect` in the `--check` report.
fn warned(file: &Path, expect: &str) {
    let (code, out, err, peak) = check(file);
    let name = file.file_name().unwrap().to_string_lossy();
    assert_eq!(code, Some(0), "{name}: {err}");
    assert!(
        out.lines()
            .any(|l| l.starts_with("warning: ") && l.contains(expect)),
        "{name}: no warning with {expect:?} in:\n{out}"
    );
    assert!(peak <= PEAK_LIMIT_KB, "{name}: peak RSS {peak} KB");
    eprintln!("{name}: loaded with a warning, peak RSS {peak} KB");
}

fn gzip(bytes: &[u8], out: &Path) {
    let f = std::fs::File::create(out).unwrap();
    let mut e = flate2::write::GzEncoder::new(f, flate2::Compression::fast());
    std::io::Write::write_all(&mut e, bytes).unwrap();
    e.finish().unwrap();
}

/// A gzip stream of `header` then `zeros` zero bytes, written without holding them.
fn gzip_zeros(header: &[u8], zeros: usize, out: &Path) {
    use std::io::Write;
    let f = std::fs::File::create(out).unwrap();
    let mut e = flate2::write::GzEncoder::new(f, flate2::Compression::fast());
    e.write_all(header).unwrap();
    let block = vec![0u8; 1 << 20];
    let mut left = zeros;
    while left > 0 {
        let n = left.min(block.len());
        e.write_all(&block[..n]).unwrap();
        left -= n;
    }
    e.finish().unwrap();
}

/// A one-triangle glTF with its buffer in `tri.bin` beside it; `edit` changes the JSON text.
pub fn tri_gltf(dir: &Path, name: &str, edit: &dyn Fn(String) -> String) -> PathBuf {
    let mut bin = Vec::new();
    for x in [0f32, 0., 0., 1., 0., 0., 0., 1., 0.] {
        bin.extend(x.to_le_bytes());
    }
    std::fs::write(dir.join("tri.bin"), &bin).unwrap();
    let json = r#"{"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
      "nodes": [{"mesh": 0}],
      "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
      "buffers": [{"uri": "tri.bin", "byteLength": 36}],
      "bufferViews": [{"buffer": 0, "byteLength": 36}],
      "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                     "min": [0, 0, 0], "max": [1, 1, 0]}]}"#;
    let p = dir.join(name);
    std::fs::write(&p, edit(json.to_string())).unwrap();
    p
}

/// `n` nodes as JSON, node k having `children(k)`, node 0 the mesh.
fn nodes(n: usize, children: &dyn Fn(usize) -> Vec<usize>) -> String {
    let v: Vec<String> = (0..n)
        .map(|k| {
            let c = children(k);
            let mesh = if k == n - 1 { "\"mesh\": 0, " } else { "" };
            format!("{{{mesh}\"children\": {c:?}}}")
        })
        .collect();
    format!("\"nodes\": [{}]", v.join(", "))
}

/// Hostile glTF files in `sub` whose node graph or buffer path is what is wrong, with the
/// error each must be refused with (the one naming `../secret.bin` is `cases[3]`).
fn graph_and_path_cases(sub: &Path) -> Vec<(PathBuf, &'static str)> {
    let node_list = |s: String, n: String| s.replace(r#""nodes": [{"mesh": 0}]"#, &n);
    vec![
        // The issue's 1 KB cycle: 0 → 1 → 0.
        (
            tri_gltf(sub, "cycle.gltf", &|s| {
                node_list(s, nodes(2, &|k| vec![1 - k]))
            }),
            "node 0: the node graph has a cycle",
        ),
        (
            tri_gltf(sub, "self.gltf", &|s| node_list(s, nodes(1, &|_| vec![0]))),
            "cycle",
        ),
        // A DAG: node k lists k+1 and k+2, 2^40 paths when walked as written.
        (
            tri_gltf(sub, "dag.gltf", &|s| {
                node_list(s, nodes(42, &|k| (k + 1..(k + 3).min(42)).collect()))
            }),
            "has two parents",
        ),
        (
            tri_gltf(sub, "outside.gltf", &|s| {
                s.replace("tri.bin", "../secret.bin")
            }),
            "outside the model's folder",
        ),
        (
            tri_gltf(sub, "outside-pct.gltf", &|s| {
                s.replace("tri.bin", "%2e%2e/secret.bin")
            }),
            "outside the model's folder",
        ),
        (
            tri_gltf(sub, "remote.gltf", &|s| {
                s.replace("tri.bin", "http://example.com/tri.bin")
            }),
            "URI scheme \"http\" is not supported",
        ),
    ]
}

/// Hostile glTF files in `sub` whose sizes, counts or required extensions are what is wrong,
/// with the error each must be refused with.
fn size_and_content_cases(sub: &Path) -> Vec<(PathBuf, &'static str)> {
    vec![
        (
            // A buffer shorter than its byteLength is read as the bytes there (three.js
            // does; tests/suite/gltf_quirks.rs); a view reaching past them is refused.
            tri_gltf(sub, "short-buffer.gltf", &|s| {
                s.replace("\"byteLength\": 36", "\"byteLength\": 40000")
            }),
            "buffer view 0: bytes 0..+40000 lie beyond buffer 0 (36 bytes)",
        ),
        (
            tri_gltf(sub, "huge-buffer.gltf", &|s| {
                s.replacen("\"byteLength\": 36", "\"byteLength\": 4000000000", 1)
            }),
            "buffer 0 (\"tri.bin\"): byteLength 4000000000 is more than glview reads",
        ),
        (
            tri_gltf(sub, "count.gltf", &|s| {
                s.replace("\"count\": 3", "\"count\": 3000000")
            }),
            "accessor 0: 3000000 elements of 12 bytes",
        ),
        (
            tri_gltf(sub, "huge-count.gltf", &|s| {
                s.replace("\"count\": 3", "\"count\": 18446744073709551615")
            }),
            "",
        ),
        (
            tri_gltf(sub, "sparse.gltf", &|s| {
                s.replace(
                    "\"max\": [1, 1, 0]}",
                    "\"max\": [1, 1, 0], \"sparse\": {\"count\": 1, \
                     \"indices\": {\"bufferView\": 0, \"byteOffset\": 12, \"componentType\": 5125}, \
                     \"values\": {\"bufferView\": 0}}}",
                )
            }),
            "sparse index 1065353216 (entry 0)",
        ),
        (
            tri_gltf(sub, "required.gltf", &|s| {
                s.replace(
                    "\"scene\": 0",
                    "\"extensionsUsed\": [\"EXT_not_an_extension\"], \
                     \"extensionsRequired\": [\"EXT_not_an_extension\"], \"scene\": 0",
                )
            }),
            "requires glTF extension EXT_not_an_extension, which glview does not support",
        ),
        // The triangle's own float bytes given as a Draco stream (issue 37), as points.
        (
            tri_gltf(sub, "draco.gltf", &|s| {
                s.replace(
                    "{\"attributes\": {\"POSITION\": 0}}",
                    "{\"attributes\": {\"POSITION\": 0}, \"mode\": 0, \"extensions\": \
                     {\"KHR_draco_mesh_compression\": {\"bufferView\": 0, \
                     \"attributes\": {\"POSITION\": 0}}}}",
                )
            }),
            "mesh 0 primitive 0: KHR_draco_mesh_compression: cannot decode",
        ),
        // One mesh instanced by 200,000 nodes, its accessor claiming 100 vertices: 20 M.
        (
            tri_gltf(sub, "instances.gltf", &|s| {
                let roots: Vec<usize> = (0..200_000).collect();
                let n = vec!["{\"mesh\": 0}"; 200_000].join(",");
                s.replace(
                    "\"scenes\": [{\"nodes\": [0]}]",
                    &format!("\"scenes\": [{{\"nodes\": {roots:?}}}]"),
                )
                .replace(r#""nodes": [{"mesh": 0}]"#, &format!("\"nodes\": [{n}]"))
                .replace("\"count\": 3", "\"count\": 100")
            }),
            "instances more than 16777216 vertices",
        ),
    ]
}

#[test]
fn hostile_gltf_files_are_refused_within_bounds() {
    let dir = out_dir("hostile-gltf");
    let sub = dir.join("model");
    std::fs::create_dir_all(&sub).unwrap();
    std::fs::write(dir.join("secret.bin"), [0u8; 36]).unwrap();
    let mut cases = graph_and_path_cases(&sub);
    cases.extend(size_and_content_cases(&sub));
    std::fs::write(sub.join("nan.bin"), {
        let mut b = Vec::new();
        for x in [0f32, 0., 0., 1., f32::NAN, 0., 0., 1., 0.] {
            b.extend(x.to_le_bytes());
        }
        b
    })
    .unwrap();
    let nan = tri_gltf(&sub, "nan.gltf", &|s| s.replace("tri.bin", "nan.bin"));
    for (file, expect) in &cases {
        refused(file, expect);
    }
    refused(
        &nan,
        "accessor 0 (POSITION of mesh 0 primitive 0): element 1 is not finite",
    );
    // With --allow-outside-paths the same buffer is read.
    let o = run(
        &[
            "--check",
            "--allow-outside-paths",
            cases[3].0.to_str().unwrap(),
        ],
        &[],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn broken_gltf_images_are_warnings() {
    let dir = out_dir("hostile-gltf-images");
    std::fs::write(dir.join("corrupt.png"), b"\x89PNG\r\n\x1a\nnot really").unwrap();
    let textured = |img: &'static str| {
        move |s: String| {
            s.replace(
                "\"meshes\"",
                &format!(
                    "\"materials\": [{{\"pbrMetallicRoughness\": {{\"baseColorTexture\": \
                     {{\"index\": 0}}}}}}], \"textures\": [{{\"source\": 0}}], \
                     \"images\": [{{\"uri\": \"{img}\"}}], \"meshes\""
                ),
            )
            .replace("\"POSITION\": 0}", "\"POSITION\": 0}, \"material\": 0")
        }
    };
    let missing = tri_gltf(&dir, "missing-image.gltf", &textured("nope.png"));
    warned(&missing, "image 0 (\"nope.png\"): file not found");
    let corrupt = tri_gltf(&dir, "corrupt-image.gltf", &textured("corrupt.png"));
    warned(&corrupt, "image 0 (\"corrupt.png\")");
    let data = tri_gltf(
        &dir,
        "data-image.gltf",
        &textured("data:image/png;base64,iVBORw0K"),
    );
    warned(&data, "image 0");
}

#[test]
fn hostile_ply_and_stl_files_are_refused_within_bounds() {
    let dir = out_dir("hostile-ply-stl");
    let ply = |n: u64| {
        format!(
            "ply\nformat binary_little_endian 1.0\nelement vertex {n}\nproperty float x\n\
             property float y\nproperty float z\nelement face 0\n\
             property list uchar int vertex_indices\nend_header\n"
        )
    };
    // The issue's bomb: 200 M vertices promised, then zeros (2.4 GB inflated).
    let bomb = dir.join("bomb.ply.gz");
    gzip_zeros(ply(200_000_000).as_bytes(), 1 << 20, &bomb);
    refused(&bomb, "header claims 200000000 vertex elements");
    // Just under the element limit, and the zeros really there: read as a stream, and
    // (vertices without faces) loaded as a point cloud within the memory bound.
    let full = dir.join("full.ply.gz");
    gzip_zeros(ply(16_000_000).as_bytes(), 16_000_000 * 12, &full);
    let (code, out, err, peak) = check(&full);
    assert_eq!(code, Some(0), "full.ply.gz: {err}");
    assert!(out.contains("point cloud: 16000000 points"), "{out}");
    assert!(peak <= PEAK_LIMIT_KB, "full.ply.gz: peak RSS {peak} KB");
    eprintln!("full.ply.gz (16 M zero vertices streamed, a cloud): peak RSS {peak} KB");
    let short = dir.join("short.ply");
    std::fs::write(&short, ply(1_000_000)).unwrap();
    refused(&short, "header claims elements needing 12000000 bytes");
    let list = dir.join("list.ply.gz");
    let text = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n\
                property float y\nproperty float z\nelement face 1\n\
                property list uint int vertex_indices\nend_header\n";
    let mut b = text.as_bytes().to_vec();
    b.extend([0u8; 36]);
    b.extend(u32::MAX.to_le_bytes());
    gzip(&b, &list);
    refused(&list, "list length 4294967295");
    let nan = dir.join("nan.ply");
    std::fs::write(
        &nan,
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
         property float z\nend_header\n0 0 0\n1 nan 0\n0 1 0\n",
    )
    .unwrap();
    refused(&nan, "nan.ply:9: vertex 1 position is not finite");

    // STL: a count the file cannot hold; a gzipped 16 M zero facets; a NaN facet.
    let mut stl = vec![0u8; 80];
    stl.extend(4_000_000_000u32.to_le_bytes());
    let claim = dir.join("claim.stl");
    std::fs::write(&claim, &stl).unwrap();
    refused(&claim, "4000000000 facets");
    let zeros = dir.join("zeros.stl.gz");
    let mut h = vec![0u8; 80];
    h.extend(16_000_000u32.to_le_bytes());
    gzip_zeros(&h, 16_000_000 * 50, &zeros);
    let peak = refused(&zeros, "no triangles");
    eprintln!("zeros.stl.gz (16 M zero facets streamed): peak RSS {peak} KB");
    let nan = dir.join("nan.stl");
    std::fs::write(
        &nan,
        "solid t\nfacet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n\
         endloop\nendfacet\nfacet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex nan 0 0\n\
         vertex 0 1 0\nendloop\nendfacet\nendsolid t\n",
    )
    .unwrap();
    warned(&nan, "facet 2: non-finite vertex coordinates; dropped");
}
