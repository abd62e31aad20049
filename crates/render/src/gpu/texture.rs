//! Textures: 2D colour maps in the formats of [`TextureFormat`], depth maps for shadow
//! comparison, and cube maps (the PBR tier's irradiance and specular levels).
use super::{Caps, GpuRef};
use crate::{Error, Result};
use glow::HasContext;

/// Texel formats, each gated on the capability probe (`TextureFormat::supported`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
pub enum TextureFormat {
    Rgba8,
    /// 8-bit colour stored sRGB-encoded; the sampler returns linear values.
    Srgb8A8,
    Rgba16F,
    /// 32-bit float colour, for render targets read back exactly (not filterable on ES).
    Rgba32F,
    Rg16F,
    Depth24,
    Depth24Stencil8,
}

/// Pixel data for an upload: 8-bit channels, or f32 channels converted by the driver.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Pixels<'a> {
    U8(&'a [u8]),
    F32(&'a [f32]),
    None,
}

impl TextureFormat {
    pub(crate) fn supported(self, caps: &Caps) -> bool {
        match self {
            TextureFormat::Rgba8 => true,
            TextureFormat::Srgb8A8 => caps.srgb_textures,
            TextureFormat::Rgba16F => caps.half_float_textures,
            TextureFormat::Rgba32F => caps.float_render,
            TextureFormat::Rg16F => caps.half_float_textures && caps.rg_textures,
            TextureFormat::Depth24 => caps.depth_texture,
            TextureFormat::Depth24Stencil8 => caps.depth_stencil,
        }
    }

    /// (internal format, format, type) for `glTexImage2D`. ES 3.0 wants sized internal formats
    /// paired with matching types; desktop GL accepts the same pairs.
    fn gl(self, pixels: &Pixels, caps: &Caps) -> (u32, u32, u32) {
        let ty = |default| match pixels {
            Pixels::F32(_) => glow::FLOAT,
            _ => default,
        };
        // ES 2.0 (WebGL 1) has unsized internal formats only, equal to the format.
        match (self, caps.es2) {
            (TextureFormat::Rgba8, true) => return (glow::RGBA, glow::RGBA, glow::UNSIGNED_BYTE),
            (TextureFormat::Depth24, true) => {
                return (
                    glow::DEPTH_COMPONENT,
                    glow::DEPTH_COMPONENT,
                    glow::UNSIGNED_INT,
                )
            }
            _ => {}
        }
        match self {
            TextureFormat::Rgba8 => (glow::RGBA8, glow::RGBA, glow::UNSIGNED_BYTE),
            TextureFormat::Srgb8A8 => (glow::SRGB8_ALPHA8, glow::RGBA, glow::UNSIGNED_BYTE),
            TextureFormat::Rgba16F => (glow::RGBA16F, glow::RGBA, ty(glow::HALF_FLOAT)),
            TextureFormat::Rgba32F => (glow::RGBA32F, glow::RGBA, glow::FLOAT),
            TextureFormat::Rg16F => (glow::RG16F, glow::RG, ty(glow::HALF_FLOAT)),
            TextureFormat::Depth24 => (
                glow::DEPTH_COMPONENT24,
                glow::DEPTH_COMPONENT,
                glow::UNSIGNED_INT,
            ),
            TextureFormat::Depth24Stencil8 => (
                glow::DEPTH24_STENCIL8,
                glow::DEPTH_STENCIL,
                glow::UNSIGNED_INT_24_8,
            ),
        }
    }
}

/// Sampler filtering and wrapping.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Sampling {
    pub(crate) linear: bool,
    pub(crate) mipmaps: bool,
    pub(crate) repeat: bool,
}

impl Sampling {
    /// Exact texel lookups, no mip chain, clamped: render targets and tables read texel by texel.
    pub(crate) const NEAREST: Sampling = Sampling {
        linear: false,
        mipmaps: false,
        repeat: false,
    };
}

