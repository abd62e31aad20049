//! glass_holder: a tea glass in a metal holder ("podstakannik") standing on a saucer.

use crate::generate::math::{dot, normalize, scale, sub, V2};
use crate::generate::path::{circle_path, rounded_path, PathPt};
use crate::generate::shapes::{revolve, tube, Frame};
use crate::generate::writer::{mtl, Material, ObjWriter};
use crate::generate::GeneratedModel;
use std::f64::consts::TAU;

/// Around-the-axis segments of the revolved parts; the holder's small radii need fewer.
const SEGS: usize = 128;
const HOLDER_SEGS: usize = 96;

const SAUCER_TOP: f64 = 0.045;
/// The glass stands 0.002 above the holder floor (`FLOOR_Y`): coplanar opposite faces would
/// z-fight where they are seen through the translucent glass.
const GLASS_Y0: f64 = 0.117;
const GLASS_H: f64 = 1.2;
const GLASS_R0: f64 = 0.32;
const GLASS_R1: f64 = 0.37;
const GLASS_WALL: f64 = 0.022;
const GLASS_BASE: f64 = 0.07;

const FLOOR_Y: f64 = 0.115;
const FLOOR_T: f64 = 0.015;
/// Clearance between glass and holder, and the holder's sheet thickness.
const GAP: f64 = 0.006;
const SHEET: f64 = 0.012;
const BAND_TOP: f64 = 0.40;
const RING_BOT: f64 = 0.83;
const RING_TOP: f64 = GLASS_Y0 + GLASS_H * 2.0 / 3.0;

/// Outer radius of the glass at height `y` (a straight flare, extended below the glass).
fn glass_r(y: f64) -> f64 {
    GLASS_R0 + (GLASS_R1 - GLASS_R0) * (y - GLASS_Y0) / GLASS_H
}

/// Inner surface of the holder sleeve, which follows the glass's flare.
fn sleeve_in(y: f64) -> f64 {
    glass_r(y) + GAP
}

fn sleeve_out(y: f64) -> f64 {
    sleeve_in(y) + SHEET
}

pub(super) fn glass_holder() -> GeneratedModel {
    let mut w = ObjWriter::new("glass_holder");
    w.object("saucer", "saucer");
    revolve(&mut w, &saucer_profile(), SEGS);
    w.object("holder", "metal");
    holder_body(&mut w);
    w.object("holder_cage", "metal");
    holder_cage(&mut w);
    w.object("holder_handle", "metal");
    holder_handle(&mut w);
    // Last, so that viewers drawing in file order blend the glass over everything else.
    w.object("glass", "glass");
    revolve(&mut w, &glass_profile(), SEGS);
    GeneratedModel {
        name: "glass_holder",
        obj: w.finish(),
        mtl: mtl(&[
            Material {
                d: 0.35,
                illum: 4,
                ..Material::phong(
                    "glass",
                    [0.05, 0.07, 0.08],
                    [0.55, 0.7, 0.8],
                    [0.9, 0.9, 0.9],
                    96.0,
                )
            },
            Material::phong(
                "metal",
                [0.2, 0.2, 0.2],
                [0.45, 0.45, 0.47],
                [0.85, 0.85, 0.85],
                64.0,
            ),
            Material::phong(
                "saucer",
                [0.2, 0.2, 0.2],
                [0.85, 0.86, 0.9],
                [0.35, 0.35, 0.35],
                32.0,
            ),
        ]),
    }
}

/// Closed porcelain shell: a foot ring underneath, a flat well, a sloped flank and a rounded
/// raised rim; radius 1, resting on y = 0.
pub(super) fn saucer_profile() -> Vec<Vec<PathPt>> {
    rounded_path(
        &[
            ([0.0, 0.010], 0.0),
            ([0.46, 0.010], 0.01),
            ([0.48, 0.0], 0.006),
            ([0.56, 0.0], 0.008),
            ([0.60, 0.018], 0.015),
            ([1.0, 0.118], 0.012),
            ([0.99, 0.142], 0.012),
            ([0.62, SAUCER_TOP], 0.25),
            ([0.0, SAUCER_TOP], 0.0),
        ],
        0.15,
    )
}

/// Closed glass shell with real wall thickness: outer bottom, outer wall, rounded rim, inner
/// wall and a thick inner bottom.
pub(super) fn glass_profile() -> Vec<Vec<PathPt>> {
    let (y0, y1, t) = (GLASS_Y0, GLASS_Y0 + GLASS_H, GLASS_WALL);
    rounded_path(
        &[
            ([0.0, y0], 0.0),
            ([GLASS_R0, y0], 0.035),
            ([GLASS_R1, y1], 0.45 * t),
            ([GLASS_R1 - t, y1], 0.45 * t),
            ([GLASS_R0 - t, y0 + GLASS_BASE], 0.05),
            ([0.0, y0 + GLASS_BASE], 0.0),
        ],
        0.2,
    )
}

