//! Primary rays: the orbit camera recomputed in f64 (same formulas as `camera.rs`, which works
//! in f32 for the GPU), un-projected through the inverse of projection · view so perspective
//! and orthographic views are one code path.
use crate::camera::OrbitCamera;
use crate::scene::Bounds;
use glam::{DMat4, DVec3, DVec4};

pub(crate) struct View {
    inverse: DMat4,
    /// Projection · view: world to clip coordinates (points and edges are projected with it).
    pub(crate) forward: DMat4,
    pub(crate) eye: DVec3,
    /// Eye-space +Z in world coordinates: where a zero normal points (see `surface`).
    pub(crate) back: DVec3,
}

impl View {
    pub(crate) fn new(c: &OrbitCamera, bounds: &Bounds, width: u32, height: u32) -> View {
        let (yaw, pitch) = (
            f64::from(c.yaw_deg).to_radians(),
            f64::from(c.pitch_deg).to_radians(),
        );
        let dir = DVec3::new(
            pitch.cos() * yaw.sin(),
            pitch.sin(),
            pitch.cos() * yaw.cos(),
        );
        let up = DVec3::new(
            -pitch.sin() * yaw.sin(),
            pitch.cos(),
            -pitch.sin() * yaw.cos(),
        );
        let target = c.target.as_dvec3();
        let eye = target + f64::from(c.distance) * dir;
        let view = DMat4::look_at_rh(eye, target, up);
        // The planes the GPU clips at, as the camera computes them for it.
        let (near, far) = c.near_far(bounds);
        let (near, far) = (f64::from(near), f64::from(far));
        let aspect = f64::from(width) / f64::from(height.max(1));
        let aspect = if aspect.is_finite() && aspect > 0.0 {
            aspect
        } else {
            1.0
        };
        let proj = match c.ortho_height {
            Some(h) => {
                let (hh, hw) = (f64::from(h) * 0.5, f64::from(h) * 0.5 * aspect);
                DMat4::orthographic_rh_gl(-hw, hw, -hh, hh, near, far)
            }
            None => {
                DMat4::perspective_rh_gl(f64::from(c.fov_y_deg).to_radians(), aspect, near, far)
            }
        };
        View {
            inverse: (proj * view).inverse(),
            forward: proj * view,
            eye,
            back: dir,
        }
    }

    /// The ray through the centre of pixel (x, y), y = 0 the top row: it starts on the near
    /// plane and reaches the far plane at t = 1, so GL's depth clipping is t ∈ [0, 1].
    pub(crate) fn ray(&self, x: u32, y: u32, width: u32, height: u32) -> (DVec3, DVec3) {
        let nx = 2.0 * (f64::from(x) + 0.5) / f64::from(width) - 1.0;
        let ny = 1.0 - 2.0 * (f64::from(y) + 0.5) / f64::from(height);
        self.ray_ndc(nx, ny)
    }

    /// The ray through normalised device coordinates (nx, ny), as [`View::ray`].
    pub(crate) fn ray_ndc(&self, nx: f64, ny: f64) -> (DVec3, DVec3) {
        let unproject = |z: f64| {
            let p = self.inverse * DVec4::new(nx, ny, z, 1.0);
            p.truncate() / p.w
        };
        let (near, far) = (unproject(-1.0), unproject(1.0));
        (near, far - near)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn bounds() -> Bounds {
        Bounds {
            min: Vec3::splat(-1.0),
            max: Vec3::splat(1.0),
        }
    }

    #[test]
    fn centre_ray_hits_target_and_spans_near_to_far() {
        let mut c = OrbitCamera::fit(&bounds(), 45.0, 1.0);
        c.yaw_deg = 30.0;
        c.pitch_deg = 20.0;
        let v = View::new(&c, &bounds(), 101, 101);
        let (o, d) = v.ray(50, 50, 101, 101);
        let to_target = c.target.as_dvec3() - v.eye;
        assert!(d.normalize().dot(to_target.normalize()) > 1.0 - 1e-12);
        let (near, far) = c.near_far(&bounds());
        let fwd = to_target.normalize();
        assert!(((o - v.eye).dot(fwd) - f64::from(near)).abs() < 1e-9);
        assert!(((o + d - v.eye).dot(fwd) - f64::from(far)).abs() < 1e-9);
        // The top-left pixel looks up and to the left of the view.
        let (_, d0) = v.ray(0, 0, 101, 101);
        let right = fwd.cross(c.up().as_dvec3());
        assert!(d0.dot(c.up().as_dvec3()) > 0.0 && d0.dot(right) < 0.0);
    }

    #[test]
    fn ortho_rays_are_parallel_and_span_the_height() {
        let mut c = OrbitCamera::fit(&bounds(), 45.0, 2.0);
        c.ortho_height = Some(4.0);
        let v = View::new(&c, &bounds(), 200, 100);
        let (o0, d0) = v.ray(0, 0, 200, 100);
        let (o1, d1) = v.ray(199, 99, 200, 100);
        assert!(d0.normalize().dot(d1.normalize()) > 1.0 - 1e-12);
        // Pixel centres 99 rows apart are 99 · (4 / 100) world units apart.
        let up = c.up().as_dvec3();
        assert!(((o0 - o1).dot(up) - 3.96).abs() < 1e-9);
        assert!(((o1 - o0).dot(d0.normalize().cross(up)) - 7.96).abs() < 1e-9);
    }
}
