//! The loader's side of motion: which nodes' meshes move ([`Plan`], read before the meshes),
//! the moving primitives' sources ([`Part`]), and the [`Rig`] built from them once the
//! scene's origin is known, which poses them again at any moment.
use crate::error::{Error, Result};
use crate::geometry::prim::Prim;
use crate::model::material::Factors;
use crate::motion::channels::{Animation, Skin};
use crate::motion::pose::MAX_MORPH;
use crate::motion::pose::{joint_matrices, Deform, Graph, Placed, Posed, Reach, Source};
use glam::DMat4;
use std::sync::atomic::AtomicUsize;
use std::sync::OnceLock;
use {crate::load::options::LoadOptions, crate::model::Bounds, crate::model::Mesh};
use {crate::motion::Moment, crate::motion::Rig};

/// Samples of an animation whose poses bound its framing: evenly spaced moments, and key
/// times up to this many more; fewer for meshes so large that the poses would take more
/// than [`FRAMING_WORK`] vertices (about a second).
const FRAMING_SAMPLES: usize = 64;
const FRAMING_KEYS: usize = 256;
const FRAMING_WORK: usize = 1 << 26;

/// What the loader needs to know before it reads the meshes: the node graph, the usable
/// skins, the playable animations, and which nodes an animation moves.
#[derive(Debug, Default)]
pub(crate) struct Plan {
    pub(super) graph: Graph,
    pub(super) skins: Vec<Option<Skin>>,
    animations: Vec<Animation>,
    /// By node: a channel moves it or one of its ancestors.
    moved: Vec<bool>,
    /// By node: it uses EXT_mesh_gpu_instancing (its copies are never skinned).
    instanced: Vec<bool>,
    /// By node: the skin it names (read once here: `doc.nodes().nth` per instance was a
    /// walk of the node list for every mesh node).
    skin_of: Vec<Option<usize>>,
    /// By animation: what it moves.
    reach: Vec<Reach>,
    /// By node: its name in the file, for `--check`.
    names: Vec<Option<String>>,
    /// The static pose's world transforms, and each usable skin's joint matrices in it.
    rest_world: Vec<DMat4>,
    rest_joints: Vec<Vec<DMat4>>,
    /// Per mesh: its primitives' morph target count (most of them).
    targets: Vec<usize>,
    /// Morph deltas (targets × vertices) the file's primitives may still read.
    morph_budget: AtomicUsize,
    /// Each material an animation animates (KHR_animation_pointer), once, with the file's
    /// factors.
    material_factors: Vec<(usize, Factors)>,
}

/// What a loader read for a [`Plan`]: the drawn scene's node graph (in walk order), which
/// nodes are instanced and which skin each names, node names, the usable skins, the
/// playable animations (merged entry included), each mesh's morph target count and the
/// animated materials with their factors.
pub(crate) struct Read {
    pub(crate) graph: Graph,
    pub(crate) instanced: Vec<bool>,
    pub(crate) skin_of: Vec<Option<usize>>,
    pub(crate) names: Vec<Option<String>>,
    pub(crate) skins: Vec<Option<Skin>>,
    pub(crate) animations: Vec<Animation>,
    pub(crate) targets: Vec<usize>,
    pub(crate) material_factors: Vec<(usize, Factors)>,
}

impl Plan {
    /// The plan of what a loader read: which nodes each animation moves, and the static
    /// pose's world transforms and joint matrices.
    pub(crate) fn new(read: Read) -> Plan {
        let Read {
            graph,
            instanced,
            skin_of,
            names,
            skins,
            animations,
            targets,
            material_factors,
        } = read;
        let mut moved = vec![false; graph.parent.len()];
        for c in animations.iter().flat_map(|a| &a.channels) {
            moved[c.node] = true;
        }
        for &i in &graph.order {
            if graph.parent[i].is_some_and(|p| moved[p]) {
                moved[i] = true;
            }
        }
        let mut plan = Plan {
            names,
            material_factors,
            graph,
            skins,
            animations,
            moved,
            instanced,
            skin_of,
            reach: Vec::new(),
            rest_world: Vec::new(),
            rest_joints: Vec::new(),
            targets,
            morph_budget: AtomicUsize::new(MAX_MORPH),
        };
        plan.reach = plan
            .animations
            .iter()
            .map(|a| plan.graph.reach(a))
            .collect();
        let rest = plan.graph.rest_world();
        plan.rest_joints = plan
            .skins
            .iter()
            .map(|s| s.as_ref().map_or(Vec::new(), |s| joint_matrices(s, &rest)))
            .collect();
        plan.rest_world = rest;
        plan
    }
}

