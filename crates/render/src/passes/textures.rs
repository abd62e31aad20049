//! The material textures both tiers draw with, made on first use and kept for the scene: one
//! GL texture per image (a file, or a glTF container's image index), colour encoding (sRGB
//! or linear) and sampler. A texture the legacy and PBR tiers read the same way — a normal
//! map — is uploaded once; a base colour is an sRGB texture for PBR and a plain one for
//! the legacy tier, which works in display values.
use crate::gpu::texture::{Pixels, Sampling, Texture2d, TextureFormat};
use crate::gpu::GpuRef;
use crate::scene::model::texture_slot::Sampler;
use crate::scene::Texture;
use crate::Result;
use std::path::PathBuf;

#[derive(Clone, Debug, PartialEq)]
struct Key {
    path: PathBuf,
    image: Option<usize>,
    srgb: bool,
    sampler: Sampler,
}

#[derive(Default)]
pub(crate) struct TextureTable {
    keys: Vec<Key>,
    textures: Vec<Texture2d>,
}

/// A mipmapped 8-bit texture of `t` (sRGB where asked and supported), fitted to the driver's
/// size limit, its cost recorded for `--stats`.
pub(crate) fn upload(gpu: &GpuRef, t: &Texture, srgb: bool) -> Result<Texture2d> {
    let format = if srgb && TextureFormat::Srgb8A8.supported(&gpu.caps) {
        TextureFormat::Srgb8A8
    } else {
        TextureFormat::Rgba8
    };
    let s = Sampling {
        linear: true,
        mipmaps: true,
        repeat: true,
    };
    super::upload::timed(gpu, t, |w, h, data| {
        Texture2d::new(gpu, format, w, h, Pixels::U8(data), s)
    })
}

impl TextureTable {
    /// The index of `t` read as `srgb` with `sampler`, uploading it the first time.
    pub(crate) fn get(
        &mut self,
        gpu: &GpuRef,
        t: &Texture,
        srgb: bool,
        sampler: &Sampler,
    ) -> Result<usize> {
        let key = Key {
            path: t.path.clone(),
            image: t.image,
            srgb,
            sampler: *sampler,
        };
        if let Some(i) = self.keys.iter().position(|k| *k == key) {
            return Ok(i);
        }
        let tex = upload(gpu, t, srgb)?;
        super::slots::apply_sampler(&tex, sampler);
        self.keys.push(key);
        self.textures.push(tex);
        Ok(self.textures.len() - 1)
    }

    pub(crate) fn texture(&self, i: usize) -> &Texture2d {
        &self.textures[i]
    }
}
