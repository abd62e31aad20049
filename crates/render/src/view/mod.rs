//! A view that someone steers with the window's keys and drags, held as options (the
//! window's, the server's viewers', `--keys` replayed headless): every picture of it is
//! `glview -o` with those options, so a still equals the command line's picture and its
//! PNG text reproduces it. The one model of a view's state; it round-trips through JSON.
//! No GL.
pub mod file_camera;
pub mod moment;
mod play;
pub mod settings;
pub mod split;

use crate::camera::{CameraMove, ZOOM_STEP};
use crate::error::Result;
use crate::keys::{self, Action, Effect};
use crate::options::{Camera, Options, Ortho};
use crate::scene::Scene;
pub use moment::{moment, pose_scene};
use settings::frame_settings;

/// Options moved by key presses and drags: the camera keys change the camera options (yaw,
/// pitch, distance, target: what `-o` takes), the state keys the options they stand for
/// ([`keys::apply`]: `S` is `--no-shadows`, `P` is `--shading`, ...).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct View {
    options: Options,
    /// The camera `R` returns to.
    home: Camera,
    /// Phong | PBR side by side, each pane half the view's width.
    compare: bool,
    /// The animation's time runs (`Space`): the moment drawn is still the options' `--time`
    /// ([`View::advance`] moves it).
    #[serde(default)]
    playing: bool,
}

impl View {
    /// A view of `options` (its camera is home).
    pub fn new(options: Options) -> View {
        let mut home = options.camera.clone();
        home.keys = None;
        View {
            home,
            options,
            compare: false,
            playing: false,
        }
    }

    /// `options` with their `--keys` replayed into them (the state and camera the keys lead
    /// to, `keys` none): what a picture of them shows, as options.
    pub fn settled(options: &Options, scene: &Scene) -> Result<Options> {
        let mut v = View::new(options.clone());
        v.settle_keys(scene)?;
        Ok(v.options)
    }

    /// Replays `--keys` into the options (once, before the first action: until then every
    /// picture replays them, which draws the same), so later keys act on their result. A
    /// view taken from elsewhere (a page given the server's) is settled before it is drawn.
    pub fn settle_keys(&mut self, scene: &Scene) -> Result<()> {
        let Some(k) = self.options.camera.keys.take() else {
            return Ok(());
        };
        for action in keys::parse_keys(&k).map_err(crate::Error::Usage)? {
            if self.act(action, scene)? == Effect::Quit {
                break;
            }
        }
        Ok(())
    }

    /// The options of the whole view (its size, its state).
    pub fn options(&self) -> &Options {
        &self.options
    }

    /// Whether the view shows Phong | PBR side by side.
    pub fn compare(&self) -> bool {
        self.compare
    }

    /// The options of one picture: the view's, or with `compare` a pane's (half the
    /// width: each pane is framed for its own aspect, as `--compare` frames it).
    pub fn picture(&self) -> Options {
        let mut o = self.options.clone();
        if self.compare {
            o.picture.size.0 = (o.picture.size.0 / 2).max(1);
        }
        o
    }

    /// Sets the view's stereo mode (`--stereo`; the eyes' separation and swap stay).
    pub fn set_stereo(&mut self, mode: crate::stereo::StereoMode) {
        self.options.stereo.mode = mode;
    }

    /// Sets the view's shading tier (`--shading`; a page's Phong and PBR buttons), leaving
    /// the side-by-side view.
    pub fn set_shading(&mut self, shading: crate::frame::Shading) {
        self.options.render.shading = shading;
        self.compare = false;
    }

    /// Shows Phong | PBR side by side, or not (the `C` key toggles it).
    pub fn set_compare(&mut self, on: bool) {
        self.compare = on;
    }

    /// Sets the view's size (the camera keeps its angles; a fitted distance refits).
    pub fn resize(&mut self, size: (u32, u32)) {
        self.options.picture.size = size;
    }

    /// Another model in the same view: the camera goes home, the state stays but the
    /// moment (its animations are not the new model's: the static pose).
    pub fn set_model(&mut self, model: Option<std::path::PathBuf>) {
        self.options.load.model = model;
        self.options.camera = self.home.clone();
        self.stop();
    }

