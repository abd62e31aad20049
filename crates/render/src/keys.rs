//! The key mapping, shared by the window, the server's page and `--keys` (which replays it
//! headless): each key is an action on the options ([`apply`]).
use crate::camera::{CameraMove, KEY_STEP_DEG, ZOOM_STEP};
use crate::frame::{EdgeMode, Shading};
use crate::options::{Diffuse, Options};

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Action {
    Camera(CameraMove),
    Reset,
    Fit,
    ToggleShadows,
    ToggleGouraud,
    /// Phong → Gouraud → PBR → Phong.
    CycleShading,
    ToggleWrap,
    /// Legacy: 0 = ambient, 1 = diffuse, 2 = specular. PBR: 0–6 = direct diffuse, direct
    /// specular, IBL diffuse, IBL specular, AO, shadows, emissive.
    ToggleTerm(u8),
    /// Side-by-side panes in the window.
    ToggleCompare,
    /// Bloom on (strength 0.05 unless `--bloom` set one) / off.
    ToggleBloom,
    /// Lines over the model: off → feature edges → wireframe → off.
    CycleEdges,
    /// The ground grid (`--grid`) on/off.
    ToggleGrid,
    /// The axes triad (`--axes`) on/off.
    ToggleAxes,
    /// Translucent opacity down / up by 0.1 (`[`, `]`).
    Opacity(i8),
    /// Look through the file's next camera (`--camera`), after the last back to the orbit.
    CycleCamera,
    /// Draw the file's next material variant (`--variant`), after the last its own
    /// materials: a load option, so the scene is loaded again.
    CycleVariant,
    /// glTF: play / pause the animation (`Space`; from the static pose it starts at time 0).
    PlayPause,
    /// glTF: one frame (1/`--fps` s) forward (+1) or back (−1), paused (`.`, `,`).
    Step(i8),
    /// glTF: the file's next animation, from its time 0 (`A`).
    CycleAnimation,
    /// Stereo: off → anaglyph → side-by-side → over-under → rows → columns → checkerboard
    /// → side-by-side-full → off (`T`).
    CycleStereo,
    /// Stereo: swap the eyes (`Y`).
    SwapEyes,
    /// Stereo: the eyes' separation times 0.8 (−1) or 1.25 (+1) (`{`, `}`): needs the
    /// scene (the default separation follows the fitted distance).
    Separation(i8),
    Screenshot,
    Help,
    Quit,
}

impl Action {}

