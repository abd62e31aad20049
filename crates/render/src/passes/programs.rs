//! Every program key the renderer can ask for, listed in one place for `--compile-shaders`
//! (which compiles them all ahead of any frame) and its test. The renderer owns the keys (each
//! pass builds its own), so the list lives here and the shader cache only stores programs.
use super::{attributes, background, edges, grid, guides, lit, pbr, post, shadow, slots, view};
use crate::scene::model::material::{AlphaMode, Material};
use crate::shader::cache::ProgramKey;

/// Every program key the renderer can ask for with up to `max_lights` lights: the legacy
/// tier's permutations (see `lit::program_key`), the PBR tier's, and the depth,
/// background and teaching-view programs.
pub fn all_keys(max_lights: u8) -> Vec<ProgramKey> {
    let mut keys = fixed_programs();
    for lights in 0..=max_lights {
        let shadow_variants: Vec<(u8, u8, u8)> = if lights == 0 {
            vec![(0, 1, 0)]
        } else {
            let all = (1u8 << lights) - 1;
            let mut v = vec![(0, 1, 0)];
            for pcf in [1, 4, 9, 16] {
                for mask in [0, 1, all] {
                    v.push((lights, pcf, mask));
                }
            }
            v.dedup();
            v
        };
        for (shadows, pcf, cube_mask) in shadow_variants {
            for textured in [false, true] {
                for gouraud in [false, true] {
                    // Vertex colours, point lights, wrap lighting and front faces only with
                    // the textured variants: every flag is compiled without doubling the
                    // permutations.
                    keys.push(
                        lit::program_key(
                            lights, shadows, pcf, cube_mask, textured, gouraud, textured,
                        )
                        .switch("POINT_LIGHTS", "pt", textured)
                        .switch("WRAP", "wrap", textured)
                        .switch("FRONT_ONLY", "front", textured)
                        .switch("FALLOFF", "fall", textured),
                    );
                }
            }
            keys.extend(pbr::all_keys(lights, shadows, pcf, cube_mask));
            keys.push(view::shadow_flags(
                grid::key(),
                lights,
                shadows,
                pcf,
                cube_mask,
            ));
        }
    }
    keys
}

/// The keys of [`all_keys`] this context can compile, and how many it cannot: programs that
/// write a fragment's depth (the grid, log depth) need `gl_FragDepth`, which ES 2.0 has only
/// with EXT_frag_depth (the frame refuses them there: [`super::plan`]).
pub fn keys_for(caps: &crate::gpu::Caps, max_lights: u8) -> (Vec<ProgramKey>, usize) {
    let all = all_keys(max_lights);
    let total = all.len();
    let keys: Vec<ProgramKey> = all
        .into_iter()
        .filter(|k| caps.frag_depth || !writes_depth(k))
        .collect();
    let skipped = total - keys.len();
    (keys, skipped)
}

/// Whether a program writes its fragments' depth (FRAG_DEPTH).
fn writes_depth(k: &ProgramKey) -> bool {
    k.name == grid::key().name
        || k.flags
            .iter()
            .any(|f| f.define == "LOG_DEPTH" && f.value != 0)
}

