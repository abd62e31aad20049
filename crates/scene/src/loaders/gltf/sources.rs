//! A moving primitive's vertex data read as the file gives it (mesh space): positions,
//! normals, tangents, morph targets' deltas and the JOINTS_n/WEIGHTS_n sets, each checked:
//! a non-finite normal or tangent is dropped (generated instead) as the static loader does,
//! a morph target of the wrong size or with non-finite deltas moves nothing, and joint
//! indices past the skin's joints make the primitive unskinned — each with a warning.
use crate::loaders::gltf::accessor::{self as accessor, Buffers};
use crate::motion::pose::{JointSet, Source, Target, MAX_MORPH};
use gltf::accessor::Dimensions as D;
use gltf::mesh::Semantic;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Reads `p`'s streams; `joints` is the applied skin's joint count (None: no skin).
/// Positions that are not finite are an error (as for every primitive).
pub(crate) fn read(
    p: &gltf::Primitive,
    buffers: &Buffers,
    (joints, morph_budget): (Option<usize>, &AtomicUsize),
    label: &str,
    warn: &mut dyn FnMut(String),
) -> Result<Source, String> {
    let pos = p
        .get(&Semantic::Positions)
        .ok_or_else(|| format!("{label}: no POSITION"))?;
    let (_, positions) = accessor::read_f32(&pos, buffers, &[D::Vec3])?;
    if let Some(k) = positions.iter().position(|x| !x.is_finite()) {
        return Err(format!(
            "accessor {} (POSITION of {label}): element {} is not finite",
            pos.index(),
            k / 3
        ));
    }
    let n = positions.len() / 3;
    let mut finite =
        |sem: Semantic, width: usize, what: &str| -> Result<Option<Vec<f32>>, String> {
            let Some(a) = p.get(&sem) else {
                return Ok(None);
            };
            let dims = if width == 4 { D::Vec4 } else { D::Vec3 };
            let (_, v) = accessor::read_f32(&a, buffers, &[dims])?;
            if v.len() != n * width || v.iter().any(|x| !x.is_finite()) {
                warn(format!(
                    "accessor {} ({what} of {label}): not finite or not one per vertex; {what}s \
                 generated",
                    a.index()
                ));
                return Ok(None);
            }
            Ok(Some(v))
        };
    let normals = finite(Semantic::Normals, 3, "NORMAL")?;
    // Lines and points have no tangent frame: their TANGENT is not read (a bad one would
    // refuse the file, as the still path never reads it).
    let triangles = !matches!(
        p.mode(),
        gltf::mesh::Mode::Points
            | gltf::mesh::Mode::Lines
            | gltf::mesh::Mode::LineLoop
            | gltf::mesh::Mode::LineStrip
    );
    let tangents = match triangles {
        true => finite(Semantic::Tangents, 4, "TANGENT")?,
        false => None,
    };
    let targets = targets(p, buffers, (n, morph_budget), label, warn)?;
    let sets = match joints {
        Some(j) => skin_sets(p, buffers, (n, j), label, warn)?,
        None => Vec::new(),
    };
    Ok(Source {
        positions,
        normals,
        tangents,
        targets,
        sets,
    })
}

/// The morph targets' deltas; a target that cannot be used stays in its place (the
/// weights are matched by position) and moves nothing.
fn targets(
    p: &gltf::Primitive,
    buffers: &Buffers,
    (n, budget): (usize, &AtomicUsize),
    label: &str,
    warn: &mut dyn FnMut(String),
) -> Result<Vec<Target>, String> {
    let count = p.morph_targets().len();
    let deltas = count.saturating_mul(n);
    if deltas > 0
        && budget
            .fetch_update(Ordering::Relaxed, Ordering::Relaxed, |left| {
                left.checked_sub(deltas)
            })
            .is_err()
    {
        warn(format!(
            "{label}: {count} morph targets of {n} vertices pass the file's {MAX_MORPH} \
             morph deltas; not morphed"
        ));
        return Ok(Vec::new());
    }
    let mut out = Vec::with_capacity(count);
    for (ti, t) in p.morph_targets().enumerate() {
        let mut read = |a: Option<gltf::Accessor>| -> Result<Option<Vec<f32>>, String> {
            let Some(a) = a else { return Ok(None) };
            let (_, v) = accessor::read_f32(&a, buffers, &[D::Vec3])?;
            if v.len() != n * 3 || v.iter().any(|x| !x.is_finite()) {
                warn(format!(
                    "{label}: morph target {ti}'s accessor {} is not finite or not one per \
                     vertex; it moves nothing",
                    a.index()
                ));
                return Ok(None);
            }
            Ok(Some(v))
        };
        out.push(Target {
            positions: read(t.positions())?,
            normals: read(t.normals())?,
            tangents: read(t.tangents())?,
        });
    }
    Ok(out)
}

