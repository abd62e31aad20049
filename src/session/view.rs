//! A view that someone steers with the window's keys and drags, held as options (the
//! server's viewers): every picture of it is `glview -o` with those options, so a still
//! equals the command line's picture and its PNG text reproduces it. No GL.
use super::settings::frame_settings;
use crate::camera::{CameraMove, ZOOM_STEP};
use crate::error::{Error, Result};
use crate::keys::{self, Action, Effect};
use crate::options::{Camera, Options, Ortho};
use crate::scene::Scene;

/// State keys kept at most (a cycle back to an earlier state is cut out, so only a walk
/// through this many different states in a row reaches it).
pub const MAX_STATE_KEYS: usize = 64;

/// Options moved by key presses and drags. The camera keys change the camera options (yaw,
/// pitch, distance, target: what `-o` takes); the state keys (shadows, tiers, terms, bloom,
/// opacity) are kept as `--keys`, replayed by [`frame_settings`] exactly as the window's.
#[derive(Clone, Debug)]
pub struct View {
    options: Options,
    /// The camera `R` returns to.
    home: Camera,
    /// The state keys pressed, each with the state it led to (to cut out cycles).
    keys: Vec<(String, String)>,
    /// Phong | PBR side by side, each pane half the view's width.
    compare: bool,
}

impl View {
    /// A view of `options` (its camera is home).
    pub fn new(options: Options) -> View {
        View {
            home: options.camera.clone(),
            options,
            keys: Vec::new(),
            compare: false,
        }
    }

    /// The options of the whole view (its size, the state keys as `--keys`).
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

    /// Sets the view's size (the camera keeps its angles; a fitted distance refits).
    pub fn resize(&mut self, size: (u32, u32)) {
        self.options.picture.size = size;
    }

    /// Another model in the same view: the camera goes home, the state keys stay.
    pub fn set_model(&mut self, model: Option<std::path::PathBuf>) {
        self.options.load.model = model;
        self.options.camera = self.home.clone();
        self.sync_keys();
    }

    /// Applies a key's action; `scene` is the model's (for zoom and fit). Returns what the
    /// caller does next ([`Effect::Redraw`] when the picture changed).
    pub fn act(&mut self, action: Action, scene: &Scene) -> Result<Effect> {
        match action {
            Action::Camera(m) => self.camera(m, scene)?,
            Action::Reset => self.options.camera = self.home_with_keys(),
            Action::Fit => {
                let c = &mut self.options.camera;
                c.target = None;
                c.distance = None;
            }
            Action::ToggleCompare => self.compare = !self.compare,
            a if a.changes_state() => self.state_key(a, scene)?,
            // Screenshot, help and quit are the caller's (a still, an overlay, a close).
            Action::Screenshot => return Ok(Effect::Screenshot),
            Action::Help => return Ok(Effect::Help),
            Action::Quit => return Ok(Effect::Quit),
            _ => {}
        }
        Ok(Effect::Redraw)
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

    /// A state key, kept as `--keys`; a press that comes back to an earlier state cuts the
    /// walk back to it (S, S is no key at all).
    fn state_key(&mut self, action: Action, scene: &Scene) -> Result<()> {
        let name = keys::name_of(action)
            .ok_or_else(|| Error::Usage(format!("{action:?} has no key")))?
            .to_string();
        self.keys.push((name, String::new()));
        self.sync_keys();
        let after = state_digest(&self.options, scene)?;
        // The new entry's state is still empty: it matches no digest.
        if self.base_digest(scene)? == after {
            self.keys.clear();
        } else if let Some(i) = self.keys.iter().position(|(_, s)| *s == after) {
            self.keys.truncate(i + 1);
        } else {
            self.keys.last_mut().expect("pushed").1 = after;
        }
        if self.keys.len() > MAX_STATE_KEYS {
            self.keys.pop();
            self.sync_keys();
            return Err(Error::Usage(format!(
                "more than {MAX_STATE_KEYS} toggles in a row without coming back to a state: \
                 reload the page to start again"
            )));
        }
        self.sync_keys();
        Ok(())
    }

    fn base_digest(&self, scene: &Scene) -> Result<String> {
        let mut o = self.options.clone();
        o.camera.keys = None;
        state_digest(&o, scene)
    }

    fn sync_keys(&mut self) {
        let words: Vec<&str> = self.keys.iter().map(|(k, _)| k.as_str()).collect();
        self.options.camera.keys = (!words.is_empty()).then(|| words.join(" "));
    }

    fn home_with_keys(&self) -> Camera {
        let mut c = self.home.clone();
        c.keys = self.options.camera.keys.clone();
        c
    }
}

/// What the state keys decide: the frame settings without the camera.
fn state_digest(o: &Options, scene: &Scene) -> Result<String> {
    let (mut s, _) = frame_settings(o, scene)?;
    s.camera = crate::camera::OrbitCamera::fit(&scene.bounds, 45.0, 1.0);
    Ok(format!("{s:?}"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::session::load_scene;

    fn view() -> (View, Scene) {
        let mut o = Options::default();
        o.picture.size = (320, 240);
        let scene = load_scene(&o).unwrap();
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

    /// The replayed keys give the window's state; a press and its undo leave no key; a
    /// cycle of P (three tiers) comes back to nothing.
    #[test]
    fn state_keys_replay_and_cycles_cut() {
        let (mut v, scene) = view();
        key(&mut v, &scene, "S");
        assert_eq!(v.options().camera.keys.as_deref(), Some("S"));
        let (s, _) = frame_settings(v.options(), &scene).unwrap();
        assert!(!s.shadows.enabled);
        key(&mut v, &scene, "B");
        key(&mut v, &scene, "S");
        assert_eq!(v.options().camera.keys.as_deref(), Some("S B S"));
        key(&mut v, &scene, "B");
        assert_eq!(v.options().camera.keys, None);
        for _ in 0..3 {
            key(&mut v, &scene, "P");
        }
        assert_eq!(v.options().camera.keys, None);
        for _ in 0..1000 {
            key(&mut v, &scene, "]");
        }
        assert!(v.options().camera.keys.as_ref().unwrap().split(' ').count() <= 11);
    }

    /// The web page's Z and X (any key of the table reaches the server by name).
    #[test]
    fn grid_and_axes_keys_are_state_keys() {
        let (mut v, scene) = view();
        key(&mut v, &scene, "Z");
        key(&mut v, &scene, "X");
        assert_eq!(v.options().camera.keys.as_deref(), Some("Z X"));
        let (s, _) = frame_settings(v.options(), &scene).unwrap();
        assert!(s.lighting.guides.grid && s.lighting.guides.axes);
        key(&mut v, &scene, "X");
        key(&mut v, &scene, "Z");
        assert_eq!(v.options().camera.keys, None);
    }

    #[test]
    fn compare_halves_the_picture() {
        let (mut v, scene) = view();
        key(&mut v, &scene, "C");
        assert!(v.compare());
        assert_eq!(v.picture().picture.size, (160, 240));
        assert_eq!(v.options().picture.size, (320, 240));
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
