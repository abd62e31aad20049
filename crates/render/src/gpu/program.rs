//! Linked GLSL programs with cached uniform locations. A uniform the compiler optimised away is
//! normal across feature permutations, so setting it is a no-op, never an error.
use super::GpuRef;
use crate::{Error, Result};
use glow::HasContext;
use std::cell::RefCell;
use std::collections::HashMap;

/// Attribute locations, bound before linking so every program shares one vertex layout.
pub(crate) const ATTRIBUTES: [(u32, &str); 18] = [
    (0, "aPosition"),
    (1, "aNormal"),
    (2, "aUv"),
    (3, "aTangent"),
    (4, "aColor"),
    (5, "aUv1"),
    // The instance matrix's columns (`instance.glsl`, super::instances).
    (6, "aInstance0"),
    (7, "aInstance1"),
    (8, "aInstance2"),
    (9, "aInstance3"),
    // A skinned mesh's joints and weights (`skin.glsl`, super::mesh::Streams::skin).
    (10, "aJoints"),
    (11, "aWeights"),
    // A mesh morphed on the GPU: its targets' deltas (`skin.glsl`, super::mesh::Streams::morph).
    (12, "aMorph0"),
    (13, "aMorph1"),
    (14, "aMorph2"),
    (15, "aMorph3"),
    // A second joint set, in the first two morph attributes' places: a program declares
    // one or the other (`skin.glsl`), never both, so the names never alias in one program.
    (12, "aJoints1"),
    (13, "aWeights1"),
];

pub struct Program {
    gpu: GpuRef,
    pub(crate) raw: glow::Program,
    uniforms: RefCell<HashMap<String, Option<glow::UniformLocation>>>,
}

fn numbered(source: &str) -> String {
    source
        .lines()
        .enumerate()
        .map(|(i, l)| format!("{:4} {l}\n", i + 1))
        .collect()
}

impl Program {
    pub fn new(gpu: &GpuRef, name: &str, vertex: &str, fragment: &str) -> Result<Program> {
        let gl = &gpu.gl;
        let dialect = gpu.caps.dialect.name().to_string();
        // SAFETY: standard compile/link sequence on objects we create and delete here.
        unsafe {
            let mut shaders = Vec::new();
            for (stage, kind, src) in [
                ("compile the vertex shader", glow::VERTEX_SHADER, vertex),
                (
                    "compile the fragment shader",
                    glow::FRAGMENT_SHADER,
                    fragment,
                ),
            ] {
                let sh = gl.create_shader(kind).map_err(Error::Unsupported)?;
                gl.shader_source(sh, src);
                gl.compile_shader(sh);
                if !gl.get_shader_compile_status(sh) {
                    let log = gl.get_shader_info_log(sh);
                    gl.delete_shader(sh);
                    for s in shaders {
                        gl.delete_shader(s);
                    }
                    return Err(Error::Shader {
                        name: name.into(),
                        dialect,
                        stage,
                        log,
                        numbered_source: numbered(src),
                    });
                }
                shaders.push(sh);
            }
            let raw = gl.create_program().map_err(Error::Unsupported)?;
            for &s in &shaders {
                gl.attach_shader(raw, s);
            }
            // A location past the driver's attributes is an error: only morphed meshes and
            // two-set skins use 12 and up, and the free-attribute budget keeps them off such
            // a driver.
            let max = gpu.caps.max_vertex_attribs.max(12);
            for (loc, attr) in ATTRIBUTES.into_iter().filter(|a| a.0 < max) {
                gl.bind_attrib_location(raw, loc, attr);
            }
            gl.link_program(raw);
            for s in shaders {
                gl.detach_shader(raw, s);
                gl.delete_shader(s);
            }
            if !gl.get_program_link_status(raw) {
                let log = gl.get_program_info_log(raw);
                gl.delete_program(raw);
                return Err(Error::Shader {
                    name: name.into(),
                    dialect,
                    stage: "link",
                    log,
                    numbered_source: format!("{}\n{}", numbered(vertex), numbered(fragment)),
                });
            }
            gpu.created();
            Ok(Program {
                gpu: gpu.clone(),
                raw,
                uniforms: RefCell::new(HashMap::new()),
            })
        }
    }