/// How one node's mesh is read when it moves: its skin's static joint matrices and the
/// morph weights of the static pose.
#[derive(Clone, Copy)]
pub(crate) struct Moving<'a> {
    pub(crate) skin: Option<(usize, &'a [DMat4])>,
    pub(crate) weights: &'a [f32],
    /// The file's morph budget, shared by its primitives.
    pub(crate) morph_budget: &'a AtomicUsize,
}

/// A moving primitive: the scene mesh it became, its node and skin, its source data and
/// the primitive as read (for the streams that do not move).
#[derive(Debug)]
pub(crate) struct Part {
    pub(crate) mesh: usize,
    pub(crate) by: Carried,
    pub(crate) prim: Prim,
}

/// Moving lines or points: where their positions start in the scene's [`Wire`], and what
/// carries them.
///
/// [`Wire`]: crate::model::Wire
#[derive(Debug)]
pub(crate) struct WirePart {
    pub(crate) first: usize,
    pub(crate) by: Carried,
}

/// What places a moving primitive (triangles, or lines and points) at a moment.
#[derive(Debug)]
pub(crate) struct Carried {
    pub(crate) node: usize,
    /// The skin applied, if any.
    pub(crate) skin: Option<usize>,
    /// A copy of an instanced node (`EXT_mesh_gpu_instancing`): its instance's transform,
    /// after the node's.
    pub(crate) instance: Option<DMat4>,
    /// Shared by every node drawing the primitive.
    pub(crate) src: std::sync::Arc<Source>,
}

impl Carried {
    /// The world transform that carries the primitive unskinned in `posed`: its node's,
    /// then its instance's.
    pub(crate) fn world(&self, posed: &Posed) -> DMat4 {
        match self.instance {
            Some(m) => posed.world[self.node] * m,
            None => posed.world[self.node],
        }
    }

    /// The skin that places its vertices, if any (one with no joint sets does not).
    fn skinned(&self) -> Option<usize> {
        self.skin.filter(|_| !self.src.sets.is_empty())
    }
}

impl std::fmt::Debug for Posed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Posed({} nodes)", self.world.len())
    }
}

impl Plan {
    /// How `node`'s `mesh` moves, or None if nothing ever moves it: no usable skin, no
    /// morph targets, and no animation moving it. An instanced node's copies are carried
    /// by the node and morphed, never skinned (as when they stood still: the extension
    /// leaves a skin on an instanced node undefined).
    pub(crate) fn moving(&self, node: usize, mesh: usize) -> Option<Moving<'_>> {
        let instanced = *self.instanced.get(node)?;
        let skin = self.skin_of[node]
            .filter(|_| !instanced)
            .filter(|&s| self.skins.get(s).is_some_and(Option::is_some))
            .map(|s| (s, self.rest_joints[s].as_slice()));
        let morphs = self.targets.get(mesh).copied().unwrap_or(0) > 0;
        let animated = self.moved[node]
            || skin.is_some_and(|(s, _)| {
                self.skins[s]
                    .as_ref()
                    .is_some_and(|k| k.joints.iter().any(|&j| self.moved[j]))
            });
        (skin.is_some() || morphs || animated).then_some(Moving {
            skin,
            weights: &self.graph.weights[node],
            morph_budget: &self.morph_budget,
        })
    }

    /// Whether a channel moves `node` or one of its ancestors (its transform or its morph
    /// weights change with the moment).
    pub(crate) fn animated(&self, node: usize) -> bool {
        self.moved.get(node).copied().unwrap_or(false)
    }

    /// By animation: the indices of the primitives `parts` (node, skin) it moves (sorted):
    /// their node's world transform or morph weights, or a joint of their skin. A part no
    /// animation of two moments moves is the same at both.
    fn reached(&self, parts: &[&Carried]) -> Vec<Vec<usize>> {
        self.animations
            .iter()
            .zip(&self.reach)
            .map(|(a, r)| {
                let hit = self.graph.touched(a, r);
                let skin_hit = |s: usize| {
                    self.skins[s]
                        .as_ref()
                        .is_some_and(|k| k.joints.iter().any(|&j| hit[j]))
                };
                parts
                    .iter()
                    .enumerate()
                    .filter(|(_, c)| hit[c.node] || c.skin.is_some_and(skin_hit))
                    .map(|(k, _)| k)
                    .collect()
            })
            .collect()
    }

    /// `--check`'s lines for the skins and morph targets.
    pub(crate) fn check_lines(&self) -> Vec<String> {
        let mut out: Vec<String> = self
            .skins
            .iter()
            .enumerate()
            .map(|(i, s)| match s {
                Some(s) => format!("skin {i}: {} joints", s.joints.len()),
                None => format!("skin {i}: not applied (see the warnings)"),
            })
            .collect();
        for (m, &t) in self.targets.iter().enumerate().filter(|(_, &t)| t > 0) {
            out.push(format!("mesh {m}: {t} morph targets"));
        }
        out
    }

    /// `--check`'s lines on playing the animations together ([`crate::motion::together`]).
    pub(crate) fn together_lines(&self) -> Vec<String> {
        crate::motion::together::check_lines(&self.animations, &self.names)
    }

    /// Whether anything in the file can move or be posed.
    pub(crate) fn is_empty(&self) -> bool {
        self.animations.is_empty() && self.skins.is_empty() && self.targets.iter().all(|&t| t == 0)
    }
}