    /// Applies a key's action; `scene` is the model's (for zoom and fit). Returns what the
    /// caller does next ([`Effect::Redraw`] when the picture may have changed).
    pub fn act(&mut self, action: Action, scene: &Scene) -> Result<Effect> {
        self.settle_keys(scene)?;
        match action {
            Action::Camera(m) => self.camera(m, scene)?,
            Action::Reset => self.options.camera = self.home.clone(),
            Action::Fit => {
                self.options.camera = crate::view::file_camera::resolve(&self.options, scene)?;
                let c = &mut self.options.camera;
                c.target = None;
                c.distance = None;
            }
            Action::CycleCamera => {
                let now = (self.options.camera.view.as_deref())
                    .and_then(|q| scene.views.camera_index(q).ok());
                self.pick_camera(next(now, scene.views.cameras.len()), scene)?;
            }
            Action::CycleVariant => {
                let n = scene.views.variants.len();
                self.pick_variant(next(scene.views.variant, n), scene)?;
            }
            Action::ToggleCompare => self.compare = !self.compare,
            Action::PlayPause => self.play_pause(scene.animations())?,
            Action::Step(n) => self.step(i32::from(n), scene.animations())?,
            Action::CycleAnimation => self.next_animation(scene.animations())?,
            Action::Separation(step) => {
                // From the separation drawn now (the default follows the fitted distance).
                let now = crate::frame::FrameSettings::new(&self.options, scene)?.stereo;
                let factor = if step < 0 { 0.8 } else { 1.25 };
                self.options.stereo.eye_separation = Some(now.separation * factor);
            }
            a => return Ok(keys::apply(a, &mut self.options)),
        }
        Ok(Effect::Redraw)
    }

    /// Looks through the file's camera `index` (`--camera index`; None: the orbit camera
    /// where it is). What `K` does for the next one and the server's camera picker for any.
    pub fn pick_camera(&mut self, index: Option<usize>, scene: &Scene) -> Result<()> {
        self.settle_keys(scene)?;
        if let Some(i) = index {
            let names: Vec<&str> = scene
                .views
                .cameras
                .iter()
                .map(|c| c.name.as_str())
                .collect();
            picked("camera", &names, i)?;
        }
        self.options.camera.view = index.map(|i| i.to_string());
        Ok(())
    }

    /// Draws the file's material variant `index` (`--variant index`; None: the file's own
    /// materials): a load option, so the scene is loaded again. What `V` does for the next
    /// one and the server's variant picker for any.
    pub fn pick_variant(&mut self, index: Option<usize>, scene: &Scene) -> Result<()> {
        self.settle_keys(scene)?;
        if let Some(i) = index {
            let names: Vec<&str> = scene.views.variants.iter().map(String::as_str).collect();
            picked("variant", &names, i)?;
        }
        self.options.load.variant = index.map(|i| i.to_string());
        Ok(())
    }

    /// A drag of `dx`, `dy` pixels, as the window turns it (dragging right turns the model
    /// right).
    pub fn drag(&mut self, dx: f32, dy: f32, scene: &Scene) -> Result<()> {
        let k = keys::DRAG_DEG_PER_PIXEL;
        self.camera(CameraMove::Yaw(-dx * k), scene)?;
        self.camera(CameraMove::Pitch(dy * k), scene)
    }

    /// `notches` of the mouse wheel (positive: away from the user, zooms in), as the window.
    pub fn wheel(&mut self, notches: f32, scene: &Scene) -> Result<()> {
        self.camera(CameraMove::Zoom(ZOOM_STEP.powf(-notches)), scene)
    }

    /// Moves the camera as the window's keys move its camera, and writes the result back
    /// as options: angles always; distance and ortho height only when they changed (a fitted
    /// view stays fitted: `glview --yaw 40` is the picture after two presses of Right).
    fn camera(&mut self, m: CameraMove, scene: &Scene) -> Result<()> {
        self.settle_keys(scene)?;
        // A file's camera becomes the options it stands for: orbiting starts from it.
        self.options.camera = crate::view::file_camera::resolve(&self.options, scene)?;
        let (s, _) = frame_settings(&self.picture(), scene)?;
        let mut cam = s.camera;
        cam.apply(m);
        let c = &mut self.options.camera;
        c.yaw = cam.yaw_deg;
        c.pitch = cam.pitch_deg;
        if let CameraMove::Zoom(_) = m {
            c.distance = Some(cam.distance);
            c.ortho = cam.ortho_height.map(Ortho::Height);
        }
        Ok(())
    }
}

