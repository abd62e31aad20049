//! The mesh cache: hits, misses, corrupt entries and the size bound.
use super::*;
use std::time::Duration;
use {crate::load::options::LoadOptions, crate::loaders::obj::load_bytes};

/// A fresh folder with `n` small models; returns it and (path, bytes, scene) per model.
fn setup(name: &str, n: usize) -> (PathBuf, Vec<(PathBuf, Vec<u8>, Scene)>) {
    let dir = std::env::temp_dir().join(format!("glview-cache-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("entries")).unwrap();
    let models = (0..n)
        .map(|i| {
            let p = dir.join(format!("m{i}.obj"));
            let bytes = format!("v 0 0 0\nv {} 0 0\nv 0 1 0\nf 1 2 3\n", i + 1).into_bytes();
            std::fs::write(&p, &bytes).unwrap();
            let s = load_bytes(&p, &bytes, &LoadOptions::default()).unwrap();
            (p, bytes, s)
        })
        .collect();
    (dir, models)
}

fn entry(dir: &Path, model: &Path) -> PathBuf {
    entry_path(&dir.join("entries"), model).unwrap()
}

#[test]
fn truncated_and_flipped_entries_are_misses_then_rebuilt() {
    let (dir, models) = setup("corrupt", 1);
    let (p, bytes, scene) = &models[0];
    let entries = dir.join("entries");
    let tex = TextureOptions::default();
    put_in(&entries, 1 << 20, p, Some(bytes), tex, (scene, &[None])).unwrap();
    let good = std::fs::read(entry(&dir, p)).unwrap();
    assert!(get_in(&entries, p, Some(bytes), tex).is_some());
    // Every truncation and a flipped bit at every 7th byte: a miss, never a panic.
    let mut cases: Vec<Vec<u8>> = (0..good.len())
        .step_by(5)
        .map(|n| good[..n].to_vec())
        .collect();
    for i in (0..good.len()).step_by(7) {
        let mut b = good.clone();
        b[i] ^= 0x10;
        cases.push(b);
    }
    for (k, bad) in cases.iter().enumerate() {
        std::fs::write(entry(&dir, p), bad).unwrap();
        let got = get_in(&entries, p, Some(bytes), tex);
        // A flip inside JSON whitespace-insensitive text can leave an equal header; then
        // the entry must still decode to the same triangles.
        if let Some((s, _)) = got {
            assert_eq!(s.meshes[0].indices, scene.meshes[0].indices, "case {k}");
            assert_eq!(s.meshes[0].vertices, scene.meshes[0].vertices, "case {k}");
        }
    }
    // Rebuilt by the next write.
    put_in(&entries, 1 << 20, p, Some(bytes), tex, (scene, &[None])).unwrap();
    assert!(get_in(&entries, p, Some(bytes), tex).is_some());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn flipped_payload_byte_is_a_miss() {
    let (dir, models) = setup("payload", 1);
    let (p, bytes, scene) = &models[0];
    let entries = dir.join("entries");
    let tex = TextureOptions::default();
    put_in(&entries, 1 << 20, p, Some(bytes), tex, (scene, &[None])).unwrap();
    let mut b = std::fs::read(entry(&dir, p)).unwrap();
    let last = b.len() - 1;
    b[last] ^= 1;
    std::fs::write(entry(&dir, p), &b).unwrap();
    assert!(get_in(&entries, p, Some(bytes), tex).is_none());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn least_recently_used_entries_are_evicted_first() {
    let (dir, models) = setup("lru", 3);
    let entries = dir.join("entries");
    let tex = TextureOptions::default();
    let put = |i: usize, limit: u64| {
        let (p, b, s) = &models[i];
        put_in(&entries, limit, p, Some(b), tex, (s, &[None])).unwrap();
    };
    let age = |i: usize, secs: u64| {
        let f = std::fs::File::options()
            .append(true)
            .open(entry(&dir, &models[i].0))
            .unwrap();
        f.set_modified(SystemTime::now() - Duration::from_secs(secs))
            .unwrap();
    };
    put(0, 1 << 20);
    put(1, 1 << 20);
    let one = std::fs::metadata(entry(&dir, &models[0].0)).unwrap().len();
    // Room for two entries (they are within a few bytes of each other in size).
    let limit = one * 2 + one / 2;
    age(0, 30);
    age(1, 20);
    // Using model 0 makes model 1 the least recently used.
    let (p0, b0, _) = &models[0];
    assert!(get_in(&entries, p0, Some(b0), tex).is_some());
    put(2, limit);
    let exists = |i: usize| entry(&dir, &models[i].0).exists();
    assert_eq!((exists(0), exists(1), exists(2)), (true, false, true));
    // A bound below one entry keeps only the newest... and an entry larger than the bound
    // is not written at all.
    evict(&entries, one, &entry(&dir, &models[2].0)).unwrap();
    assert_eq!((exists(0), exists(1), exists(2)), (false, false, true));
    let (p1, b1, s1) = &models[1];
    assert!(put_in(&entries, 8, p1, Some(b1), tex, (s1, &[None])).is_err());
    assert!(!exists(1));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Scene bytes (the browser's: `glview export --live`, serve's local mode) read back as the
/// scene they were made of, its compact first section and levels included; any truncation or
/// flipped byte is refused (None), never a panic, and never a lazy failure later: the second
/// section is checked when the bytes are read.
#[test]
fn scene_bytes_read_back_as_the_scene_and_refuse_damage() {
    // A wavy 120x120 grid (28,800 triangles): over the cluster threshold, so the bytes carry
    // clusters and levels.
    let n = 120;
    let mut obj = String::new();
    for j in 0..=n {
        for i in 0..=n {
            let (x, z) = (i as f32 / n as f32, j as f32 / n as f32);
            obj.push_str(&format!(
                "v {x} {} {z}\n",
                0.05 * (9.0 * x).sin() * (7.0 * z).cos()
            ));
        }
    }
    for j in 0..n {
        for i in 0..n {
            let a = j * (n + 1) + i + 1;
            let (b, c, d) = (a + 1, a + n + 1, a + n + 2);
            obj.push_str(&format!("f {a} {c} {b}\nf {b} {c} {d}\n"));
        }
    }
    let p = Path::new("grid.obj");
    let mut scene = load_bytes(p, obj.as_bytes(), &LoadOptions::default()).unwrap();
    let clusters = crate::lod::clusters::prepare(&mut scene);
    assert!(clusters.iter().any(Option::is_some), "no clusters to carry");
    let bytes = to_bytes((&scene, &clusters), &[]).unwrap();
    let (back, back_clusters) = from_bytes(bytes.clone()).expect("reads back");
    assert_eq!(back.meshes.len(), scene.meshes.len());
    for (a, b) in back.meshes.iter().zip(scene.meshes.iter()) {
        assert!(a.vertices == b.vertices && a.indices == b.indices);
    }
    assert_eq!(back.bounds, scene.bounds);
    let levels = |c: &[Option<Clusters>]| -> Vec<usize> {
        c.iter().flatten().map(|c| c.lod.index_count).collect()
    };
    assert_eq!(levels(&back_clusters), levels(&clusters));
    let step = bytes.len() / 97 + 1;
    for n in (0..bytes.len()).step_by(step) {
        assert!(
            from_bytes(bytes[..n].to_vec()).is_none(),
            "truncated to {n}"
        );
    }
    for i in (0..bytes.len()).step_by(step) {
        let mut b = bytes.clone();
        b[i] ^= 0x10;
        // A flip in the header's JSON may still parse to an equal header; then the scene
        // is the same one.
        if let Some((s, _)) = from_bytes(b) {
            assert!(
                s.meshes[0].indices == scene.meshes[0].indices,
                "flip at {i}"
            );
        }
    }
}