/// What the loader built the meshes with, for posing them again.
pub(crate) struct Built<'a> {
    pub(crate) origin: glam::DVec3,
    pub(crate) default_material: usize,
    pub(crate) opts: &'a LoadOptions,
    pub(crate) path: &'a std::path::Path,
}

impl Rig {
    /// The rig of a loaded scene: `parts` are its moving triangle primitives, `meshes` all
    /// its meshes in the static pose, `wires` its moving lines and points and `wire` all of
    /// them (positions re-centred).
    pub(crate) fn new(
        plan: Plan,
        (parts, wires): (Vec<Part>, Vec<WirePart>),
        (meshes, wire, materials): (
            &[Mesh],
            &crate::model::Wire,
            &[crate::model::material::Material],
        ),
        b: Built,
    ) -> Rig {
        let moving: Vec<usize> = parts.iter().map(|p| p.mesh).collect();
        let mut still_bounds = Bounds::empty();
        let mut static_bounds = Bounds::empty();
        let mut wire_moves = vec![false; wire.positions.len()];
        for w in &wires {
            let n = w.by.src.positions.len() / 3;
            wire_moves[w.first..w.first + n].fill(true);
        }
        for (q, moves) in wire.positions.iter().zip(&wire_moves) {
            static_bounds.include((*q).into());
            if !moves {
                still_bounds.include((*q).into());
            }
        }
        for (i, m) in meshes.iter().enumerate() {
            for v in &m.vertices {
                static_bounds.include(v.position.into());
                if moving.binary_search(&i).is_err() {
                    still_bounds.include(v.position.into());
                }
            }
        }
        let reached = plan.reached(&parts.iter().map(|p| &p.by).collect::<Vec<_>>());
        let wire_reached = plan
            .reached(&wires.iter().map(|w| &w.by).collect::<Vec<_>>())
            .iter()
            .map(|r| !r.is_empty())
            .collect();
        Rig {
            materials: crate::motion::materials::Materials::new(&plan.material_factors, materials),
            animations: plan.animations.iter().map(|a| a.info.clone()).collect(),
            reached,
            wire_reached,
            framing: plan.animations.iter().map(|_| OnceLock::new()).collect(),
            meshes: moving,
            plan,
            parts,
            wires,
            origin: b.origin,
            up: b.opts.up,
            default_material: b.default_material,
            creases: b.opts.creases,
            path: b.path.to_path_buf(),
            static_bounds,
            still_bounds,
        }
    }

    /// Sets the materials animations animate to `moment` (None: as loaded).
    pub(crate) fn pose_materials(
        &self,
        moment: Option<Moment>,
        materials: &mut [crate::model::material::Material],
    ) {
        self.materials
            .pose(&self.plan.animations, moment, materials);
    }

    /// Whether going from moment `since` to `moment` may change a material (either
    /// moment's animation animates one): the shadow maps depend on a cut-out material's
    /// alpha.
    pub fn materials_may_change(&self, since: Option<Moment>, moment: Option<Moment>) -> bool {
        [since, moment].into_iter().flatten().any(|m| {
            self.plan
                .animations
                .get(m.animation)
                .is_some_and(|a| !a.materials.is_empty())
        })
    }

    /// The node transforms of `moment` (None: the static pose).
    pub(super) fn posed(&self, moment: Option<Moment>) -> Posed {
        let p = &self.plan;
        match moment {
            None => Graph::rest_pose(&p.rest_world),
            Some(m) => p.graph.pose(
                &p.rest_world,
                (&p.animations[m.animation], &p.reach[m.animation]),
                m.seconds,
            ),
        }
    }

