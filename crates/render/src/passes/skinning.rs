//! Skinning on the GPU (issue 39): the meshes a rig skins that can be
//! ([`crate::scene::motion::gpu`]: one joint set or two (the second in attributes 12 and
//! 13, without morph targets on the GPU), the file's normals, a skin within the
//! context's vertex uniform budget, morph targets (if any) within the free attributes, and
//! the file's tangents where the material needs tangents) are uploaded once in bind space
//! with their joints and weights (attributes 10 and 11; morph deltas from 12), and drawn by
//! the `SKINNED` variant (and `MORPHED` with targets) of every program that reads
//! positions (lit, PBR, depth, attributes) with their skin's joint matrices as a uniform
//! array, set per draw. A pose computes the joint matrices only ([`Renderer::pose`] poses the
//! other meshes on the CPU). `GLVIEW_SKINNING=cpu` keeps every mesh on the CPU path (the
//! comparisons of the tests and `bench --motion`).
use crate::gpu::program::Program;
use crate::gpu::GpuRef;
use crate::scene::motion::gpu::{joint_budget, morph_budget, morph_uniforms, GpuSkinned};
use crate::scene::motion::Moment;
use crate::scene::Scene;
use crate::shader::cache::ProgramKey;
use glam::Mat4;

/// A draw mesh skinned on the GPU: its skin, and the joints its programs declare.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SkinDraw {
    pub(crate) skin: usize,
    pub(crate) joints: usize,
    /// Joint sets: 1, or 2 (JOINTS_1/WEIGHTS_1 in attributes 12 and 13, never morphed).
    pub(crate) sets: usize,
    /// Morphed on the GPU: the rig part (its weights in [`GpuSkins::weights`]) and the
    /// morph uniforms' slot layout's index in [`GpuSkins::slots`], and its attribute count.
    pub(crate) morph: Option<(usize, usize)>,
}

/// The scene meshes skinned on the GPU (sorted), and each skin's joint matrices at the
/// moment the renderer is posed at.
#[derive(Default)]
pub(crate) struct GpuSkins {
    pub(crate) meshes: Vec<usize>,
    pub(crate) joints: Vec<Vec<Mat4>>,
    /// Each rig part's morph weights at that moment.
    pub(crate) weights: Vec<Vec<f32>>,
    /// Each GPU-morphed part's attribute slots (by part).
    pub(crate) slots: Vec<(usize, Vec<(crate::scene::motion::gpu::MorphKind, usize)>)>,
    /// The moment they are posed at (None: the static pose, which the scene meshes hold).
    pub(crate) moment: Option<Moment>,
}

/// Whether GPU skinning is allowed (`GLVIEW_SKINNING=cpu`: no, for comparisons).
pub(crate) fn allowed() -> bool {
    std::env::var_os("GLVIEW_SKINNING").is_none_or(|v| v != "cpu")
}

/// Which of `scene`'s meshes are skinned on the GPU with this context's budget (the static
/// pose's joint matrices), and their streams sorted by mesh.
pub(crate) fn plan(gpu: &GpuRef, scene: &Scene, allowed: bool) -> (GpuSkins, Vec<GpuSkinned>) {
    let Some(rig) = scene.motion.as_ref().filter(|_| allowed) else {
        return (GpuSkins::default(), Vec::new());
    };
    let budget = joint_budget(gpu.caps.max_vertex_uniform_components);
    let morphs = morph_budget(gpu.caps.max_vertex_attribs);
    let (mut skinned, cpu) = rig.gpu_skinned(scene, budget, morphs);
    // Tangents made by MikkTSpace from the bind pose would not be the posed mesh's.
    skinned.retain(|s| {
        let m = &scene.meshes[s.mesh];
        let needs = m.has_uv && scene.materials[m.material].needs_tangents();
        !(needs && s.tangents.is_none())
    });
    skinned.sort_by_key(|s| s.mesh);
    for (mesh, why) in cpu {
        log::debug!("mesh {mesh}: posed on the CPU ({why:?})");
    }
    let (joints, weights) = rig.gpu_pose(scene.posed);
    let skins = GpuSkins {
        meshes: skinned.iter().map(|s| s.mesh).collect(),
        joints,
        weights,
        slots: skinned
            .iter()
            .filter_map(|s| s.morph.as_ref().map(|m| (m.part, m.slots.clone())))
            .collect(),
        moment: scene.posed,
    };
    (skins, skinned)
}

/// The sphere around bounds `b`.
pub(crate) fn framing_sphere(b: &crate::scene::Bounds) -> (glam::Vec3, f32) {
    (b.center(), (b.max - b.min).length() * 0.5)
}

/// `key` for a draw mesh skinned as `skin` says: its `SKINNED` variant when it is skinned on
/// the GPU, and `MORPHED` when its morph targets are too (the key is unchanged otherwise).
pub(crate) fn key(key: ProgramKey, skin: Option<SkinDraw>) -> ProgramKey {
    match skin {
        Some(s) => {
            let key =
                key.switch("SKINNED", "skin", true)
                    .count("SKIN_JOINTS", "j", s.joints as i32);
            // One set keeps the key (and so the programs) skins had before two sets.
            let key = if s.sets > 1 {
                key.count("SKIN_SETS", "s", s.sets as i32)
            } else {
                key
            };
            match s.morph {
                Some((_, n)) => {
                    key.switch("MORPHED", "morph", true)
                        .count("MORPH_ATTRIBUTES", "m", n as i32)
                }
                None => key,
            }
        }
        None => key,
    }
}

/// Sets the joint matrices of a draw mesh's `skin` on the bound `program` (nothing for a
/// mesh not skinned on the GPU).
pub(crate) fn set_joints(program: &Program, skins: &GpuSkins, skin: Option<SkinDraw>) {
    if let Some(s) = skin {
        if let Some(j) = skins.joints.get(s.skin) {
            program.set_mat4_array("uJoints", &j[..j.len().min(s.joints)]);
        }
        if let Some((part, _)) = s.morph {
            let slots = skins
                .slots
                .iter()
                .find(|x| x.0 == part)
                .map(|x| x.1.as_slice());
            let weights = skins.weights.get(part).map(Vec::as_slice);
            let [p, n, t] = morph_uniforms(slots.unwrap_or(&[]), weights.unwrap_or(&[]));
            program.set_vec4("uMorphPosition", p.into());
            program.set_vec4("uMorphNormal", n.into());
            program.set_vec4("uMorphTangent", t.into());
        }
    }
}
