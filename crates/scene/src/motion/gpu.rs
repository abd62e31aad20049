//! What the renderer needs to skin or morph a mesh on the GPU instead of posing it on the
//! CPU: which moving meshes can be (skinned: one JOINTS_0/WEIGHTS_0 set, the file's normals,
//! a joint count within the context's vertex uniform budget; morphed: the file's normals,
//! the targets' deltas within the free vertex attributes; a mesh with both is skinned and
//! morphed by one program when both fit), their
//! bind-space streams in the order of the scene mesh's vertices, each skin's joint matrices
//! at a moment in the scene's local coordinates, and each morphed part's node matrix (drawn
//! as a one-joint skin) and weights. Everything else stays on the CPU path, mesh by mesh.
//! No GL.
use crate::motion::pose::joint_matrices;
use glam::{DMat4, DVec3, Mat4};
use {crate::model::Scene, crate::model::UpAxis};
use {crate::motion::Moment, crate::motion::Rig};

/// Vertex uniform components kept for the programs' other uniforms (matrices, point size,
/// the Gouraud variant's lights, a morphed draw's three weight vectors, which a skinned and
/// morphed draw adds to its joints): a joint matrix is 16 components, GL 2.1's minimum budget
/// is 512, so a GL 2.1 driver at the minimum skins up to 16 joints.
pub const RESERVED_COMPONENTS: u32 = 256;

/// The joints a skinned program may declare with `components` vertex uniform components
/// (`GL_MAX_VERTEX_UNIFORM_COMPONENTS`).
pub fn joint_budget(components: u32) -> usize {
    (components.saturating_sub(RESERVED_COMPONENTS) / 16) as usize
}

/// Why a moving mesh is posed on the CPU rather than skinned on the GPU.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CpuBecause {
    NotSkinned,
    /// More than two joint sets; or two, with morph targets on the GPU too or fewer than
    /// two free attributes (the second set takes the first two morph attributes' places).
    JointSets(usize),
    NoFileNormals,
    /// The skin's joints, over the budget.
    OverBudget(usize),
    /// Another primitive shares the scene mesh, or the vertex count changed.
    Shape,
    /// Morph targets whose deltas need this many vertex attributes, over the free ones.
    MorphOverBudget(usize),
}

/// The vertex attributes the fixed layout takes (position ... weights: 0–11); the rest of
/// `GL_MAX_VERTEX_ATTRIBS`, at most 4 (the shaders' `aMorph0..3`), carry morph deltas.
pub const FIXED_ATTRIBUTES: u32 = 12;

/// The attributes free for morph deltas with `max_attribs` (`GL_MAX_VERTEX_ATTRIBS`).
pub fn morph_budget(max_attribs: u32) -> usize {
    max_attribs.saturating_sub(FIXED_ATTRIBUTES).min(4) as usize
}

/// Which delta of a morph target an attribute carries.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MorphKind {
    Position,
    Normal,
    Tangent,
}

/// A mesh morphed on the GPU: one attribute per (kind, target) in `slots`, its deltas in
/// `deltas`; `part` indexes [`Rig::gpu_weights`]'s result.
#[derive(Clone, Debug)]
pub struct GpuMorph {
    pub part: usize,
    pub slots: Vec<(MorphKind, usize)>,
    pub deltas: Vec<Vec<[f32; 3]>>,
}

/// The uniforms of a morphed draw: per kind (position, normal, tangent), the weight of the
/// target each attribute slot carries (0 for the slots of other kinds).
pub fn morph_uniforms(slots: &[(MorphKind, usize)], weights: &[f32]) -> [[f32; 4]; 3] {
    let mut u = [[0.0; 4]; 3];
    for (k, &(kind, t)) in slots.iter().enumerate().take(4) {
        u[kind as usize][k] = weights.get(t).copied().unwrap_or(0.0);
    }
    u
}

/// The attribute slots a part's morph targets need: each target's position deltas, its
/// normal deltas, and its tangent deltas when `tangents` (the material needs tangents);
/// `has(kind, target)` says whether the target moves that attribute.
pub fn morph_slots(
    targets: usize,
    tangents: bool,
    has: impl Fn(MorphKind, usize) -> bool,
) -> Vec<(MorphKind, usize)> {
    let mut kinds = vec![MorphKind::Position, MorphKind::Normal];
    if tangents {
        kinds.push(MorphKind::Tangent);
    }
    kinds
        .into_iter()
        .flat_map(|k| (0..targets).map(move |t| (k, t)))
        .filter(|&(k, t)| has(k, t))
        .collect()
}