    /// Each of `parts`' vertices placed in `posed` (`positions_only`: for bounds). Only
    /// the skins these parts use get joint matrices.
    fn place_parts(&self, posed: &Posed, parts: &[&Carried], positions_only: bool) -> Vec<Placed> {
        let mut joints: Vec<Vec<DMat4>> = vec![Vec::new(); self.plan.skins.len()];
        let mut done = vec![false; self.plan.skins.len()];
        for s in parts.iter().filter_map(|c| c.skinned()) {
            if !std::mem::replace(&mut done[s], true) {
                if let Some(skin) = &self.plan.skins[s] {
                    joints[s] = joint_matrices(skin, &posed.world);
                }
            }
        }
        parts
            .iter()
            .map(|c| {
                let deform = match c.skinned() {
                    Some(s) => Deform::Skin(&joints[s]),
                    None => Deform::Node(c.world(posed)),
                };
                let weights = posed
                    .weights(c.node)
                    .unwrap_or(&self.plan.graph.weights[c.node]);
                c.src.place(&deform, weights, self.up, positions_only)
            })
            .collect()
    }

    /// Whether part `k` may differ between the meshes posed at `since` and at `moment`:
    /// always, unless both are moments of animations that do not move it (then both are
    /// its static pose as a pose computes it). From or to the static pose (None) every
    /// part is posed, as the loader's meshes are not a pose's.
    fn may_move(&self, k: usize, since: Option<Moment>, moment: Option<Moment>) -> bool {
        let (Some(a), Some(b)) = (since, moment) else {
            return true;
        };
        [a, b]
            .iter()
            .any(|m| self.reached[m.animation].binary_search(&k).is_ok())
    }

    /// The parts of the scene meshes not in `skip` (sorted) placed at `moment`, each checked
    /// to fit f32 (an error before any mesh is changed); of meshes posed at `since`, only
    /// the parts that may move between the two. Nothing is posed when no part is left
    /// (every moving mesh skinned on the GPU: a frame poses only their joints).
    fn placed_except(
        &self,
        (since, moment): (Option<Moment>, Option<Moment>),
        skip: &[usize],
    ) -> Result<Vec<(&Part, crate::motion::pose::Placed)>> {
        let parts: Vec<&Part> = self
            .parts
            .iter()
            .enumerate()
            .filter(|(k, p)| {
                skip.binary_search(&p.mesh).is_err() && self.may_move(*k, since, moment)
            })
            .map(|(_, p)| p)
            .collect();
        if parts.is_empty() {
            return Ok(Vec::new());
        }
        let posed = self.posed(moment);
        let placing: Vec<&Carried> = parts.iter().map(|p| &p.by).collect();
        let placed = self.place_parts(&posed, &placing, false);
        parts
            .into_iter()
            .zip(placed)
            .map(|(p, placed)| {
                crate::geometry::prim::check_range(&placed.0).map_err(|e| {
                    Error::model(&self.path, None, format!("node {}: {e}", p.by.node))
                })?;
                Ok((p, placed))
            })
            .collect()
    }

    /// The options the loader built the meshes with that a pose builds them with again.
    fn build_options(&self) -> LoadOptions {
        LoadOptions {
            creases: self.creases,
            ..LoadOptions::default()
        }
    }

    /// The moving meshes at `moment`, built as the loader builds them, with each one's
    /// scene mesh index; without the scene meshes `skip` (sorted: those skinned on the GPU).
    /// New meshes, beside the scene's (for `--edges` of GPU-skinned meshes); a pose of the
    /// scene itself is [`Rig::pose_into`].
    pub fn posed_meshes_except(
        &self,
        moment: Option<Moment>,
        skip: &[usize],
    ) -> Result<Vec<(usize, Mesh)>> {
        let opts = self.build_options();
        Ok(self
            .placed_except((None, moment), skip)?
            .into_iter()
            .map(|(p, placed)| {
                let mesh = p.prim.with_geometry(placed).into_mesh(
                    self.origin,
                    self.default_material,
                    &opts,
                );
                (p.mesh, mesh)
            })
            .collect())
    }

    /// Poses the scene's `meshes`, posed at `since`, at `moment`, but for `skip` (sorted:
    /// those skinned on the GPU), and returns the indices of those rewritten: only the
    /// meshes that may move between the two moments ([`Rig::may_move`]), and of those only
    /// what a pose moves (positions, normals, tangents: [`Prim::pose_into`]). On an error
    /// no mesh has changed.
    ///
    /// [`Prim::pose_into`]: crate::geometry::prim::Prim::pose_into
    pub(crate) fn pose_into(
        &self,
        (since, moment): (Option<Moment>, Option<Moment>),
        skip: &[usize],
        meshes: &mut crate::model::meshes::Meshes,
    ) -> Result<Vec<usize>> {
        let placed = self.placed_except((since, moment), skip)?;
        if placed.is_empty() {
            return Ok(Vec::new());
        }
        let opts = self.build_options();
        let mut changed = Vec::with_capacity(placed.len());
        for (p, placed) in placed {
            let mesh = &mut meshes[p.mesh];
            p.prim
                .pose_into(placed, mesh, (self.origin, self.default_material), &opts);
            changed.push(p.mesh);
        }
        Ok(changed)
    }

