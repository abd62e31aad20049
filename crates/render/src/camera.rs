//! Orbit camera, pure math (no GL, no winit). Right-handed, +Y up;
//! eye = target + distance · (cos(pitch)·sin(yaw), sin(pitch), cos(pitch)·cos(yaw)).
//!
//! Past the poles the camera does not clamp: its up vector is the derivative of the eye
//! direction with respect to pitch, which is always perpendicular to the view and never zero,
//! so the view rolls smoothly over the top (the picture turns upside down, like a trackball)
//! and pitch ±90° is an ordinary view straight down or up.
use crate::scene::Bounds;
use glam::{Mat4, Vec3};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrbitCamera {
    pub target: Vec3,
    pub distance: f32,
    pub yaw_deg: f32,
    pub pitch_deg: f32,
    pub fov_y_deg: f32,
    /// Orthographic view of this height, if set.
    pub ortho_height: Option<f32>,
    /// `--near`: a fixed near plane instead of the one fitted to the bounds.
    pub near: Option<f32>,
    /// A stereo eye: the camera moved this far along its right axis, target with it, so
    /// the eyes look in parallel (never toe-in). 0 for a mono view.
    pub offset: f32,
    /// Lens shift (`--lens-shift`, Blender's Shift X): the frustum's window moved right by
    /// this fraction of the picture's width, the picture's content moving left. With
    /// `offset` it makes an eye's off-axis frustum (`crate::stereo`).
    pub shift_x: f32,
    /// The projection's aspect is the viewport's times this: 1, or an eye squeezed into half
    /// a side-by-side (2) or an over-under (0.5) picture, which the display stretches back.
    pub squeeze: f32,
}

/// Camera input, independent of any windowing library.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CameraMove {
    Yaw(f32),
    Pitch(f32),
    /// Multiplies the distance (and the ortho height).
    Zoom(f32),
}

pub(crate) const KEY_STEP_DEG: f32 = 5.0;
pub(crate) const ZOOM_STEP: f32 = 1.1;

impl OrbitCamera {
    /// The default view: looks at the bounds' centre from +Z at a distance where the bounding
    /// sphere fills the smaller field of view.
    pub fn fit(bounds: &Bounds, fov_y_deg: f32, aspect: f32) -> Self {
        let mut c = OrbitCamera {
            target: bounds.center(),
            distance: 1.0,
            yaw_deg: 0.0,
            pitch_deg: 0.0,
            fov_y_deg,
            ortho_height: None,
            near: None,
            offset: 0.0,
            shift_x: 0.0,
            squeeze: 1.0,
        };
        c.distance = c.fit_distance(bounds, aspect);
        c
    }

    pub fn fit_distance(&self, bounds: &Bounds, aspect: f32) -> f32 {
        let half_v = (self.fov_y_deg.to_radians() * 0.5).clamp(1e-3, 1.55);
        let half_h = (half_v.tan() * aspect.max(1e-3)).atan();
        bounds.radius() / half_v.min(half_h).sin()
    }

    /// The orthographic view height that fits the bounding sphere: it touches the top and
    /// bottom edges of a landscape picture, the left and right edges of a portrait one.
    pub fn fit_ortho_height(bounds: &Bounds, aspect: f32) -> f32 {
        2.0 * bounds.radius() * (1.0 / aspect.max(1e-3)).max(1.0)
    }

    pub(crate) fn direction(&self) -> Vec3 {
        let (y, p) = (self.yaw_deg.to_radians(), self.pitch_deg.to_radians());
        Vec3::new(p.cos() * y.sin(), p.sin(), p.cos() * y.cos())
    }

    /// Where the camera is: on its orbit, moved by the eye's `offset` along `right`.
    pub fn eye(&self) -> Vec3 {
        self.looked_at() + self.distance * self.direction()
    }

    /// The camera's right axis (the view's +X).
    pub fn right(&self) -> Vec3 {
        self.up().cross(self.direction()).normalize_or(Vec3::X)
    }

    /// The point the view is centred on: the target, moved with the eye.
    fn looked_at(&self) -> Vec3 {
        if self.offset == 0.0 {
            self.target
        } else {
            self.target + self.offset * self.right()
        }
    }