/// (key names, action, description) — the table `H`/`F1` prints and the README shows.
pub const KEY_TABLE: &[(&[&str], Action, &str)] = &[
    (
        &["Left"],
        Action::Camera(CameraMove::Yaw(-KEY_STEP_DEG)),
        "orbit: yaw -5°",
    ),
    (
        &["Right"],
        Action::Camera(CameraMove::Yaw(KEY_STEP_DEG)),
        "orbit: yaw +5°",
    ),
    (
        &["Up"],
        Action::Camera(CameraMove::Pitch(KEY_STEP_DEG)),
        "orbit: pitch +5°",
    ),
    (
        &["Down"],
        Action::Camera(CameraMove::Pitch(-KEY_STEP_DEG)),
        "orbit: pitch -5°",
    ),
    (
        &["Plus", "+", "PageUp"],
        Action::Camera(CameraMove::Zoom(1.0 / ZOOM_STEP)),
        "zoom in",
    ),
    (
        &["Minus", "-", "PageDown"],
        Action::Camera(CameraMove::Zoom(ZOOM_STEP)),
        "zoom out",
    ),
    (&["R", "Home"], Action::Reset, "reset the view"),
    (&["F"], Action::Fit, "fit the model in view"),
    (&["S"], Action::ToggleShadows, "shadows on/off"),
    (&["G"], Action::ToggleGouraud, "Phong / Gouraud shading"),
    (&["P"], Action::CycleShading, "cycle Phong → Gouraud → PBR"),
    (
        &["W"],
        Action::ToggleWrap,
        "half-Lambert (wrap) diffuse on/off",
    ),
    (&["["], Action::Opacity(-1), "translucent opacity −0.1"),
    (&["]"], Action::Opacity(1), "translucent opacity +0.1"),
    (
        &["1"],
        Action::ToggleTerm(0),
        "ambient term on/off (PBR: direct diffuse)",
    ),
    (
        &["2"],
        Action::ToggleTerm(1),
        "diffuse term on/off (PBR: direct specular)",
    ),
    (
        &["3"],
        Action::ToggleTerm(2),
        "specular term on/off (PBR: IBL diffuse)",
    ),
    (&["4"], Action::ToggleTerm(3), "PBR: IBL specular on/off"),
    (
        &["5"],
        Action::ToggleTerm(4),
        "PBR: ambient occlusion on/off",
    ),
    (&["6"], Action::ToggleTerm(5), "PBR: shadows on/off"),
    (&["7"], Action::ToggleTerm(6), "PBR: emissive on/off"),
    (
        &["8"],
        Action::ToggleTerm(7),
        "PBR: glTF clearcoat layer on/off",
    ),
    (
        &["9"],
        Action::ToggleTerm(8),
        "PBR: glTF sheen layer on/off",
    ),
    (
        &["0"],
        Action::ToggleTerm(9),
        "PBR: glTF transmission on/off",
    ),
    (
        &["C"],
        Action::ToggleCompare,
        "compare: Phong and PBR side by side",
    ),
    (&["B"], Action::ToggleBloom, "bloom on/off"),
    (
        &["E"],
        Action::CycleEdges,
        "lines: off → feature edges → wireframe → off",
    ),
    (
        &["Z"],
        Action::ToggleGrid,
        "ground grid on/off (receives the shadow)",
    ),
    (&["X"], Action::ToggleAxes, "axes triad on/off"),
    (
        &["K"],
        Action::CycleCamera,
        "glTF: look through the file's next camera (then back to the orbit)",
    ),
    (
        &["V"],
        Action::CycleVariant,
        "glTF: the next material variant (then the file's own materials)",
    ),
    (
        &["Space"],
        Action::PlayPause,
        "glTF: play / pause the animation",
    ),
    (
        &["."],
        Action::Step(1),
        "glTF: one frame (1/--fps s) forward, paused",
    ),
    (&[","], Action::Step(-1), "glTF: one frame back, paused"),
    (
        &["A"],
        Action::CycleAnimation,
        "glTF: the file's next animation (then all together), from its start",
    ),
    (
        &["T"],
        Action::CycleStereo,
        "stereo: off → anaglyph → side-by-side → over-under → rows → columns → checkerboard → side-by-side-full",
    ),
    (&["Y"], Action::SwapEyes, "stereo: swap the eyes"),
    (&["{"], Action::Separation(-1), "stereo: eye separation ×0.8"),
    (&["}"], Action::Separation(1), "stereo: eye separation ×1.25"),
    (
        &["F12"],
        Action::Screenshot,
        "save a screenshot (PNG of the window's framebuffer)",
    ),
    (
        &["H", "F1"],
        Action::Help,
        "overlay: model, tier, toggles, frame time and this table",
    ),
    (&["Escape", "Esc", "Q"], Action::Quit, "quit"),
];

/// The keys a remote view takes (the server's page: no quit, no help overlay of the
/// window's, no window screenshot), as JSON for the page's hello: `[{names, what}]`.
pub fn remote_table() -> serde_json::Value {
    KEY_TABLE
        .iter()
        .filter(|(_, a, _)| !matches!(a, Action::Quit | Action::Help | Action::Screenshot))
        .map(|(names, _, what)| serde_json::json!({ "names": names, "what": what }))
        .collect()
}

/// Degrees of orbit per pixel of a left-drag (the window's and the server's).
pub const DRAG_DEG_PER_PIXEL: f32 = 0.4;

/// The bloom strength `B` switches on.
pub(crate) const DEFAULT_KEY_BLOOM: f32 = 0.05;

/// Where `[` and `]` start when no `--opacity` was given.
pub(crate) const DEFAULT_KEY_OPACITY: f32 = 0.5;