    /// Whether a pose from `since` to `moment` may move the scene's lines and points (as
    /// [`Rig::may_move`] for each part).
    pub fn wire_may_move(&self, since: Option<Moment>, moment: Option<Moment>) -> bool {
        if self.wires.is_empty() {
            return false;
        }
        let (Some(a), Some(b)) = (since, moment) else {
            return true;
        };
        self.wire_reached[a.animation] || self.wire_reached[b.animation]
    }

    /// The moving lines and points placed at `moment` if a pose from `since` may move them
    /// (None: it does not), each checked to fit f32.
    pub(crate) fn placed_wires(
        &self,
        (since, moment): (Option<Moment>, Option<Moment>),
    ) -> Result<Option<Vec<Placed>>> {
        if !self.wire_may_move(since, moment) {
            return Ok(None);
        }
        let placing: Vec<&Carried> = self.wires.iter().map(|w| &w.by).collect();
        let placed = self.place_parts(&self.posed(moment), &placing, false);
        for (w, (q, _, _)) in self.wires.iter().zip(&placed) {
            crate::geometry::prim::check_range(q)
                .map_err(|e| Error::model(&self.path, None, format!("node {}: {e}", w.by.node)))?;
        }
        Ok(Some(placed))
    }

    /// Writes [`Rig::placed_wires`]' positions (re-centred) and, where the lines and points
    /// are lit by their normals, normals into `wire`: zero where the pose has none (a
    /// singular node matrix), so a kept renderer and a fresh one draw the same (the lit
    /// programs turn a zero normal towards the eye).
    pub(crate) fn write_wires(&self, placed: Vec<Placed>, wire: &mut crate::model::Wire) {
        let lit = wire.normals.len() == wire.positions.len();
        for (w, (q, n, _)) in self.wires.iter().zip(placed) {
            let at = w.first..w.first + q.len();
            for (dst, q) in wire.positions[at.clone()].iter_mut().zip(q) {
                *dst = (q - self.origin).as_vec3().to_array();
            }
            if lit {
                let dst = &mut wire.normals[at];
                match n {
                    Some(n) => {
                        for (dst, n) in dst.iter_mut().zip(n) {
                            *dst = n.normalize_or_zero().as_vec3().to_array();
                        }
                    }
                    None => dst.fill([0.0; 3]),
                }
            }
        }
    }

    /// The bounds of every moment of `animation`: its poses at evenly spaced moments and at
    /// its key times (at most [`FRAMING_SAMPLES`] + [`FRAMING_KEYS`] poses), with what
    /// never moves.
    pub(crate) fn framing(&self, animation: usize) -> Bounds {
        *self.framing[animation].get_or_init(|| {
            let a = &self.plan.animations[animation];
            let d = a.info.duration;
            let all: Vec<&Carried> = (self.parts.iter().map(|p| &p.by))
                .chain(self.wires.iter().map(|w| &w.by))
                .collect();
            let vertices: usize = all.iter().map(|c| c.src.positions.len() / 3).sum();
            let affordable = (FRAMING_WORK / vertices.max(1)).max(2);
            let samples = FRAMING_SAMPLES.min(affordable);
            let mut times: Vec<f64> = (0..=samples)
                .map(|k| d * k as f64 / samples as f64)
                .collect();
            let mut keys: Vec<f64> = a
                .channels
                .iter()
                .flat_map(|c| c.keys.times.iter().map(|&t| f64::from(t)))
                .collect();
            keys.sort_by(f64::total_cmp);
            keys.dedup();
            let keys_kept = FRAMING_KEYS.min(affordable.saturating_sub(samples));
            let step = keys.len().div_ceil(keys_kept.max(1)).max(1);
            times.extend(keys.iter().step_by(step).take(keys_kept));
            let mut b = self.still_bounds;
            for t in times {
                let posed = self.posed(Some(Moment {
                    animation,
                    seconds: t,
                }));
                for (positions, _, _) in self.place_parts(&posed, &all, true) {
                    for q in positions {
                        b.include((q - self.origin).as_vec3());
                    }
                }
            }
            b
        })
    }
}
