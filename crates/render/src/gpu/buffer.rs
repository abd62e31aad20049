//! Static vertex and index buffers, uploaded once.
use super::GpuRef;
use crate::{Error, Result};
use glow::HasContext;

pub(crate) struct Buffer {
    gpu: GpuRef,
    pub(crate) raw: glow::Buffer,
    pub(crate) target: u32,
}

impl Buffer {
    pub(crate) fn new_static(gpu: &GpuRef, target: u32, data: &[u8]) -> Result<Buffer> {
        Self::new_with(gpu, target, data, glow::STATIC_DRAW)
    }

    /// As [`Buffer::new_static`] with a usage hint (`DYNAMIC_DRAW` for data rewritten often).
    pub(crate) fn new_with(gpu: &GpuRef, target: u32, data: &[u8], usage: u32) -> Result<Buffer> {
        // SAFETY: a fresh buffer is bound and filled with a slice that lives for the call.
        unsafe {
            let raw = gpu.gl.create_buffer().map_err(Error::Unsupported)?;
            gpu.created();
            gpu.gl.bind_buffer(target, Some(raw));
            gpu.gl.buffer_data_u8_slice(target, data, usage);
            gpu.gl.bind_buffer(target, None);
            Ok(Buffer {
                gpu: gpu.clone(),
                raw,
                target,
            })
        }
    }

    /// A buffer of `parts` end to end, filled part by part (no joined copy of them).
    pub(crate) fn new_static_parts(gpu: &GpuRef, target: u32, parts: &[&[u8]]) -> Result<Buffer> {
        let total: usize = parts.iter().map(|p| p.len()).sum();
        // SAFETY: a fresh buffer is bound, sized, and filled with slices that live for the
        // call, each within the size.
        unsafe {
            let raw = gpu.gl.create_buffer().map_err(Error::Unsupported)?;
            gpu.created();
            gpu.gl.bind_buffer(target, Some(raw));
            gpu.gl
                .buffer_data_size(target, total as i32, glow::STATIC_DRAW);
            let mut at = 0;
            for p in parts {
                gpu.gl.buffer_sub_data_u8_slice(target, at as i32, p);
                at += p.len();
            }
            gpu.gl.bind_buffer(target, None);
            Ok(Buffer {
                gpu: gpu.clone(),
                raw,
                target,
            })
        }
    }

    /// Rewrites the buffer's bytes from the start with `data`, no longer than the buffer
    /// (a posed mesh's new vertices: the same objects, no new VAO to record).
    pub(crate) fn rewrite(&self, data: &[u8]) {
        // SAFETY: our live buffer is bound and written within the size the caller checked.
        unsafe {
            self.gpu.gl.bind_buffer(self.target, Some(self.raw));
            self.gpu.gl.buffer_sub_data_u8_slice(self.target, 0, data);
            self.gpu.gl.bind_buffer(self.target, None);
        }
    }

    pub(crate) fn bind(&self) {
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