    /// The mono camera a stereo eye was made from (no offset, no lens shift): what the
    /// eyes share, such as the level of detail.
    pub fn centre(&self) -> OrbitCamera {
        OrbitCamera {
            offset: 0.0,
            shift_x: 0.0,
            ..*self
        }
    }

    pub fn up(&self) -> Vec3 {
        let (y, p) = (self.yaw_deg.to_radians(), self.pitch_deg.to_radians());
        Vec3::new(-p.sin() * y.sin(), p.cos(), -p.sin() * y.cos())
    }

    pub fn view(&self) -> Mat4 {
        Mat4::look_at_rh(self.eye(), self.looked_at(), self.up())
    }

    /// Near and far planes that hold the whole bounding sphere. Inside the sphere the near
    /// plane is a tenth of the distance to the target (so what the camera looks at is never
    /// clipped, even zoomed far into a detail), but never below far·10⁻⁷: the ratio can pass
    /// 10⁶, which costs depth precision far away, never a NaN or a blank frame.
    pub fn near_far(&self, bounds: &Bounds) -> (f32, f32) {
        let r = bounds.radius();
        let d = (self.eye() - bounds.center()).length();
        let far = (d + r) * 1.01;
        if self.ortho_height.is_some() {
            return (d - r * 1.01, far);
        }
        if let Some(n) = self.near.filter(|n| *n > 0.0 && *n < far) {
            return (n, far);
        }
        let inside = (far * 1e-4).min(self.distance * 0.1).max(far * 1e-7);
        let near = (d - r * 1.01).max(inside);
        (near, far)
    }

    pub fn projection(&self, bounds: &Bounds, aspect: f32) -> Mat4 {
        let (near, far) = self.near_far(bounds);
        self.projection_between(aspect, near, far)
    }

    /// The view's projection with clip planes `near` and `far`: the frame's come from
    /// [`Self::near_far`]; the ground grid reaches further (`render/grid.rs`).
    pub(crate) fn projection_between(&self, aspect: f32, near: f32, far: f32) -> Mat4 {
        let aspect = aspect * self.squeeze;
        let aspect = if aspect.is_finite() && aspect > 0.0 {
            aspect
        } else {
            1.0
        };
        let p = match self.ortho_height {
            Some(h) => {
                let (hh, hw) = (h * 0.5, h * 0.5 * aspect);
                Mat4::orthographic_rh_gl(-hw, hw, -hh, hh, near, far)
            }
            None => Mat4::perspective_rh_gl(self.fov_y_deg.to_radians(), aspect, near, far),
        };
        if self.shift_x == 0.0 {
            return p;
        }
        // The window moved right by shift·width: clip x' = x − 2·shift·w (NDC spans 2).
        Mat4::from_translation(Vec3::new(-2.0 * self.shift_x, 0.0, 0.0)) * p
    }

