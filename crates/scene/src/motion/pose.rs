//! Posing on the CPU: node transforms at a moment (the file's own, or an animation's
//! sampled translation, rotation and scale), then each moving primitive's vertices morphed
//! (position, normal and tangent deltas times the weights) and carried to the scene by its
//! node's transform or, skinned, by the weighted sum of its joints' matrices. The static
//! pose of an unskinned primitive uses the loader's own formulas (`gltf_primitive`), so a
//! file's still does not move by a rounding when its meshes become posable.
use crate::model::UpAxis;
use crate::motion::channels::{Animation, Skin};
use crate::motion::Path;
use glam::{DMat3, DMat4, DVec3, Mat4, Quat, Vec3};

/// Morph targets × vertices of the whole file beyond this are not read (8 M deltas of each
/// attribute, 96 MB each): a primitive that would pass it is not morphed.
pub(crate) const MAX_MORPH: usize = 1 << 23;

/// A node's translation, rotation (x, y, z, w) and scale.
pub(crate) type Trs = ([f32; 3], [f32; 4], [f32; 3]);
/// One JOINTS_n set with its WEIGHTS_n.
pub(crate) type JointSet = (Vec<[u16; 4]>, Vec<[f32; 4]>);

/// The drawn scene's nodes: the walk's order (parents first), each node's parent, its own
/// transform as the file gives it, and the morph weights its mesh takes without an
/// animation (the node's `weights`, else the mesh's, else zeros).
#[derive(Clone, Debug, Default)]
pub(crate) struct Graph {
    pub(crate) order: Vec<usize>,
    pub(crate) parent: Vec<Option<usize>>,
    pub(crate) local: Vec<DMat4>,
    pub(crate) rest: Vec<Trs>,
    pub(crate) weights: Vec<Vec<f32>>,
}

/// Node transforms and morph weights of one moment.
pub(crate) struct Posed {
    pub(crate) world: Vec<DMat4>,
    /// The animated weights, by node (sorted; of a node set twice, the later channel's
    /// last): only the nodes a channel sets.
    weights: Vec<(usize, Vec<f32>)>,
}

impl Posed {
    /// The morph weights a channel sets on `node` at this moment (None: the node's own).
    pub(crate) fn weights(&self, node: usize) -> Option<&[f32]> {
        let end = self.weights.partition_point(|w| w.0 <= node);
        end.checked_sub(1)
            .map(|k| &self.weights[k])
            .filter(|w| w.0 == node)
            .map(|w| w.1.as_slice())
    }
}

/// What one animation moves, worked out once from the graph (so that a pose computes
/// again only that): the slot of each channel (the translation, rotation and scale of one
/// node it writes; None: a weights channel), the node of each slot, and the nodes whose
/// world transform follows the animation (a slot's, or below one) in walk order with
/// their slot.
#[derive(Clone, Debug, Default)]
pub(crate) struct Reach {
    slot: Vec<Option<usize>>,
    slot_node: Vec<usize>,
    walk: Vec<(usize, Option<usize>)>,
}

impl Graph {
    /// The world transforms of the static pose (by node index; identity for nodes outside
    /// the scene): the file's own matrices, so the static pose is the loader's to the bit.
    pub(crate) fn rest_world(&self) -> Vec<DMat4> {
        let mut world = vec![DMat4::IDENTITY; self.local.len()];
        for &i in &self.order {
            let up = self.parent[i].map_or(DMat4::IDENTITY, |p| world[p]);
            world[i] = up * self.local[i];
        }
        world
    }

    /// What `a` moves ([`Reach`]).
    pub(crate) fn reach(&self, a: &Animation) -> Reach {
        let n = self.local.len();
        let mut slot_of: Vec<Option<usize>> = vec![None; n];
        let mut slot_node = Vec::new();
        let slot = a
            .channels
            .iter()
            .map(|c| {
                (c.path != Path::Weights).then(|| {
                    *slot_of[c.node].get_or_insert_with(|| {
                        slot_node.push(c.node);
                        slot_node.len() - 1
                    })
                })
            })
            .collect();
        let mut follows = vec![false; n];
        let mut walk = Vec::new();
        for &i in &self.order {
            if slot_of[i].is_some() || self.parent[i].is_some_and(|p| follows[p]) {
                follows[i] = true;
                walk.push((i, slot_of[i]));
            }
        }
        Reach {
            slot,
            slot_node,
            walk,
        }
    }

