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
        // The entry holds the indices reordered for clusters, as an uncached render does.
        let mut reordered = b.indices.clone();
        glview::scene::clusters::reorder(&b.vertices, &mut reordered);
        assert_eq!(a.indices, reordered);
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
    // A load trusts the metadata (size, time, inode: unchanged here) unless asked to verify.
    assert!(cache::lookup(&model, tex).is_some());
    cache::set_verify(true);
    assert!(cache::lookup(&model, tex).is_none(), "verified lookup");
    load(&model, &on).unwrap();
    cache::set_verify(false);
    assert!(cache::get(&model, &bytes(), tex).is_some(), "rewritten");

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

/// A cached load is the uncached one: the same pixels and the same `--check` report (but for
/// the load's timing line), for an OBJ and for a format that used to bypass the cache (STL).
#[test]
fn cached_loads_render_and_check_as_uncached_ones() {
    let dir = common::out_dir("cache_equal");
    let entries = dir.join("entries");
    let _ = std::fs::remove_dir_all(&entries);
    let env = [("GLVIEW_CACHE_DIR", entries.to_str().unwrap())];
    // An ASCII STL sphere above cache::MIN_SIZE.
    let mut stl = String::from("solid s\n");
    let (rings, segments) = (80u32, 160u32);
    let p = |j: u32, i: u32| {
        let th = std::f64::consts::PI * f64::from(j) / f64::from(rings);
        let ph = std::f64::consts::TAU * f64::from(i) / f64::from(segments);
        [th.sin() * ph.sin(), th.cos(), th.sin() * ph.cos()]
    };
    for j in 0..rings {
        for i in 0..segments {
            for t in [
                [p(j, i), p(j + 1, i), p(j + 1, i + 1)],
                [p(j, i), p(j + 1, i + 1), p(j, i + 1)],
            ] {
                stl.push_str("facet normal 0 0 0\nouter loop\n");
                for v in t {
                    stl.push_str(&format!("vertex {} {} {}\n", v[0], v[1], v[2]));
                }
                stl.push_str("endloop\nendfacet\n");
            }
        }
    }
    stl.push_str("endsolid s\n");
    let sphere = dir.join("sphere.stl");
    std::fs::write(&sphere, stl).unwrap();
    assert!(std::fs::metadata(&sphere).unwrap().len() >= cache::MIN_SIZE);
    let dragon = common::shared().join("models/dragon-200k/dragon_vrip_res2.obj");
    let check = |model: &str, extra: &[&str]| -> String {
        let o = common::run(&[&[model, "--check"], extra].concat(), &env);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stdout)
            .lines()
            .filter(|l| !l.starts_with("load: "))
            .collect::<Vec<_>>()
            .join("\n")
    };
    for (name, model) in [
        ("stl", sphere.to_str().unwrap()),
        ("obj", dragon.to_str().unwrap()),
    ] {
        let args = [model, "--size", "160x120", "--yaw", "60"];
        let fresh = common::render(
            &dir,
            &format!("{name}-fresh"),
            &[&args[..], &["--no-cache"]].concat(),
            &env,
        );
        let entries_before = std::fs::read_dir(&entries).map(|d| d.count()).unwrap_or(0);
        let miss = common::render(&dir, &format!("{name}-miss"), &args, &env);
        let written = std::fs::read_dir(&entries).unwrap().count();
        assert_eq!(written, entries_before + 1, "{name}: one entry written");
        let hit = common::render(&dir, &format!("{name}-hit"), &args, &env);
        for (what, img) in [("miss", &miss), ("hit", &hit)] {
            let d = common::diff(&fresh, img, 0);
            assert_eq!(d.max, 0, "{name} {what}: {} pixels differ", d.over);
        }
        let uncached = check(model, &["--no-cache"]);
        assert_eq!(
            uncached,
            check(model, &[]),
            "{name}: --check from the entry"
        );
        assert!(uncached.contains("result: renders"), "{uncached}");
    }
}
