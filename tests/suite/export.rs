//! `glview export`: the lesson page's pictures are `glview -o`'s (pixel for pixel in PNG
//! mode, within the JPEG bound otherwise), its first view is the default camera's, its
//! numbers are `--diff phong,pbr`'s, the SCORM package holds the page and a manifest that
//! launches it, and bad export options are one-line errors. Tiny grids: 4 × 2 at 96 × 72.
use crate::common::*;
use glview::image_out::Rgba;
use std::path::{Path, PathBuf};

const MODEL: &str = "models/box_on_floor.obj";
const SIZE: &str = "96x72";

/// Runs `glview export MODEL -o dir/NAME.html` with `extra` and returns the page's data.
fn export(dir: &Path, name: &str, extra: &[&str]) -> (PathBuf, serde_json::Value) {
    let page = dir.join(format!("{name}.html"));
    let mut args = vec![
        "export",
        MODEL,
        "-o",
        page.to_str().unwrap(),
        "--size",
        SIZE,
    ];
    args.extend_from_slice(&["--yaw-steps", "4", "--pitch-steps", "2"]);
    args.extend_from_slice(extra);
    let o = run(&args, &[]);
    assert!(
        o.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    let html = std::fs::read_to_string(&page).unwrap();
    (page, page_data(&html))
}

/// The JSON block the page's script reads.
fn page_data(html: &str) -> serde_json::Value {
    let open = r#"<script type="application/json" id="glview-data">"#;
    let start = html.find(open).expect("data block") + open.len();
    let end = start + html[start..].find("</script>").expect("end of data block");
    serde_json::from_str(&html[start..end]).expect("data is JSON")
}

fn base64_decode(s: &str) -> Vec<u8> {
    let val = |c: u8| match c {
        b'A'..=b'Z' => c - b'A',
        b'a'..=b'z' => c - b'a' + 26,
        b'0'..=b'9' => c - b'0' + 52,
        b'+' => 62,
        b'/' => 63,
        _ => panic!("not base64: {c}"),
    };
    let bytes: Vec<u8> = s.bytes().filter(|&c| c != b'=').map(val).collect();
    bytes
        .chunks(4)
        .flat_map(|q| {
            let n = q
                .iter()
                .enumerate()
                .fold(0u32, |n, (i, &v)| n | u32::from(v) << (18 - 6 * i));
            let b = n.to_be_bytes();
            b[1..q.len()].to_vec()
        })
        .collect()
}

/// Picture `v` of `tier` ("phong", "pbr") decoded from its data URI.
fn picture(data: &serde_json::Value, tier: &str, v: usize) -> Rgba {
    let uri = data[tier][v].as_str().expect("a data URI");
    let b64 = uri.split_once(";base64,").expect("base64 data URI").1;
    let img = image::load_from_memory(&base64_decode(b64))
        .expect("a picture")
        .to_rgba8();
    Rgba {
        width: img.width(),
        height: img.height(),
        data: img.into_raw(),
    }
}

/// Yaw and pitch of view `v` as the command line words the page's numbers are (f32).
fn angles(data: &serde_json::Value, v: usize) -> (String, String) {
    let ny = data["yaws"].as_array().unwrap().len();
    let f = |x: &serde_json::Value| (x.as_f64().unwrap() as f32).to_string();
    (f(&data["yaws"][v % ny]), f(&data["pitches"][v / ny]))
}

#[test]
fn png_views_are_the_pictures_of_glview_o() {
    let dir = out_dir("export-png");
    let (_, data) = export(&dir, "png", &["--png"]);
    let start = data["start"].as_u64().unwrap() as usize;
    // The first view is `glview MODEL -o` with no camera option at all.
    let default = render(&dir, "default", &[MODEL, "--size", SIZE], &[]);
    assert_eq!(
        picture(&data, "phong", start).data,
        default.data,
        "first view"
    );
    for v in 0..8 {
        let (yaw, pitch) = angles(&data, v);
        for tier in ["phong", "pbr"] {
            let name = format!("v{v}-{tier}");
            let args = [
                MODEL,
                "--size",
                SIZE,
                "--yaw",
                &yaw,
                "--pitch",
                &pitch,
                "--shading",
                tier,
            ];
            let o = render(&dir, &name, &args, &[]);
            let p = picture(&data, tier, v);
            if p.data != o.data {
                let d = write_diff(&dir, &name, &p, &o);
                panic!(
                    "view {v} {tier} (yaw {yaw} pitch {pitch}) is not glview -o's: {}",
                    d.display()
                );
            }
        }
    }
    // The page's numbers are `--diff phong,pbr`'s over the model's pixels.
    let out = dir.join("d.png");
    let o = run(
        &[
            "--diff",
            "phong,pbr",
            MODEL,
            "--size",
            SIZE,
            "-o",
            out.to_str().unwrap(),
        ],
        &[],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let diff: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("d.json")).unwrap()).unwrap();
    let n = &data["numbers"][start];
    for k in ["mean", "p99", "over_8"] {
        assert_eq!(
            n[k].as_f64(),
            diff["model"][k].as_f64(),
            "{k}: {n} against {diff}"
        );
    }
    assert_eq!(n["pixels"].as_u64(), diff["model_pixels"].as_u64());
}