/// The decision for a part's morph targets (skinned or not), without GL: `slots` delta
/// attributes against `budget` free attributes ([`morph_budget`]), file normals or not.
pub fn decide_morph(slots: usize, normals: bool, budget: usize) -> Result<(), CpuBecause> {
    if !normals {
        return Err(CpuBecause::NoFileNormals);
    }
    if slots > budget {
        return Err(CpuBecause::MorphOverBudget(slots));
    }
    Ok(())
}

/// A scene mesh skinned on the GPU: its vertices in bind space (mesh space as the file
/// gives it), in the order of the scene mesh's vertices, and one joint set.
#[derive(Clone, Debug)]
pub struct GpuSkinned {
    pub mesh: usize,
    /// Index of its skin in [`Rig::gpu_joints`]'s result.
    pub skin: usize,
    /// Joints of that skin (the length of its uniform array).
    pub joints: usize,
    pub positions: Vec<[f32; 3]>,
    pub normals: Vec<[f32; 3]>,
    /// The file's tangents, the handedness made ±1 as the CPU pose makes it (None: none).
    pub tangents: Option<Vec<[f32; 4]>>,
    /// JOINTS_0 as floats (exact below 2^24) and WEIGHTS_0 (a morphed part without a skin:
    /// joint 0, weight 1, its node's matrix the one joint).
    pub joint_ids: Vec<[f32; 4]>,
    pub weights: Vec<[f32; 4]>,
    /// JOINTS_1 (as floats) and WEIGHTS_1, where the file has a second set.
    pub second: Option<GpuJointSet>,
    /// Morphed on the GPU (with its skin, or alone as a one-joint skin): its targets'
    /// deltas, added before the skin's matrices as the spec orders.
    pub morph: Option<GpuMorph>,
}

/// One joint set on the GPU: joint indices (as floats) and weights, per vertex.
pub type GpuJointSet = (Vec<[f32; 4]>, Vec<[f32; 4]>);

/// The decision for one skinned part's skin, without GL: a skin with `joints` joints,
/// `sets` joint sets (one or two), file normals or not, against `budget` joints (its morph
/// targets, if any, are [`decide_morph`]'s; a second set's attributes are checked with
/// them).
pub fn decide(
    joints: Option<usize>,
    sets: usize,
    normals: bool,
    budget: usize,
) -> Result<(), CpuBecause> {
    let Some(joints) = joints else {
        return Err(CpuBecause::NotSkinned);
    };
    if !(1..=2).contains(&sets) {
        return Err(CpuBecause::JointSets(sets));
    }
    if !normals {
        return Err(CpuBecause::NoFileNormals);
    }
    if joints > budget {
        return Err(CpuBecause::OverBudget(joints));
    }
    Ok(())
}

/// The up-axis rotation as a matrix.
fn up_matrix(up: UpAxis) -> DMat4 {
    DMat4::from_cols(
        up.rotate(DVec3::X).extend(0.0),
        up.rotate(DVec3::Y).extend(0.0),
        up.rotate(DVec3::Z).extend(0.0),
        glam::DVec4::W,
    )
}

fn f3(v: &[f32]) -> Vec<[f32; 3]> {
    v.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect()
}

/// The file's tangents, the handedness made ±1 as the CPU pose makes it (None: none).
fn file_tangents(src: &crate::motion::pose::Source) -> Option<Vec<[f32; 4]>> {
    src.tangents.as_ref().map(|t| {
        t.chunks_exact(4)
            .map(|c| [c[0], c[1], c[2], if c[3] < 0.0 { -1.0 } else { 1.0 }])
            .collect()
    })
}