    /// The pose of `a` (whose [`Reach`] is `reach`) at `t` seconds, from the static pose's
    /// world transforms `rest`: only the nodes the animation reaches are computed again, by
    /// the same products in the same order as the static pose's, so a node it does not
    /// move keeps the file's own matrix to the bit.
    pub(crate) fn pose(&self, rest: &[DMat4], (a, reach): (&Animation, &Reach), t: f64) -> Posed {
        let mut trs: Vec<Trs> = reach.slot_node.iter().map(|&i| self.rest[i]).collect();
        let mut weights = Vec::new();
        for (c, slot) in a.channels.iter().zip(&reach.slot) {
            let v = c.keys.sample(t);
            let Some(s) = *slot else {
                weights.push((c.node, v));
                continue;
            };
            let e = &mut trs[s];
            match c.path {
                Path::Translation => e.0 = [v[0], v[1], v[2]],
                Path::Rotation => e.1 = [v[0], v[1], v[2], v[3]],
                Path::Scale => e.2 = [v[0], v[1], v[2]],
                Path::Weights => {}
            }
        }
        // Stable: of two channels on one node's weights, the later stays last.
        weights.sort_by_key(|w| w.0);
        let local: Vec<DMat4> = trs
            .into_iter()
            .map(|(t, r, s)| {
                Mat4::from_scale_rotation_translation(
                    Vec3::from(s),
                    Quat::from_array(r),
                    Vec3::from(t),
                )
                .as_dmat4()
            })
            .collect();
        let mut world = rest.to_vec();
        for &(i, s) in &reach.walk {
            let up = self.parent[i].map_or(DMat4::IDENTITY, |p| world[p]);
            world[i] = up * s.map_or(self.local[i], |s| local[s]);
        }
        Posed { world, weights }
    }

    /// By node: whether `a` (whose [`Reach`] is `reach`) changes its world transform or
    /// its morph weights.
    pub(crate) fn touched(&self, a: &Animation, reach: &Reach) -> Vec<bool> {
        let mut hit = vec![false; self.local.len()];
        for &(i, _) in &reach.walk {
            hit[i] = true;
        }
        for c in a.channels.iter().filter(|c| c.path == Path::Weights) {
            hit[c.node] = true;
        }
        hit
    }

    /// The static pose, from its world transforms `rest`.
    pub(crate) fn rest_pose(rest: &[DMat4]) -> Posed {
        Posed {
            world: rest.to_vec(),
            weights: Vec::new(),
        }
    }
}

/// One morph target's deltas (each None where the target does not move that attribute).
#[derive(Clone, Debug, Default)]
pub(crate) struct Target {
    pub(crate) positions: Option<Vec<f32>>,
    pub(crate) normals: Option<Vec<f32>>,
    pub(crate) tangents: Option<Vec<f32>>,
}

/// A moving primitive's vertex data as the file gives it, in the mesh's own space.
#[derive(Clone, Debug, Default)]
pub(crate) struct Source {
    pub(crate) positions: Vec<f32>,
    pub(crate) normals: Option<Vec<f32>>,
    pub(crate) tangents: Option<Vec<f32>>,
    pub(crate) targets: Vec<Target>,
    /// JOINTS_n and WEIGHTS_n sets (indices checked against the skin's joints).
    pub(crate) sets: Vec<JointSet>,
}

/// What carries a primitive into the scene.
pub(crate) enum Deform<'a> {
    /// Its node's world transform.
    Node(DMat4),
    /// Its skin's joint matrices (joint world × inverse bind).
    Skin(&'a [DMat4]),
}

/// Positions, normals and tangents placed in the scene's (up-rotated, not re-centred) space.
pub(crate) type Placed = (Vec<DVec3>, Option<Vec<DVec3>>, Option<Vec<[f32; 4]>>);

