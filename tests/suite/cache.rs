//! The mesh cache: a second load of an unchanged large OBJ comes from the cache and equals a
//! fresh parse; any change to the file (time, size, content) or its MTL invalidates it.
use crate::common;
use glview::scene::cache;
use glview::scene::model::material::TextureOptions;
use glview::scene::{load, LoadOptions};
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
        glview::scene::lod::clusters::reorder(&b.vertices, &mut reordered);
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
    assert_eq!(reloaded.materials[0].base_color, [0.9, 0.1, 0.1]);
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
        // Levels of detail are built for cache entries, not for one uncached picture.
        let args = [model, "--size", "160x120", "--yaw", "60", "--lod", "off"];
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

/// glTF files without textures go through the cache too, material model included: the hit
/// (`--check` says "(mesh cache)") renders the same pixels and reports the same as an
/// uncached load — an unlit material and a single-sided one seen from behind among them — and
/// rewriting the file makes the next load a miss.
#[test]
fn gltf_without_textures_is_cached_with_its_material_model() {
    let dir = common::out_dir("cache_gltf");
    let entries = dir.join("entries");
    let _ = std::fs::remove_dir_all(&entries);
    let env = [("GLVIEW_CACHE_DIR", entries.to_str().unwrap())];
    // A wavy 300×300 grid in two primitives (left half unlit, right half single-sided and
    // emissive), embedded as base64 so the one file is above cache::MIN_SIZE.
    let n = 300u32;
    let mut pos = Vec::new();
    let mut nrm = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let (x, z) = (
                f32::from(i as u16) / n as f32 - 0.5,
                f32::from(j as u16) / n as f32 - 0.5,
            );
            let y = 0.05 * (x * 20.0).sin() * (z * 15.0).cos();
            pos.extend([x, y, z]);
            nrm.extend([0.0f32, 1.0, 0.0]);
        }
    }
    let (mut left, mut right) = (Vec::new(), Vec::new());
    for j in 0..n {
        for i in 0..n {
            let a = j * (n + 1) + i;
            let (b, c, d) = (a + n + 1, a + n + 2, a + 1);
            let half = if i < n / 2 { &mut left } else { &mut right };
            half.extend([a, b, c, a, c, d]);
        }
    }
    let mut bin: Vec<u8> = Vec::new();
    let mut views = Vec::new();
    for part in [
        bytemuck::cast_slice::<f32, u8>(&pos),
        bytemuck::cast_slice(&nrm),
        bytemuck::cast_slice::<u32, u8>(&left),
        bytemuck::cast_slice(&right),
    ] {
        views.push(format!(
            r#"{{"buffer": 0, "byteOffset": {}, "byteLength": {}}}"#,
            bin.len(),
            part.len()
        ));
        bin.extend_from_slice(part);
    }
    let verts = (n + 1) * (n + 1);
    let json = format!(
        r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}],
      "extensionsUsed": ["KHR_materials_unlit"],
      "nodes": [{{"mesh": 0}}],
      "meshes": [{{"primitives": [
        {{"attributes": {{"POSITION": 0, "NORMAL": 1}}, "indices": 2, "material": 0}},
        {{"attributes": {{"POSITION": 0, "NORMAL": 1}}, "indices": 3, "material": 1}}]}}],
      "materials": [
        {{"pbrMetallicRoughness": {{"baseColorFactor": [0.9, 0.3, 0.1, 1]}},
          "extensions": {{"KHR_materials_unlit": {{}}}}, "doubleSided": true}},
        {{"pbrMetallicRoughness": {{"baseColorFactor": [0.2, 0.5, 0.9, 1]}},
          "emissiveFactor": [0.1, 0.2, 0.0], "doubleSided": false}}],
      "buffers": [{{"byteLength": {}, "uri": "data:application/octet-stream;base64,{}"}}],
      "bufferViews": [{}],
      "accessors": [
        {{"bufferView": 0, "componentType": 5126, "count": {verts}, "type": "VEC3",
          "min": [-0.5, -0.05, -0.5], "max": [0.5, 0.05, 0.5]}},
        {{"bufferView": 1, "componentType": 5126, "count": {verts}, "type": "VEC3"}},
        {{"bufferView": 2, "componentType": 5125, "count": {}, "type": "SCALAR"}},
        {{"bufferView": 3, "componentType": 5125, "count": {}, "type": "SCALAR"}}]}}"#,
        bin.len(),
        crate::gltf_materials::b64(&bin),
        views.join(", "),
        left.len(),
        right.len()
    );
    let model = dir.join("grid.gltf");
    std::fs::write(&model, json).unwrap();
    assert!(std::fs::metadata(&model).unwrap().len() >= cache::MIN_SIZE);
    let model = model.to_str().unwrap();
    let check = |extra: &[&str]| -> (String, String) {
        let o = common::run(&[&[model, "--check"], extra].concat(), &env);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let out = String::from_utf8_lossy(&o.stdout).into_owned();
        let (load, rest): (Vec<&str>, Vec<&str>) =
            out.lines().partition(|l| l.starts_with("load: "));
        (load.join("\n"), rest.join("\n"))
    };
    for (view, pitch) in [("above", "30"), ("below", "-30")] {
        for shading in ["phong", "pbr"] {
            let name = format!("{view}-{shading}");
            let args = [
                model,
                "--size",
                "160x120",
                "--pitch",
                pitch,
                "--shading",
                shading,
            ];
            miss_and_hit_equal_uncached(&dir, &name, &args, &env);
        }
    }
    let (uncached_load, uncached) = check(&["--no-cache"]);
    let (cached_load, cached) = check(&[]);
    assert!(!uncached_load.contains("(mesh cache)"), "{uncached_load}");
    assert!(
        cached_load.contains("(mesh cache)"),
        "not a hit: {cached_load}"
    );
    assert_eq!(uncached, cached, "--check from the entry");
    assert!(
        cached.contains("KHR_materials_unlit") && cached.contains("doubleSided false"),
        "{cached}"
    );
    // A rewritten file (same content, new modification time) is a miss, then a hit again.
    let bytes = std::fs::read(model).unwrap();
    std::thread::sleep(std::time::Duration::from_millis(20));
    std::fs::write(model, bytes).unwrap();
    assert!(
        !check(&[]).0.contains("(mesh cache)"),
        "a rewritten file hit"
    );
    assert!(check(&[]).0.contains("(mesh cache)"));
}

