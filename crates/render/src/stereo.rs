//! Stereo 3D, pure math (no GL): the two eyes of a view as parallel cameras with off-axis
//! frusta, where each eye's picture goes in the composed one, and the anaglyph matrices.
//! The renderer draws each eye into a target of its own and composes them in one
//! full-screen pass (`passes/stereo.rs`), so the stencil buffer stays the translucency's.
//!
//! Eyes: both cameras look along the mono camera's direction from ∓s along its right
//! axis (s = half the separation); each frustum's window is shifted so that the plane at
//! the convergence distance c is the screen for both: a point there lands on the same pixel
//! in both eyes, a point at depth z shifts by ±(s / (t·a))·(1/z − 1/c) in NDC (t: the half
//! field of view's tangent, a: the projection's aspect), nearer points towards the nose.
use crate::camera::OrbitCamera;
use glam::Mat3;

crate::choice! {
    /// How the two eyes make one picture.
    pub enum StereoMode {
        /// One picture, no stereo.
        Off = "off",
        /// Both eyes in one picture for coloured glasses (`--anaglyph`, `--glasses`).
        Anaglyph = "anaglyph",
        /// Each eye squeezed into half the width, left eye left (3D TVs' half side-by-side).
        SideBySide = "side-by-side",
        /// Each eye at full size side by side: the picture is twice as wide (headsets,
        /// cross-eye viewing; in a window each eye gets half of it, unsqueezed).
        SideBySideFull = "side-by-side-full",
        /// Each eye squeezed into half the height, left eye on top (3D TVs' top-bottom).
        OverUnder = "over-under",
        /// Row-interlaced (passive 3D monitors): even rows left, odd rows right, counted
        /// from the top of the screen in a window and of the picture in a file.
        Rows = "rows",
        /// Column-interlaced: even columns left, odd right.
        Columns = "columns",
        /// Checkerboard (DLP 3D): cells with an even row + column left.
        Checkerboard = "checkerboard",
        /// A quad-buffered (GL_STEREO) window, where the driver offers one.
        QuadBuffer = "quad-buffer",
    }
}

crate::choice! {
    /// How an anaglyph mixes the eyes' colours.
    pub enum AnaglyphMethod {
        /// Dubois's least-squares matrices (the colours best kept through the filters).
        Dubois = "dubois",
        /// Each eye's own channels (brightest, most retinal rivalry).
        Color = "color",
        /// The left eye's luminance, the right eye's colours.
        HalfColor = "half-color",
        /// Both eyes' luminance (no colour, least rivalry).
        Gray = "gray",
    }
}

crate::choice! {
    /// The glasses' colours, left eye first.
    pub enum Glasses {
        RedCyan = "red-cyan",
        GreenMagenta = "green-magenta",
        AmberBlue = "amber-blue",
    }
}

crate::choice! {
    /// One eye of a stereo pair.
    pub enum Eye {
        Left = "left",
        Right = "right",
    }
}

impl Eye {
    pub fn other(self) -> Eye {
        match self {
            Eye::Left => Eye::Right,
            Eye::Right => Eye::Left,
        }
    }
}

impl StereoMode {
    /// The modes drawn as two eyes composed into one picture (not off, not the window's
    /// quad buffers).
    pub fn composed(self) -> bool {
        !matches!(self, StereoMode::Off | StereoMode::QuadBuffer)
    }

    /// The modes that interlace the eyes by pixels (rows, columns, checkerboard).
    pub fn interlaced(self) -> bool {
        interlaced_eye(self, 0, 0).is_some()
    }
}

/// What a frame's stereo is: the mode and, for its eyes, the separation and convergence
/// distance (world units) and whether the eyes are swapped.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stereo {
    pub mode: StereoMode,
    pub method: AnaglyphMethod,
    pub glasses: Glasses,
    pub swap: bool,
    pub separation: f32,
    pub convergence: f32,
    /// Where the picture's top-left pixel is on the screen, modulo 2 (column, row): the
    /// interlaced modes follow absolute screen pixels in a window; (0, 0) in a file.
    pub parity: (u32, u32),
}

impl Default for Stereo {
    fn default() -> Stereo {
        Stereo {
            mode: StereoMode::Off,
            method: AnaglyphMethod::Dubois,
            glasses: Glasses::RedCyan,
            swap: false,
            separation: 0.0,
            convergence: 1.0,
            parity: (0, 0),
        }
    }
}

/// The separation without `--eye-separation`: the convergence distance / 30 (Blender's and
/// the 3D-film "1/30 rule", comfortable on a monitor).
pub fn default_separation(convergence: f32) -> f32 {
    convergence / 30.0
}

