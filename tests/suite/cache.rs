//! The mesh cache: a second load of an unchanged large OBJ comes from the cache and equals a
//! fresh parse; any change to the file (time, size, content) or its MTL invalidates it.
use crate::common;
use glview::scene::cache;
use glview::scene::material::TextureOptions;
use glview::scene::obj::{load, LoadOptions};
use std::time::{Duration, SystemTime};

#[test]
fn second_load_hits_and_changes_invalidate() {
    let dir = common::out_dir("cache");
    let entries = dir.join("entries");
    let _ = std::fs::remove_dir_all(&entries);
    // In-process loads of this test binary use this folder from now on (other tests load
    // with the cache off, or through child processes with their own environment).
    cache::set_dir(entries.clone());
    let model = dir.join("dragon.obj");
    std::fs::copy(
        common::shared().join("models/dragon-200k/dragon_vrip_res2.obj"),
        &model,
    )
    .unwrap();
    let mtl = dir.join("dragon.mtl");
    std::fs::write(&mtl, "newmtl m\nKd 0.5 0.6 0.7\n").unwrap();
    let text = std::fs::read_to_string(&model).unwrap();
    std::fs::write(&model, format!("mtllib dragon.mtl\nusemtl m\n{text}")).unwrap();
    let tex = TextureOptions::default();
    let bytes = || std::fs::read(&model).unwrap();

    let off = LoadOptions {
        cache: false,
        ..Default::default()
    };
    let on = LoadOptions {
        cache: true,
        ..Default::default()
    };
    let fresh = load(&model, &off).unwrap();
    assert!(!entries.exists(), "--no-cache must not write an entry");
    assert!(cache::get(&model, &bytes(), tex).is_none());

    let t = std::time::Instant::now();
    load(&model, &on).unwrap(); // miss: parses and writes the entry
    let miss = t.elapsed();
    let t = std::time::Instant::now();
    let hit = load(&model, &on).unwrap();
    let hit_time = t.elapsed();
    eprintln!("dragon: parse {miss:?}, cache hit {hit_time:?}");
    assert!(
        cache::get(&model, &bytes(), tex).is_some(),
        "no valid entry after a load"
    );
    assert_eq!(hit.meshes.len(), fresh.meshes.len());
    for (a, b) in hit.meshes.iter().zip(&fresh.meshes) {
        assert_eq!(a.vertices, b.vertices);
        assert_eq!(a.indices, b.indices);
        assert_eq!(a.material, b.material);
    }
    assert_eq!(hit.materials, fresh.materials);
    assert_eq!(
        (hit.origin, hit.bounds, hit.file_bounds),
        (fresh.origin, fresh.bounds, fresh.file_bounds)
    );

    // A newer modification time: miss.
    let f = std::fs::File::options().append(true).open(&model).unwrap();
    f.set_modified(SystemTime::now() + Duration::from_secs(5))
        .unwrap();
    assert!(
        cache::get(&model, &bytes(), tex).is_none(),
        "mtime change not seen"
    );
    load(&model, &on).unwrap();
    assert!(cache::get(&model, &bytes(), tex).is_some());

    // Same size, same time, other content: the hash catches it.
    let when = std::fs::metadata(&model).unwrap().modified().unwrap();
    let mut b = bytes();
    let i = b.iter().position(|&c| c == b'1').unwrap();
    b[i] = b'2';
    std::fs::write(&model, &b).unwrap();
    std::fs::File::options()
        .append(true)
        .open(&model)
        .unwrap()
        .set_modified(when)
        .unwrap();
    assert!(
        cache::get(&model, &bytes(), tex).is_none(),
        "content change not seen"
    );
    load(&model, &on).unwrap();

    // The MTL changed: the cached materials are stale.
    std::fs::write(&mtl, "newmtl m\nKd 0.9 0.1 0.1\n").unwrap();
    std::fs::File::options()
        .append(true)
        .open(&mtl)
        .unwrap()
        .set_modified(SystemTime::now() + Duration::from_secs(9))
        .unwrap();
    assert!(
        cache::get(&model, &bytes(), tex).is_none(),
        "MTL change not seen"
    );
    let reloaded = load(&model, &on).unwrap();
    assert_eq!(reloaded.materials[0].diffuse, [0.9, 0.1, 0.1]);
}