/// A textured glTF is cached with everything it gives: its decoded images (shared between
/// slots that name the same one), the second UV set and the supplied tangents. Rendered from
/// the entry in both tiers it equals the uncached picture, and a hit decodes no image; an
/// external image is a dependency, so rewriting it makes the entry a miss.
#[test]
fn textured_gltf_is_cached_with_its_images_uv_sets_and_tangents() {
    let dir = common::out_dir("cache_gltf_textured");
    let entries = dir.join("entries");
    let _ = std::fs::remove_dir_all(&entries);
    let env = [("GLVIEW_CACHE_DIR", entries.to_str().unwrap())];
    let model = textured_quad(&dir);
    assert!(std::fs::metadata(&model).unwrap().len() >= cache::MIN_SIZE);
    let m = model.to_str().unwrap();
    for shading in ["phong", "pbr"] {
        let args = [
            m,
            "--size",
            "96x96",
            "--ortho",
            "2",
            "--yaw",
            "20",
            "--pitch",
            "10",
            "--shading",
            shading,
        ];
        miss_and_hit_equal_uncached(&dir, shading, &args, &env);
    }
    // `--check` from the entry says what the fresh load says (texture lines included).
    let check = |extra: &[&str]| -> (bool, Vec<String>) {
        let o = common::run(&[&[m, "--check"], extra].concat(), &env);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let out = String::from_utf8_lossy(&o.stdout).into_owned();
        let hit = out
            .lines()
            .any(|l| l.starts_with("load: ") && l.contains("(mesh cache)"));
        let rest = out.lines().filter(|l| !l.starts_with("load: "));
        (hit, rest.map(str::to_owned).collect())
    };
    let ((hit, cached), (_, fresh)) = (check(&[]), check(&["--no-cache"]));
    assert!(hit, "not a hit: {cached:?}");
    assert_eq!(cached, fresh, "--check from the entry");
    assert!(cached
        .iter()
        .any(|l| l.contains("TEXCOORD_1") || l.contains("UV set 1")));

    let own = dir.join("own-entries");
    let _ = std::fs::remove_dir_all(&own);
    entry_equals_fresh_scene(&own, &model);
    external_image_is_a_dependency(&dir, &own);
}