/// The JPEG pictures against the PNG export's (the same renders, so only the encoding
/// differs). The bound is the measurement at the default quality on this grid
/// (`scripts/export_quality.py models/box_on_floor.obj --size 96x72 --grid 4x2`: worst mean
/// 2.24/255, worst 99th percentile 28/255; docs/export.md) with margin: a wrong view or a
/// lower quality is far outside it.
#[test]
fn jpeg_views_are_within_the_measured_bound() {
    let dir = out_dir("export-jpeg");
    let (_, png) = export(&dir, "png", &["--png"]);
    let (_, jpeg) = export(&dir, "jpeg", &[]);
    for v in 0..8 {
        for tier in ["phong", "pbr"] {
            let (mean, share) = jpeg_error(&picture(&png, tier, v), &picture(&jpeg, tier, v));
            assert!(
                mean < 3.0 && share < 0.01,
                "view {v} {tier}: mean {mean} share over 40/255 {share}"
            );
        }
    }
    // A wrong view is far outside the bound: view 1 against view 0.
    let (mean, share) = jpeg_error(&picture(&png, "phong", 0), &picture(&jpeg, "phong", 1));
    assert!(mean > 3.0 || share > 0.01, "{mean} {share}");
}

/// As scripts/export_quality.py measures: the mean over channels (in 1/255) and the share
/// of pixels whose largest channel differs by more than 40/255.
fn jpeg_error(a: &Rgba, b: &Rgba) -> (f64, f64) {
    let mut sum = 0u64;
    let mut over = 0usize;
    for (p, q) in a.data.chunks_exact(4).zip(b.data.chunks_exact(4)) {
        let d = [0, 1, 2].map(|c| p[c].abs_diff(q[c]));
        sum += d.iter().map(|&x| u64::from(x)).sum::<u64>();
        over += usize::from(d.into_iter().max().unwrap_or(0) > 40);
    }
    let n = (a.width * a.height) as f64;
    (sum as f64 / (3.0 * n), over as f64 / n)
}