/// `centre`'s camera for `eye`: moved by half the separation along its right axis, its
/// frustum's window shifted so the convergence plane is the screen. `aspect` is the
/// projection's (the eye viewport's times the camera's squeeze).
pub fn eye_camera(
    centre: &OrbitCamera,
    eye: Eye,
    separation: f32,
    convergence: f32,
    aspect: f32,
) -> OrbitCamera {
    let s = 0.5 * separation * if eye == Eye::Left { -1.0 } else { 1.0 };
    let t = (centre.fov_y_deg.to_radians() * 0.5).tan();
    // The target sits at x = −s in the eye's view; NDC x = −s / (c·t·a), moved to 0 by a
    // window shift of (−s / (c·t·a)) / 2 of the width (NDC spans 2).
    let shift = -s / (convergence.max(1e-9) * t * aspect.max(1e-9)) * 0.5;
    OrbitCamera {
        offset: s,
        shift_x: shift,
        ..centre.centre()
    }
}

/// Where one eye's picture goes: its size and squeeze (the camera's), and the composed
/// picture's size, for an output rectangle of `w`×`h` (a window's; a file's is the picture
/// size except side-by-side-full's, twice as wide: [`output_size`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Layout {
    pub eye: (u32, u32),
    pub squeeze: f32,
}

impl Layout {
    pub fn of(mode: StereoMode, w: u32, h: u32) -> Layout {
        let (eye, squeeze) = match mode {
            StereoMode::SideBySide => ((w / 2, h), 2.0),
            StereoMode::SideBySideFull => ((w / 2, h), 1.0),
            StereoMode::OverUnder => ((w, h / 2), 0.5),
            _ => ((w, h), 1.0),
        };
        Layout {
            eye: (eye.0.max(1), eye.1.max(1)),
            squeeze,
        }
    }

    /// `centre`'s camera for `eye` drawn into this layout's eye: squeezed as the mode
    /// squeezes it, its off-axis frustum for the eye's projection aspect.
    pub fn eye_camera(&self, centre: &OrbitCamera, eye: Eye, stereo: &Stereo) -> OrbitCamera {
        let mut camera = *centre;
        camera.squeeze = self.squeeze;
        let aspect = self.eye.0 as f32 / self.eye.1 as f32 * self.squeeze;
        eye_camera(&camera, eye, stereo.separation, stereo.convergence, aspect)
    }
}

/// The composed picture's size for `--size w×h`: side-by-side-full is twice as wide (each
/// eye keeps the size asked for), every other mode the size asked for.
pub fn output_size(mode: StereoMode, (w, h): (u32, u32)) -> (u32, u32) {
    match mode {
        StereoMode::SideBySideFull => (w * 2, h),
        _ => (w, h),
    }
}

/// Why `mode` cannot be drawn into a `w`×`h` picture (halves need an even side), if so.
pub fn size_refusal(mode: StereoMode, (w, h): (u32, u32)) -> Option<String> {
    match mode {
        StereoMode::SideBySide if w % 2 == 1 => Some(format!(
            "--stereo side-by-side puts each eye in half the width: {w}x{h} has an odd width"
        )),
        StereoMode::OverUnder if h % 2 == 1 => Some(format!(
            "--stereo over-under puts each eye in half the height: {w}x{h} has an odd height"
        )),
        _ => None,
    }
}

/// Rec. 601 luma on display values: the half-colour and grey anaglyphs' luminance.
const LUMA: [f32; 3] = [0.299, 0.587, 0.114];

/// The anaglyph's matrices (left, right): each output pixel is clamp(L·left + R·right) on
/// display (sRGB-encoded) values, as Dubois defines his matrices, rows = output channels.
pub fn anaglyph_matrices(method: AnaglyphMethod, glasses: Glasses) -> (Mat3, Mat3) {
    if method == AnaglyphMethod::Dubois {
        return dubois(glasses);
    }
    // The channels the left filter passes (the right one passes the others).
    let left = match glasses {
        Glasses::RedCyan => [1.0, 0.0, 0.0],
        Glasses::GreenMagenta => [0.0, 1.0, 0.0],
        Glasses::AmberBlue => [1.0, 1.0, 0.0],
    };
    let own = |pass: [f32; 3]| Mat3::from_diagonal(pass.into());
    let luma = |pass: [f32; 3]| {
        // Row c: pass[c] · LUMA (a matrix's rows are its output channels).
        Mat3::from_cols_array_2d(&[
            [pass[0] * LUMA[0], pass[1] * LUMA[0], pass[2] * LUMA[0]],
            [pass[0] * LUMA[1], pass[1] * LUMA[1], pass[2] * LUMA[1]],
            [pass[0] * LUMA[2], pass[1] * LUMA[2], pass[2] * LUMA[2]],
        ])
    };
    let right = left.map(|c| 1.0 - c);
    match method {
        AnaglyphMethod::Color => (own(left), own(right)),
        AnaglyphMethod::HalfColor => (luma(left), own(right)),
        _ => (luma(left), luma(right)),
    }
}

