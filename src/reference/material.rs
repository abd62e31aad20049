//! The material ([`crate::scene::model::material`]) read on the CPU the way the shaders
//! read it (`material.glsl`, `normalmap.glsl`, `lit.frag`, `pbr.frag`): each slot's UV set and
//! `KHR_texture_transform`, its sampler's wrap modes and filter, MASK cut-outs, BLEND alpha
//! from the base colour texture, single-sided culling, tangent-space normal maps.
//!
//! Level 0 only, with the magnification filter (a `*_MIPMAP_*` minification filter reads
//! level 0 with its own nearest or linear rule): where the GPU minifies a texture its mipmaps
//! differ from this, as for the legacy tier's diffuse map before. Colour textures are decoded
//! per texel before filtering when `srgb`, as an sRGB texture format does.
use super::bvh::Hit;
use super::Context;
use crate::pbr::srgb_decode;
use crate::scene::model::material::AlphaMode;
use crate::scene::model::texture_slot::{Filter, Sampler, Slot, Wrap};
use crate::scene::{Material, Mesh, Texture};
use glam::{DVec2, DVec3, DVec4};

/// A hit's triangle corners and barycentric weights: what attributes are interpolated from.
pub(crate) struct Corners<'a> {
    pub(crate) mesh: &'a Mesh,
    pub(crate) idx: [usize; 3],
    pub(crate) w: [f64; 3],
    /// The file's tangents, or those the upload would generate (empty: none).
    tangents: &'a [[f32; 4]],
}

impl<'a> Corners<'a> {
    pub(crate) fn new(ctx: &'a Context, hit: &Hit) -> Self {
        let mesh = &ctx.scene.meshes[hit.tri.mesh as usize];
        let base = 3 * hit.tri.tri as usize;
        let generated = &ctx.generated_tangents[hit.tri.mesh as usize];
        Corners {
            mesh,
            idx: std::array::from_fn(|k| mesh.indices[base + k] as usize),
            w: [1.0 - hit.u - hit.v, hit.u, hit.v],
            tangents: if generated.is_empty() {
                &mesh.tangents
            } else {
                generated
            },
        }
    }

    /// A point sprite's: no triangle, `mesh` (one vertex, no UVs) reads no map, as the GPU
    /// draws points without texture coordinates.
    pub(crate) fn at_point(mesh: &'a Mesh) -> Self {
        Corners {
            mesh,
            idx: [0; 3],
            w: [1.0, 0.0, 0.0],
            tangents: &[],
        }
    }

    /// UV set `set` (set 1 falls back to set 0 where the mesh has none, as `SLOT_UV` does).
    pub(crate) fn uv(&self, set: u32) -> DVec2 {
        let uv1 = set == 1 && self.mesh.uv1.len() == self.mesh.vertices.len();
        (0..3).fold(DVec2::ZERO, |a, k| {
            let i = self.idx[k];
            let uv = if uv1 {
                self.mesh.uv1[i]
            } else {
                self.mesh.vertices[i].uv
            };
            a + self.w[k] * DVec2::from(uv.map(f64::from))
        })
    }

    /// The interpolated tangent (xyz, handedness w), where the mesh has tangents.
    pub(crate) fn tangent(&self) -> Option<DVec4> {
        (self.tangents.len() == self.mesh.vertices.len()).then(|| {
            (0..3).fold(DVec4::ZERO, |a, k| {
                a + self.w[k] * DVec4::from(self.tangents[self.idx[k]].map(f64::from))
            })
        })
    }
}

/// The UV slot `slot` reads: its set, through its transform (`uSlotXf`).
pub(crate) fn slot_uv(model: &Material, slot: Slot, c: &Corners) -> DVec2 {
    let Some(s) = model.slot(slot) else {
        return c.uv(0);
    };
    let uv = c.uv(s.uv_set);
    match s.transform {
        None => uv,
        Some(x) => {
            let (sin, cos) = f64::from(x.rotation).sin_cos();
            let (u, v) = (uv.x * f64::from(x.scale[0]), uv.y * f64::from(x.scale[1]));
            DVec2::new(
                cos * u + sin * v + f64::from(x.offset[0]),
                -sin * u + cos * v + f64::from(x.offset[1]),
            )
        }
    }
}

/// The sampler a slot is read with (the viewer's repeat/linear where the file has none).
pub(crate) fn slot_sampler(model: &Material, slot: Slot) -> Sampler {
    model.slot(slot).map(|s| s.sampler).unwrap_or_default()
}

/// GL's wrap of an integer texel coordinate `i` into [0, n).
fn wrap(mode: Wrap, i: i64, n: i64) -> i64 {
    match mode {
        Wrap::Repeat => i.rem_euclid(n),
        Wrap::ClampToEdge => i.clamp(0, n - 1),
        Wrap::MirroredRepeat => {
            let m = i.rem_euclid(2 * n);
            if m < n {
                m
            } else {
                2 * n - 1 - m
            }
        }
    }
}

/// Whether `f` (as a magnification filter, or read at level 0) is linear.
fn is_linear(f: Filter) -> bool {
    matches!(
        f,
        Filter::Linear | Filter::LinearMipmapNearest | Filter::LinearMipmapLinear
    )
}