/// The textured test's model: a quad with a 1100² base colour of noise, a normal map and an
/// emissive ramp, the metallic-roughness and emissive slots naming one image; two UV sets and
/// supplied tangents.
fn textured_quad(dir: &std::path::Path) -> std::path::PathBuf {
    use crate::gltf_draw::{png, quad, Quad};
    // A 1100² base colour of noise (PNG cannot compress it), so the file is above MIN_SIZE.
    let mut seed = 0x2545_f491_u32;
    let mut next = || {
        seed ^= seed << 13;
        seed ^= seed >> 17;
        seed ^= seed << 5;
        seed
    };
    let noise: Vec<[u8; 4]> = (0..1100 * 1100)
        .map(|_| {
            let v = next().to_le_bytes();
            [v[0], v[1], v[2], 255]
        })
        .collect();
    // A normal map of slopes in x and y, and an emissive ramp.
    let normals: Vec<[u8; 4]> = (0..16 * 16)
        .map(|i| [96 + (i % 16) as u8 * 4, 96 + (i / 16) as u8 * 4, 230, 255])
        .collect();
    let emissive: Vec<[u8; 4]> = (0..8 * 8).map(|i| [i as u8 * 3, 0, 40, 255]).collect();
    let q = Quad {
        uv0: [[0., 0.], [3., 0.], [3., 3.], [0., 3.]],
        uv1: Some([[0., 0.], [1., 0.], [1., 1.], [0., 1.]]),
        tangent: Some([1., 0., 0., 1.]),
        ..Quad::default()
    };
    let materials = format!(
        r#""materials": [{{"pbrMetallicRoughness": {{"baseColorTexture": {{"index": 0}},
            "metallicRoughnessTexture": {{"index": 2, "texCoord": 1}}}},
          "normalTexture": {{"index": 1, "texCoord": 1}},
          "emissiveTexture": {{"index": 2, "texCoord": 1}}, "emissiveFactor": [1, 1, 1]}}],
        "textures": [{{"source": 0}}, {{"source": 1}}, {{"source": 2}}],
        "images": [{{"uri": "{}"}}, {{"uri": "{}"}}, {{"uri": "{}"}}]"#,
        png(1100, 1100, &noise),
        png(16, 16, &normals),
        png(8, 8, &emissive)
    );
    quad(dir, "textured", &q, &materials)
}

/// The textured model put in and read back from `own` in process equals the fresh scene:
/// every stream and every image, the metallic-roughness and emissive slots sharing one image.
fn entry_equals_fresh_scene(own: &std::path::Path, model: &std::path::Path) {
    use glview::scene::lod::clusters;
    let off = LoadOptions {
        cache: false,
        ..Default::default()
    };
    let tex = TextureOptions::default();
    let mut fresh = load(model, &off).unwrap();
    let prepared = clusters::prepare(&mut fresh);
    cache::put_in(own, 1 << 30, model, None, tex, (&fresh, &prepared)).unwrap();
    let (hit, _) = cache::get_in(own, model, None, tex).expect("a hit");
    for (a, b) in hit.meshes.iter().zip(&fresh.meshes) {
        assert_eq!(
            (&a.vertices, &a.indices, &a.uv1, &a.tangents, &a.colors),
            (&b.vertices, &b.indices, &b.uv1, &b.tangents, &b.colors)
        );
        assert_eq!(a.uv1.len(), a.vertices.len());
        assert_eq!(a.tangents.len(), a.vertices.len());
    }
    let (a, b) = (&hit.materials[0], &fresh.materials[0]);
    assert_eq!(a, b);
    use glview::scene::model::texture_slot::Slot;
    let pixels = |m: &glview::scene::Material, s: Slot| {
        let t = m.image(s).expect("a texture");
        (t.width, t.height, t.rgba.clone(), t.image)
    };
    for s in [
        Slot::BaseColor,
        Slot::Normal,
        Slot::Emissive,
        Slot::MetallicRoughness,
    ] {
        assert_eq!(pixels(a, s), pixels(b, s), "{s:?}");
    }
    assert!(std::sync::Arc::ptr_eq(
        a.image(Slot::Emissive).unwrap(),
        a.image(Slot::MetallicRoughness).unwrap()
    ));
}

