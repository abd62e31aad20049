//! Static vertex and index buffers, uploaded once.
use super::GpuRef;
use crate::{Error, Result};
use glow::HasContext;

pub struct Buffer {
    gpu: GpuRef,
    pub raw: glow::Buffer,
    pub target: u32,
}

impl Buffer {
    pub fn new_static(gpu: &GpuRef, target: u32, data: &[u8]) -> Result<Buffer> {
        // SAFETY: a fresh buffer is bound and filled with a slice that lives for the call.
        unsafe {
            let raw = gpu.gl.create_buffer().map_err(Error::Unsupported)?;
            gpu.created();
            gpu.gl.bind_buffer(target, Some(raw));
            gpu.gl.buffer_data_u8_slice(target, data, glow::STATIC_DRAW);
            gpu.gl.bind_buffer(target, None);
            Ok(Buffer {
                gpu: gpu.clone(),
                raw,
                target,
            })
        }
    }

    pub fn bind(&self) {
        // SAFETY: raw is a live buffer of this context.
        unsafe { self.gpu.gl.bind_buffer(self.target, Some(self.raw)) }
    }
}

impl Drop for Buffer {
    fn drop(&mut self) {
        // SAFETY: deleting our own buffer once.
        unsafe { self.gpu.gl.delete_buffer(self.raw) };
        self.gpu.deleted();
    }
}
