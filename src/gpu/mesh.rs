//! A mesh in static GPU buffers, drawn through a vertex array object where the driver has
//! one, or with per-draw attribute binding on GL 2.1 drivers without VAOs.
use super::buffer::Buffer;
use super::GpuRef;
use crate::scene::Vertex;
use crate::{Error, Result};
use glow::HasContext;

pub struct GpuMesh {
    gpu: GpuRef,
    vbo: Buffer,
    ibo: Buffer,
    /// Per-vertex tangents (xyz, w = handedness) for normal mapping, attribute 3.
    tangents: Option<Buffer>,
    vao: Option<glow::VertexArray>,
    index_type: u32,
    pub index_count: i32,
}

/// Attribute location of the optional tangent stream.
pub const TANGENT_ATTRIBUTE: u32 = 3;

fn set_attributes(gl: &glow::Context, vbo: &Buffer, tangents: Option<&Buffer>) {
    let stride = std::mem::size_of::<Vertex>() as i32;
    // SAFETY: offsets match the #[repr(C)] Vertex layout; tangents are tightly packed vec4.
    unsafe {
        vbo.bind();
        for (loc, size, offset) in [(0u32, 3, 0), (1, 3, 12), (2, 2, 24)] {
            gl.enable_vertex_attrib_array(loc);
            gl.vertex_attrib_pointer_f32(loc, size, glow::FLOAT, false, stride, offset);
        }
        match tangents {
            Some(t) => {
                t.bind();
                gl.enable_vertex_attrib_array(TANGENT_ATTRIBUTE);
                gl.vertex_attrib_pointer_f32(TANGENT_ATTRIBUTE, 4, glow::FLOAT, false, 16, 0);
            }
            // A disabled array reads the current generic value: (0, 0, 0, 1).
            None => gl.disable_vertex_attrib_array(TANGENT_ATTRIBUTE),
        }
    }
}

impl GpuMesh {
    pub fn new(gpu: &GpuRef, vertices: &[Vertex], indices: &[u32]) -> Result<GpuMesh> {
        Self::with_tangents(gpu, vertices, indices, None)
    }

    /// A mesh with a second vertex stream of tangents (one per vertex) where given.
    pub fn with_tangents(
        gpu: &GpuRef,
        vertices: &[Vertex],
        indices: &[u32],
        tangents: Option<&[[f32; 4]]>,
    ) -> Result<GpuMesh> {
        let tangents = match tangents {
            Some(t) => Some(Buffer::new_static(
                gpu,
                glow::ARRAY_BUFFER,
                bytemuck::cast_slice(t),
            )?),
            None => None,
        };
        let vbo = Buffer::new_static(gpu, glow::ARRAY_BUFFER, bytemuck::cast_slice(vertices))?;
        // 16-bit indices where they suffice: half the memory, and the only kind ES 2 had.
        let (ibo, index_type) = if vertices.len() <= u16::MAX as usize + 1 {
            let small: Vec<u16> = indices.iter().map(|&i| i as u16).collect();
            (
                Buffer::new_static(
                    gpu,
                    glow::ELEMENT_ARRAY_BUFFER,
                    bytemuck::cast_slice(&small),
                )?,
                glow::UNSIGNED_SHORT,
            )
        } else if gpu.caps.uint_indices {
            (
                Buffer::new_static(
                    gpu,
                    glow::ELEMENT_ARRAY_BUFFER,
                    bytemuck::cast_slice(indices),
                )?,
                glow::UNSIGNED_INT,
            )
        } else {
            return Err(Error::Unsupported(format!(
                "mesh with {} vertices needs 32-bit indices, which this driver lacks",
                vertices.len()
            )));
        };
        let vao = if gpu.caps.vao {
            // SAFETY: recording the attribute layout into a new VAO, then unbinding it.
            unsafe {
                let vao = gpu.gl.create_vertex_array().map_err(Error::Unsupported)?;
                gpu.created();
                gpu.gl.bind_vertex_array(Some(vao));
                set_attributes(&gpu.gl, &vbo, tangents.as_ref());
                ibo.bind();
                gpu.gl.bind_vertex_array(None);
                Some(vao)
            }
        } else {
            None
        };
        Ok(GpuMesh {
            gpu: gpu.clone(),
            vbo,
            ibo,
            tangents,
            vao,
            index_type,
            index_count: indices.len() as i32,
        })
    }

    pub fn draw(&self) {
        let gl = &self.gpu.gl;
        // SAFETY: draws from our own buffers; the caller has bound a program.
        unsafe {
            match self.vao {
                Some(vao) => gl.bind_vertex_array(Some(vao)),
                None => {
                    set_attributes(gl, &self.vbo, self.tangents.as_ref());
                    self.ibo.bind();
                }
            }
            gl.draw_elements(glow::TRIANGLES, self.index_count, self.index_type, 0);
            if self.vao.is_some() {
                gl.bind_vertex_array(None);
            }
        }
    }
}

impl Drop for GpuMesh {
    fn drop(&mut self) {
        if let Some(vao) = self.vao {
            // SAFETY: deleting our own VAO once.
            unsafe { self.gpu.gl.delete_vertex_array(vao) };
            self.gpu.deleted();
        }
    }
}