    pub(crate) fn apply(&mut self, m: CameraMove) {
        match m {
            CameraMove::Yaw(d) => self.yaw_deg = (self.yaw_deg + d) % 360.0,
            CameraMove::Pitch(d) => self.pitch_deg = (self.pitch_deg + d) % 360.0,
            CameraMove::Zoom(f) => {
                self.distance = (self.distance * f).max(1e-6);
                if let Some(h) = &mut self.ortho_height {
                    *h = (*h * f).max(1e-6);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_bounds() -> Bounds {
        Bounds {
            min: Vec3::splat(-1.0),
            max: Vec3::splat(1.0),
        }
    }

    /// `--ortho` alone: the sphere's outline touches the nearer pair of edges exactly, from
    /// any direction and for landscape and portrait pictures alike.
    #[test]
    fn fitted_ortho_height_touches_the_nearer_edges() {
        let b = unit_bounds();
        for (aspect, yaw, pitch) in [(1.5, 30.0, 25.0), (0.5, -70.0, 10.0), (1.0, 200.0, -80.0)] {
            let mut c = OrbitCamera::fit(&b, 45.0, aspect);
            (c.yaw_deg, c.pitch_deg) = (yaw, pitch);
            c.ortho_height = Some(OrbitCamera::fit_ortho_height(&b, aspect));
            let vp = c.projection(&b, aspect) * c.view();
            // Extreme points of the sphere along the view's right and up axes.
            let right = c.up().cross(c.direction()).normalize();
            let r = b.radius();
            let x = (vp * (b.center() + right * r).extend(1.0)).x;
            let y = (vp * (b.center() + c.up() * r).extend(1.0)).y;
            let nearer = x.abs().max(y.abs());
            assert!((nearer - 1.0).abs() < 1e-4, "aspect {aspect}: {x} {y}");
            assert!(x.abs() <= 1.0 + 1e-4 && y.abs() <= 1.0 + 1e-4);
        }
    }

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).length() < 1e-5
    }

    #[test]
    fn zero_angles_look_down_minus_z() {
        let c = OrbitCamera::fit(&unit_bounds(), 45.0, 1.0);
        assert!(close(c.direction(), Vec3::Z));
        let v = c.view();
        // The target is straight ahead on -Z in eye space.
        let t = v.transform_point3(c.target);
        assert!(t.x.abs() < 1e-5 && t.y.abs() < 1e-5 && t.z < 0.0);
    }

    #[test]
    fn yaw_90_looks_from_plus_x() {
        let mut c = OrbitCamera::fit(&unit_bounds(), 45.0, 1.0);
        c.apply(CameraMove::Yaw(90.0));
        assert!(close(c.direction(), Vec3::X));
    }

    #[test]
    fn key_steps_and_pitch_up_moves_eye_up() {
        let mut c = OrbitCamera::fit(&unit_bounds(), 45.0, 1.0);
        c.apply(CameraMove::Pitch(KEY_STEP_DEG));
        assert!(c.eye().y > 0.0);
        assert_eq!(c.pitch_deg, 5.0);
        c.apply(CameraMove::Yaw(-KEY_STEP_DEG));
        assert_eq!(c.yaw_deg, -5.0);
    }

    #[test]
    fn fit_holds_the_sphere() {
        let c = OrbitCamera::fit(&unit_bounds(), 60.0, 1.0);
        let r = 3f32.sqrt();
        assert!((c.distance - r / 30f32.to_radians().sin()).abs() < 1e-5);
        let (n, f) = c.near_far(&unit_bounds());
        assert!(n > 0.0 && n <= c.distance - r && f >= c.distance + r);
        // A narrow window is limited by the horizontal field of view.
        assert!(OrbitCamera::fit(&unit_bounds(), 60.0, 0.5).distance > c.distance);
    }

    #[test]
    fn poles_and_beyond_are_finite_and_continuous() {
        let mut c = OrbitCamera::fit(&unit_bounds(), 45.0, 1.0);
        let mut prev_up = c.up();
        for _ in 0..72 {
            c.apply(CameraMove::Pitch(2.5));
            let (v, up) = (c.view(), c.up());
            assert!(v.is_finite(), "pitch {}", c.pitch_deg);
            assert!(up.dot(c.direction()).abs() < 1e-5);
            // No sudden flip: the up vector turns by the step, never by 180°.
            assert!(up.dot(prev_up) > 0.99, "flip at pitch {}", c.pitch_deg);
            prev_up = up;
        }
        c.pitch_deg = 90.0;
        assert!(c.view().is_finite() && close(c.direction(), Vec3::Y));
    }

    #[test]
    fn inside_the_model_near_stays_positive() {
        let mut c = OrbitCamera::fit(&unit_bounds(), 45.0, 1.0);
        c.distance = 0.01;
        let (n, f) = c.near_far(&unit_bounds());
        assert!(n > 0.0 && n < 0.01 && f > 1.7);
        assert!(c.projection(&unit_bounds(), 1.0).is_finite());
    }

    #[test]
    fn zero_aspect_is_safe() {
        let c = OrbitCamera::fit(&unit_bounds(), 45.0, 0.0);
        assert!(c.projection(&unit_bounds(), 0.0).is_finite());
    }
}