impl Rig {
    /// The moving meshes that can be skinned on the GPU with `budget` joints per program
    /// ([`joint_budget`]) or morphed there with `morphs` free attributes ([`morph_budget`]),
    /// and why each other one cannot. `scene` is the loaded scene (for the vertex counts and
    /// the materials).
    pub fn gpu_skinned(
        &self,
        scene: &Scene,
        budget: usize,
        morphs: usize,
    ) -> (Vec<GpuSkinned>, Vec<(usize, CpuBecause)>) {
        let mut gpu = Vec::new();
        let mut cpu = Vec::new();
        for (i, p) in self.parts.iter().enumerate() {
            let shared = self.parts.iter().filter(|q| q.mesh == p.mesh).count() > 1;
            let same = scene
                .meshes
                .get(p.mesh)
                .is_some_and(|m| m.vertices.len() == p.by.src.positions.len() / 3);
            let shape = if shared || !same {
                Err(CpuBecause::Shape)
            } else {
                Ok(())
            };
            let made = shape.and_then(|()| match p.by.skin {
                None if !p.by.src.targets.is_empty() => self.gpu_morphed(scene, i, morphs),
                _ => self.gpu_skin_part(scene, i, (budget, morphs)),
            });
            match made {
                Ok(s) => gpu.push(s),
                Err(why) => cpu.push((p.mesh, why)),
            }
        }
        (gpu, cpu)
    }

    /// Part `i` skinned on the GPU (`budget`: joints, free attributes), its morph targets
    /// with it where they move anything, or why not.
    fn gpu_skin_part(
        &self,
        scene: &Scene,
        i: usize,
        (budget, morphs): (usize, usize),
    ) -> Result<GpuSkinned, CpuBecause> {
        let p = &self.parts[i];
        let (src, skin) = (&p.by.src, p.by.skin);
        let joints = skin
            .and_then(|s| self.plan.skins.get(s)?.as_ref())
            .map(|s| s.joints.len());
        decide(joints, src.sets.len(), src.normals.is_some(), budget)?;
        let (Some(skin), Some(joints), Some(normals), Some((js, ws))) =
            (skin, joints, &src.normals, src.sets.first())
        else {
            return Err(CpuBecause::Shape);
        };
        // Targets that move nothing (or no targets) take no attribute: plain skinning.
        let morph = Some(self.gpu_morph(scene, i, morphs)?).filter(|m| !m.slots.is_empty());
        let second = match src.sets.get(1) {
            None => None,
            // The second set takes attributes 12 and 13, the first morph attributes'.
            Some(_) if morph.is_some() || morphs < 2 => return Err(CpuBecause::JointSets(2)),
            Some((js, ws)) => Some((js.iter().map(|j| j.map(f32::from)).collect(), ws.clone())),
        };
        Ok(GpuSkinned {
            mesh: p.mesh,
            skin,
            joints,
            positions: f3(&src.positions),
            normals: f3(normals),
            tangents: file_tangents(src),
            joint_ids: js.iter().map(|j| j.map(f32::from)).collect(),
            weights: ws.clone(),
            second,
            morph,
        })
    }

    /// Part `i`'s morph targets on the GPU within `budget` free attributes, skinned or not:
    /// one slot per delta stream the draw uses ([`morph_slots`]: tangents only where its
    /// material needs them), or why not ([`decide_morph`]).
    fn gpu_morph(&self, scene: &Scene, i: usize, budget: usize) -> Result<GpuMorph, CpuBecause> {
        let p = &self.parts[i];
        let src = &p.by.src;
        let tangents = scene.meshes.get(p.mesh).is_some_and(|m| {
            m.has_uv
                && scene
                    .materials
                    .get(m.material)
                    .is_some_and(|mat| mat.needs_tangents())
        }) && src.tangents.is_some();
        let pick = |k: MorphKind, t: usize| {
            let t = &src.targets[t];
            match k {
                MorphKind::Position => t.positions.as_ref(),
                MorphKind::Normal => t.normals.as_ref(),
                MorphKind::Tangent => t.tangents.as_ref(),
            }
        };
        let slots = morph_slots(src.targets.len(), tangents, |k, t| pick(k, t).is_some());
        decide_morph(slots.len(), src.normals.is_some(), budget)?;
        let deltas = slots
            .iter()
            .map(|&(k, t)| pick(k, t).map_or_else(Vec::new, |d| f3(d)))
            .collect();
        Ok(GpuMorph {
            part: i,
            slots,
            deltas,
        })
    }

