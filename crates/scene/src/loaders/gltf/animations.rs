//! Reading a glTF file's animations and skins, every size bounded before it is read and
//! every value checked: a sampler whose keys are not finite or go back in time, or whose
//! output does not match its input, is dropped with a warning (the model still loads, in
//! its static pose); a skin whose joints lie outside the scene or whose inverse bind
//! matrices are not invertible is not applied, with a warning. Equal neighbouring key
//! times, which exporters write routinely (a step cut in two keys) and the specification
//! forbids, are played as three.js plays them (the later key holds from the shared time
//! on: [`crate::motion::sample`]), with one warning per animation.
use crate::loaders::gltf::accessor::{self as accessor, Buffers};
use crate::loaders::gltf::pointer::MaterialChannel;
use crate::motion::channels::{Animation, Channel, MaterialKeys, Skin, MAX_JOINTS};
use crate::motion::sample::{Interp, Keys};
use glam::{DMat4, Mat4};
use gltf::accessor::Dimensions as D;
use gltf::animation::{Interpolation, Property};
use gltf::json::validation::Checked;
use {crate::motion::AnimationInfo, crate::motion::Path};

/// Keys of one sampler beyond this are refused before they are read (a million keys is
/// over nine hours at 30 per second).
pub(crate) const MAX_KEYS: usize = 1 << 20;
/// Floats of all the samplers kept (64 MB): later animations are dropped with a warning.
/// Each channel also counts [`CHANNEL_COST`], so a file of millions of one-key channels is
/// bounded too.
pub(crate) const MAX_ANIMATION_FLOATS: usize = 1 << 24;
const CHANNEL_COST: usize = 32;

/// Every animation of the file, each with the channels that can be played, and the material
/// channels `pointed` (KHR_animation_pointer's, taken out of the document) that can.
/// `in_scene` marks the nodes of the drawn scene (channels of other nodes are dropped
/// silently: a file with several scenes animates them all).
pub(crate) fn animations(
    doc: &gltf::Document,
    (buffers, pointed): (&Buffers, &[MaterialChannel]),
    in_scene: &[bool],
    warn: &mut dyn FnMut(String),
) -> Vec<Animation> {
    let mut budget = MAX_ANIMATION_FLOATS;
    let mut out = Vec::new();
    for a in doc.animations() {
        let label = match a.name() {
            Some(n) => format!("animation {} \"{n}\"", a.index()),
            None => format!("animation {}", a.index()),
        };
        let mut channels = Vec::new();
        let mut repeats = Repeats::default();
        for (ci, c) in a.channels().enumerate() {
            let node = c.target().node().index();
            if !in_scene.get(node).copied().unwrap_or(false) {
                continue;
            }
            let json = &doc.as_json().animations[a.index()];
            match channel((&c, json), buffers, &mut budget) {
                Ok((property, keys)) => {
                    repeats.note(ci, &keys);
                    let path = match property {
                        Property::Translation => Path::Translation,
                        Property::Rotation => Path::Rotation,
                        Property::Scale => Path::Scale,
                        Property::MorphTargetWeights => Path::Weights,
                    };
                    channels.push(Channel {
                        node,
                        path,
                        keys: keys.into(),
                    });
                }
                Err(e) => warn(format!(
                    "{label} channel {ci}: {e}; the channel is not played"
                )),
            }
        }
        let json = &doc.as_json().animations[a.index()];
        let mut materials = Vec::new();
        for p in pointed.iter().filter(|p| p.animation == a.index()) {
            match material_keys(doc, (&a, json), p, buffers, &mut budget) {
                Ok(keys) => {
                    repeats.note(p.channel, &keys);
                    materials.push(MaterialKeys {
                        material: p.material,
                        property: p.property,
                        keys: keys.into(),
                    });
                }
                Err(e) => warn(format!(
                    "{label} channel {}: {e}; the channel is not played",
                    p.channel
                )),
            }
        }
        if let Some(w) = repeats.warning(&label) {
            warn(w);
        }
        let duration = (channels.iter().map(|c| &c.keys))
            .chain(materials.iter().map(|m| &m.keys))
            .map(|k| k.end())
            .fold(0.0f32, f32::max);
        out.push(Animation {
            info: AnimationInfo {
                name: a
                    .name()
                    .map_or_else(|| format!("animation {}", a.index()), str::to_string),
                duration: f64::from(duration),
                channels: channels.len() + materials.len(),
                together: false,
                default: false,
            },
            channels,
            materials,
        });
    }
    out
}

