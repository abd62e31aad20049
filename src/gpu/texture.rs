//! 2D textures: RGBA8 colour maps and depth maps for shadow comparison.
use super::GpuRef;
use crate::{Error, Result};
use glow::HasContext;

pub struct Texture2d {
    gpu: GpuRef,
    pub raw: glow::Texture,
    pub width: u32,
    pub height: u32,
}

impl Texture2d {
    fn create(gpu: &GpuRef, width: u32, height: u32) -> Result<Texture2d> {
        // SAFETY: creating and binding a new texture object.
        unsafe {
            let raw = gpu.gl.create_texture().map_err(Error::Unsupported)?;
            gpu.created();
            gpu.gl.bind_texture(glow::TEXTURE_2D, Some(raw));
            Ok(Texture2d {
                gpu: gpu.clone(),
                raw,
                width,
                height,
            })
        }
    }

    fn params(&self, min: u32, mag: u32, wrap: u32) {
        let gl = &self.gpu.gl;
        // SAFETY: parameters on the texture bound by `create`.
        unsafe {
            gl.tex_parameter_i32(glow::TEXTURE_2D, glow::TEXTURE_MIN_FILTER, min as i32);
            gl.tex_parameter_i32(glow::TEXTURE_2D, glow::TEXTURE_MAG_FILTER, mag as i32);
            gl.tex_parameter_i32(glow::TEXTURE_2D, glow::TEXTURE_WRAP_S, wrap as i32);
            gl.tex_parameter_i32(glow::TEXTURE_2D, glow::TEXTURE_WRAP_T, wrap as i32);
        }
    }

    /// An RGBA8 colour texture, row 0 = top of the image (sampled at v = 0), with mipmaps where
    /// `glGenerateMipmap` exists (GL 3.0, ES 3.0 or the FBO extensions).
    pub fn from_rgba(gpu: &GpuRef, width: u32, height: u32, rgba: &[u8]) -> Result<Texture2d> {
        let t = Self::create(gpu, width, height)?;
        let mipmaps = gpu.caps.generate_mipmap;
        // SAFETY: rgba holds width*height*4 bytes (checked by the loader); UNPACK_ALIGNMENT 1.
        unsafe {
            let gl = &gpu.gl;
            gl.pixel_store_i32(glow::UNPACK_ALIGNMENT, 1);
            gl.tex_image_2d(
                glow::TEXTURE_2D,
                0,
                glow::RGBA8 as i32,
                width as i32,
                height as i32,
                0,
                glow::RGBA,
                glow::UNSIGNED_BYTE,
                glow::PixelUnpackData::Slice(Some(rgba)),
            );
            if mipmaps {
                gl.generate_mipmap(glow::TEXTURE_2D);
            }
        }
        let min = if mipmaps {
            glow::LINEAR_MIPMAP_LINEAR
        } else {
            glow::LINEAR
        };
        t.params(min, glow::LINEAR, glow::REPEAT);
        Ok(t)
    }

    /// A `width` x `height` depth texture set up for hardware comparison
    /// (`sampler2DShadow`): compare mode COMPARE_REF_TO_TEXTURE, LEQUAL, linear filtering
    /// (the driver then blends the 2×2 compared results where it supports it), clamped to the
    /// edge.
    pub fn depth(gpu: &GpuRef, width: u32, height: u32) -> Result<Texture2d> {
        let t = Self::create(gpu, width, height)?;
        // ES 3.0 needs a sized internal format paired with UNSIGNED_INT; desktop GL 1.4+
        // accepts the same pair, so one choice serves every dialect.
        // SAFETY: allocating storage for the bound texture with no initial data.
        unsafe {
            let gl = &gpu.gl;
            gl.tex_image_2d(
                glow::TEXTURE_2D,
                0,
                glow::DEPTH_COMPONENT24 as i32,
                width as i32,
                height as i32,
                0,
                glow::DEPTH_COMPONENT,
                glow::UNSIGNED_INT,
                glow::PixelUnpackData::Slice(None),
            );
            gl.tex_parameter_i32(
                glow::TEXTURE_2D,
                glow::TEXTURE_COMPARE_MODE,
                glow::COMPARE_REF_TO_TEXTURE as i32,
            );
            gl.tex_parameter_i32(
                glow::TEXTURE_2D,
                glow::TEXTURE_COMPARE_FUNC,
                glow::LEQUAL as i32,
            );
        }
        t.params(glow::LINEAR, glow::LINEAR, glow::CLAMP_TO_EDGE);
        Ok(t)
    }

    /// Switches between comparison (for lighting) and raw depth reads (for `--show shadow-map`).
    pub fn set_compare(&self, on: bool) {
        let mode = if on {
            glow::COMPARE_REF_TO_TEXTURE
        } else {
            glow::NONE
        };
        // SAFETY: parameter on our own texture.
        unsafe {
            self.gpu.gl.bind_texture(glow::TEXTURE_2D, Some(self.raw));
            self.gpu.gl.tex_parameter_i32(
                glow::TEXTURE_2D,
                glow::TEXTURE_COMPARE_MODE,
                mode as i32,
            );
        }
    }

    pub fn bind(&self, unit: u32) {
        // SAFETY: binding our own texture to a unit below the driver's limit (we use < 8).
        unsafe {
            self.gpu.gl.active_texture(glow::TEXTURE0 + unit);
            self.gpu.gl.bind_texture(glow::TEXTURE_2D, Some(self.raw));
        }
    }

    /// Copies a `size`² square from the lower-left corner of the bound read framebuffer's
    /// depth into level 0 at (x, y): the shadow-map path for drivers without framebuffer
    /// objects.
    pub fn copy_from_framebuffer(&self, x: u32, y: u32, size: u32) {
        // SAFETY: the caller keeps (x, y, size) inside the texture and size within the
        // framebuffer.
        unsafe {
            self.gpu.gl.bind_texture(glow::TEXTURE_2D, Some(self.raw));
            self.gpu.gl.copy_tex_sub_image_2d(
                glow::TEXTURE_2D,
                0,
                x as i32,
                y as i32,
                0,
                0,
                size as i32,
                size as i32,
            );
        }
    }
}

impl Drop for Texture2d {
    fn drop(&mut self) {
        // SAFETY: deleting our own texture once.
        unsafe { self.gpu.gl.delete_texture(self.raw) };
        self.gpu.deleted();
    }
}