/// `index` checked against the file's `names` (the error lists them, as `--camera` does).
fn picked(kind: &str, names: &[&str], index: usize) -> Result<()> {
    crate::scene::model::views::pick(kind, names, &index.to_string())
        .map(|_| ())
        .map_err(crate::Error::Usage)
}

/// The next of `n` choices after `now` (None: the default before the first and after the
/// last); None when there are none.
fn next(now: Option<usize>, n: usize) -> Option<usize> {
    match now {
        None if n > 0 => Some(0),
        Some(i) if i + 1 < n => Some(i + 1),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::view::settings::adjust_scene;

    fn view() -> (View, Scene) {
        let mut o = Options::default();
        o.picture.size = (320, 240);
        let mut scene = glview_scene::builtin::load(&Default::default()).unwrap();
        adjust_scene(&o, &mut scene).unwrap();
        (View::new(o), scene)
    }

    fn key(v: &mut View, scene: &Scene, name: &str) {
        v.act(keys::action_for(name).unwrap(), scene).unwrap();
    }

    /// Two presses of Right are `--yaw` 10° more, and nothing else moves: the picture is
    /// the command line's.
    #[test]
    fn camera_keys_are_options() {
        let (mut v, scene) = view();
        key(&mut v, &scene, "Right");
        key(&mut v, &scene, "Right");
        let mut want = Options::default();
        want.picture.size = (320, 240);
        want.camera.yaw += 10.0;
        assert_eq!(v.options(), &want);
        key(&mut v, &scene, "Plus");
        let (s, _) = frame_settings(v.options(), &scene).unwrap();
        let (fit, _) = frame_settings(&want, &scene).unwrap();
        assert!((s.camera.distance * ZOOM_STEP - fit.camera.distance).abs() < 1e-4);
        key(&mut v, &scene, "R");
        want.camera.yaw -= 10.0;
        assert_eq!(v.options(), &want);
    }

    /// State keys are options: S is `--no-shadows`, a press and its undo leave the
    /// options as they were, a cycle of P (three tiers) comes back, `]` stops at 1.
    #[test]
    fn state_keys_are_options() {
        let (mut v, scene) = view();
        let start = v.options().clone();
        key(&mut v, &scene, "S");
        assert!(!v.options().shadow.enabled);
        let (s, _) = frame_settings(v.options(), &scene).unwrap();
        assert!(!s.shadows.enabled);
        for k in ["B", "S", "B"] {
            key(&mut v, &scene, k);
        }
        assert_eq!(v.options(), &start);
        for _ in 0..3 {
            key(&mut v, &scene, "P");
        }
        assert_eq!(v.options(), &start);
        for _ in 0..1000 {
            key(&mut v, &scene, "]");
        }
        assert_eq!(v.options().render.opacity, Some(1.0));
        key(&mut v, &scene, "1");
        assert!(!v.options().render.legacy_terms.ambient);
        key(&mut v, &scene, "P");
        key(&mut v, &scene, "P");
        key(&mut v, &scene, "8");
        assert!(!v.options().render.terms.clearcoat);
    }

    /// `--keys` replayed headless is the same options as the keys pressed one by one, and
    /// the camera keys among them are the camera options.
    #[test]
    fn keys_option_replays_as_presses() {
        let (mut v, scene) = view();
        for k in ["Left", "S", "Z", "P", "P", "B", "Plus"] {
            key(&mut v, &scene, k);
        }
        let mut o = Options::default();
        o.picture.size = (320, 240);
        o.camera.keys = Some("Left S Z P P B Plus".into());
        assert_eq!(&View::settled(&o, &scene).unwrap(), v.options());
        // A view made with --keys absorbs them before its first press.
        let mut w = View::new(o);
        key(&mut w, &scene, "S");
        assert!(w.options().shadow.enabled && w.options().camera.keys.is_none());
    }

    /// The web page's Z and X (any key of the table reaches the server by name).
    #[test]
    fn grid_and_axes_keys_are_state_keys() {
        let (mut v, scene) = view();
        key(&mut v, &scene, "Z");
        key(&mut v, &scene, "X");
        assert!(v.options().render.grid && v.options().render.axes);
        let (s, _) = frame_settings(v.options(), &scene).unwrap();
        assert!(s.lighting.guides.grid && s.lighting.guides.axes);
    }

    /// A view's state (options, home, panes) survives JSON, as a server or a link keeps it.
    #[test]
    fn view_round_trips_through_json() {
        let (mut v, scene) = view();
        for k in ["Right", "Up", "S", "P", "P", "C", "E", "]", "Minus"] {
            key(&mut v, &scene, k);
        }
        let json = serde_json::to_string(&v).unwrap();
        let back: View = serde_json::from_str(&json).unwrap();
        assert_eq!(back, v);
    }

    /// K cycles the file's cameras and back to the orbit; V the variants (from the one the
    /// scene was loaded with) and back to the file's own materials.
    #[test]
    fn k_and_v_cycle_the_files_cameras_and_variants() {
        use crate::scene::model::views::{FileCamera, Projection};
        let (mut v, mut scene) = view();
        let camera = FileCamera {
            name: "c".into(),
            node_name: None,
            eye: [0.0, 0.0, 5.0],
            forward: [0.0, 0.0, -1.0],
            up: [0.0, 1.0, 0.0],
            projection: Projection::Perspective {
                yfov: 0.7,
                aspect_ratio: None,
                znear: 0.1,
                zfar: None,
            },
        };
        scene.views.cameras = vec![camera.clone(), camera];
        let mut seen = Vec::new();
        for _ in 0..3 {
            key(&mut v, &scene, "K");
            seen.push(v.options().camera.view.clone());
        }
        assert_eq!(seen, [Some("0".into()), Some("1".into()), None]);
        scene.views.variants = vec!["a".into(), "b".into()];
        let mut seen = Vec::new();
        for now in [None, Some(0), Some(1)] {
            scene.views.variant = now;
            key(&mut v, &scene, "V");
            seen.push(v.options().load.variant.clone());
        }
        assert_eq!(seen, [Some("0".into()), Some("1".into()), None]);
        // A picker's choice is the options K and V lead to; a choice the file lacks is an
        // error listing what it has, and the view stays.
        let (mut p, _) = view();
        p.pick_camera(Some(1), &scene).unwrap();
        p.pick_variant(Some(1), &scene).unwrap();
        assert_eq!(p.options().camera.view.as_deref(), Some("1"));
        assert_eq!(p.options().load.variant.as_deref(), Some("1"));
        let e = p.pick_variant(Some(2), &scene).unwrap_err().to_string();
        assert!(
            e.contains("no variant \"2\"") && e.contains("1 \"b\""),
            "{e}"
        );
        assert!(p.pick_camera(Some(2), &scene).is_err());
        assert_eq!(p.options().load.variant.as_deref(), Some("1"));
        // Orbiting from a file camera leaves its options, not the camera.
        key(&mut v, &scene, "K");
        key(&mut v, &scene, "Left");
        let c = &v.options().camera;
        assert!(c.view.is_none() && c.distance.is_some() && c.near == Some(0.1));
        assert!((c.yaw - -5.0).abs() < 1e-4 && c.pitch.abs() < 1e-4, "{c:?}");
    }

    #[test]
    fn compare_halves_the_picture() {
        let (mut v, scene) = view();
        key(&mut v, &scene, "C");
        assert!(v.compare());
        assert_eq!(v.picture().picture.size, (160, 240));
        assert_eq!(v.options().picture.size, (320, 240));
        // A page's buttons: a tier shows one pane; compare on and off as C does.
        v.set_shading(crate::frame::Shading::Pbr);
        assert!(!v.compare() && v.options().render.shading == crate::frame::Shading::Pbr);
        v.set_compare(true);
        assert!(v.compare() && v.picture().picture.size == (160, 240));
        v.set_compare(false);
        assert_eq!(v.picture().picture.size, (320, 240));
    }

    #[test]
    fn drag_and_wheel_turn_as_the_window() {
        let (mut v, scene) = view();
        v.drag(10.0, -5.0, &scene).unwrap();
        let o = v.options();
        assert_eq!(
            o.camera.yaw,
            (30.0 - 10.0 * keys::DRAG_DEG_PER_PIXEL) % 360.0
        );
        assert_eq!(
            o.camera.pitch,
            (25.0 - 5.0 * keys::DRAG_DEG_PER_PIXEL) % 360.0
        );
        v.wheel(1.0, &scene).unwrap();
        assert!(v.options().camera.distance.is_some());
    }
}