/// `t` at `uv` with sampler `s` (RGBA in [0, 1]; rgb decoded from sRGB per texel when `srgb`).
/// Row 0 at v = 0, texel centres at (i + 0.5) / size, as GL reads an uploaded image.
pub(crate) fn sample(t: &Texture, s: &Sampler, uv: DVec2, srgb: bool) -> DVec4 {
    if t.width == 0 || t.height == 0 || !uv.is_finite() {
        return DVec4::ONE;
    }
    let (w, h) = (i64::from(t.width), i64::from(t.height));
    // Keep the integer part small before it becomes an index: a huge u would lose its
    // fraction in the float-to-integer step. Every wrap mode has period 2n, so u mod 2
    // changes no texel (clamp-to-edge is decided by the sign and the edge, kept too).
    let reduce = |x: f64, n: i64, mode: Wrap| {
        if mode == Wrap::ClampToEdge {
            x.clamp(-1.0, n as f64 + 1.0)
        } else {
            x.rem_euclid(2.0 * n as f64)
        }
    };
    let texel = |i: i64, j: i64| {
        let (i, j) = (wrap(s.wrap_s, i, w), wrap(s.wrap_t, j, h));
        let k = 4 * (j * w + i) as usize;
        let c = |x: u8| f64::from(x) / 255.0;
        let rgb = DVec3::new(c(t.rgba[k]), c(t.rgba[k + 1]), c(t.rgba[k + 2]));
        let rgb = if srgb { rgb.map(srgb_decode) } else { rgb };
        rgb.extend(c(t.rgba[k + 3]))
    };
    if !is_linear(s.mag) {
        let x = reduce(uv.x * w as f64, w, s.wrap_s).floor() as i64;
        let y = reduce(uv.y * h as f64, h, s.wrap_t).floor() as i64;
        return texel(x, y);
    }
    let x = reduce(uv.x * w as f64 - 0.5, w, s.wrap_s);
    let y = reduce(uv.y * h as f64 - 0.5, h, s.wrap_t);
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let (i, j) = (x0 as i64, y0 as i64);
    let top = texel(i, j) * (1.0 - fx) + texel(i + 1, j) * fx;
    let bottom = texel(i, j + 1) * (1.0 - fx) + texel(i + 1, j + 1) * fx;
    top * (1.0 - fy) + bottom * fy
}

/// A slot's texture at the hit, or None where the material has no image there or the mesh
/// no UVs (the GPU then leaves the slot's map out of the program).
pub(crate) fn read(
    m: &Material,
    t: Option<&Texture>,
    slot: Slot,
    c: &Corners,
    srgb: bool,
) -> Option<DVec4> {
    let t = t.filter(|_| c.mesh.has_uv)?;
    Some(sample(t, &slot_sampler(m, slot), slot_uv(m, slot, c), srgb))
}

/// The base colour texture's alpha times the vertex colour's (glTF COLOR_0) times the
/// factor's: what MASK tests; and the first two alone, which multiply BLEND's opacity.
pub(crate) fn base_alpha(m: &Material, c: &Corners) -> (f64, f64) {
    let image = m.image(Slot::BaseColor).map(|t| &**t);
    let mut tex = read(m, image, Slot::BaseColor, c, false).map_or(1.0, |t| t.w);
    let a = &c.mesh.color_alpha;
    if a.len() == c.mesh.vertices.len() && c.mesh.colors.len() == a.len() {
        tex *= (0..3).map(|k| c.w[k] * f64::from(a[c.idx[k]])).sum::<f64>();
    }
    (f64::from(m.base_alpha) * tex, tex)
}

/// Whether the rasterizer draws this hit at all: single-sided materials show no back faces
/// (`facing` is the ray's direction for a primary ray, towards the viewer), MASK cut-outs are
/// discarded. Both hold in the shadow pass too, where the light is the viewer.
pub(crate) fn drawn(ctx: &Context, hit: &Hit, dir: DVec3) -> bool {
    let mesh = &ctx.scene.meshes[hit.tri.mesh as usize];
    let Some(m) = ctx.scene.materials.get(mesh.material) else {
        return true;
    };
    if !m.double_sided {
        let base = 3 * hit.tri.tri as usize;
        let p = |k: usize| {
            DVec3::from(
                mesh.vertices[mesh.indices[base + k] as usize]
                    .position
                    .map(f64::from),
            )
        };
        let ng = (p(1) - p(0)).cross(p(2) - p(0));
        if ng.dot(dir) >= 0.0 {
            return false;
        }
    }
    match m.alpha_mode {
        AlphaMode::Mask(cutoff) => base_alpha(m, &Corners::new(ctx, hit)).0 >= f64::from(cutoff),
        _ => true,
    }
}

/// `glviewNormalMap`: the map's normal (xy scaled) in the frame of the interpolated tangent,
/// Gram-Schmidt against `n`, bitangent cross(n, t)·w; tangent and bitangent flip with the
/// normal on back faces. `n` is the unit normal already turned to the viewer's side.
pub(crate) fn normal_map(m: &Material, c: &Corners, n: DVec3, front: bool) -> DVec3 {
    normal_map_slot(m, Slot::Normal, m.normal_scale, c, n, front)
}