/// An external image is a dependency of the entry: rewriting it makes the entry a miss.
fn external_image_is_a_dependency(dir: &std::path::Path, own: &std::path::Path) {
    use crate::gltf_draw::{quad, Quad};
    use glview::scene::lod::clusters;
    let off = LoadOptions {
        cache: false,
        ..Default::default()
    };
    let tex = TextureOptions::default();
    let ext = dir.join("ext.png");
    image::RgbaImage::from_raw(2, 1, vec![255, 0, 0, 255, 0, 255, 0, 255])
        .unwrap()
        .save(&ext)
        .unwrap();
    let materials = r#""materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
        "textures": [{"source": 0}], "images": [{"uri": "ext.png"}]"#;
    let model = quad(dir, "external", &Quad::default(), materials);
    let mut fresh = load(&model, &off).unwrap();
    assert_eq!(fresh.dependencies, vec![ext.canonicalize().unwrap()]);
    let prepared = clusters::prepare(&mut fresh);
    cache::put_in(own, 1 << 30, &model, None, tex, (&fresh, &prepared)).unwrap();
    assert!(cache::get_in(own, &model, None, tex).is_some());
    std::thread::sleep(Duration::from_millis(20));
    image::RgbaImage::from_raw(1, 1, vec![0, 0, 255, 255])
        .unwrap()
        .save(&ext)
        .unwrap();
    assert!(
        cache::get_in(own, &model, None, tex).is_none(),
        "a rewritten external image hit"
    );
}

/// Renders `args` uncached, then twice with the cache (the miss that writes the entry, the
/// hit that reads it): both must be the uncached picture exactly (a diff image on failure).
fn miss_and_hit_equal_uncached(
    dir: &std::path::Path,
    name: &str,
    args: &[&str],
    env: &[(&str, &str)],
) {
    // Levels of detail are built for cache entries, not for one uncached picture.
    let args = &[args, &["--lod", "off"]].concat();
    let fresh = common::render(
        dir,
        &format!("{name}-fresh"),
        &[args, &["--no-cache"][..]].concat(),
        env,
    );
    for what in ["first", "hit"] {
        let img = common::render(dir, &format!("{name}-{what}"), args, env);
        let d = common::diff(&fresh, &img, 0);
        if d.max != 0 {
            common::write_diff(dir, &format!("{name}-{what}"), &fresh, &img);
        }
        assert_eq!(d.max, 0, "{name} {what}: {} pixels differ", d.over);
    }
}

/// A large mesh's entry: its first section holds the whole levels compact, the rest the
/// full arrays. A flipped byte in the first is a miss; one in the rest is found when the
/// meshes are first used, and the model is read again (the same meshes): never a wrong one.
#[test]
fn a_flipped_byte_in_either_section_never_gives_a_wrong_mesh() {
    use glview::scene::lod::clusters;
    let dir = common::out_dir("cache_sections");
    let own = dir.join("entries");
    let _ = std::fs::remove_dir_all(&own);
    let model = dir.join("sphere.obj");
    std::fs::write(&model, crate::culling::sphere_obj(129, 256, false)).unwrap();
    let off = LoadOptions::default();
    let mut fresh = load(&model, &off).unwrap();
    let prepared = clusters::prepare(&mut fresh);
    let tex = TextureOptions::default();
    cache::put_in(&own, 1 << 30, &model, None, tex, (&fresh, &prepared)).unwrap();
    let path = std::fs::read_dir(&own)
        .unwrap()
        .flatten()
        .next()
        .unwrap()
        .path();
    let good = std::fs::read(&path).unwrap();
    let header = 12 + u64::from_le_bytes(good[4..12].try_into().unwrap()) as usize;
    let same = |hit: &glview::scene::Scene| {
        hit.meshes.len() == fresh.meshes.len()
            && hit
                .meshes
                .iter()
                .zip(fresh.meshes.iter())
                .all(|(a, b)| a.vertices == b.vertices && a.indices == b.indices)
    };

    let (hit, _) = cache::get_in(&own, &model, None, tex).expect("a hit");
    assert!(
        !hit.meshes.is_read(),
        "the full arrays were read at the hit"
    );
    assert!(same(&hit));
    assert!(
        hit.meshes.bytes_read_later() > 0,
        "the rest came from the entry"
    );

    let mut first = good.clone();
    first[header + 5] ^= 1;
    std::fs::write(&path, &first).unwrap();
    assert!(
        cache::get_in(&own, &model, None, tex).is_none(),
        "first section"
    );

    let mut rest = good.clone();
    let last = rest.len() - 3;
    rest[last] ^= 1;
    std::fs::write(&path, &rest).unwrap();
    let (hit, _) = cache::get_in(&own, &model, None, tex).expect("the first section is sound");
    assert!(same(&hit), "a corrupt rest gave other meshes");
    assert_eq!(
        hit.meshes.bytes_read_later(),
        0,
        "the model, not the entry, was read"
    );
    std::fs::remove_dir_all(&own).unwrap();
}