/// Looks up a key by name (case-insensitive for letters).
pub fn action_for(name: &str) -> Option<Action> {
    KEY_TABLE
        .iter()
        .find(|(names, _, _)| names.iter().any(|n| n.eq_ignore_ascii_case(name)))
        .map(|(_, a, _)| *a)
}

/// Parses `--keys "Left Left Up"`. `V` is refused: it changes what is loaded, and `--keys`
/// is replayed on a scene already loaded (`--variant` says it instead).
pub(crate) fn parse_keys(s: &str) -> Result<Vec<Action>, String> {
    s.split_whitespace()
        .map(|k| match action_for(k) {
            Some(Action::CycleVariant) => Err(format!(
                "key {k:?} in --keys changes the loaded material variant: use --variant"
            )),
            Some(a) => Ok(a),
            None => Err(format!(
                "unknown key {k:?} in --keys (see the key table in --help)"
            )),
        })
        .collect()
}

pub fn help_text() -> String {
    let mut s = String::from("keys:\n");
    for (names, _, what) in KEY_TABLE {
        s += &format!("  {:<22} {what}\n", names.join(" / "));
    }
    s += "  left-drag              orbit\n  mouse wheel            zoom\n";
    s
}

/// The stereo mode `T` goes to after `mode` (quad-buffer is the window's start-up choice,
/// not in the cycle: it needs a context of its own).
fn next_stereo(mode: crate::stereo::StereoMode) -> crate::stereo::StereoMode {
    use crate::stereo::StereoMode::*;
    match mode {
        Off | QuadBuffer => Anaglyph,
        Anaglyph => SideBySide,
        SideBySide => OverUnder,
        OverUnder => Rows,
        Rows => Columns,
        Columns => Checkerboard,
        Checkerboard => SideBySideFull,
        SideBySideFull => Off,
    }
}

/// What the caller must do after an action.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Effect {
    Redraw,
    /// A camera action: the caller moves the camera ([`crate::view::View::act`]).
    Camera,
    /// Toggle the window's side-by-side panes (the frame settings do not change).
    Compare,
    Screenshot,
    Help,
    Quit,
}

