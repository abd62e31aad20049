//! Per-instance transforms for instanced draws (`EXT_mesh_gpu_instancing`): one buffer of
//! column-major 4x4 matrices, 64 bytes an instance, fed to the vertex attributes
//! `aInstance0..3` (one column each) with divisor 1. A draw may send a subset (the instances
//! a view can see), written over the buffer's start; the buffer remembers which it holds. Only on contexts with instanced arrays
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
    matrices: Vec<[f32; 16]>,
    /// The instances the buffer holds, in order (None: all of them).
    held: std::cell::RefCell<Option<Vec<u32>>>,
}

impl Instances {
    pub(crate) fn new(gpu: &GpuRef, matrices: &[Mat4]) -> Result<Instances> {
        let cols: Vec<[f32; 16]> = matrices.iter().map(Mat4::to_cols_array).collect();
        // Rewritten by draws that send a subset.
        let buffer = Buffer::new_with(
            gpu,
            glow::ARRAY_BUFFER,
            bytemuck::cast_slice(&cols),
            glow::DYNAMIC_DRAW,
        )?;
        Ok(Instances {
            buffer,
            matrices: cols,
            held: std::cell::RefCell::new(None),
        })
    }

    /// Bytes on the GPU (`--stats`' upload count).
    pub(crate) fn bytes(&self) -> u64 {
        self.matrices.len() as u64 * 64
    }

    /// Makes the buffer hold instances `which` (in order; None: all) and returns how many
    /// a draw sends; a no-op when it holds them already.
    pub(crate) fn hold(&self, gl: &glow::Context, which: Option<&[u32]>) -> i32 {
        let mut held = self.held.borrow_mut();
        if held.as_deref() != which {
            let rows: Vec<[f32; 16]> = match which {
                Some(w) => w.iter().map(|&k| self.matrices[k as usize]).collect(),
                None => self.matrices.clone(),
            };
            self.buffer.bind();
            // SAFETY: rewriting the start of our own buffer with at most its own length.
            unsafe {
                gl.buffer_sub_data_u8_slice(glow::ARRAY_BUFFER, 0, bytemuck::cast_slice(&rows))
            };
            *held = which.map(<[u32]>::to_vec);
        }
        let n = held.as_ref().map_or(self.matrices.len(), Vec::len);
        i32::try_from(n).unwrap_or(i32::MAX)
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