unsafe fn tex_image(
    gpu: &super::Gpu,
    target: u32,
    level: i32,
    format: TextureFormat,
    w: u32,
    h: u32,
    pixels: Pixels,
) {
    let gl = &gpu.gl;
    let (internal, fmt, ty) = format.gl(&pixels, &gpu.caps);
    let data = match pixels {
        Pixels::U8(d) => Some(d),
        Pixels::F32(d) => Some(bytemuck::cast_slice(d)),
        Pixels::None => None,
    };
    gl.pixel_store_i32(glow::UNPACK_ALIGNMENT, 1);
    gl.tex_image_2d(
        target,
        level,
        internal as i32,
        w as i32,
        h as i32,
        0,
        fmt,
        ty,
        glow::PixelUnpackData::Slice(data),
    );
}

/// Where a colour texture's mipmaps come from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MipSource {
    /// Built on the CPU (`super::mipmaps`): fast on every driver, and present without
    /// `glGenerateMipmap`.
    Cpu,
    /// `glGenerateMipmap`, where the driver has it (else no mipmaps).
    Driver,
}

/// Levels 1.. of the bound 2D texture, each RGBA8 data of its size.
unsafe fn upload_levels(gpu: &super::Gpu, format: TextureFormat, levels: &[super::mipmaps::Level]) {
    for (i, (w, h, data)) in levels.iter().enumerate() {
        tex_image(
            gpu,
            glow::TEXTURE_2D,
            i as i32 + 1,
            format,
            *w,
            *h,
            Pixels::U8(data),
        );
    }
}

unsafe fn sampler_params(gpu: &super::Gpu, target: u32, s: Sampling) {
    let gl = &gpu.gl;
    let mag = if s.linear {
        glow::LINEAR
    } else {
        glow::NEAREST
    };
    let min = match (s.linear, s.mipmaps) {
        (true, true) => glow::LINEAR_MIPMAP_LINEAR,
        (false, true) => glow::NEAREST_MIPMAP_NEAREST,
        _ => mag,
    };
    let wrap = if s.repeat {
        glow::REPEAT
    } else {
        glow::CLAMP_TO_EDGE
    };
    gl.tex_parameter_i32(target, glow::TEXTURE_MIN_FILTER, min as i32);
    gl.tex_parameter_i32(target, glow::TEXTURE_MAG_FILTER, mag as i32);
    gl.tex_parameter_i32(target, glow::TEXTURE_WRAP_S, wrap as i32);
    gl.tex_parameter_i32(target, glow::TEXTURE_WRAP_T, wrap as i32);
    // ES 2.0 (WebGL 1) has no TEXTURE_WRAP_R (GL 1.2's and ES 3.0's; WebGL 1 answers
    // INVALID_ENUM) and needs none: a cube lookup never wraps, whatever R says.
    if target == glow::TEXTURE_CUBE_MAP && !gpu.caps.es2 {
        gl.tex_parameter_i32(target, glow::TEXTURE_WRAP_R, wrap as i32);
    }
}

/// A cube map: six square faces in GL order (+X, −X, +Y, −Y, +Z, −Z).
pub(crate) struct TextureCube {
    gpu: GpuRef,
    pub(crate) raw: glow::Texture,
}

impl TextureCube {
    /// Uploads six faces (each `size`² texels of the format's channels), or allocates
    /// them empty (render target) with `Pixels::None` faces.
    pub(crate) fn new(
        gpu: &GpuRef,
        format: TextureFormat,
        size: u32,
        faces: [Pixels; 6],
        sampling: Sampling,
    ) -> Result<TextureCube> {
        if !format.supported(&gpu.caps) {
            return Err(Error::Unsupported(format!(
                "{}: {format:?} textures are not supported",
                gpu.caps.version
            )));
        }
        // SAFETY: creating a new cube texture and filling each face with data of the size
        // the caller promises (size² texels of the format's channels).
        unsafe {
            let gl = &gpu.gl;
            let raw = gl.create_texture().map_err(Error::Unsupported)?;
            gpu.created();
            gl.bind_texture(glow::TEXTURE_CUBE_MAP, Some(raw));
            for (i, face) in faces.into_iter().enumerate() {
                tex_image(
                    gpu,
                    glow::TEXTURE_CUBE_MAP_POSITIVE_X + i as u32,
                    0,
                    format,
                    size,
                    size,
                    face,
                );
            }
            if sampling.mipmaps {
                gl.generate_mipmap(glow::TEXTURE_CUBE_MAP);
            }
            sampler_params(gpu, glow::TEXTURE_CUBE_MAP, sampling);
            Ok(TextureCube {
                gpu: gpu.clone(),
                raw,
            })
        }
    }

