//! The GPU scene apart from the view: a kept session keys its uploaded scenes by the model
//! and its load options only, and the environment maps by their request, shared by every
//! scene of the context. A change of tier, exposure, bloom, terms, shadows, camera or keys
//! uploads nothing and makes no environment map (`--stats`' profile counts both), and the
//! kept session draws exactly the bytes a fresh one draws.
use super::common;
use glview::session::{Profile, Session};
use glview::Options;

/// Small environment maps, so the first PBR picture's precomputation stays short.
const BASE: &[&str] = &[
    "--size",
    "96x72",
    "--ibl-size",
    "16",
    "--irradiance-size",
    "8",
    "--ibl-samples",
    "8",
];

fn options(extra: &[&str]) -> Options {
    Options::from_words(BASE.iter().chain(extra).copied()).expect("valid options")
}

fn draw(session: &mut Session, o: &Options) -> (Vec<u8>, Profile) {
    let mut p = Profile::default();
    let drawn = session
        .draw(o, None, Default::default(), &mut p)
        .unwrap_or_else(|e| panic!("{o:?}: {e}"));
    (drawn.image.data, p)
}

#[test]
fn view_changes_upload_nothing_and_draw_as_a_fresh_session() {
    common::at_repo();
    let views: &[&[&str]] = &[
        &["--shading", "pbr"],
        &["--shading", "pbr", "--exposure", "1"],
        &["--shading", "phong"],
        &["--shading", "pbr", "--bloom", "0.3"],
        &["--shading", "pbr", "--terms", "ibl-diffuse,ibl-specular"],
        &["--shading", "gouraud", "--no-shadows"],
        &["--shading", "pbr", "--yaw", "60", "--tonemap", "aces"],
        &["--keys", "S P P 4"],
        &["--shading", "pbr"],
    ];
    // One headless context is current per thread: the fresh sessions come after the kept
    // one is gone.
    let mut kept = Session::new();
    let mut pictures = Vec::new();
    for (i, v) in views.iter().enumerate() {
        let (pixels, p) = draw(&mut kept, &options(v));
        let first = u32::from(i == 0);
        assert_eq!(p.scene_uploads, first, "{v:?}: scene uploads");
        assert_eq!(
            p.environments_made,
            u64::from(first),
            "{v:?}: environments made"
        );
        pictures.push(pixels);
    }
    drop(kept);
    for (v, pixels) in views.iter().zip(pictures) {
        let (fresh, _) = draw(&mut Session::new(), &options(v));
        let differ = pixels
            .chunks(4)
            .zip(fresh.chunks(4))
            .filter(|(a, b)| a != b)
            .count();
        assert!(
            differ == 0,
            "{v:?}: the kept session drew other pixels than a fresh one ({differ} differ)"
        );
    }
}

/// Two scenes of one context share the environment's maps: the second scene's first PBR
/// picture makes none, and a new environment is made once for both.
#[test]
fn scenes_of_a_context_share_their_environments() {
    common::at_repo();
    let mut s = Session::new();
    s.keep_scenes(2);
    let sphere = ["--shading", "pbr", "models/sphere.obj"];
    let (_, p) = draw(&mut s, &options(&["--shading", "pbr"]));
    assert_eq!((p.scene_uploads, p.environments_made), (1, 1));
    let (_, p) = draw(&mut s, &options(&sphere));
    assert_eq!((p.scene_uploads, p.environments_made), (1, 0));
    let uniform = ["--shading", "pbr", "--env-color", "0.5,0.4,0.3"];
    let (_, p) = draw(&mut s, &options(&uniform));
    assert_eq!((p.scene_uploads, p.environments_made), (0, 1));
    let mut sphere_uniform = sphere.to_vec();
    sphere_uniform.extend(&uniform[2..]);
    let (_, p) = draw(&mut s, &options(&sphere_uniform));
    assert_eq!((p.scene_uploads, p.environments_made), (0, 0));
}

/// A scene loaded on another thread (`Prepared::load`, as the server's loading workers do)
/// and adopted by a session draws exactly the bytes a session loading it itself draws, and
/// the picture uploads nothing more; a failed load is `adopt`'s error, naming the file.
#[test]
fn a_scene_loaded_off_thread_draws_as_one_loaded_here() {
    use glview::session::{same_scene, Prepared};
    common::at_repo();
    let o = options(&["models/sphere.obj"]);
    let (here, _) = draw(&mut Session::new(), &o);
    let mut s = Session::open(&o).expect("a headless context");
    assert!(!s.has_scene(&o));
    let prepared = std::thread::scope(|t| t.spawn(|| Prepared::load(&o)).join().unwrap());
    s.adopt(&o, prepared).expect("adopted");
    assert!(s.has_scene(&o));
    let (adopted, p) = draw(&mut s, &o);
    assert_eq!(p.scene_uploads, 0);
    assert!(adopted == here, "the adopted scene drew other pixels");
    let missing = options(&["models/no-such-model.obj"]);
    assert!(!same_scene(&o, &missing) && same_scene(&o, &o.clone()));
    let e = s.adopt(&missing, Prepared::load(&missing)).unwrap_err();
    assert!(e.to_string().contains("no-such-model.obj"), "{e}");
    assert!(s.has_scene(&o), "a failed load keeps the scenes there");
}