    /// Part `i` (morph targets, no skin) morphed on the GPU, or why not: a one-joint skin
    /// (index `skins + i` of [`Rig::gpu_joints`]: its node's matrix) with its deltas.
    fn gpu_morphed(
        &self,
        scene: &Scene,
        i: usize,
        budget: usize,
    ) -> Result<GpuSkinned, CpuBecause> {
        let morph = self.gpu_morph(scene, i, budget)?;
        let p = &self.parts[i];
        let src = &p.by.src;
        let Some(normals) = &src.normals else {
            return Err(CpuBecause::NoFileNormals);
        };
        let n = src.positions.len() / 3;
        Ok(GpuSkinned {
            mesh: p.mesh,
            skin: self.plan.skins.len() + i,
            joints: 1,
            positions: f3(&src.positions),
            normals: f3(normals),
            tangents: file_tangents(src),
            joint_ids: vec![[0.0; 4]; n],
            weights: vec![[1.0, 0.0, 0.0, 0.0]; n],
            second: None,
            morph: Some(morph),
        })
    }

    /// [`Rig::gpu_joints`] and [`Rig::gpu_weights`] at `moment`, from one pose of the
    /// node graph (what a frame of a GPU-skinned or -morphed scene sets).
    pub fn gpu_pose(&self, moment: Option<Moment>) -> (Vec<Vec<Mat4>>, Vec<Vec<f32>>) {
        let posed = self.posed(moment);
        (self.joints_in(&posed), self.weights_in(&posed))
    }

    /// Each part's morph weights at `moment` (the node's animated weights, else the node's
    /// or the mesh's), for [`morph_uniforms`].
    pub fn gpu_weights(&self, moment: Option<Moment>) -> Vec<Vec<f32>> {
        self.weights_in(&self.posed(moment))
    }

    fn weights_in(&self, posed: &crate::motion::pose::Posed) -> Vec<Vec<f32>> {
        self.parts
            .iter()
            .map(|p| {
                posed
                    .weights(p.by.node)
                    .unwrap_or(&self.plan.graph.weights[p.by.node])
                    .to_vec()
            })
            .collect()
    }

    /// Every skin's joint matrices at `moment` (None: the static pose) in the scene's local
    /// coordinates: T(−origin) · up rotation · joint world · inverse bind, in f64, then f32
    /// (an unusable skin: none); then each part's node matrix as a one-joint skin (what a
    /// part morphed on the GPU is drawn with).
    pub fn gpu_joints(&self, moment: Option<Moment>) -> Vec<Vec<Mat4>> {
        self.joints_in(&self.posed(moment))
    }

