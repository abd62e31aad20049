//! Per-instance transforms for instanced draws (`EXT_mesh_gpu_instancing`): one static
//! buffer of column-major 4x4 matrices, 64 bytes an instance, fed to the vertex attributes
//! `aInstance0..3` (one column each) with divisor 1. Only on contexts with instanced arrays
//! (GL 3.3, ES 3.0: [`super::Caps::instancing`]); GL 2.1 draws the written-out copies.
use super::buffer::Buffer;
use super::GpuRef;
use crate::Result;
use glam::Mat4;
use glow::HasContext;

/// Attribute location of the first matrix column; the other three follow.
pub(crate) const INSTANCE_ATTRIBUTE: u32 = 6;

pub(crate) struct Instances {
    buffer: Buffer,
    pub(crate) count: i32,
}

impl Instances {
    pub(crate) fn new(gpu: &GpuRef, matrices: &[Mat4]) -> Result<Instances> {
        let cols: Vec<[f32; 16]> = matrices.iter().map(Mat4::to_cols_array).collect();
        let buffer = Buffer::new_static(gpu, glow::ARRAY_BUFFER, bytemuck::cast_slice(&cols))?;
        Ok(Instances {
            buffer,
            count: i32::try_from(matrices.len()).unwrap_or(i32::MAX),
        })
    }

    /// Bytes on the GPU (`--stats`' upload count).
    pub(crate) fn bytes(&self) -> u64 {
        self.count as u64 * 64
    }

    /// Points the four column attributes at the buffer, advancing once per instance.
    /// SAFETY: the caller has the mesh's attributes set (its vertex array bound) and turns
    /// them off with [`Instances::unbind`] after its draws.
    pub(crate) unsafe fn bind(&self, gl: &glow::Context) {
        self.buffer.bind();
        for c in 0..4 {
            let loc = INSTANCE_ATTRIBUTE + c;
            gl.enable_vertex_attrib_array(loc);
            gl.vertex_attrib_pointer_f32(loc, 4, glow::FLOAT, false, 64, 16 * c as i32);
            gl.vertex_attrib_divisor(loc, 1);
        }
    }

    /// Leaves the column attributes off and per-vertex again, so a vertex array (or, without
    /// one, the shared attribute state) is as a plain draw expects it.
    /// SAFETY: as [`Instances::bind`].
    pub(crate) unsafe fn unbind(gl: &glow::Context) {
        for c in 0..4 {
            let loc = INSTANCE_ATTRIBUTE + c;
            gl.vertex_attrib_divisor(loc, 0);
            gl.disable_vertex_attrib_array(loc);
        }
    }
}
