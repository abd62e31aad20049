//! A picture is a function of the model's bytes and the options (issue #41): the same pixels
//! with the mesh cache cold, warm and off, with 1 and 2 threads, and through every front end
//! (`-o`, `glview batch`, the Rust API, the server's still), for a model above the
//! level-of-detail threshold and one below it; and the levels a cache hit brings are the
//! levels built fresh, whatever the thread count.
use crate::common::*;
use crate::culling::sphere_obj;
use crate::serve_client::{decode_png, Server};
use glview::api::{self, Outputs};
use glview::image_out::Rgba;
use glview::image_out::RgbaFiles;
use glview::scene::lod::clusters::{self, Clusters};
use glview::scene::{cache, load, LoadOptions};
use std::path::{Path, PathBuf};

const SIZE: &str = "200x150";

/// 2·256·128 = 65,536 triangles: more than the 30,000 pixels of SIZE, so `--lod auto` draws
/// its levels of detail (the sphere).
const ABOVE: (u32, u32) = (129, 256);
/// 2·160·64 = 20,480 triangles: clustered (more than `clusters::MIN_TRIANGLES`) but fewer than
/// SIZE's pixels, so every triangle is drawn.
const BELOW: (u32, u32) = (65, 160);

/// The sphere OBJ at `dir/sphere.obj`, written every run (a new modification time: no mesh
/// cache entry of an older build is hit) and over the cache's size threshold (comment lines
/// pad a small one), so the first load writes an entry.
fn sphere(dir: &Path, (rings, segments): (u32, u32)) -> String {
    let mut text = sphere_obj(rings, segments, false);
    let min = cache::MIN_SIZE as usize;
    if text.len() < min {
        let pad = "# padding: large enough for a mesh cache entry\n";
        text.push_str(&pad.repeat((min - text.len()) / pad.len() + 1));
    }
    let p = dir.join("sphere.obj");
    std::fs::write(&p, text).unwrap();
    p.to_str().unwrap().to_string()
}