/// [`normal_map`] with the map of slot `slot` and its scale (the clearcoat's normal map).
pub(crate) fn normal_map_slot(
    m: &Material,
    slot: Slot,
    scale: f32,
    c: &Corners,
    n: DVec3,
    front: bool,
) -> DVec3 {
    let (Some(t), Some(tan)) = (
        read(m, m.image(slot).map(|t| &**t), slot, c, false),
        c.tangent(),
    ) else {
        return n;
    };
    let side = if front { 1.0 } else { -1.0 };
    let tv = tan.truncate() * side;
    let tt = tv - n * n.dot(tv);
    let tl = tt.length();
    if tl <= 0.0 {
        return n;
    }
    let tt = tt / tl;
    let b = n.cross(tt) * if tan.w < 0.0 { -side } else { side };
    let mut mn = t.truncate() * 2.0 - DVec3::ONE;
    let scale = f64::from(scale);
    mn.x *= scale;
    mn.y *= scale;
    let r = tt * mn.x + b * mn.y + n * mn.z;
    let len = r.length();
    if len > 0.0 {
        r / len
    } else {
        n
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ramp() -> Texture {
        // 4×2: red = x·60, green = y·100, alpha 255.
        let rgba = (0..8u8)
            .flat_map(|i| [(i % 4) * 60, (i / 4) * 100, 0, 255])
            .collect();
        Texture {
            path: "ramp".into(),
            image: None,
            width: 4,
            height: 2,
            rgba,
        }
    }

    fn nearest(ws: Wrap, wt: Wrap) -> Sampler {
        Sampler {
            wrap_s: ws,
            wrap_t: wt,
            mag: Filter::Nearest,
            min: Some(Filter::Nearest),
        }
    }

    #[test]
    fn wrap_modes_pick_the_texel_gl_picks() {
        let t = ramp();
        let red = |mode: Wrap, u: f64| {
            (sample(&t, &nearest(mode, Wrap::Repeat), DVec2::new(u, 0.25), false).x * 255.0).round()
                as u32
        };
        // Texel x = floor(u·4): u = 1.1 is x 4, which repeat makes 0, mirror 3, clamp 3;
        // u = -0.1 is x -1: repeat 3, mirror 0, clamp 0; u = 2.3 is x 9: repeat 1, mirror 1.
        assert_eq!(red(Wrap::Repeat, 1.1), 0);
        assert_eq!(red(Wrap::MirroredRepeat, 1.1), 180);
        assert_eq!(red(Wrap::ClampToEdge, 1.1), 180);
        assert_eq!(red(Wrap::Repeat, -0.1), 180);
        assert_eq!(red(Wrap::MirroredRepeat, -0.1), 0);
        assert_eq!(red(Wrap::ClampToEdge, -0.1), 0);
        assert_eq!(red(Wrap::Repeat, 2.3), 60);
        assert_eq!(red(Wrap::MirroredRepeat, 2.3), 60);
        assert_eq!(red(Wrap::MirroredRepeat, 1.6), 60);
        // A huge coordinate keeps its fraction (u mod 2 first): 1e9 + 0.3 is texel 1.
        assert_eq!(red(Wrap::Repeat, 1e9 + 0.3), 60);
    }

    #[test]
    fn linear_filter_blends_neighbours_and_clamps_at_edges() {
        let t = ramp();
        let s = |ws: Wrap| Sampler {
            wrap_s: ws,
            wrap_t: Wrap::ClampToEdge,
            mag: Filter::Linear,
            min: None,
        };
        let red = |ws: Wrap, u: f64| sample(&t, &s(ws), DVec2::new(u, 0.25), false).x * 255.0;
        // Halfway between the centres of texels 1 and 2 (u = 0.5): (60 + 120) / 2.
        assert!((red(Wrap::Repeat, 0.5) - 90.0).abs() < 1e-9);
        // At u = 0 repeat blends texel 3 and 0 equally; clamp reads texel 0 alone.
        assert!((red(Wrap::Repeat, 0.0) - 90.0).abs() < 1e-9);
        assert!(red(Wrap::ClampToEdge, 0.0).abs() < 1e-9);
        // Green at v = 0.5 (between rows 0 and 1) with clamp: 50.
        let g = sample(&t, &s(Wrap::Repeat), DVec2::new(0.125, 0.5), false).y * 255.0;
        assert!((g - 50.0).abs() < 1e-9, "{g}");
    }

    #[test]
    fn srgb_is_decoded_per_texel_before_filtering() {
        let t = ramp();
        let s = Sampler {
            wrap_s: Wrap::ClampToEdge,
            wrap_t: Wrap::ClampToEdge,
            mag: Filter::Linear,
            min: None,
        };
        let r = sample(&t, &s, DVec2::new(0.5, 0.25), true).x;
        let want = (srgb_decode(60.0 / 255.0) + srgb_decode(120.0 / 255.0)) / 2.0;
        assert!((r - want).abs() < 1e-12, "{r} {want}");
    }
}