/// Dubois's least-squares anaglyph matrices (E. Dubois, "A projection method to generate
/// anaglyph stereo images", ICASSP 2001; the values of his site's 2009 revision, which
/// three.js's AnaglyphEffect uses for red-cyan), rows = output channels.
fn dubois(glasses: Glasses) -> (Mat3, Mat3) {
    let rows = |m: [[f32; 3]; 3]| Mat3::from_cols_array_2d(&m).transpose();
    match glasses {
        Glasses::RedCyan => (
            rows([
                [0.456_100, 0.500_484, 0.176_381],
                [-0.040_082_2, -0.037_824_6, -0.015_758_9],
                [-0.015_216_1, -0.020_597_1, -0.005_468_56],
            ]),
            rows([
                [-0.043_470_6, -0.087_938_8, -0.001_555_29],
                [0.378_476, 0.733_64, -0.018_450_3],
                [-0.072_152_7, -0.112_961, 1.226_4],
            ]),
        ),
        Glasses::GreenMagenta => (
            rows([
                [-0.062, -0.158, -0.039],
                [0.284, 0.668, 0.143],
                [-0.015, -0.027, 0.021],
            ]),
            rows([
                [0.529, 0.705, 0.024],
                [-0.016, -0.015, -0.065],
                [0.009, 0.075, 0.937],
            ]),
        ),
        Glasses::AmberBlue => (
            rows([
                [1.062, -0.205, 0.299],
                [-0.026, 0.908, 0.068],
                [-0.038, -0.173, 0.022],
            ]),
            rows([
                [-0.016, -0.123, -0.017],
                [0.006, 0.062, -0.017],
                [0.094, 0.185, 0.911],
            ]),
        ),
    }
}

