//! What the renderer needs to skin a mesh on the GPU instead of posing it on the CPU: which
//! moving meshes can be (one JOINTS_0/WEIGHTS_0 set, the file's normals, no morph targets,
//! a joint count within the context's vertex uniform budget), their bind-space streams in
//! the order of the scene mesh's vertices, and each skin's joint matrices at a moment in the
//! scene's local coordinates. Everything else stays on the CPU path, mesh by mesh. No GL.
use super::pose::joint_matrices;
use super::{Moment, Rig};
use crate::scene::{Scene, UpAxis};
use glam::{DMat4, DVec3, Mat4};

/// Vertex uniform components kept for the programs' other uniforms (matrices, point size,
/// the Gouraud variant's lights): a joint matrix is 16 components, GL 2.1's minimum budget
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
    JointSets(usize),
    NoFileNormals,
    MorphTargets,
    /// The skin's joints, over the budget.
    OverBudget(usize),
    /// Another primitive shares the scene mesh, or the vertex count changed.
    Shape,
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
    /// JOINTS_0 as floats (exact below 2^24) and WEIGHTS_0.
    pub joint_ids: Vec<[f32; 4]>,
    pub weights: Vec<[f32; 4]>,
}

/// The decision for one part, without GL: a skin with `joints` joints, `sets` joint sets,
/// file normals or not, morph targets or not, against `budget` joints.
pub fn decide(
    joints: Option<usize>,
    sets: usize,
    normals: bool,
    morphs: bool,
    budget: usize,
) -> Result<(), CpuBecause> {
    let Some(joints) = joints else {
        return Err(CpuBecause::NotSkinned);
    };
    if sets != 1 {
        return Err(CpuBecause::JointSets(sets));
    }
    if !normals {
        return Err(CpuBecause::NoFileNormals);
    }
    if morphs {
        return Err(CpuBecause::MorphTargets);
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

impl Rig {
    /// The moving meshes that can be skinned on the GPU with `budget` joints per program
    /// ([`joint_budget`]), and why each other one cannot. `scene` is the loaded scene (for
    /// the vertex counts).
    pub fn gpu_skinned(
        &self,
        scene: &Scene,
        budget: usize,
    ) -> (Vec<GpuSkinned>, Vec<(usize, CpuBecause)>) {
        let mut gpu = Vec::new();
        let mut cpu = Vec::new();
        for p in &self.parts {
            let joints = p
                .skin
                .and_then(|s| self.plan.skins.get(s)?.as_ref())
                .map(|s| s.joints.len());
            let morphs = p
                .src
                .targets
                .iter()
                .any(|t| t.positions.is_some() || t.normals.is_some() || t.tangents.is_some());
            let n = p.src.positions.len() / 3;
            let shared = self.parts.iter().filter(|q| q.mesh == p.mesh).count() > 1;
            let same = scene
                .meshes
                .get(p.mesh)
                .is_some_and(|m| m.vertices.len() == n);
            let verdict = decide(
                joints,
                p.src.sets.len(),
                p.src.normals.is_some(),
                morphs,
                budget,
            )
            .and(if shared || !same {
                Err(CpuBecause::Shape)
            } else {
                Ok(())
            });
            let (Ok(()), Some(skin), Some(joints), Some(normals)) =
                (verdict, p.skin, joints, &p.src.normals)
            else {
                cpu.push((p.mesh, verdict.err().unwrap_or(CpuBecause::Shape)));
                continue;
            };
            let (js, ws) = &p.src.sets[0];
            gpu.push(GpuSkinned {
                mesh: p.mesh,
                skin,
                joints,
                positions: f3(&p.src.positions),
                normals: f3(normals),
                tangents: p.src.tangents.as_ref().map(|t| {
                    t.chunks_exact(4)
                        .map(|c| [c[0], c[1], c[2], if c[3] < 0.0 { -1.0 } else { 1.0 }])
                        .collect()
                }),
                joint_ids: js.iter().map(|j| j.map(f32::from)).collect(),
                weights: ws.clone(),
            });
        }
        (gpu, cpu)
    }

    /// Every skin's joint matrices at `moment` (None: the static pose) in the scene's local
    /// coordinates: T(−origin) · up rotation · joint world · inverse bind, in f64, then f32
    /// (an unusable skin: none).
    pub fn gpu_joints(&self, moment: Option<Moment>) -> Vec<Vec<Mat4>> {
        let posed = self.posed(moment);
        let to_scene = DMat4::from_translation(-self.origin) * up_matrix(self.up);
        self.plan
            .skins
            .iter()
            .map(|s| {
                s.as_ref().map_or(Vec::new(), |s| {
                    joint_matrices(s, &posed.world)
                        .into_iter()
                        .map(|m| (to_scene * m).as_mat4())
                        .collect()
                })
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::LoadOptions;

    fn rigged_simple() -> Scene {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data/khronos/motion/RiggedSimple.glb");
        crate::scene::load::load_bytes(
            &path,
            &std::fs::read(&path).expect("committed sample"),
            &LoadOptions::default(),
        )
        .expect("loads")
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
        let (gpu, cpu) = rig.gpu_skinned(&scene, 16);
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
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data/khronos/motion/CesiumMan.glb");
        let bytes = std::fs::read(&path).expect("committed sample");
        let mut scene =
            crate::scene::load::load_bytes(&path, &bytes, &LoadOptions::default()).expect("loads");
        let rig = scene.motion.clone().expect("a rig");
        let (gpu, _) = rig.gpu_skinned(&scene, 64);
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
            let own = crate::scene::bounding_sphere(v).1;
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
        let (gpu, cpu) = rig.gpu_skinned(&scene, 1);
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

    #[test]
    fn the_budget_leaves_room_and_gl21s_minimum_skins_16_joints() {
        assert_eq!(joint_budget(512), 16);
        assert_eq!(joint_budget(100), 0);
        assert_eq!(joint_budget(4096), (4096 - 256) / 16);
    }

    #[test]
    fn a_skin_over_the_budget_stays_on_the_cpu() {
        let b = joint_budget(512);
        assert_eq!(decide(Some(16), 1, true, false, b), Ok(()));
        assert_eq!(
            decide(Some(19), 1, true, false, b),
            Err(CpuBecause::OverBudget(19))
        );
        assert_eq!(
            decide(Some(2), 2, true, false, b),
            Err(CpuBecause::JointSets(2))
        );
        assert_eq!(
            decide(Some(2), 1, false, false, b),
            Err(CpuBecause::NoFileNormals)
        );
        assert_eq!(
            decide(Some(2), 1, true, true, b),
            Err(CpuBecause::MorphTargets)
        );
        assert_eq!(decide(None, 0, true, false, b), Err(CpuBecause::NotSkinned));
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
}