/// Applies a key's action to the options it stands for (the typed groups: shading, shadow,
/// light, render, post), so every front end keeps one model of a view's state: the options
/// a picture is drawn from. Camera actions ([`Action::Camera`], [`Action::Reset`],
/// [`Action::Fit`]), the file's cameras and variants and the animation keys need the scene
/// and the view's home and are the caller's ([`crate::view::View`]); they return
/// [`Effect::Camera`] untouched.
pub fn apply(action: Action, o: &mut Options) -> Effect {
    match action {
        Action::Camera(_)
        | Action::Reset
        | Action::Fit
        | Action::CycleCamera
        | Action::CycleVariant
        | Action::PlayPause
        | Action::Step(_)
        | Action::CycleAnimation
        | Action::Separation(_) => return Effect::Camera,
        Action::CycleStereo => {
            // SSAA's box filter would average interlaced rows and columns together.
            let ssaa = o.post.aa == crate::options::AaMode::Ssaa;
            let mut next = next_stereo(o.stereo.mode);
            while ssaa && next.interlaced() {
                next = next_stereo(next);
            }
            o.stereo.mode = next;
        }
        Action::SwapEyes => o.stereo.swap_eyes = !o.stereo.swap_eyes,
        Action::ToggleShadows => o.shadow.enabled = !o.shadow.enabled,
        Action::ToggleGouraud => {
            o.render.shading = match o.render.shading {
                Shading::Phong => Shading::Gouraud,
                Shading::Gouraud => Shading::Phong,
                Shading::Pbr => Shading::Pbr,
            }
        }
        Action::CycleShading => o.render.shading = o.render.shading.next(),
        Action::ToggleWrap => {
            o.light.diffuse = match o.light.diffuse {
                Diffuse::Lambert => Diffuse::Wrap,
                Diffuse::Wrap => Diffuse::Lambert,
            }
        }
        Action::Opacity(step) => {
            let now = o.render.opacity.unwrap_or(DEFAULT_KEY_OPACITY);
            o.render.opacity = Some((now + 0.1 * f32::from(step)).clamp(0.0, 1.0));
        }
        Action::ToggleTerm(t) => {
            let switch = if o.render.shading == Shading::Pbr {
                o.render.terms.key_switch(t)
            } else {
                o.render.legacy_terms.key_switch(t)
            };
            if let Some(b) = switch {
                *b = !*b;
            }
        }
        Action::CycleEdges => {
            let r = &mut o.render;
            let now = if r.wireframe || r.wireframe_only {
                EdgeMode::Wireframe
            } else if r.edges {
                EdgeMode::Feature
            } else {
                EdgeMode::Off
            };
            let next = now.next();
            r.edges = next == EdgeMode::Feature;
            r.wireframe = next == EdgeMode::Wireframe;
            r.wireframe_only = false;
        }
        Action::ToggleGrid => o.render.grid = !o.render.grid,
        Action::ToggleAxes => o.render.axes = !o.render.axes,
        Action::ToggleCompare => return Effect::Compare,
        Action::ToggleBloom => {
            let p = &mut o.post;
            let on = !p.no_bloom && p.bloom > 0.0;
            p.no_bloom = false;
            p.bloom = if on { 0.0 } else { DEFAULT_KEY_BLOOM };
        }
        Action::Screenshot => return Effect::Screenshot,
        Action::Help => return Effect::Help,
        Action::Quit => return Effect::Quit,
    }
    Effect::Redraw
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parse() {
        let k = parse_keys("Left left UP + F12 esc").unwrap();
        assert_eq!(k[0], Action::Camera(CameraMove::Yaw(-5.0)));
        assert_eq!(k[1], k[0]);
        assert_eq!(k[2], Action::Camera(CameraMove::Pitch(5.0)));
        assert_eq!(k[4], Action::Screenshot);
        assert_eq!(k[5], Action::Quit);
        assert!(parse_keys("Left Banana").is_err());
        assert_eq!(
            parse_keys("z X").unwrap(),
            [Action::ToggleGrid, Action::ToggleAxes]
        );
    }

    /// The page's keys are the table's (its hello carries them): every name maps back to
    /// its action, and quit, help and the window's screenshot are not among them.
    /// `T` visits every composed mode once and comes back to mono; under SSAA it skips the
    /// interlaced ones (the box filter would average their rows together). `Y` swaps.
    #[test]
    fn t_cycles_the_stereo_modes_and_y_swaps_the_eyes() {
        use crate::stereo::StereoMode;
        let mut o = Options::default();
        let mut seen = Vec::new();
        for _ in 0..8 {
            apply(Action::CycleStereo, &mut o);
            seen.push(o.stereo.mode);
        }
        assert_eq!(seen.last(), Some(&StereoMode::Off));
        let composed = StereoMode::ALL
            .iter()
            .filter(|(m, _, _)| m.composed())
            .count();
        assert_eq!(seen.len() - 1, composed, "{seen:?}");
        o.post.aa = crate::options::AaMode::Ssaa;
        for _ in 0..8 {
            apply(Action::CycleStereo, &mut o);
            assert!(!o.stereo.mode.interlaced());
        }
        apply(Action::SwapEyes, &mut o);
        assert!(o.stereo.swap_eyes);
        assert_eq!(parse_keys("T Y { }").unwrap()[3], Action::Separation(1));
    }

    #[test]
    fn remote_table_is_the_key_table() {
        let table = remote_table();
        let mut names = 0;
        for entry in table.as_array().unwrap() {
            for n in entry["names"].as_array().unwrap() {
                let a = action_for(n.as_str().unwrap()).unwrap();
                assert!(!matches!(
                    a,
                    Action::Quit | Action::Help | Action::Screenshot
                ));
                names += 1;
            }
        }
        let all: usize = KEY_TABLE.iter().map(|(n, _, _)| n.len()).sum();
        assert_eq!(
            names,
            all - 6,
            "Escape/Esc/Q, H/F1 and F12 are the window's"
        );
    }
}
