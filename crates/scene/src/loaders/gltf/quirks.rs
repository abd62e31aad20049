//! What real exporters write that glTF forbids, read as three.js and model-viewer read it:
//! each tolerated quirk is changed in the parsed JSON before the document is used, and each
//! kind is named in one warning (its first place and how many more), saying what was
//! assumed. docs/gltf/quirks.md lists them, each with its generated file and test. Quirks
//! that only the reader meets later (equal key times, Draco counts, short buffers) are
//! tolerated where they are read. Whatever is left after the repairs is refused as before,
//! with the validator's message.
use gltf::json::validation::Error as E;
use gltf::json::{Index, Root};
use serde_json::Value;

/// The kinds of quirk glview tolerates, each with its warning's words.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) enum Kind {
    ZeroStride,
    ViewTarget,
    NoMinMax,
    SamplerMissing,
    SourceMissing,
    TextureMissing,
    MaterialMissing,
    SceneMissing,
    NoScenes,
    ChildMissing,
    ChannelMissing,
    ChannelWithoutNode,
    Interpolation,
    UnknownAttribute,
}

impl Kind {
    /// What was off and what glview assumed (after "PLACE: ").
    fn words(self) -> &'static str {
        match self {
            Kind::ZeroStride => {
                "byteStride 0, which glTF forbids (4 to 252); read as tightly packed, as \
                 three.js reads it"
            }
            Kind::ViewTarget => "a target glTF does not define; ignored (glview does not need it)",
            Kind::NoMinMax => {
                "POSITION accessor without min and max, which glTF requires; bounds are \
                 taken from the positions, as three.js does"
            }
            Kind::SamplerMissing => {
                "sampler index names no sampler; the default sampler (repeat, trilinear) is \
                 used, as three.js does"
            }
            Kind::SourceMissing => {
                "texture without an image glview can read; materials using it render \
                 without it"
            }
            Kind::TextureMissing => {
                "texture index names no texture; the material renders without that map"
            }
            Kind::MaterialMissing => {
                "material index names no material; drawn with the default material"
            }
            Kind::SceneMissing => "the default scene index names no scene; scene 0 is drawn",
            Kind::NoScenes => "no scenes; every root node is drawn",
            Kind::ChildMissing => "child index names no node; ignored",
            Kind::ChannelMissing => {
                "channel's sampler or node index names nothing; the channel is not played"
            }
            Kind::ChannelWithoutNode => {
                "channel without a node (glTF says to ignore it unless an extension names \
                 its target); not played"
            }
            Kind::Interpolation => {
                "interpolation other than STEP, LINEAR or CUBICSPLINE; played as LINEAR, as \
                 three.js plays it"
            }
            Kind::UnknownAttribute => {
                "attribute names glTF does not define (application attributes start with \
                 an underscore); ignored"
            }
        }
    }
}

/// The quirks found in one file, by kind, in the order first met.
#[derive(Default, Debug)]
pub(crate) struct Found {
    kinds: Vec<(Kind, String, usize)>,
    /// Every place noted, so a place validated again is counted once.
    seen: std::collections::HashSet<(Kind, String)>,
    /// Images added in place of textures' missing ones: drawn as absent, without a warning
    /// of their own ([`Kind::SourceMissing`] says it).
    pub(crate) placeholders: Vec<usize>,
}

impl Found {
    pub(crate) fn note(&mut self, kind: Kind, place: impl Into<String>) {
        let place = place.into();
        if !self.seen.insert((kind, place.clone())) {
            return;
        }
        match self.kinds.iter_mut().find(|k| k.0 == kind) {
            Some(k) => k.2 += 1,
            None => self.kinds.push((kind, place, 1)),
        }
    }

    /// One warning per kind: "PLACE (and N more): WORDS".
    pub(crate) fn warnings(&self) -> Vec<String> {
        self.kinds
            .iter()
            .map(|(kind, place, n)| match n {
                1 => format!("{place}: {}", kind.words()),
                n => format!("{place} and {} more: {}", n - 1, kind.words()),
            })
            .collect()
    }
}

/// Quirks of the parsed JSON value, for a file whose JSON the crate's types refuse: a
/// channel whose target names no node (valid glTF where an extension names the target;
/// the crate requires a node) is taken out.
pub(crate) fn tolerate_value(root: &mut Value, found: &mut Found) {
    let Some(animations) = root.get_mut("animations").and_then(Value::as_array_mut) else {
        return;
    };
    for (ai, a) in animations.iter_mut().enumerate() {
        let Some(channels) = a.get_mut("channels").and_then(Value::as_array_mut) else {
            continue;
        };
        let mut ci = 0;
        channels.retain(|c| {
            ci += 1;
            let keep = c.get("target").is_none_or(|t| t.get("node").is_some());
            if !keep {
                found.note(
                    Kind::ChannelWithoutNode,
                    format!("animations[{ai}].channels[{}]", ci - 1),
                );
            }
            keep
        });
    }
}

