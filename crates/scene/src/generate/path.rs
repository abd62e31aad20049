//! 2D paths: straight lines with circular fillets, sampled with exact tangents.

use crate::generate::math::{sub2, unit2, V2};
use std::f64::consts::{PI, TAU};

/// Longest chord of an arc sample, in radians and in scene units: small fillets would
/// otherwise cost as many triangles as large ones while being invisible.
const ARC_STEP_ANGLE: f64 = PI / 18.0;
const ARC_STEP_LEN: f64 = 0.012;

/// A path sample and its unit tangent (direction of travel).
#[derive(Clone, Copy, Debug)]
pub(super) struct PathPt {
    pub(super) p: V2,
    pub(super) t: V2,
}

impl PathPt {
    /// Normal on the right of the direction of travel: outward for a profile walked with the
    /// solid on its left.
    pub(super) fn normal(&self) -> V2 {
        [self.t[1], -self.t[0]]
    }
}

/// Samples a polyline whose interior corners are rounded by circular fillets of the given
/// radius. A radius of 0 keeps a sharp crease: the path is split there into separate smooth
/// runs so that normals are not averaged across the crease. Endpoint radii are ignored.
pub(super) fn rounded_path(corners: &[(V2, f64)], max_len: f64) -> Vec<Vec<PathPt>> {
    assert!(corners.len() >= 2, "a path needs two points");
    let first_dir = unit2(sub2(corners[1].0, corners[0].0));
    let mut runs = vec![vec![PathPt {
        p: corners[0].0,
        t: first_dir,
    }]];
    for win in corners.windows(3) {
        let [(prev, _), (corner, radius), (next, _)] = [win[0], win[1], win[2]];
        let d_in = unit2(sub2(corner, prev));
        let d_out = unit2(sub2(next, corner));
        let angle = (d_in[0] * d_out[0] + d_in[1] * d_out[1])
            .clamp(-1.0, 1.0)
            .acos();
        let run = runs.last_mut().expect("runs is never empty");
        if radius <= 0.0 || angle < 1e-9 {
            line_to(run, corner, d_in, max_len);
            if angle >= 1e-9 {
                runs.push(vec![PathPt {
                    p: corner,
                    t: d_out,
                }]);
            }
            continue;
        }
        let left = (d_in[0] * d_out[1] - d_in[1] * d_out[0]).signum();
        let back = radius * (angle / 2.0).tan();
        let t1 = [corner[0] - d_in[0] * back, corner[1] - d_in[1] * back];
        let centre = [
            t1[0] - d_in[1] * radius * left,
            t1[1] + d_in[0] * radius * left,
        ];
        line_to(run, t1, d_in, max_len);
        arc(
            run,
            centre,
            radius,
            (t1[1] - centre[1]).atan2(t1[0] - centre[0]),
            left * angle,
        );
    }
    let n = corners.len();
    let last_dir = unit2(sub2(corners[n - 1].0, corners[n - 2].0));
    let run = runs.last_mut().expect("runs is never empty");
    line_to(run, corners[n - 1].0, last_dir, max_len);
    runs
}

fn line_to(run: &mut Vec<PathPt>, to: V2, dir: V2, max_len: f64) {
    let from = run.last().expect("a run starts with a point").p;
    let delta = sub2(to, from);
    let len = delta[0].hypot(delta[1]);
    if len < 1e-9 {
        return;
    }
    // A backwards step means two fillets overlap on this edge: the radii are too large.
    assert!(
        delta[0] * dir[0] + delta[1] * dir[1] > 0.0,
        "fillets overlap before {to:?}"
    );
    let steps = (len / max_len).ceil().max(1.0) as usize;
    for k in 1..=steps {
        let s = k as f64 / steps as f64;
        run.push(PathPt {
            p: [from[0] + delta[0] * s, from[1] + delta[1] * s],
            t: dir,
        });
    }
}

/// Appends an arc from angle `start` sweeping `sweep` radians (positive = counter-clockwise);
/// the first point is assumed to be on the run already.
fn arc(run: &mut Vec<PathPt>, centre: V2, radius: f64, start: f64, sweep: f64) {
    let by_angle = (sweep.abs() / ARC_STEP_ANGLE).ceil();
    let by_len = (radius * sweep.abs() / ARC_STEP_LEN).ceil();
    let steps = by_angle.min(by_len).max(2.0) as usize;
    let sign = sweep.signum();
    for k in 1..=steps {
        let (s, c) = (start + sweep * k as f64 / steps as f64).sin_cos();
        run.push(PathPt {
            p: [centre[0] + radius * c, centre[1] + radius * s],
            t: [-s * sign, c * sign],
        });
    }
}

/// A full circle walked counter-clockwise (disc on the left), e.g. a torus cross-section.
pub(super) fn circle_path(centre: V2, radius: f64) -> Vec<Vec<PathPt>> {
    let mut run = vec![PathPt {
        p: [centre[0] + radius, centre[1]],
        t: [0.0, 1.0],
    }];
    arc(&mut run, centre, radius, 0.0, TAU);
    vec![run]
}