/// A fresh mesh cache folder.
fn empty(dir: &Path, name: &str) -> PathBuf {
    let d = dir.join(name);
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// The binary's `-o` picture of `model` at SIZE with `extra` words, with `cache` as the mesh
/// cache's folder and `threads` rayon threads.
fn cli(dir: &Path, name: &str, model: &str, extra: &[&str], cache: &Path, threads: &str) -> Rgba {
    let out = dir.join(format!("{name}.png"));
    let mut args = vec![model, "--size", SIZE, "-o", out.to_str().unwrap()];
    args.extend_from_slice(extra);
    let env = [
        ("GLVIEW_CACHE_DIR", cache.to_str().unwrap()),
        ("RAYON_NUM_THREADS", threads),
    ];
    let o = run(&args, &env);
    assert!(
        o.status.success(),
        "{name}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    Rgba::load_png(&out).unwrap()
}

/// `glview batch` of `copies` jobs drawing `model` at SIZE, in one process.
fn batch(dir: &Path, name: &str, model: &str, copies: usize, cache: &Path) -> Vec<Rgba> {
    let outs: Vec<PathBuf> = (0..copies)
        .map(|k| dir.join(format!("{name}-{k}.png")))
        .collect();
    let jobs: Vec<String> = outs
        .iter()
        .map(|o| format!("'{model}' --size {SIZE} -o '{}'", o.display()))
        .collect();
    let file = dir.join(format!("{name}.txt"));
    std::fs::write(&file, jobs.join("\n")).unwrap();
    let env = [("GLVIEW_CACHE_DIR", cache.to_str().unwrap())];
    let o = run(&["batch", file.to_str().unwrap()], &env);
    assert!(
        o.status.success(),
        "{name}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    outs.iter().map(|o| Rgba::load_png(o).unwrap()).collect()
}

/// The Rust API's picture (in this process, whatever mesh cache folder it uses: the picture
/// must not depend on it).
fn rust_api(model: &str, extra: &[&str]) -> Rgba {
    let words = [&[model, "--size", SIZE][..], extra].concat();
    let o = glview::Options::from_words(words).expect("valid options");
    api::render(&o, Outputs::default()).unwrap().color
}

/// The first still of `glview serve MODEL --size SIZE`.
fn served(model: &str, cache: &Path) -> Rgba {
    let server = Server::start_with_env(
        &[model, "--size", SIZE],
        &[("GLVIEW_CACHE_DIR", cache.to_str().unwrap())],
    );
    let mut c = server.viewer("");
    c.text("hello");
    decode_png(&c.still(None).1)
}

/// Every way of drawing the picture, named: each must equal the first (cache cold).
fn every_way(dir: &Path, model: &str) -> Vec<(String, Rgba)> {
    let (two, one) = (empty(dir, "cache-2"), empty(dir, "cache-1"));
    let mut all = vec![
        ("cold".into(), cli(dir, "cold", model, &[], &two, "2")),
        ("warm".into(), cli(dir, "warm", model, &[], &two, "2")),
        (
            "no-cache".into(),
            cli(dir, "nc", model, &["--no-cache"], &two, "2"),
        ),
        // The entry written with one thread read with two, and the other way round.
        (
            "cold, 1 thread".into(),
            cli(dir, "cold1", model, &[], &one, "1"),
        ),
        (
            "warm 1 → 2 threads".into(),
            cli(dir, "w12", model, &[], &one, "2"),
        ),
        (
            "warm 2 → 1 thread".into(),
            cli(dir, "w21", model, &[], &two, "1"),
        ),
        (
            "no-cache, 1 thread".into(),
            cli(dir, "nc1", model, &["--no-cache"], &two, "1"),
        ),
    ];
    // A cold batch: the first job misses, the second draws with the kept renderer.
    let cold = batch(dir, "batch-cold", model, 2, &empty(dir, "cache-batch"));
    let warm = batch(dir, "batch-warm", model, 1, &two);
    for (k, img) in cold.into_iter().chain(warm).enumerate() {
        all.push((format!("batch job {k}"), img));
    }
    all.push(("Rust API".into(), rust_api(model, &[])));
    all.push(("Rust API again".into(), rust_api(model, &[])));
    all.push((
        "Rust API, no cache".into(),
        rust_api(model, &["--no-cache"]),
    ));
    // Every combination of read-backs: the colour is drawn from the geometry they are.
    for k in 1..16u8 {
        let outputs = Outputs {
            depth: k & 1 != 0,
            normals: k & 2 != 0,
            ids: k & 4 != 0,
            linear: k & 8 != 0,
        };
        let words = [model, "--size", SIZE];
        let o = glview::Options::from_words(words).expect("valid options");
        let frame = api::render(&o, outputs).unwrap();
        all.push((format!("Rust API with {outputs:?}"), frame.color));
    }
    all.push((
        "server still, cold".into(),
        served(model, &empty(dir, "cache-serve")),
    ));
    all.push(("server still, warm".into(), served(model, &two)));
    all
}

fn assert_all_equal(dir: &Path, all: &[(String, Rgba)]) {
    let (first_name, first) = &all[0];
    for (name, img) in &all[1..] {
        if img.data != first.data {
            let d = write_diff(dir, &name.replace([' ', ','], "_"), img, first);
            let dd = diff(img, first, 0);
            panic!(
                "{name}: {} pixels differ (by up to {}/255) from the {first_name} picture; see {}",
                dd.over,
                dd.max,
                d.display()
            );
        }
    }
}

/// Every way's pictures of a sphere of `size` (all equal, asserted), and the one `--lod
/// off` draws.
fn every_way_and_lod_off(name: &str, size: (u32, u32)) -> (Vec<(String, Rgba)>, Rgba) {
    let dir = out_dir(name);
    let model = sphere(&dir, size);
    let all = every_way(&dir, &model);
    assert_all_equal(&dir, &all);
    let off = cli(
        &dir,
        "lod-off",
        &model,
        &["--lod", "off"],
        &dir.join("cache-2"),
        "2",
    );
    (all, off)
}

#[test]
fn above_the_lod_threshold_every_way_gives_one_picture() {
    let (all, off) = every_way_and_lod_off("determinism_above", ABOVE);
    // The levels take part: every triangle (`--lod off`) is another picture.
    assert!(off.data != all[0].1.data, "--lod off drew the same picture");
}

#[test]
fn below_the_lod_threshold_every_way_gives_one_picture() {
    let (all, off) = every_way_and_lod_off("determinism_below", BELOW);
    // Fewer triangles than pixels: auto draws every one, as `--lod off` does.
    let dir = out_dir("determinism_below");
    assert_all_equal(&dir, &[all[0].clone(), ("--lod off".into(), off)]);
}

/// The clusters and levels `prepare` builds, with a pool of `threads` rayon threads.
fn prepared_with(
    threads: usize,
    scene: &glview::scene::Scene,
) -> (Vec<Vec<u32>>, Vec<Option<Clusters>>) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let mut s = scene.clone();
        let c = clusters::prepare(&mut s);
        (s.meshes.into_iter().map(|m| m.indices).collect(), c)
    })
}