/// Quirks fixed before validation, which the validator would not name precisely enough.
pub(crate) fn tolerate(json: &mut Root, found: &mut Found) {
    for (i, v) in json.buffer_views.iter_mut().enumerate() {
        if v.byte_stride.is_some_and(|s| s.0 == 0) {
            v.byte_stride = None;
            found.note(Kind::ZeroStride, format!("bufferViews[{i}]"));
        }
    }
    // The crate's validator does not check a channel's node (its accessor would panic).
    let nodes = json.nodes.len();
    for (ai, a) in json.animations.iter_mut().enumerate() {
        let samplers = a.samplers.len();
        let mut ci = 0;
        a.channels.retain(|c| {
            ci += 1;
            let keep = c.sampler.value() < samplers && c.target.node.value() < nodes;
            if !keep {
                found.note(
                    Kind::ChannelMissing,
                    format!("animations[{ai}].channels[{}]", ci - 1),
                );
            }
            keep
        });
    }
    if json.scenes.is_empty() && !json.nodes.is_empty() {
        let mut child = vec![false; json.nodes.len()];
        for n in &json.nodes {
            for c in n.children.iter().flatten() {
                if let Some(x) = child.get_mut(c.value()) {
                    *x = true;
                }
            }
        }
        let roots = (0..json.nodes.len()).filter(|&i| !child[i]);
        json.scenes.push(gltf::json::Scene {
            extensions: None,
            extras: Default::default(),
            name: None,
            nodes: roots.map(|i| Index::new(i as u32)).collect(),
        });
        json.scene = Some(Index::new(0));
        found.note(Kind::NoScenes, "scenes");
    }
}

/// The place of a validation error, split: `meshes[0].primitives[1].material` is
/// `[Name("meshes"), At(0), Name("primitives"), At(1), Name("material")]`; a map key
/// (`attributes["POSITION"]`) is a `Key`.
#[derive(Debug, PartialEq)]
enum Part<'a> {
    Name(&'a str),
    At(usize),
    Key(&'a str),
}

fn parts(path: &str) -> Vec<Part<'_>> {
    let mut out = Vec::new();
    for seg in path.split('.') {
        let (name, mut rest) = seg.split_once('[').map_or((seg, ""), |(n, r)| (n, r));
        if !name.is_empty() {
            out.push(Part::Name(name));
        }
        while let Some((inside, after)) = rest.split_once(']') {
            match inside.parse() {
                Ok(i) => out.push(Part::At(i)),
                Err(_) => out.push(Part::Key(inside.trim_matches('"'))),
            }
            rest = after.strip_prefix('[').unwrap_or(after);
        }
    }
    out
}

/// What the repair of one validation error did.
pub(crate) enum Repair {
    /// The JSON was changed; validate again.
    Fixed,
    /// Nothing to change: glview does not need what is missing.
    Ignored,
}