/// The joint matrices of `skin` in the pose `world`.
pub(crate) fn joint_matrices(skin: &Skin, world: &[DMat4]) -> Vec<DMat4> {
    skin.joints
        .iter()
        .zip(&skin.inverse_bind)
        .map(|(&j, ib)| world[j] * *ib)
        .collect()
}

impl Source {
    fn count(&self) -> usize {
        self.positions.len() / 3
    }

    /// The morphed attribute `get` of vertex i (`width` floats: 3, or 4 for tangents whose
    /// fourth, the handedness, no target moves).
    fn morphed(
        &self,
        base: &[f32],
        width: usize,
        get: fn(&Target) -> Option<&Vec<f32>>,
        weights: &[f32],
        i: usize,
    ) -> DVec3 {
        let b = &base[i * width..];
        let mut v = Vec3::new(b[0], b[1], b[2]).as_dvec3();
        for (t, &w) in self.targets.iter().zip(weights) {
            if w == 0.0 {
                continue;
            }
            if let Some(d) = get(t) {
                let d = &d[i * 3..];
                v += f64::from(w) * Vec3::new(d[0], d[1], d[2]).as_dvec3();
            }
        }
        v
    }

    /// The skinning matrix of vertex i: its joints' matrices weighted (every set).
    fn skin_matrix(&self, joints: &[DMat4], i: usize) -> DMat4 {
        let mut m = DMat4::ZERO;
        for (js, ws) in &self.sets {
            for k in 0..4 {
                let w = ws[i][k];
                if w != 0.0 {
                    m += joints[usize::from(js[i][k])] * f64::from(w);
                }
            }
        }
        m
    }

    /// The vertices placed by `deform` with `weights` (the morph targets'), turned to the up
    /// axis; normals and tangents skipped when `positions_only` (bounds of a pose). One pass
    /// over the vertices: a skinned vertex's matrix is summed once for its position, normal
    /// and tangent.
    pub(crate) fn place(
        &self,
        deform: &Deform,
        weights: &[f32],
        up: UpAxis,
        positions_only: bool,
    ) -> Placed {
        let n = self.count();
        let node_m = match deform {
            Deform::Node(m) => Some(DMat3::from_mat4(*m).inverse().transpose()),
            Deform::Skin(_) => None,
        };
        let node_singular = match deform {
            Deform::Node(m) => !DMat3::from_mat4(*m).inverse().is_finite(),
            Deform::Skin(_) => false,
        };
        // A node without a normal matrix (a zero scale): normals are generated, as the
        // loader does; a skinned vertex whose matrix is singular gets an unusable normal
        // that the mesh's repair replaces.
        let normal_base = self
            .normals
            .as_deref()
            .filter(|_| !positions_only && node_m.is_none_or(|m| m.is_finite()));
        let tangent_base = self
            .tangents
            .as_deref()
            .filter(|_| !positions_only && !node_singular);
        let mut positions = Vec::with_capacity(n);
        let mut normals = normal_base.map(|_| Vec::with_capacity(n));
        let mut tangents = tangent_base.map(|_| Vec::with_capacity(n));
        for i in 0..n {
            let m = match deform {
                Deform::Node(m) => *m,
                Deform::Skin(j) => self.skin_matrix(j, i),
            };
            let p = self.morphed(&self.positions, 3, |t| t.positions.as_ref(), weights, i);
            positions.push(up.rotate(m.transform_point3(p)));
            if let (Some(base), Some(out)) = (normal_base, normals.as_mut()) {
                let v = self.morphed(base, 3, |t| t.normals.as_ref(), weights, i);
                let nm = node_m.unwrap_or_else(|| DMat3::from_mat4(m).inverse().transpose());
                out.push(up.rotate(nm * v));
            }
            if let (Some(base), Some(out)) = (tangent_base, tangents.as_mut()) {
                let v = self.morphed(base, 4, |t| t.tangents.as_ref(), weights, i);
                let m3 = DMat3::from_mat4(m);
                let flip = if m3.determinant() < 0.0 { -1.0 } else { 1.0 };
                let t = up.rotate(m3 * v).normalize_or_zero().as_vec3();
                let w = if base[i * 4 + 3] < 0.0 { -flip } else { flip };
                out.push([t.x, t.y, t.z, w as f32]);
            }
        }
        (positions, normals, tangents)
    }
}