/// JOINTS_n with WEIGHTS_n for every n the primitive has; empty (drawn unskinned, with a
/// warning) if a weighted joint index is past the skin's `joints`, or a set is malformed.
fn skin_sets(
    p: &gltf::Primitive,
    buffers: &Buffers,
    (n, joints): (usize, usize),
    label: &str,
    warn: &mut dyn FnMut(String),
) -> Result<Vec<JointSet>, String> {
    let mut sets = Vec::new();
    for set in 0.. {
        let (Some(ja), Some(wa)) = (
            p.get(&Semantic::Joints(set)),
            p.get(&Semantic::Weights(set)),
        ) else {
            break;
        };
        let (_, j) = accessor::read_f32(&ja, buffers, &[D::Vec4])?;
        let (_, w) = accessor::read_f32(&wa, buffers, &[D::Vec4])?;
        if j.len() != n * 4 || w.len() != n * 4 || w.iter().any(|x| !x.is_finite()) {
            warn(format!(
                "{label}: JOINTS_{set}/WEIGHTS_{set} are not one finite VEC4 per vertex; \
                 drawn unskinned"
            ));
            return Ok(Vec::new());
        }
        let bad = j
            .iter()
            .zip(&w)
            .position(|(&j, &w)| w != 0.0 && !(j >= 0.0 && (j as usize) < joints));
        if let Some(k) = bad {
            warn(format!(
                "{label}: vertex {} names joint {} of a skin with {joints} joints; drawn \
                 unskinned",
                k / 4,
                j[k]
            ));
            return Ok(Vec::new());
        }
        let js = j
            .chunks_exact(4)
            .zip(w.chunks_exact(4))
            .map(|(j, w)| {
                // An unweighted slot may name any joint: it is read as joint 0, unused.
                std::array::from_fn(|k| if w[k] == 0.0 { 0 } else { j[k] as u16 })
            })
            .collect();
        let ws = w
            .chunks_exact(4)
            .map(|w| [w[0], w[1], w[2], w[3]])
            .collect();
        sets.push((js, ws));
    }
    normalise_weights(&mut sets, (p, buffers, joints), label, warn)?;
    Ok(sets)
}

/// Weights off their sum of 1 by more than this are normalised (a float's rounding of four
/// weights is ~1e-7).
const WEIGHT_SUM_SLACK: f32 = 1e-3;

/// Each vertex's weights, over every set, scaled to sum to 1 where they do not (exporters
/// write sums of 1.75 and 0: FBX2glTF's RobotExpressive), as three.js normalises them
/// (`SkinnedMesh.normalizeSkinWeights`: L1, and a vertex of no weight at all on its first
/// joint); one warning for the primitive. Weights that already sum to 1 are left to the bit.
fn normalise_weights(
    sets: &mut [JointSet],
    (p, buffers, skin_joints): (&gltf::Primitive, &Buffers, usize),
    label: &str,
    warn: &mut dyn FnMut(String),
) -> Result<(), String> {
    let Some(n) = sets.first().map(|s| s.1.len()) else {
        return Ok(());
    };
    let (mut off, mut lo, mut hi) = (0usize, f32::MAX, f32::MIN);
    let mut first_joint: Option<Vec<f32>> = None;
    for v in 0..n {
        let sum: f32 = sets.iter().map(|s| s.1[v].iter().sum::<f32>()).sum();
        if (sum - 1.0).abs() <= WEIGHT_SUM_SLACK {
            continue;
        }
        off += 1;
        (lo, hi) = (lo.min(sum), hi.max(sum));
        if sum > 0.0 {
            for s in sets.iter_mut() {
                s.1[v].iter_mut().for_each(|w| *w /= sum);
            }
        } else {
            // No weight at all: the vertex follows its first joint, as three.js has it.
            let joints = match &first_joint {
                Some(j) => j,
                None => {
                    let a = p.get(&Semantic::Joints(0)).ok_or("no JOINTS_0")?;
                    first_joint.insert(accessor::read_f32(&a, buffers, &[D::Vec4])?.1)
                }
            };
            let j = joints[v * 4];
            sets[0].0[v][0] = if j >= 0.0 && (j as usize) < skin_joints {
                j as u16
            } else {
                0
            };
            sets[0].1[v] = [1.0, 0.0, 0.0, 0.0];
        }
    }
    if off > 0 {
        warn(format!(
            "{label}: the skin weights of {off} of {n} vertices do not sum to 1 (sums from \
             {lo:.3} to {hi:.3}), which glTF requires; normalised, as three.js does"
        ));
    }
    Ok(())
}