    pub(crate) fn bind(&self) {
        // SAFETY: using our own linked program.
        unsafe { self.gpu.gl.use_program(Some(self.raw)) }
    }

    fn location(&self, name: &str) -> Option<glow::UniformLocation> {
        self.uniforms
            .borrow_mut()
            .entry(name.to_string())
            // SAFETY: query on our own program.
            .or_insert_with(|| unsafe { self.gpu.gl.get_uniform_location(self.raw, name) })
            .to_owned()
    }

    pub(crate) fn set_mat4(&self, name: &str, m: &glam::Mat4) {
        if let Some(l) = self.location(name) {
            // SAFETY: the program is bound by the caller; 16 floats.
            unsafe {
                self.gpu
                    .gl
                    .uniform_matrix_4_f32_slice(Some(&l), false, &m.to_cols_array())
            }
        }
    }

    /// Sets the array `name` from its first element on (a skin's joint matrices).
    pub(crate) fn set_mat4_array(&self, name: &str, ms: &[glam::Mat4]) {
        if let (Some(l), false) = (self.location(name), ms.is_empty()) {
            let flat: Vec<f32> = ms.iter().flat_map(glam::Mat4::to_cols_array).collect();
            // SAFETY: the program is bound by the caller; 16 floats per matrix, no more
            // matrices than the array declares (the key's SKIN_JOINTS is the skin's count).
            unsafe {
                self.gpu
                    .gl
                    .uniform_matrix_4_f32_slice(Some(&l), false, &flat)
            }
        }
    }

    pub(crate) fn set_mat3(&self, name: &str, m: &glam::Mat3) {
        if let Some(l) = self.location(name) {
            // SAFETY: as above; 9 floats.
            unsafe {
                self.gpu
                    .gl
                    .uniform_matrix_3_f32_slice(Some(&l), false, &m.to_cols_array())
            }
        }
    }

    pub(crate) fn set_vec3(&self, name: &str, v: glam::Vec3) {
        if let Some(l) = self.location(name) {
            // SAFETY: as above.
            unsafe { self.gpu.gl.uniform_3_f32(Some(&l), v.x, v.y, v.z) }
        }
    }

    pub(crate) fn set_vec2(&self, name: &str, v: glam::Vec2) {
        if let Some(l) = self.location(name) {
            // SAFETY: as above.
            unsafe { self.gpu.gl.uniform_2_f32(Some(&l), v.x, v.y) }
        }
    }

    pub(crate) fn set_vec4(&self, name: &str, v: glam::Vec4) {
        if let Some(l) = self.location(name) {
            // SAFETY: as above.
            unsafe { self.gpu.gl.uniform_4_f32(Some(&l), v.x, v.y, v.z, v.w) }
        }
    }

    pub(crate) fn set_f32(&self, name: &str, v: f32) {
        if let Some(l) = self.location(name) {
            // SAFETY: as above.
            unsafe { self.gpu.gl.uniform_1_f32(Some(&l), v) }
        }
    }

    pub(crate) fn set_i32(&self, name: &str, v: i32) {
        if let Some(l) = self.location(name) {
            // SAFETY: as above.
            unsafe { self.gpu.gl.uniform_1_i32(Some(&l), v) }
        }
    }

    pub(crate) fn set_ivec2(&self, name: &str, x: i32, y: i32) {
        if let Some(l) = self.location(name) {
            // SAFETY: as above.
            unsafe { self.gpu.gl.uniform_2_i32(Some(&l), x, y) }
        }
    }
}

impl Drop for Program {
    fn drop(&mut self) {
        // SAFETY: deleting our own program once.
        unsafe { self.gpu.gl.delete_program(self.raw) };
        self.gpu.deleted();
    }
}