/// Which eye shows at pixel (`col`, `row`) of an interlaced mode, counted from the top left
/// of the screen (a window) or of the picture (a file); None for the other modes.
pub fn interlaced_eye(mode: StereoMode, col: u64, row: u64) -> Option<Eye> {
    let left = match mode {
        StereoMode::Rows => row.is_multiple_of(2),
        StereoMode::Columns => col.is_multiple_of(2),
        StereoMode::Checkerboard => (row + col).is_multiple_of(2),
        _ => return None,
    };
    Some(if left { Eye::Left } else { Eye::Right })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Bounds;
    use glam::{Vec3, Vec4};

    fn centre() -> OrbitCamera {
        let b = Bounds {
            min: Vec3::splat(-1.0),
            max: Vec3::splat(1.0),
        };
        let mut c = OrbitCamera::fit(&b, 45.0, 1.5);
        (c.yaw_deg, c.pitch_deg) = (30.0, 25.0);
        c
    }

    fn ndc(c: &OrbitCamera, p: Vec3, aspect: f32) -> Vec3 {
        let (n, f) = (0.1, 100.0);
        let clip = c.projection_between(aspect, n, f) * c.view() * p.extend(1.0);
        clip.truncate() / clip.w
    }

    /// The eye's matrices equal an off-axis frustum written out independently: the eye at
    /// target + distance·dir ± s·right looking parallel, glFrustum's window shifted by
    /// ∓s·n/c.
    #[test]
    fn eyes_are_the_spelled_out_off_axis_frusta() {
        let c = centre();
        let (sep, conv, aspect) = (0.4, c.distance, 1.5);
        for (eye, sign) in [(Eye::Left, -1.0f32), (Eye::Right, 1.0)] {
            let e = eye_camera(&c, eye, sep, conv, aspect);
            let (y, p) = (c.yaw_deg.to_radians(), c.pitch_deg.to_radians());
            let dir = Vec3::new(p.cos() * y.sin(), p.sin(), p.cos() * y.cos());
            let up = Vec3::new(-p.sin() * y.sin(), p.cos(), -p.sin() * y.cos());
            let right = up.cross(dir).normalize();
            let s = sign * sep * 0.5;
            let pos = c.target + c.distance * dir + s * right;
            let view = glam::Mat4::look_at_rh(pos, pos - dir, up);
            let (n, f) = (0.1f32, 100.0f32);
            let top = n * (c.fov_y_deg.to_radians() * 0.5).tan();
            let half_w = top * aspect;
            let d = -s * n / conv;
            let l = -half_w + d;
            let r = half_w + d;
            // glFrustum(l, r, −top, top, n, f), written out (column-major).
            let proj = glam::Mat4::from_cols(
                Vec4::new(2.0 * n / (r - l), 0.0, 0.0, 0.0),
                Vec4::new(0.0, n / top, 0.0, 0.0),
                Vec4::new((r + l) / (r - l), 0.0, -(f + n) / (f - n), -1.0),
                Vec4::new(0.0, 0.0, -2.0 * f * n / (f - n), 0.0),
            );
            let got = e.projection_between(aspect, n, f) * e.view();
            let want = proj * view;
            assert!(got.abs_diff_eq(want, 1e-5), "{eye:?}: {got:?} vs {want:?}");
        }
    }

    /// Zero parallax at the convergence distance; nearer and farther points shift in
    /// opposite directions by ±(s/(t·a))(1/z − 1/c).
    #[test]
    fn parallax_is_zero_at_the_convergence_distance() {
        let c = centre();
        let aspect = 1.5;
        let (sep, conv) = (0.3, c.distance);
        let (l, r) = (
            eye_camera(&c, Eye::Left, sep, conv, aspect),
            eye_camera(&c, Eye::Right, sep, conv, aspect),
        );
        let at = ndc(&l, c.target, aspect);
        assert!(
            at.truncate().length() < 1e-5,
            "left sees the target at {at}"
        );
        assert!(ndc(&r, c.target, aspect).truncate().length() < 1e-5);
        let t = (c.fov_y_deg.to_radians() * 0.5).tan();
        let forward = (c.target - c.eye()).normalize();
        for z in [0.5 * conv, 0.8 * conv, 1.5 * conv, 3.0 * conv] {
            let p = c.eye() + forward * z;
            let (xl, xr) = (ndc(&l, p, aspect).x, ndc(&r, p, aspect).x);
            let want = (sep * 0.5 / (t * aspect)) * (1.0 / z - 1.0 / conv);
            assert!((xl - want).abs() < 1e-4, "z {z}: left {xl}, formula {want}");
            assert!(
                (xr + want).abs() < 1e-4,
                "z {z}: right {xr}, formula {}",
                -want
            );
        }
    }

    /// Every matrix's columns sum as its filters pass light: colour and the luminance
    /// forms split the channels between the eyes without loss.
    #[test]
    fn simple_anaglyphs_split_the_channels() {
        let white = Vec3::ONE;
        for g in [Glasses::RedCyan, Glasses::GreenMagenta, Glasses::AmberBlue] {
            for m in [
                AnaglyphMethod::Color,
                AnaglyphMethod::HalfColor,
                AnaglyphMethod::Gray,
            ] {
                let (l, r) = anaglyph_matrices(m, g);
                let sum = l * white + r * white;
                assert!(sum.abs_diff_eq(white, 1e-5), "{g:?} {m:?}: {sum}");
            }
        }
        let (l, r) = anaglyph_matrices(AnaglyphMethod::Color, Glasses::RedCyan);
        assert_eq!(l * Vec3::new(0.2, 0.5, 0.7), Vec3::new(0.2, 0.0, 0.0));
        assert_eq!(r * Vec3::new(0.2, 0.5, 0.7), Vec3::new(0.0, 0.5, 0.7));
        // Dubois red-cyan: a white left eye is mostly red (0.456 + 0.500 + 0.176).
        let (l, _) = anaglyph_matrices(AnaglyphMethod::Dubois, Glasses::RedCyan);
        assert!(((l * white).x - 1.132_965).abs() < 1e-5);
    }

    #[test]
    fn layouts_and_interlacing() {
        assert_eq!(Layout::of(StereoMode::SideBySide, 640, 480).eye, (320, 480));
        assert_eq!(Layout::of(StereoMode::OverUnder, 640, 480).eye, (640, 240));
        assert_eq!(
            output_size(StereoMode::SideBySideFull, (640, 480)),
            (1280, 480)
        );
        assert!(size_refusal(StereoMode::SideBySide, (641, 480)).is_some());
        assert_eq!(interlaced_eye(StereoMode::Rows, 5, 0), Some(Eye::Left));
        assert_eq!(
            interlaced_eye(StereoMode::Checkerboard, 1, 2),
            Some(Eye::Right)
        );
        assert_eq!(interlaced_eye(StereoMode::Anaglyph, 0, 0), None);
    }
}