    fn joints_in(&self, posed: &crate::motion::pose::Posed) -> Vec<Vec<Mat4>> {
        let to_scene = DMat4::from_translation(-self.origin) * up_matrix(self.up);
        let skins = self.plan.skins.iter().map(|s| {
            s.as_ref().map_or(Vec::new(), |s| {
                joint_matrices(s, &posed.world)
                    .into_iter()
                    .map(|m| (to_scene * m).as_mat4())
                    .collect()
            })
        });
        let nodes = self
            .parts
            .iter()
            .map(|p| vec![(to_scene * p.by.world(posed)).as_mat4()]);
        skins.chain(nodes).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rigged_simple() -> Scene {
        crate::motion::tests::sample("RiggedSimple.glb")
    }

    /// The GPU's formula on the CPU: the weighted joint matrices times the bind position.
    fn skin(s: &GpuSkinned, joints: &[Mat4], v: usize) -> glam::Vec3 {
        let mut m = Mat4::ZERO;
        for k in 0..4 {
            m += joints[s.joint_ids[v][k] as usize] * s.weights[v][k];
        }
        m.transform_point3(glam::Vec3::from(s.positions[v]))
    }

    /// The streams are in the scene mesh's vertex order and the joint matrices carry them
    /// where the CPU pose puts them: at the static pose and at a moment of the bend.
    #[test]
    fn gpu_joints_times_bind_streams_are_the_cpu_pose() {
        let mut scene = rigged_simple();
        let rig = scene.motion.clone().expect("a rig");
        let (gpu, cpu) = rig.gpu_skinned(&scene, 16, 4);
        assert!(cpu.is_empty(), "{cpu:?}");
        assert_eq!(gpu.len(), 1);
        for moment in [
            None,
            Some(Moment {
                animation: 0,
                seconds: 1.25,
            }),
        ] {
            scene.pose(moment).expect("poses");
            let joints = &rig.gpu_joints(moment)[gpu[0].skin];
            let mesh = &scene.meshes[gpu[0].mesh];
            let mut worst = 0.0f32;
            for (v, want) in mesh.vertices.iter().enumerate() {
                let d = skin(&gpu[0], joints, v) - glam::Vec3::from(want.position);
                worst = worst.max(d.abs().max_element());
            }
            assert!(worst < 1e-5, "{moment:?}: off by {worst}");
        }
    }

    /// The conservative bound of a GPU-skinned mesh (the sphere around the animation's
    /// framing bounds, which the renderer culls it by) holds every vertex of CesiumMan at 21
    /// moments of its walk; how much larger it is than each moment's own sphere is printed.
    #[test]
    fn the_framing_sphere_holds_every_moment() {
        let mut scene = crate::motion::tests::sample("CesiumMan.glb");
        let rig = scene.motion.clone().expect("a rig");
        let (gpu, _) = rig.gpu_skinned(&scene, 64, 4);
        let mesh = gpu.first().expect("skinned on the GPU").mesh;
        let duration = scene.animations()[0].duration;
        let mut worst = 0.0f32;
        for k in 0..=20 {
            let seconds = duration * f64::from(k) / 20.0;
            scene
                .pose(Some(Moment {
                    animation: 0,
                    seconds,
                }))
                .expect("poses");
            let b = scene.bounds;
            let (center, radius) = (b.center(), (b.max - b.min).length() * 0.5);
            let v = &scene.meshes[mesh].vertices;
            let far = v
                .iter()
                .map(|v| (glam::Vec3::from(v.position) - center).length())
                .fold(0.0f32, f32::max);
            assert!(
                far <= radius * (1.0 + 1e-6),
                "{seconds} s: {far} > {radius}"
            );
            let own = crate::model::bounding_sphere(v).1;
            worst = worst.max(radius / own);
        }
        eprintln!("framing sphere / the moment's own sphere: at most {worst:.3}");
    }

    /// A skin over the budget (a fake one, below RiggedSimple's two joints) stays on the
    /// CPU, and `pose_except` leaves the GPU's meshes as they were.
    #[test]
    fn over_the_budget_the_mesh_is_posed_on_the_cpu() {
        let mut scene = rigged_simple();
        let rig = scene.motion.clone().expect("a rig");
        let (gpu, cpu) = rig.gpu_skinned(&scene, 1, 4);
        assert!(gpu.is_empty());
        assert_eq!(cpu, vec![(0, CpuBecause::OverBudget(2))]);
        let before = scene.meshes[0].vertices.clone();
        let moment = Some(Moment {
            animation: 0,
            seconds: 1.25,
        });
        assert_eq!(
            scene.pose_except(moment, &[0]).expect("poses"),
            Vec::<usize>::new()
        );
        assert_eq!(scene.meshes[0].vertices, before);
        assert_eq!(scene.pose(moment).expect("poses"), vec![0]);
        assert_ne!(scene.meshes[0].vertices, before);
    }

    /// A second joint set goes to the GPU in attributes 12 and 13, so it needs two free
    /// ones (16 attributes leave 4); with fewer the mesh is posed on the CPU.
    #[test]
    fn a_second_joint_set_needs_two_free_attributes() {
        let scene = crate::motion::tests::committed("tests/data/motion/TwoJointSets.glb");
        let rig = scene.motion.clone().expect("a rig");
        let (gpu, cpu) = rig.gpu_skinned(&scene, 16, 4);
        assert!(cpu.is_empty(), "{cpu:?}");
        let (j1, w1) = gpu[0].second.as_ref().expect("the second set");
        assert_eq!(
            (j1.len(), w1.len()),
            (gpu[0].positions.len(), gpu[0].positions.len())
        );
        // Ring 6 (y = 2.4) weighs joints 4 and 5 in set 1.
        assert_eq!(j1[48], [4.0, 5.0, 0.0, 0.0]);
        assert!(w1[48][0] > 0.0 && w1[48][1] > 0.0);
        let (gpu, cpu) = rig.gpu_skinned(&scene, 16, 1);
        assert!(gpu.is_empty());
        assert_eq!(cpu, vec![(0, CpuBecause::JointSets(2))]);
    }

    #[test]
    fn the_budget_leaves_room_and_gl21s_minimum_skins_16_joints() {
        assert_eq!(joint_budget(512), 16);
        assert_eq!(joint_budget(100), 0);
        assert_eq!(joint_budget(4096), (4096 - 256) / 16);
    }

    #[test]
    fn a_skin_over_the_budget_stays_on_the_cpu() {
        let b = joint_budget(512);
        assert_eq!(decide(Some(16), 1, true, b), Ok(()));
        assert_eq!(
            decide(Some(19), 1, true, b),
            Err(CpuBecause::OverBudget(19))
        );
        assert_eq!(decide(Some(2), 2, true, b), Ok(()));
        assert_eq!(decide(Some(2), 3, true, b), Err(CpuBecause::JointSets(3)));
        assert_eq!(decide(Some(2), 1, false, b), Err(CpuBecause::NoFileNormals));
        assert_eq!(decide(None, 0, true, b), Err(CpuBecause::NotSkinned));
    }

    #[test]
    fn the_up_matrix_is_the_up_rotation() {
        for up in [
            UpAxis::PosY,
            UpAxis::NegY,
            UpAxis::PosX,
            UpAxis::NegX,
            UpAxis::PosZ,
            UpAxis::NegZ,
        ] {
            let p = DVec3::new(1.0, 2.0, 3.0);
            assert_eq!(up_matrix(up).transform_point3(p), up.rotate(p));
        }
    }

    fn morph_cube() -> Scene {
        crate::motion::tests::sample("AnimatedMorphCube.glb")
    }

    /// The GPU's morph formula on the CPU: the node matrix (the one joint) times the bind
    /// position plus the slots' deltas weighted by the uniforms; the normal by the matrix's
    /// inverse transpose, normalised. At the static pose and two moments of the weights
    /// animation, it is where the CPU pose puts each vertex.
    #[test]
    fn gpu_morph_streams_and_uniforms_are_the_cpu_pose() {
        let mut scene = morph_cube();
        let rig = scene.motion.clone().expect("a rig");
        let (gpu, cpu) = rig.gpu_skinned(&scene, 16, morph_budget(16));
        assert!(cpu.is_empty(), "{cpu:?}");
        let s = &gpu[0];
        let m = s.morph.as_ref().expect("morphed on the GPU");
        assert_eq!(s.joints, 1);
        assert_eq!(m.slots.len(), 4, "two targets, positions and normals");
        for seconds in [None, Some(0.5), Some(1.5)] {
            let moment = seconds.map(|seconds| Moment {
                animation: 0,
                seconds,
            });
            scene.pose(moment).expect("poses");
            let worst = shader_pose_error(&rig, s, moment, &scene.meshes[s.mesh].vertices);
            // Positions are in the scene's units (the cube is 2 wide): f32 rounding.
            assert!(
                worst.0 < 1e-5 && worst.1 < 1e-5,
                "{seconds:?}: off by {worst:?}"
            );
        }
    }

    /// How far the shader's pose of `s` at `moment` — the slots' deltas weighted by the
    /// uniforms added to the bind streams, then the vertex's skin matrix (a morphed part's:
    /// its node's, the one joint), normals by its inverse transpose, normalised — lies from
    /// `posed` (the CPU pose), in position and in normal.
    fn shader_pose_error(
        rig: &Rig,
        s: &GpuSkinned,
        moment: Option<Moment>,
        posed: &[crate::model::Vertex],
    ) -> (f32, f32) {
        let m = s.morph.as_ref().expect("morphed");
        let joints = &rig.gpu_joints(moment)[s.skin];
        let [up, un, _] = morph_uniforms(&m.slots, &rig.gpu_weights(moment)[m.part]);
        let mut worst = (0.0f32, 0.0f32);
        for (v, want) in posed.iter().enumerate() {
            let sum = |u: [f32; 4], base: [f32; 3]| {
                let mut p = glam::Vec3::from(base);
                for (k, d) in m.deltas.iter().enumerate() {
                    p += u[k] * glam::Vec3::from(d[v]);
                }
                p
            };
            let mut skin_m = Mat4::ZERO;
            for k in 0..4 {
                skin_m += joints[s.joint_ids[v][k] as usize] * s.weights[v][k];
            }
            let p = skin_m.transform_point3(sum(up, s.positions[v]));
            let normal_m = glam::Mat3::from_mat4(skin_m).inverse().transpose();
            let n = (normal_m * sum(un, s.normals[v])).normalize();
            let dp = (p - glam::Vec3::from(want.position)).abs().max_element();
            let dn = (n - glam::Vec3::from(want.normal)).abs().max_element();
            worst = (worst.0.max(dp), worst.1.max(dn));
        }
        worst
    }

    /// A mesh both skinned and morphed (tests/data/motion/SkinnedMorphed.glb, made by
    /// scripts/make_skinned_morphed.py): the shader's order, the weighted deltas added to
    /// the bind streams and then the vertex's skin matrix (normals by its inverse transpose,
    /// normalised), puts every vertex and normal where the CPU pose does, at the static pose
    /// and at two moments where both the joint and the weights are away from rest.
    #[test]
    fn gpu_skin_and_morph_streams_are_the_cpu_pose() {
        let mut scene = crate::motion::tests::committed("tests/data/motion/SkinnedMorphed.glb");
        let rig = scene.motion.clone().expect("a rig");
        let (gpu, cpu) = rig.gpu_skinned(&scene, 2, 4);
        assert!(cpu.is_empty(), "{cpu:?}");
        let s = &gpu[0];
        let m = s.morph.as_ref().expect("morphed with its skin");
        assert_eq!((s.skin, s.joints, m.slots.len()), (0, 2, 4));
        let rest = scene.meshes[s.mesh].vertices.clone();
        for seconds in [None, Some(0.6), Some(1.3)] {
            let moment = seconds.map(|seconds| Moment {
                animation: 0,
                seconds,
            });
            scene.pose(moment).expect("poses");
            if moment.is_some() {
                assert_ne!(scene.meshes[s.mesh].vertices, rest, "{seconds:?}: moved");
            }
            let worst = shader_pose_error(&rig, s, moment, &scene.meshes[s.mesh].vertices);
            assert!(
                worst.0 < 1e-5 && worst.1 < 1e-5,
                "{seconds:?}: off by {worst:?}"
            );
        }
    }

    /// Fewer free attributes than the cube's four delta streams: the CPU.
    #[test]
    fn a_morph_over_the_attribute_budget_stays_on_the_cpu() {
        let scene = morph_cube();
        let rig = scene.motion.clone().expect("a rig");
        let (gpu, cpu) = rig.gpu_skinned(&scene, 16, 3);
        assert!(gpu.is_empty());
        assert_eq!(cpu, vec![(0, CpuBecause::MorphOverBudget(4))]);
    }

    #[test]
    fn the_morph_budget_is_what_16_attributes_leave() {
        assert_eq!(morph_budget(16), 4);
        assert_eq!(morph_budget(32), 4, "the shaders declare four");
        assert_eq!(morph_budget(8), 0);
        let all = |_: MorphKind, _: usize| true;
        assert_eq!(
            morph_slots(4, false, |k, _| k == MorphKind::Position).len(),
            4
        );
        assert_eq!(morph_slots(2, false, all).len(), 4);
        // With a normal map the tangents' deltas too: 2 targets need 6.
        assert_eq!(morph_slots(2, true, all).len(), 6);
        let b = morph_budget(16);
        assert_eq!(decide_morph(4, true, b), Ok(()));
        assert_eq!(
            decide_morph(6, true, b),
            Err(CpuBecause::MorphOverBudget(6))
        );
        assert_eq!(decide_morph(2, false, b), Err(CpuBecause::NoFileNormals));
    }

    #[test]
    fn morph_uniforms_weigh_each_slot_by_its_target() {
        let slots = morph_slots(2, false, |_, _| true);
        assert_eq!(
            morph_uniforms(&slots, &[0.25, 0.75]),
            [[0.25, 0.75, 0.0, 0.0], [0.0, 0.0, 0.25, 0.75], [0.0; 4]]
        );
        // Fewer weights than targets: the missing ones are 0.
        assert_eq!(morph_uniforms(&slots, &[0.5])[0], [0.5, 0.0, 0.0, 0.0]);
    }
}