/// The reordering, clusters and levels are the same with 1 and 2 threads, built at once or
/// added later (a miss's way), and a cache hit's levels are those bit for bit.
#[test]
fn levels_are_the_same_however_built() {
    let dir = out_dir("determinism_levels");
    let model = sphere(&dir, ABOVE);
    let off = LoadOptions {
        cache: false,
        ..Default::default()
    };
    let scene = load(Path::new(&model), &off).unwrap();
    let (indices, built) = prepared_with(1, &scene);
    assert!(
        built.iter().flatten().all(|c| !c.lod.groups.is_empty()),
        "no levels built"
    );
    assert!(
        prepared_with(2, &scene) == (indices.clone(), built.clone()),
        "1 and 2 threads differ"
    );

    // A miss's way: clusters first, levels added later.
    let mut later = scene.clone();
    let mut c = clusters::prepare_without_lod(&mut later);
    assert!(c.iter().flatten().all(|c| c.lod.groups.is_empty()));
    clusters::add_lod(&later, &mut c);
    assert!(
        c == built,
        "levels added later differ from levels built at once"
    );

    // Through an entry and back: the hit's mesh and levels are the fresh ones.
    let own = empty(&dir, "entries");
    let tex = Default::default();
    let mut fresh = scene.clone();
    let prepared = clusters::prepare(&mut fresh);
    cache::put_in(
        &own,
        1 << 30,
        Path::new(&model),
        None,
        tex,
        (&fresh, &prepared),
    )
    .unwrap();
    let (hit, mut from_entry) = cache::get_in(&own, Path::new(&model), None, tex).expect("a hit");
    // Meshes the entry's first section holds compact bring their levels with their arrays.
    hit.meshes.complete(&mut from_entry);
    let hit_indices: Vec<Vec<u32>> = hit.meshes.iter().map(|m| m.indices.clone()).collect();
    assert!(hit_indices == indices, "the entry's indices differ");
    assert!(from_entry == built, "the entry's clusters or levels differ");
    // And the levels built from the hit's own mesh are the entry's.
    let mut rebuilt = from_entry.clone();
    for c in rebuilt.iter_mut().flatten() {
        c.lod = Default::default();
    }
    clusters::add_lod(&hit, &mut rebuilt);
    assert!(
        rebuilt == from_entry,
        "levels rebuilt from the hit's mesh differ"
    );
}

/// `--stats`' last line of `glview ARGS` with `cache` as the mesh cache's folder.
fn stats_of(args: &[&str], cache: &Path) -> serde_json::Value {
    let o = run(args, &[("GLVIEW_CACHE_DIR", cache.to_str().unwrap())]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = String::from_utf8_lossy(&o.stdout);
    let line = out
        .lines()
        .rfind(|l| l.starts_with('{'))
        .expect("a --stats line");
    serde_json::from_str(line).unwrap()
}

/// A warm first view of a model above the threshold reads and uploads only the entry's
/// first section (the whole-mesh levels it draws, compact) and draws the cold picture; a
/// later view of the same kept scene that needs every triangle (`--lod off`, a batch's
/// second job) reads the rest then and draws what `--no-cache --lod off` draws. Without
/// shadows: this small sphere's 2048² shadow map needs finer levels than the whole ones
/// (then the first view reads everything, as the shadowed views of the other tests do).
#[test]
fn a_warm_first_view_reads_only_the_levels_it_draws() {
    let dir = out_dir("determinism_compact");
    let model = sphere(&dir, ABOVE);
    let cache = empty(&dir, "cache");
    let cold = cli(&dir, "cold", &model, &["--no-shadows"], &cache, "2");
    let entry: u64 = std::fs::read_dir(&cache)
        .unwrap()
        .flatten()
        .map(|e| e.metadata().unwrap().len())
        .sum();
    let warm = dir.join("warm.png");
    let out = warm.to_str().unwrap();
    let words = [&model, "--size", SIZE, "--no-shadows", "-o", out, "--stats"];
    let s = stats_of(&words, &cache);
    let read = s["profile"]["load"]["entry_bytes"].as_u64().unwrap();
    let uploaded = s["mesh_bytes_uploaded"].as_u64().unwrap();
    assert!(s["profile"]["load"]["cached"].as_bool().unwrap(), "{s}");
    // The whole levels are a small part of the mesh; the full arrays are most of the entry.
    assert!(read > 0 && read * 4 < entry, "read {read} of {entry} bytes");
    assert!(uploaded * 4 < entry, "uploaded {uploaded} of {entry} bytes");
    assert_eq!(s["meshes_completed"], 0, "{s}");
    assert_eq!(s["mesh_bytes_read_later"], 0, "{s}");
    assert_all_equal(
        &dir,
        &[
            ("cold".into(), cold),
            ("warm".into(), Rgba::load_png(&warm).unwrap()),
        ],
    );

    // One process: a compact first view, then one needing every triangle.
    let (first, second) = (dir.join("job1.png"), dir.join("job2.png"));
    let jobs = format!(
        "'{model}' --size {SIZE} --no-shadows -o '{}'\n\
         '{model}' --size {SIZE} --no-shadows --lod off --stats -o '{}'\n",
        first.display(),
        second.display()
    );
    let file = dir.join("jobs.txt");
    std::fs::write(&file, jobs).unwrap();
    let s = stats_of(&["batch", file.to_str().unwrap()], &cache);
    assert_eq!(
        s["profile"]["scene_uploads"], 0,
        "the second job's scene is the kept one"
    );
    assert_eq!(s["meshes_completed"], 1, "{s}");
    assert!(s["mesh_bytes_read_later"].as_u64().unwrap() > read, "{s}");
    let off = cli(
        &dir,
        "off",
        &model,
        &["--lod", "off", "--no-cache"],
        &cache,
        "2",
    );
    assert_all_equal(
        &dir,
        &[
            ("cold --lod off".into(), off),
            (
                "batch job 2, --lod off".into(),
                Rgba::load_png(&second).unwrap(),
            ),
        ],
    );
}