    pub(crate) fn bind(&self, unit: u32) {
        // SAFETY: binding our own texture to a unit the caller keeps below the driver's limit.
        unsafe {
            self.gpu.active_unit(unit);
            self.gpu
                .gl
                .bind_texture(glow::TEXTURE_CUBE_MAP, Some(self.raw));
        }
    }
}

impl Drop for TextureCube {
    fn drop(&mut self) {
        // SAFETY: deleting our own texture once.
        unsafe { self.gpu.gl.delete_texture(self.raw) };
        self.gpu.deleted();
    }
}

pub struct Texture2d {
    gpu: GpuRef,
    pub(crate) raw: glow::Texture,
    pub(crate) width: u32,
    pub(crate) height: u32,
}

impl Texture2d {
    /// A texture of any supported format; `Pixels::None` allocates it empty (render target).
    pub(crate) fn new(
        gpu: &GpuRef,
        format: TextureFormat,
        width: u32,
        height: u32,
        pixels: Pixels,
        sampling: Sampling,
    ) -> Result<Texture2d> {
        if !format.supported(&gpu.caps) {
            return Err(Error::Unsupported(format!(
                "{}: {format:?} textures are not supported",
                gpu.caps.version
            )));
        }
        // 8-bit colour gets its chain from the CPU (see `mipmaps`), so every driver has one.
        let cpu_chain = match (format, pixels) {
            (TextureFormat::Rgba8 | TextureFormat::Srgb8A8, Pixels::U8(d)) if sampling.mipmaps => {
                Some(super::mipmaps::chain(
                    width,
                    height,
                    d,
                    format == TextureFormat::Srgb8A8,
                ))
            }
            _ => None,
        };
        let mipmaps = sampling.mipmaps && (cpu_chain.is_some() || gpu.caps.generate_mipmap);
        let (t, _rebind) = Self::create(gpu, width, height)?;
        // SAFETY: the caller's data holds width*height texels of the format's channels; each
        // CPU level holds its own w*h RGBA8 texels.
        unsafe {
            tex_image(gpu, glow::TEXTURE_2D, 0, format, width, height, pixels);
            match &cpu_chain {
                Some(levels) => upload_levels(gpu, format, levels),
                None if mipmaps => gpu.gl.generate_mipmap(glow::TEXTURE_2D),
                None => {}
            }
            sampler_params(
                gpu,
                glow::TEXTURE_2D,
                Sampling {
                    mipmaps,
                    ..sampling
                },
            );
        }
        Ok(t)
    }

    /// A mipmapped texture from explicit levels (level 0 first, each half the last), for
    /// formats a driver cannot `glGenerateMipmap` (ES 3.0: RGBA16F is not colour-renderable
    /// there) and for chains that must equal a CPU-computed one.
    pub(crate) fn with_levels(
        gpu: &GpuRef,
        format: TextureFormat,
        levels: &[(u32, u32, Pixels)],
        clamp: bool,
    ) -> Result<Texture2d> {
        if !format.supported(&gpu.caps) || levels.is_empty() {
            return Err(Error::Unsupported(format!(
                "{}: {format:?} textures are not supported",
                gpu.caps.version
            )));
        }
        let (t, _rebind) = Self::create(gpu, levels[0].0, levels[0].1)?;
        // SAFETY: each level's data holds w*h texels of the format's channels.
        unsafe {
            for (i, (w, h, px)) in levels.iter().enumerate() {
                tex_image(gpu, glow::TEXTURE_2D, i as i32, format, *w, *h, *px);
            }
            let gl = &gpu.gl;
            gl.tex_parameter_i32(
                glow::TEXTURE_2D,
                glow::TEXTURE_MAX_LEVEL,
                levels.len() as i32 - 1,
            );
            sampler_params(
                gpu,
                glow::TEXTURE_2D,
                Sampling {
                    linear: true,
                    mipmaps: true,
                    repeat: !clamp,
                },
            );
        }
        Ok(t)
    }
}