/// The channels of one animation whose keys repeat a time, for its one warning.
#[derive(Default)]
struct Repeats {
    count: usize,
    /// The first such channel, its key that repeats the time before it, and the time.
    first: Option<(usize, usize, f32)>,
}

impl Repeats {
    fn note(&mut self, channel: usize, keys: &Keys) {
        let Some(k) = keys.times.windows(2).position(|w| w[1] == w[0]) else {
            return;
        };
        self.count += 1;
        self.first
            .get_or_insert((channel, k + 1, keys.times[k + 1]));
    }

    fn warning(&self, label: &str) -> Option<String> {
        let (c, k, t) = self.first?;
        let n = self.count;
        let which = if n == 1 {
            format!("channel {c} has")
        } else {
            format!("{n} channels have")
        };
        Some(format!(
            "{label}: {which} equal neighbouring key times (channel {c}: key {k} at {t} \
             repeats key {}'s time), which glTF forbids; played as three.js plays them: \
             the earlier key is reached just before the shared time, the later one holds \
             from it on",
            k - 1
        ))
    }
}

/// One channel's keys, checked: the input is finite, non-decreasing scalar seconds;
/// the output has one value (three for CUBICSPLINE) per key of the property's width.
fn channel(
    (c, json): (&gltf::animation::Channel, &gltf::json::Animation),
    buffers: &Buffers,
    budget: &mut usize,
) -> Result<(Property, Keys), String> {
    let s = c.sampler();
    // Read from the JSON: the crate's accessors unwrap these and panic on a word glTF does
    // not define (found by the gltf fuzz target).
    let raw = json
        .channels
        .get(c.index())
        .map(|c| (c.target.path, c.sampler.value()));
    let Some((Checked::Valid(property), sampler)) = raw else {
        return Err("its target path is not translation, rotation, scale or weights".into());
    };
    let interpolation = json.samplers.get(sampler).map(|s| s.interpolation);
    let Some(Checked::Valid(interpolation)) = interpolation else {
        return Err("its interpolation is not STEP, LINEAR or CUBICSPLINE".into());
    };
    let kind = match property {
        Property::Translation | Property::Scale => Output::of(&[D::Vec3]),
        Property::Rotation => Output {
            rotation: true,
            ..Output::of(&[D::Vec4])
        },
        Property::MorphTargetWeights => Output {
            many: true,
            ..Output::of(&[D::Scalar])
        },
    };
    Ok((property, keys(&s, interpolation, kind, buffers, budget)?))
}

/// What a sampler's output values are: quaternions (interpolated on the sphere and
/// normalised) or not, their accessor types, and whether a key holds several (morph
/// weights: one per target).
#[derive(Clone, Copy)]
struct Output {
    rotation: bool,
    dims: &'static [D],
    many: bool,
}

impl Output {
    fn of(dims: &'static [D]) -> Output {
        Output {
            rotation: false,
            dims,
            many: false,
        }
    }
}

/// The keys of sampler `s` with `interpolation` and output values of `kind`, checked (see
/// [`channel`]).
fn keys(
    s: &gltf::animation::Sampler,
    interpolation: Interpolation,
    kind: Output,
    buffers: &Buffers,
    budget: &mut usize,
) -> Result<Keys, String> {
    let (input, output) = (s.input(), s.output());
    let n = input.count();
    if n == 0 {
        return Err("the sampler has no keys".into());
    }
    if n > MAX_KEYS {
        return Err(format!(
            "{n} keys, more than glview reads ({MAX_KEYS}); refused before reading them"
        ));
    }
    let interp = match interpolation {
        Interpolation::Step => Interp::Step,
        Interpolation::Linear => Interp::Linear,
        Interpolation::CubicSpline => Interp::Cubic,
    };
    let per = if interp == Interp::Cubic { 3 } else { 1 };
    let m = output.count();
    if m == 0 || m % (n * per) != 0 {
        return Err(format!(
            "{m} output values for {n} keys{}",
            if per == 3 {
                " (CUBICSPLINE needs three per key)"
            } else {
                ""
            }
        ));
    }
    let Output {
        rotation,
        dims,
        many: weights,
    } = kind;
    if !weights && m != n * per {
        return Err(format!("{m} output values for {n} keys"));
    }
    let floats = m.saturating_mul(output.dimensions().multiplicity());
    let cost = floats.saturating_add(n).saturating_add(CHANNEL_COST);
    if cost > *budget {
        return Err(format!(
            "the file's animations hold more than {MAX_ANIMATION_FLOATS} values"
        ));
    }
    let (_, times) = accessor::read_f32(&input, buffers, &[D::Scalar])?;
    if let Some(k) = times.iter().position(|t| !t.is_finite()) {
        return Err(format!("key {k}'s time is not finite"));
    }
    if let Some(k) = times.windows(2).position(|w| w[1] < w[0]) {
        return Err(format!(
            "key times go back ({} then {} at key {})",
            times[k],
            times[k + 1],
            k + 1
        ));
    }
    let (width, values) = accessor::read_f32(&output, buffers, dims)?;
    if values.iter().any(|v| !v.is_finite()) {
        return Err("an output value is not finite".into());
    }
    *budget -= cost;
    let keys = Keys {
        // Weights: one per target, however many the file's keys hold.
        width: if weights { m / (n * per) } else { width },
        times,
        values,
        interp,
        rotation,
    };
    Ok(keys)
}