/// Reads the files of a zip by its central directory (as unzip does).
fn unzip(z: &[u8]) -> Vec<(String, Vec<u8>)> {
    use std::io::Read;
    let le16 = |o: usize| u16::from_le_bytes([z[o], z[o + 1]]) as usize;
    let le32 = |o: usize| u32::from_le_bytes(z[o..o + 4].try_into().unwrap()) as usize;
    let end = z.len() - 22;
    assert_eq!(le32(end), 0x0605_4b50, "end of central directory");
    let mut at = le32(end + 16);
    let mut files = Vec::new();
    for _ in 0..le16(end + 10) {
        assert_eq!(le32(at), 0x0201_4b50);
        let (packed, nlen, local) = (le32(at + 20), le16(at + 28), le32(at + 42));
        let name = String::from_utf8(z[at + 46..at + 46 + nlen].to_vec()).unwrap();
        let start = local + 30 + le16(local + 26) + le16(local + 28);
        let mut data = Vec::new();
        flate2::read::DeflateDecoder::new(&z[start..start + packed])
            .read_to_end(&mut data)
            .unwrap();
        assert_eq!(data.len(), le32(at + 24), "{name}");
        files.push((name, data));
        at += 46 + nlen + le16(at + 30) + le16(at + 32);
    }
    files
}

#[test]
fn scorm_package_launches_the_page() {
    let dir = out_dir("export-scorm");
    let zip = dir.join("lesson.zip");
    let title = "Bunny & <friends>";
    let (page, data) = export(
        &dir,
        "scorm",
        &[
            "--scorm",
            zip.to_str().unwrap(),
            "--title",
            title,
            "--caption",
            "Turn it",
        ],
    );
    assert_eq!(data["title"], title);
    let files = unzip(&std::fs::read(&zip).unwrap());
    let names: Vec<&str> = files.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["imsmanifest.xml", "index.html"]);
    assert_eq!(
        files[1].1,
        std::fs::read(&page).unwrap(),
        "the package's page is the page"
    );
    let manifest = String::from_utf8(files[0].1.clone()).unwrap();
    for must in [
        "<schemaversion>1.2</schemaversion>",
        r#"adlcp:scormtype="sco" href="index.html""#,
        "<title>Bunny &amp; &lt;friends&gt;</title>",
        "Turn it",
    ] {
        assert!(manifest.contains(must), "{must} missing:\n{manifest}");
    }
    // The same options make the same bytes (fixed zip timestamps, no clock in the page).
    let again = dir.join("again.zip");
    export(
        &dir,
        "again",
        &[
            "--scorm",
            again.to_str().unwrap(),
            "--title",
            title,
            "--caption",
            "Turn it",
        ],
    );
    assert_eq!(std::fs::read(&zip).unwrap(), std::fs::read(&again).unwrap());
}

/// The page asks for nothing: no URL outside data URIs, a policy that forbids requests.
#[test]
fn page_is_self_contained() {
    let dir = out_dir("export-self-contained");
    let (page, _) = export(
        &dir,
        "page",
        &["--caption", "</script><script>alert(1)</script>"],
    );
    let html = std::fs::read_to_string(page).unwrap();
    assert!(html.contains("default-src 'none'"));
    assert_eq!(html.matches("<script").count(), 2, "the caption stays text");
    for bad in ["http:", "https:", "src=\"//", "<link", "import "] {
        assert!(!html.contains(bad), "{bad}");
    }
}

#[test]
fn bad_export_options_are_one_line_errors() {
    let dir = out_dir("export-bad");
    let page = dir.join("bad.html");
    let p = page.to_str().unwrap();
    for (args, says) in [
        (
            vec!["export", MODEL, "-o", p, "--yaw-steps", "0"],
            "--yaw-steps",
        ),
        (
            vec!["export", MODEL, "-o", p, "--pitch-steps", "11"],
            "within",
        ),
        (
            vec!["export", MODEL, "-o", p, "--quality", "0"],
            "--quality",
        ),
        (vec!["export", MODEL, "-o", p, "--", "--aa", "msaa"], "--aa"),
        (vec!["export", "models/missing.obj", "-o", p], "missing.obj"),
        (
            vec![
                "export",
                MODEL,
                "-o",
                "no/such/dir/x.html",
                "--size",
                "16x12",
            ],
            "no/such/dir",
        ),
    ] {
        let o = run(&args, &[]);
        let err = String::from_utf8_lossy(&o.stderr);
        let last = err.lines().last().unwrap_or_default();
        assert!(
            !o.status.success() && last.starts_with("error: ") && last.contains(says),
            "{args:?}: {err}"
        );
    }
    // Over --max-size: written, with a warning.
    let o = run(
        &[
            "export",
            MODEL,
            "-o",
            p,
            "--size",
            "16x12",
            "--max-size",
            "1K",
        ],
        &[],
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        o.status.success() && err.contains("over --max-size"),
        "{err}"
    );
}