impl Texture2d {
    /// A new texture, bound on the active unit until the returned guard goes: then that
    /// unit's previous texture is bound again, so a texture made mid-frame (post targets, the
    /// RGBM frame's copy) does not replace what a pass bound there.
    fn create(gpu: &GpuRef, width: u32, height: u32) -> Result<(Texture2d, Rebind)> {
        // SAFETY: a binding query, then creating and binding a new texture object.
        unsafe {
            let previous = gpu.bound_texture_2d();
            let raw = gpu.gl.create_texture().map_err(Error::Unsupported)?;
            gpu.created();
            gpu.bind_texture_2d(Some(raw));
            Ok((
                Texture2d {
                    gpu: gpu.clone(),
                    raw,
                    width,
                    height,
                },
                Rebind {
                    gpu: gpu.clone(),
                    previous,
                },
            ))
        }
    }

    /// Binds this texture on the active unit until the returned guard goes, then puts that
    /// unit's previous texture back: a parameter change mid-frame (a sampler set on first use
    /// of a material's texture) must not replace what a pass bound there, e.g. a shadow map.
    fn bound(&self) -> Rebind {
        let previous = self.gpu.bound_texture_2d();
        self.gpu.bind_texture_2d(Some(self.raw));
        Rebind {
            gpu: self.gpu.clone(),
            previous,
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

    /// An RGBA8 colour texture, row 0 = top of the image (sampled at v = 0), mipmapped.
    pub fn from_rgba(gpu: &GpuRef, width: u32, height: u32, rgba: &[u8]) -> Result<Texture2d> {
        Self::from_rgba_with(
            gpu,
            TextureFormat::Rgba8,
            width,
            height,
            rgba,
            MipSource::Cpu,
        )
    }

    /// A mipmapped 8-bit colour texture (`Rgba8` or `Srgb8A8`, linear filtering, repeat) with
    /// the chain from `source`: the driver's (`glGenerateMipmap`, where it exists) is kept for
    /// tests that compare the two.
    pub fn from_rgba_with(
        gpu: &GpuRef,
        format: TextureFormat,
        width: u32,
        height: u32,
        rgba: &[u8],
        source: MipSource,
    ) -> Result<Texture2d> {
        let srgb = match format {
            TextureFormat::Rgba8 => false,
            TextureFormat::Srgb8A8 if format.supported(&gpu.caps) => true,
            _ => {
                return Err(Error::Unsupported(format!(
                    "{}: {format:?} is not an 8-bit colour format here",
                    gpu.caps.version
                )))
            }
        };
        let levels = match source {
            MipSource::Cpu => Some(super::mipmaps::chain(width, height, rgba, srgb)),
            MipSource::Driver => None,
        };
        let mipmaps = levels.is_some() || gpu.caps.generate_mipmap;
        let (t, _rebind) = Self::create(gpu, width, height)?;
        // SAFETY: rgba holds width*height*4 bytes (checked by the loader); UNPACK_ALIGNMENT 1.
        unsafe {
            let gl = &gpu.gl;
            let level0 = Pixels::U8(rgba);
            tex_image(gpu, glow::TEXTURE_2D, 0, format, width, height, level0);
            match &levels {
                Some(levels) => upload_levels(gpu, format, levels),
                None if mipmaps => gl.generate_mipmap(glow::TEXTURE_2D),
                None => {}
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
    pub(crate) fn depth(gpu: &GpuRef, width: u32, height: u32) -> Result<Texture2d> {
        let (t, _rebind) = Self::create(gpu, width, height)?;
        // ES 3.0 needs a sized internal format paired with UNSIGNED_INT; desktop GL 1.4+
        // accepts the same pair, so one choice serves every dialect.
        // SAFETY: allocating storage for the bound texture with no initial data.
        unsafe {
            let gl = &gpu.gl;
            // ES 2.0 (OES/WEBGL_depth_texture) takes the unsized format only.
            let internal = if gpu.caps.es2 {
                glow::DEPTH_COMPONENT
            } else {
                glow::DEPTH_COMPONENT24
            };
            gl.tex_image_2d(
                glow::TEXTURE_2D,
                0,
                internal as i32,
                width as i32,
                height as i32,
                0,
                glow::DEPTH_COMPONENT,
                glow::UNSIGNED_INT,
                glow::PixelUnpackData::Slice(None),
            );
            if gpu.caps.shadow_compare {
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
        }
        // Compared in the shader (ES 2.0): four NEAREST lookups make the bilinear weights
        // that LINEAR filtering gives a comparing sampler.
        let filter = if gpu.caps.shadow_compare {
            glow::LINEAR
        } else {
            glow::NEAREST
        };
        t.params(filter, filter, glow::CLAMP_TO_EDGE);
        Ok(t)
    }

    /// A shadow map where there are no depth textures ([`Caps::packed_shadow`]): RGBA8 holding
    /// the light's depth packed 8 bits a channel, read with NEAREST lookups and compared in the
    /// shader (filtering would blend the packed bytes, not the depths).
    pub(crate) fn packed_depth(gpu: &GpuRef, width: u32, height: u32) -> Result<Texture2d> {
        Texture2d::new(
            gpu,
            TextureFormat::Rgba8,
            width,
            height,
            Pixels::None,
            Sampling::NEAREST,
        )
    }

    /// Linear or nearest filtering (no mipmaps).
    pub fn set_filter(&self, linear: bool) {
        let f = if linear { glow::LINEAR } else { glow::NEAREST } as i32;
        let _bound = self.bound();
        // SAFETY: parameters on our own texture, bound above.
        unsafe {
            self.gpu
                .gl
                .tex_parameter_i32(glow::TEXTURE_2D, glow::TEXTURE_MIN_FILTER, f);
            self.gpu
                .gl
                .tex_parameter_i32(glow::TEXTURE_2D, glow::TEXTURE_MAG_FILTER, f);
        }
    }

    /// Level `level` as RGBA8 bytes (row 0 first), on desktop GL (glGetTexImage); None on ES,
    /// which cannot read a texture back. For tests of the mipmap chain.
    pub fn read_level(&self, level: u32) -> Option<(u32, u32, Vec<u8>)> {
        if self.gpu.caps.embedded {
            return None;
        }
        let (w, h) = ((self.width >> level).max(1), (self.height >> level).max(1));
        let mut buf = vec![0u8; (w * h * 4) as usize];
        // SAFETY: buf holds the level's w*h RGBA8 texels; PACK_ALIGNMENT 1 makes rows tight.
        unsafe {
            let gl = &self.gpu.gl;
            self.gpu.bind_texture_2d(Some(self.raw));
            gl.pixel_store_i32(glow::PACK_ALIGNMENT, 1);
            gl.get_tex_image(
                glow::TEXTURE_2D,
                level as i32,
                glow::RGBA,
                glow::UNSIGNED_BYTE,
                glow::PixelPackData::Slice(Some(&mut buf)),
            );
        }
        Some((w, h, buf))
    }

    /// Switches between comparison (for lighting) and raw depth reads (for `--show shadow-map`).
    pub fn set_compare(&self, on: bool) {
        if !self.gpu.caps.shadow_compare || self.gpu.caps.packed_shadow() {
            return;
        }
        let mode = if on {
            glow::COMPARE_REF_TO_TEXTURE
        } else {
            glow::NONE
        };
        let _bound = self.bound();
        // SAFETY: parameter on our own texture, bound above.
        unsafe {
            self.gpu.gl.tex_parameter_i32(
                glow::TEXTURE_2D,
                glow::TEXTURE_COMPARE_MODE,
                mode as i32,
            );
        }
    }

    /// Wrap modes (S, T) and filters (min, mag) as GL enums: a material's sampler, set after
    /// the upload. A mipmapped min filter needs the chain `Sampling::mipmaps` uploaded.
    pub fn set_sampler(&self, wrap: [u32; 2], min: u32, mag: u32) {
        let _bound = self.bound();
        // SAFETY: parameters of our own 2D texture, bound above.
        unsafe {
            let gl = &self.gpu.gl;
            gl.tex_parameter_i32(glow::TEXTURE_2D, glow::TEXTURE_WRAP_S, wrap[0] as i32);
            gl.tex_parameter_i32(glow::TEXTURE_2D, glow::TEXTURE_WRAP_T, wrap[1] as i32);
            gl.tex_parameter_i32(glow::TEXTURE_2D, glow::TEXTURE_MIN_FILTER, min as i32);
            gl.tex_parameter_i32(glow::TEXTURE_2D, glow::TEXTURE_MAG_FILTER, mag as i32);
        }
    }

    pub fn bind(&self, unit: u32) {
        self.gpu.active_unit(unit);
        self.gpu.bind_texture_2d(Some(self.raw));
    }

    /// Rebuilds the mip chain from level 0 (`glGenerateMipmap`, where the driver has it),
    /// binding the texture on `unit`.
    pub(crate) fn generate_mipmaps(&self, unit: u32) {
        if !self.gpu.caps.generate_mipmap {
            return;
        }
        // SAFETY: our own texture, level 0 allocated; the driver has glGenerateMipmap.
        unsafe {
            self.gpu.active_unit(unit);
            self.gpu.bind_texture_2d(Some(self.raw));
            self.gpu.gl.generate_mipmap(glow::TEXTURE_2D);
        }
    }

    /// Copies rectangle `[x, y, width, height]` of the bound read framebuffer's depth into
    /// level 0 at `to`: the shadow-map path for drivers without framebuffer objects.
    pub(crate) fn copy_from_framebuffer(&self, to: (u32, u32), [x, y, w, h]: [u32; 4]) {
        // SAFETY: the caller keeps the rectangle inside the framebuffer and, placed at
        // `to`, inside the texture.
        unsafe {
            self.gpu.bind_texture_2d(Some(self.raw));
            self.gpu.gl.copy_tex_sub_image_2d(
                glow::TEXTURE_2D,
                0,
                to.0 as i32,
                to.1 as i32,
                x as i32,
                y as i32,
                w as i32,
                h as i32,
            );
        }
    }
}

impl Texture2d {
    /// Copies the `self.width`×`self.height` rectangle at (x, y) of the bound read framebuffer
    /// into level 0 (glCopyTexSubImage2D, GL 1.1 / ES 2.0): how post-processing reads the frame
    /// on drivers without framebuffer objects.
    pub(crate) fn copy_region_from_framebuffer(&self, unit: u32, x: u32, y: u32) {
        // SAFETY: level 0 is allocated at this size; the caller keeps the rectangle inside
        // the (single-sampled) read framebuffer. The texture is bound on `unit` (where it is
        // read next, or a unit the next step rebinds), never on whatever unit was active.
        unsafe {
            self.gpu.active_unit(unit);
            self.gpu.bind_texture_2d(Some(self.raw));
            self.gpu.gl.copy_tex_sub_image_2d(
                glow::TEXTURE_2D,
                0,
                0,
                0,
                x as i32,
                y as i32,
                self.width as i32,
                self.height as i32,
            );
        }
    }
}

/// Puts back the 2D texture a unit had before [`Texture2d::create`].
struct Rebind {
    gpu: GpuRef,
    previous: Option<glow::Texture>,
}

impl Drop for Rebind {
    fn drop(&mut self) {
        // SAFETY: the previous binding is a live texture (or none) of this context: nothing
        // is deleted while a constructor runs.
        self.gpu.bind_texture_2d(self.previous);
    }
}

impl Drop for Texture2d {
    fn drop(&mut self) {
        // SAFETY: deleting our own texture once.
        unsafe { self.gpu.gl.delete_texture(self.raw) };
        self.gpu.forget_texture(self.raw);
        self.gpu.deleted();
    }
}
