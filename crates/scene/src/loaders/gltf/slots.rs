//! A texture info as the loader reads it, for the core slots (the `gltf` crate's types) and
//! for the extensions read from raw JSON alike: its sampler, image, UV set (a
//! KHR_texture_transform's texCoord overriding the slot's), transform and scale, and the
//! number readers the extensions share. Its own file, so the material and the extensions
//! that both read slots do not import each other.
use crate::model::texture_slot::{self as mm, Slot, TexTransform};
use crate::report::material::SlotFacts;
use gltf::texture::{MagFilter, MinFilter, WrappingMode};
use serde_json::Value;

fn wrap(w: WrappingMode) -> mm::Wrap {
    match w {
        WrappingMode::ClampToEdge => mm::Wrap::ClampToEdge,
        WrappingMode::MirroredRepeat => mm::Wrap::MirroredRepeat,
        WrappingMode::Repeat => mm::Wrap::Repeat,
    }
}

fn min_filter(f: MinFilter) -> mm::Filter {
    match f {
        MinFilter::Nearest => mm::Filter::Nearest,
        MinFilter::Linear => mm::Filter::Linear,
        MinFilter::NearestMipmapNearest => mm::Filter::NearestMipmapNearest,
        MinFilter::LinearMipmapNearest => mm::Filter::LinearMipmapNearest,
        MinFilter::NearestMipmapLinear => mm::Filter::NearestMipmapLinear,
        MinFilter::LinearMipmapLinear => mm::Filter::LinearMipmapLinear,
    }
}

/// The slot's facts as the file gives them (its `--check` line is made from these whether or
/// not the image decodes).
pub(crate) fn facts(
    s: Slot,
    tex: gltf::Texture,
    tex_coord: u32,
    transform: Option<gltf::texture::TextureTransform>,
    scale: f32,
) -> SlotFacts {
    let smp = tex.sampler();
    SlotFacts {
        slot: s,
        image: tex.source().index(),
        loaded: false,
        sampler: mm::Sampler {
            wrap_s: wrap(smp.wrap_s()),
            wrap_t: wrap(smp.wrap_t()),
            mag: match smp.mag_filter() {
                Some(MagFilter::Nearest) => mm::Filter::Nearest,
                _ => mm::Filter::Linear,
            },
            min: smp.min_filter().map(min_filter),
        },
        uv_set: transform
            .as_ref()
            .and_then(|t| t.tex_coord())
            .unwrap_or(tex_coord),
        transform: transform.map(|t| mm::TexTransform {
            offset: t.offset(),
            rotation: t.rotation(),
            scale: t.scale(),
        }),
        scale,
    }
}

pub(crate) fn num(v: &Value, key: &str, default: f32) -> f32 {
    v.get(key)
        .and_then(Value::as_f64)
        .filter(|x| x.is_finite())
        .map_or(default, |x| x as f32)
}

/// An array of exactly `N` finite numbers (its non-numbers skipped), else `default`.
pub(crate) fn floats<const N: usize>(v: &Value, key: &str, default: [f32; N]) -> [f32; N] {
    let Some(a) = v.get(key).and_then(Value::as_array) else {
        return default;
    };
    let c: Vec<f32> = a
        .iter()
        .filter_map(Value::as_f64)
        .map(|x| x as f32)
        .collect();
    <[f32; N]>::try_from(c)
        .ok()
        .filter(|c| c.iter().all(|x| x.is_finite()))
        .unwrap_or(default)
}

/// A texture info's facts: the texture's sampler and image, the UV set (the transform's
/// texCoord overrides), the transform and the normal scale.
pub(crate) fn texture_info(doc: &gltf::Document, slot: Slot, info: &Value) -> Option<SlotFacts> {
    let index = info.get("index")?.as_u64()? as usize;
    let tex = doc.textures().nth(index)?;
    let tex_coord = info.get("texCoord").and_then(Value::as_u64).unwrap_or(0) as u32;
    let xf = info
        .get("extensions")
        .and_then(|e| e.get("KHR_texture_transform"));
    let mut f = facts(slot, tex, tex_coord, None, num(info, "scale", 1.0));
    if let Some(x) = xf {
        f.transform = Some(TexTransform {
            offset: floats(x, "offset", [0.0, 0.0]),
            rotation: num(x, "rotation", 0.0),
            scale: floats(x, "scale", [1.0, 1.0]),
        });
        if let Some(t) = x.get("texCoord").and_then(Value::as_u64) {
            f.uv_set = t as u32;
        }
    }
    Some(f)
}