/// A stereo lesson page (`-- --stereo MODE`): its PNG views are `glview -o --stereo MODE`'s,
/// pixel for pixel, and the page is laid out at the pictures' size (side-by-side-full's
/// twice as wide).
#[test]
fn stereo_views_are_the_stereo_pictures_of_glview_o() {
    let dir = out_dir("export-stereo");
    for (mode, width) in [("anaglyph", 96), ("side-by-side-full", 192)] {
        let (page, data) = export(&dir, mode, &["--png", "--", "--stereo", mode]);
        assert_eq!(data["size"], serde_json::json!([width, 72]), "{mode}");
        let html = std::fs::read_to_string(page).unwrap();
        assert!(
            html.contains(&format!("width=\"{width}\"")),
            "{mode}: the page's canvas"
        );
        for v in [0, 5] {
            let (yaw, pitch) = angles(&data, v);
            let args = [
                MODEL, "--size", SIZE, "--yaw", &yaw, "--pitch", &pitch, "--stereo", mode,
            ];
            let o = render(&dir, &format!("{mode}-v{v}"), &args, &[]);
            let p = picture(&data, "phong", v);
            assert_eq!((p.width, p.height), (o.width, o.height), "{mode} view {v}");
            assert!(
                p.data == o.data,
                "{mode} view {v} is not glview -o --stereo's"
            );
        }
    }
}

/// A stand-in for the browser build in `dir/web`: the export reads it, nothing runs it.
fn fake_web_dir(dir: &Path) -> PathBuf {
    let web = dir.join("web");
    std::fs::create_dir_all(web.join("no-modules")).unwrap();
    std::fs::write(web.join("glview_web_bg.wasm"), b"\0asm-not-really").unwrap();
    std::fs::write(web.join("no-modules/glview_web.js"), b"let wasm_bindgen;").unwrap();
    web
}