/// The revolved metal: a base (floor, flared foot and lower band) as one closed shell, a top
/// ring, and beads (tori) that roll over the raw edges of the band and ring.
fn holder_body(w: &mut ObjWriter) {
    let base = rounded_path(
        &[
            ([0.0, FLOOR_Y - FLOOR_T], 0.0),
            ([0.25, FLOOR_Y - FLOOR_T], 0.03),
            ([0.345, SAUCER_TOP], 0.006),
            ([0.415, SAUCER_TOP], 0.012),
            ([sleeve_out(0.15), 0.15], 0.04),
            ([sleeve_out(BAND_TOP), BAND_TOP], 0.004),
            ([sleeve_in(BAND_TOP), BAND_TOP], 0.004),
            ([sleeve_in(FLOOR_Y), FLOOR_Y], 0.004),
            ([0.0, FLOOR_Y], 0.0),
        ],
        0.12,
    );
    revolve(w, &base, HOLDER_SEGS);
    // Start and end mid-way up the outer wall so the closed loop has no crease at its seam.
    let mid = (RING_BOT + RING_TOP) / 2.0;
    let ring = rounded_path(
        &[
            ([sleeve_out(mid), mid], 0.0),
            ([sleeve_out(RING_TOP), RING_TOP], 0.004),
            ([sleeve_in(RING_TOP), RING_TOP], 0.004),
            ([sleeve_in(RING_BOT), RING_BOT], 0.004),
            ([sleeve_out(RING_BOT), RING_BOT], 0.004),
            ([sleeve_out(mid), mid], 0.0),
        ],
        0.12,
    );
    revolve(w, &ring, HOLDER_SEGS);
    for (y, radius) in [
        (0.17, 0.01),
        (BAND_TOP, 0.012),
        (RING_BOT, 0.012),
        (RING_TOP, 0.016),
    ] {
        revolve(w, &circle_path(bead_centre(y, radius), radius), HOLDER_SEGS);
    }
}

/// Beads sit so that their inner side keeps 4e-3 clear of the glass and they swallow the
/// sheet's edge whole.
fn bead_centre(y: f64, radius: f64) -> V2 {
    [sleeve_in(y) - 0.002 + radius, y]
}

/// Openwork between the lower band and the top ring: two families of helical wires crossing
/// into a diamond lattice. Wire ends are buried inside the beads.
fn holder_cage(w: &mut ObjWriter) {
    const WIRES: usize = 12;
    let pitch = TAU / WIRES as f64;
    for i in 0..WIRES {
        let start = pitch * (i as f64 + 0.5);
        for dir in [1.0, -1.0] {
            tube(w, &cage_wire(start, dir * pitch, 10), 0.0075, 0.0075, 8);
        }
    }
}

/// Frames along one wire: a helix on the sleeve's mid-surface from the band to the ring,
/// turning by `turn` radians; tangents are the analytic derivative.
fn cage_wire(start: f64, turn: f64, steps: usize) -> Vec<Frame> {
    let rise = RING_BOT - BAND_TOP;
    let flare = (GLASS_R1 - GLASS_R0) / GLASS_H * rise;
    (0..=steps)
        .map(|k| {
            let s = k as f64 / steps as f64;
            let y = BAND_TOP + rise * s;
            let r = sleeve_in(y) + SHEET / 2.0;
            let (sn, cs) = (start + turn * s).sin_cos();
            let d = [flare * cs - r * turn * sn, rise, flare * sn + r * turn * cs];
            let t = normalize(d);
            let radial = [cs, 0.0, sn];
            Frame {
                c: [r * cs, y, r * sn],
                t,
                n: normalize(sub(radial, scale(t, dot(radial, t)))),
            }
        })
        .collect()
}

/// An ear-shaped strap handle on the +X side, in the XY plane, fixed into the top ring and
/// the lower band; its elliptic section is wider across (Z) than it is thick.
fn holder_handle(w: &mut ObjWriter) {
    let mid = |y: f64| sleeve_in(y) + SHEET / 2.0;
    let (top, low) = ((RING_BOT + RING_TOP) / 2.0, 0.27);
    let path = rounded_path(
        &[
            ([mid(top), top], 0.0),
            ([0.66, top], 0.25),
            ([0.60, low], 0.15),
            ([mid(low), low], 0.0),
        ],
        0.04,
    );
    let frames: Vec<Frame> = path
        .iter()
        .flatten()
        .map(|pt| Frame {
            c: [pt.p[0], pt.p[1], 0.0],
            t: [pt.t[0], pt.t[1], 0.0],
            n: [pt.t[1], -pt.t[0], 0.0],
        })
        .collect();
    tube(w, &frames, 0.02, 0.03, 20);
}