/// Repairs the error `error` at `path` in `json` if it is a tolerated quirk, noting it.
pub(crate) fn repair(json: &mut Root, path: &str, error: &E, found: &mut Found) -> Option<Repair> {
    use Part::{At, Key, Name};
    let out = matches!(error, E::IndexOutOfBounds);
    let p = parts(path);
    let fixed = |found: &mut Found, kind| {
        found.note(kind, path);
        Some(Repair::Fixed)
    };
    match p.as_slice() {
        [Name("bufferViews"), At(v), Name("target")] if matches!(error, E::Invalid) => {
            json.buffer_views.get_mut(*v)?.target = None;
            fixed(found, Kind::ViewTarget)
        }
        [Name("meshes"), At(_), Name("primitives"), At(_), Name("attributes"), Key("POSITION"), Name("min" | "max")]
            if matches!(error, E::Missing) =>
        {
            // Noted once per accessor (min and max are two errors).
            if path.ends_with(".min") {
                found.note(Kind::NoMinMax, path.trim_end_matches(".min"));
            }
            Some(Repair::Ignored)
        }
        [Name("meshes"), At(m), Name("primitives"), At(q), Name("attributes"), Key(_)]
            if matches!(error, E::Invalid) =>
        {
            let a = &mut json.meshes.get_mut(*m)?.primitives.get_mut(*q)?.attributes;
            a.retain(|k, _| matches!(k, gltf::json::validation::Checked::Valid(_)));
            found.note(
                Kind::UnknownAttribute,
                path.split("[\"").next().unwrap_or(path),
            );
            Some(Repair::Fixed)
        }
        [Name("textures"), At(t), Name("sampler")] if out => {
            json.textures.get_mut(*t)?.sampler = None;
            fixed(found, Kind::SamplerMissing)
        }
        [Name("textures"), At(t), Name("source")] if out || matches!(error, E::Missing) => {
            // An image with neither a uri nor a view: decoding it fails, as a missing file's.
            let at = json.images.len();
            json.images.push(gltf::json::Image {
                buffer_view: None,
                mime_type: None,
                name: None,
                uri: None,
                extensions: None,
                extras: Default::default(),
            });
            json.textures.get_mut(*t)?.source = Index::new(at as u32);
            found.placeholders.push(at);
            fixed(found, Kind::SourceMissing)
        }
        [Name("materials"), At(m), rest @ ..] if out && rest.last() == Some(&Name("index")) => {
            let m = json.materials.get_mut(*m)?;
            match rest {
                [Name("pbrMetallicRoughness"), Name("baseColorTexture"), _] => {
                    m.pbr_metallic_roughness.base_color_texture = None;
                }
                [Name("pbrMetallicRoughness"), Name("metallicRoughnessTexture"), _] => {
                    m.pbr_metallic_roughness.metallic_roughness_texture = None;
                }
                [Name("normalTexture"), _] => m.normal_texture = None,
                [Name("occlusionTexture"), _] => m.occlusion_texture = None,
                [Name("emissiveTexture"), _] => m.emissive_texture = None,
                _ => return None,
            }
            fixed(found, Kind::TextureMissing)
        }
        [Name("meshes"), At(m), Name("primitives"), At(q), Name("material")] if out => {
            json.meshes.get_mut(*m)?.primitives.get_mut(*q)?.material = None;
            fixed(found, Kind::MaterialMissing)
        }
        [Name("scene")] if out => {
            json.scene = (!json.scenes.is_empty()).then(|| Index::new(0));
            fixed(found, Kind::SceneMissing)
        }
        [Name("nodes"), At(n), Name("children"), At(_)] if out => {
            let count = json.nodes.len();
            let node = json.nodes.get_mut(*n)?;
            if let Some(c) = &mut node.children {
                c.retain(|c| c.value() < count);
            }
            fixed(found, Kind::ChildMissing)
        }
        [Name("animations"), At(a), Name("channels"), At(_), ..] if out => {
            let (nodes, a) = (json.nodes.len(), json.animations.get_mut(*a)?);
            let samplers = a.samplers.len();
            a.channels
                .retain(|c| c.sampler.value() < samplers && c.target.node.value() < nodes);
            fixed(found, Kind::ChannelMissing)
        }
        [Name("animations"), At(a), Name("samplers"), At(s), Name("interpolation")]
            if matches!(error, E::Invalid) =>
        {
            let s = json.animations.get_mut(*a)?.samplers.get_mut(*s)?;
            s.interpolation =
                gltf::json::validation::Checked::Valid(gltf::animation::Interpolation::Linear);
            fixed(found, Kind::Interpolation)
        }
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::loaders::gltf::quirks::Part::*;

    #[test]
    fn validation_paths_split_into_names_indices_and_keys() {
        assert_eq!(
            parts("meshes[0].primitives[12].attributes[\"POSITION\"].min"),
            [
                Name("meshes"),
                At(0),
                Name("primitives"),
                At(12),
                Name("attributes"),
                Key("POSITION"),
                Name("min")
            ]
        );
        assert_eq!(parts("scene"), [Name("scene")]);
        assert_eq!(
            parts("nodes[3].children[1]"),
            [Name("nodes"), At(3), Name("children"), At(1)]
        );
    }

    #[test]
    fn one_warning_per_kind_names_the_first_place_and_counts_the_rest() {
        let mut f = Found::default();
        f.note(Kind::ZeroStride, "bufferViews[2]");
        f.note(Kind::ZeroStride, "bufferViews[5]");
        f.note(Kind::SceneMissing, "scene");
        let w = f.warnings();
        assert_eq!(w.len(), 2);
        assert!(
            w[0].starts_with("bufferViews[2] and 1 more: byteStride 0"),
            "{}",
            w[0]
        );
        assert!(w[1].starts_with("scene: the default scene"), "{}", w[1]);
    }
}