/// `--live`'s page carries the model as scene bytes (what the export's loader made of it,
/// through a linked folder too, named under /lesson/), the options naming it, the maps and
/// the browser build's bytes, all gzipped: each unpacks to what it was. The browser's side
/// is python/tests_web/test_live_export.py (scripts/test_web.sh).
#[test]
fn live_pages_carry_the_scene_bytes_the_maps_and_the_renderer() {
    at_repo();
    let dir = out_dir("export_live");
    let web = fake_web_dir(&dir);
    let avocado = shared().join("gltf-samples/Avocado");
    let link = dir.join("linked");
    let _ = std::fs::remove_file(&link);
    std::os::unix::fs::symlink(&avocado, &link).unwrap();
    let model = link.join("Avocado.gltf");
    let page = dir.join("live.html");
    let args = [
        "export",
        model.to_str().unwrap(),
        "-o",
        page.to_str().unwrap(),
        "--live",
        "--web-dir",
        web.to_str().unwrap(),
        "--size",
        "64x48",
        "--yaw-steps",
        "2",
        "--pitch-steps",
        "1",
    ];
    let o = run(&args, &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let html = std::fs::read_to_string(&page).unwrap();
    assert!(
        html.contains("'wasm-unsafe-eval'"),
        "the policy lets the renderer compile"
    );
    assert!(html.contains("let wasm_bindgen;"), "the glue is inlined");
    let data = page_data(&html);
    let live = &data["live"];
    let gunzip = |s: &serde_json::Value| {
        let mut out = Vec::new();
        let z = base64_decode(s.as_str().unwrap());
        std::io::Read::read_to_end(&mut flate2::read::GzDecoder::new(&z[..]), &mut out).unwrap();
        out
    };
    assert_eq!(gunzip(&live["wasm"]), b"\0asm-not-really");
    // The Avocado travels as scene bytes (its decoded textures gzip to about its PNGs:
    // SCENE_BYTES_MAX_RATIO), not as its files: the scene glview loads, with its textures,
    // named under /lesson/ and nowhere by the teacher's folders (the link's or its target's).
    assert!(
        live["files"].as_array().unwrap().is_empty(),
        "{}",
        live["files"]
    );
    let (scene, _) = glview::scene::cache::from_bytes(gunzip(&live["prepared"]))
        .expect("the scene bytes read back");
    let native = glview::scene::load::load(&model, &Default::default()).unwrap();
    let triangles =
        |s: &glview::scene::Scene| -> usize { s.meshes.iter().map(|m| m.indices.len() / 3).sum() };
    assert_eq!(triangles(&scene), triangles(&native));
    let textures = scene
        .materials
        .iter()
        .flat_map(|m| m.slots())
        .flatten()
        .count();
    assert_eq!(
        textures,
        native
            .materials
            .iter()
            .flat_map(|m| m.slots())
            .flatten()
            .count()
    );
    assert!(textures > 0);
    let bytes = String::from_utf8_lossy(&gunzip(&live["prepared"])).into_owned();
    for folder in [&avocado, &link] {
        assert!(
            !bytes.contains(folder.to_str().unwrap()),
            "the scene bytes name {}",
            folder.display()
        );
    }
    assert!(bytes.contains("/lesson/"), "its textures are the page's");
    let words: Vec<&str> = live["words"]
        .as_array()
        .unwrap()
        .iter()
        .map(|w| w.as_str().unwrap())
        .collect();
    assert!(words.contains(&"/lesson/Avocado.gltf"), "{words:?}");
    let maps = glview::pbr::store::bytes::decode(&gunzip(&live["maps"])).expect("maps decode");
    assert_eq!(
        maps.specular.first().map(|c| c.size),
        Some(128),
        "the default --ibl-size"
    );
    // Without the browser build: one line that says how to make it.
    let none = dir.join("none");
    std::fs::create_dir_all(&none).unwrap();
    let mut bad = args.to_vec();
    bad[6] = none.to_str().unwrap();
    let o = run(&bad, &[]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && err.trim().lines().count() == 1,
        "{err}"
    );
    assert!(err.contains("scripts/build_web.sh"), "{err}");
}

/// A model whose scene bytes would outgrow its files (here a triangle and its MTL: the bytes'
/// header alone is larger) travels as its files, exactly those the loader read.
#[test]
fn live_pages_carry_small_models_as_their_files() {
    at_repo();
    let dir = out_dir("export_live_small");
    let web = fake_web_dir(&dir);
    let obj = "mtllib tri.mtl\nusemtl a\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    std::fs::write(dir.join("tri.obj"), obj).unwrap();
    std::fs::write(dir.join("tri.mtl"), "newmtl a\nKd 1 0 0\n").unwrap();
    let page = dir.join("live.html");
    let o = run(
        &[
            "export",
            dir.join("tri.obj").to_str().unwrap(),
            "-o",
            page.to_str().unwrap(),
            "--live-only",
            "--web-dir",
            web.to_str().unwrap(),
            "--size",
            "64x48",
        ],
        &[],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let data = page_data(&std::fs::read_to_string(&page).unwrap());
    let live = &data["live"];
    assert!(live["prepared"].is_null(), "{}", live["prepared"]);
    let mut paths: Vec<&str> = live["files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["path"].as_str().unwrap())
        .collect();
    paths.sort_unstable();
    assert_eq!(paths, ["/lesson/tri.mtl", "/lesson/tri.obj"]);
}