/// Programs that exist once regardless of lights and materials (for `--compile-shaders`).
pub(crate) fn fixed_programs() -> Vec<ProgramKey> {
    vec![
        shadow::depth_key(),
        shadow::show_key(),
        attributes::key(),
        edges::key(),
        edges::key().switch("LOG_DEPTH", "logz", true),
        view::shadow_flags(grid::key(), 1, 1, 1, 0).switch("LOG_DEPTH", "logz", true),
        view::shadow_flags(grid::key(), 1, 1, 1, 0).switch("LINEAR_OUTPUT", "lin", true),
        guides::key(),
        edges::key().switch("WIDE", "wide", true),
        edges::key().switch("BARYCENTRIC", "bary", true),
    ]
    .into_iter()
    .chain((0..4).flat_map(|tm| {
        [
            background::skybox_key(false, tm),
            background::skybox_key(true, tm),
        ]
    }))
    .chain(post::keys())
    .chain([super::stereo::key()])
    .chain(variant_keys())
    // Points: disks of gl_PointSize, lit (with normals) or unlit, coloured, both tiers.
    .chain([false, true].into_iter().flat_map(|unlit| {
        [
            lit::program_key(1, 1, 1, 0, false, false, true),
            lit::program_key(1, 1, 1, 0, false, true, true),
            pbr::all_keys(1, 1, 1, 0).swap_remove(0),
        ]
        .map(|k| {
            k.switch("POINTS", "pts", true)
                .switch("UNLIT", "unlit", unlit)
        })
    }))
    // EXT_mesh_gpu_instancing's instanced draws and skinning on the GPU (GL 2.1's minimum
    // budget's 16 joints): both tiers (Gouraud and a normal map for the tangent), the depth
    // program plain and cut out, and the attribute pass.
    .chain(vertex_variants().map(|k| k.switch("INSTANCED", "inst", true)))
    .chain(vertex_variants().map(|k| {
        k.switch("SKINNED", "skin", true)
            .count("SKIN_JOINTS", "j", 16)
    }))
    // Two joint sets (JOINTS_1/WEIGHTS_1 in attributes 12 and 13).
    .chain(vertex_variants().map(|k| {
        k.switch("SKINNED", "skin", true)
            .count("SKIN_JOINTS", "j", 16)
            .count("SKIN_SETS", "s", 2)
    }))
    // Morph targets on the GPU: a one-joint skin with all four delta attributes.
    .chain(vertex_variants().map(|k| {
        k.switch("SKINNED", "skin", true)
            .count("SKIN_JOINTS", "j", 1)
            .switch("MORPHED", "morph", true)
            .count("MORPH_ATTRIBUTES", "m", 4)
    }))
    // The copy path's RGBM-encoded linear frame (bloom without float render targets).
    .chain(
        [
            background::skybox_key(true, 3),
            lit::program_key(1, 1, 1, 0, true, false, true),
            view::shadow_flags(grid::key(), 1, 1, 1, 0),
        ]
        .map(|k| {
            k.switch("LINEAR_OUTPUT", "lin", true)
                .switch("FRAME_RGBM", "hdr8", true)
        }),
    )
    .collect()
}

/// The programs whose vertex stage moves the mesh (instances, skins), as their plain keys.
fn vertex_variants() -> [ProgramKey; 6] {
    [
        lit::program_key(1, 1, 1, 0, true, false, true).switch("HAS_NORMAL_MAP", "nrm", true),
        lit::program_key(1, 1, 1, 0, true, true, true),
        pbr::all_keys(1, 1, 1, 0).swap_remove(0),
        shadow::depth_key(),
        slots::flags(
            shadow::depth_key().switch("HAS_TEXTURE", "tex", true),
            &Material {
                alpha_mode: AlphaMode::Mask(0.5),
                ..Material::gltf_default()
            },
            true,
            true,
            false,
        ),
        attributes::key(),
    ]
}

/// The material variants of each lit program and of the depth program, for
/// `--compile-shaders` (every flag of slots.rs in both tiers, with every map on).
fn variant_keys() -> Vec<ProgramKey> {
    let models = [
        Material {
            alpha_mode: AlphaMode::Mask(0.5),
            ..Material::gltf_default()
        },
        Material {
            alpha_mode: AlphaMode::Blend,
            unlit: true,
            ..Material::gltf_default()
        },
    ];
    let mut keys = Vec::new();
    for m in &models {
        for gouraud in [false, true] {
            let lit = lit::program_key(1, 1, 1, 0, true, gouraud, true)
                .switch("HAS_NORMAL_MAP", "nrm", !gouraud)
                .switch("HAS_EMISSIVE_MAP", "emi", true);
            keys.push(slots::flags(lit, m, true, true, true));
        }
        for pbr in pbr::all_keys(1, 1, 1, 0) {
            keys.push(slots::flags(pbr, m, true, true, true));
        }
        for (textured, colored) in [(false, false), (true, false), (true, true)] {
            let depth = shadow::depth_key()
                .switch("HAS_TEXTURE", "tex", textured)
                .switch("HAS_COLOR", "vc", colored);
            keys.push(slots::flags(depth, m, textured, textured, colored));
        }
    }
    keys
}