/// The keys of a KHR_animation_pointer channel `p` setting a material factor, checked as a
/// node channel's are (one value of the factor's width per key).
fn material_keys(
    doc: &gltf::Document,
    (a, json): (&gltf::Animation, &gltf::json::Animation),
    p: &MaterialChannel,
    buffers: &Buffers,
    budget: &mut usize,
) -> Result<Keys, String> {
    if p.material >= doc.materials().len() {
        return Err(format!("material {} does not exist", p.material));
    }
    let Some(s) = a.samplers().nth(p.sampler) else {
        return Err(format!("sampler {} does not exist", p.sampler));
    };
    let interpolation = json.samplers.get(p.sampler).map(|s| s.interpolation);
    let Some(Checked::Valid(interpolation)) = interpolation else {
        return Err("its interpolation is not STEP, LINEAR or CUBICSPLINE".into());
    };
    let dims: &'static [D] = match p.property.width() {
        4 => &[D::Vec4],
        3 => &[D::Vec3],
        _ => &[D::Scalar],
    };
    keys(&s, interpolation, Output::of(dims), buffers, budget)
}

/// Every skin of the file; None for a skin that cannot be applied (with a warning).
pub(crate) fn skins(
    doc: &gltf::Document,
    buffers: &Buffers,
    in_scene: &[bool],
    warn: &mut dyn FnMut(String),
) -> Vec<Option<Skin>> {
    doc.skins()
        .map(|s| {
            skin(&s, buffers, in_scene)
                .map_err(|e| warn(format!("skin {}: {e}; drawn unskinned", s.index())))
                .ok()
        })
        .collect()
}

fn skin(s: &gltf::Skin, buffers: &Buffers, in_scene: &[bool]) -> Result<Skin, String> {
    let joints: Vec<usize> = s.joints().map(|j| j.index()).collect();
    if joints.is_empty() || joints.len() > MAX_JOINTS {
        return Err(format!(
            "{} joints (glview applies 1 to {MAX_JOINTS})",
            joints.len()
        ));
    }
    if let Some(j) = joints
        .iter()
        .find(|&&j| !in_scene.get(j).copied().unwrap_or(false))
    {
        return Err(format!("joint node {j} is not in the drawn scene"));
    }
    let inverse_bind = match s.inverse_bind_matrices() {
        None => vec![DMat4::IDENTITY; joints.len()],
        Some(a) => {
            if a.count() < joints.len() || a.count() > MAX_JOINTS {
                return Err(format!(
                    "{} inverse bind matrices for {} joints",
                    a.count(),
                    joints.len()
                ));
            }
            let (_, v) = accessor::read_f32(&a, buffers, &[D::Mat4])?;
            let m: Vec<DMat4> = v
                .chunks_exact(16)
                .take(joints.len())
                .map(|c| Mat4::from_cols_slice(c).as_dmat4())
                .collect();
            // A zero scale is as singular as a NaN: nothing it binds can be posed.
            if let Some(k) = m
                .iter()
                .position(|m| m.determinant() == 0.0 || !m.inverse().is_finite())
            {
                return Err(format!(
                    "the inverse bind matrix of joint {k} is not invertible"
                ));
            }
            m
        }
    };
    Ok(Skin {
        joints,
        inverse_bind,
    })
}
