//! KHR_animation_pointer (issue 39): an animation channel may name what it animates by a
//! JSON pointer instead of a node and a path (`"path": "pointer"`, no `node`). The `gltf`
//! crate's types require the node, so such a file would not even parse. Before the crate
//! reads the JSON, each pointer channel is rewritten here: one naming a node's
//! `translation`, `rotation`, `scale` or `weights` becomes the plain channel it means (the
//! extension defines it so), and is played as one; one naming a material factor glview
//! animates ([`MaterialProperty`]) is taken out and returned, for `motion::read` to read its
//! sampler; any other (a light's intensity, a camera's field of view, a texture transform)
//! is taken out with a warning naming its pointer, and the rest of the file plays. Files
//! without the extension's name in their JSON are not touched (one scan of the JSON's
//! bytes).
use serde_json::Value;

/// The extension's name, as it appears in a channel target's `extensions`.
pub(crate) const NAME: &str = "KHR_animation_pointer";

pub(crate) use crate::motion::materials::MaterialProperty;

/// A pointer channel animating a material factor: where its sampler is, and what it sets.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct MaterialChannel {
    pub(crate) animation: usize,
    pub(crate) channel: usize,
    pub(crate) sampler: usize,
    pub(crate) material: usize,
    pub(crate) property: MaterialProperty,
}

/// A channel taken out: the animation and channel indices, and its pointer.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Dropped {
    pub(crate) animation: usize,
    pub(crate) channel: usize,
    pub(crate) pointer: String,
}

impl Dropped {
    pub(crate) fn message(&self) -> String {
        format!(
            "animation {} channel {}: {NAME} {} is not played (glview plays pointers to \
             nodes' translation, rotation, scale and weights, and to materials' base colour, \
             metallic, roughness and emissive factors and emissive strength)",
            self.animation, self.channel, self.pointer
        )
    }
}

/// Whether JSON text `json` may hold pointer channels (its bytes name the extension).
pub(crate) fn mentions(json: &[u8]) -> bool {
    memchr::memmem::find(json, NAME.as_bytes()).is_some()
}

/// `pointer` split after `/{array}/{index}/`: the index and the rest (JSON pointer escapes
/// cannot occur in the paths glview reads).
fn indexed<'a>(pointer: &'a str, array: &str) -> Option<(usize, &'a str)> {
    let rest = pointer
        .strip_prefix('/')?
        .strip_prefix(array)?
        .strip_prefix('/')?;
    let (index, rest) = rest.split_once('/')?;
    // A JSON array index: digits, no sign, no leading zero.
    if index.is_empty()
        || !index.bytes().all(|b| b.is_ascii_digit())
        || index.len() > 1 && index.starts_with('0')
    {
        return None;
    }
    Some((index.parse().ok()?, rest))
}

/// The node and path a pointer names, if it is one of a node's four animated properties:
/// `/nodes/{n}/translation` and so on.
fn node_path(pointer: &str) -> Option<(usize, &'static str)> {
    let (index, property) = indexed(pointer, "nodes")?;
    let path = ["translation", "rotation", "scale", "weights"]
        .into_iter()
        .find(|p| *p == property)?;
    Some((index, path))
}

/// The material and factor a pointer names, if glview animates it.
fn material_path(pointer: &str) -> Option<(usize, MaterialProperty)> {
    let (index, property) = indexed(pointer, "materials")?;
    let p = match property {
        "pbrMetallicRoughness/baseColorFactor" => MaterialProperty::BaseColor,
        "pbrMetallicRoughness/metallicFactor" => MaterialProperty::Metallic,
        "pbrMetallicRoughness/roughnessFactor" => MaterialProperty::Roughness,
        "emissiveFactor" => MaterialProperty::Emissive,
        "extensions/KHR_materials_emissive_strength/emissiveStrength" => {
            MaterialProperty::EmissiveStrength
        }
        _ => return None,
    };
    Some((index, p))
}

/// Rewrites the pointer channels of glTF JSON `root` in place (see the module): returns the
/// channels it took out, those animating materials and the others. Targets without a node
/// that are not pointer channels are left for [`crate::loaders::gltf::quirks::tolerate_value`].
pub(crate) fn rewrite(root: &mut Value) -> (Vec<MaterialChannel>, Vec<Dropped>) {
    let (mut materials, mut dropped) = (Vec::new(), Vec::new());
    let Some(animations) = root.get_mut("animations").and_then(Value::as_array_mut) else {
        return (materials, dropped);
    };
    for (ai, a) in animations.iter_mut().enumerate() {
        let Some(channels) = a.get_mut("channels").and_then(Value::as_array_mut) else {
            continue;
        };
        let mut ci = 0;
        channels.retain_mut(|c| {
            let index = ci;
            ci += 1;
            let sampler = c.get("sampler").and_then(Value::as_u64);
            let Some(target) = c.get_mut("target").and_then(Value::as_object_mut) else {
                return true;
            };
            if target.contains_key("node") || target.get("path") != Some(&Value::from("pointer")) {
                return true;
            }
            let pointer = target
                .get("extensions")
                .and_then(|e| e.get(NAME))
                .and_then(|x| x.get("pointer"))
                .and_then(Value::as_str)
                .unwrap_or("(none)")
                .to_string();
            if let Some((node, path)) = node_path(&pointer) {
                target.insert("node".into(), node.into());
                target.insert("path".into(), path.into());
                return true;
            }
            match (material_path(&pointer), sampler) {
                (Some((material, property)), Some(sampler)) => materials.push(MaterialChannel {
                    animation: ai,
                    channel: index,
                    sampler: usize::try_from(sampler).unwrap_or(usize::MAX),
                    material,
                    property,
                }),
                _ => dropped.push(Dropped {
                    animation: ai,
                    channel: index,
                    pointer,
                }),
            }
            false
        });
    }
    (materials, dropped)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn channel(target: Value) -> Value {
        serde_json::json!({"sampler": 0, "target": target})
    }

    fn pointer(p: &str) -> Value {
        serde_json::json!({"path": "pointer", "extensions": {NAME: {"pointer": p}}})
    }

    #[test]
    fn node_pointers_become_plain_channels_material_ones_are_returned_and_the_rest_dropped() {
        let mut root = serde_json::json!({"animations": [{"channels": [
            channel(serde_json::json!({"node": 1, "path": "rotation"})),
            channel(pointer("/nodes/3/translation")),
            channel(pointer("/materials/0/pbrMetallicRoughness/baseColorFactor")),
            channel(pointer("/nodes/12/weights")),
            channel(pointer("/nodes/01/scale")),
            channel(pointer("/nodes/2/matrix")),
            channel(pointer("/materials/1/alphaCutoff")),
            channel(serde_json::json!({"path": "pointer"})),
        ]}]});
        let (materials, dropped) = rewrite(&mut root);
        let channels = root["animations"][0]["channels"].as_array().unwrap();
        let targets: Vec<(u64, &str)> = channels
            .iter()
            .map(|c| {
                let t = &c["target"];
                (t["node"].as_u64().unwrap(), t["path"].as_str().unwrap())
            })
            .collect();
        assert_eq!(
            targets,
            [(1, "rotation"), (3, "translation"), (12, "weights")]
        );
        assert_eq!(
            materials,
            [MaterialChannel {
                animation: 0,
                channel: 2,
                sampler: 0,
                material: 0,
                property: MaterialProperty::BaseColor,
            }]
        );
        let out: Vec<(usize, &str)> = dropped
            .iter()
            .map(|d| (d.channel, d.pointer.as_str()))
            .collect();
        assert_eq!(
            out,
            [
                (4, "/nodes/01/scale"),
                (5, "/nodes/2/matrix"),
                (6, "/materials/1/alphaCutoff"),
                (7, "(none)"),
            ]
        );
        assert!(dropped[2]
            .message()
            .contains("animation 0 channel 6: KHR_animation_pointer /materials/1/alphaCutoff"));
    }

    #[test]
    fn material_pointers_name_the_factors_glview_animates() {
        use MaterialProperty as P;
        for (p, want) in [
            (
                "/materials/3/pbrMetallicRoughness/metallicFactor",
                Some((3, P::Metallic)),
            ),
            (
                "/materials/0/pbrMetallicRoughness/roughnessFactor",
                Some((0, P::Roughness)),
            ),
            ("/materials/2/emissiveFactor", Some((2, P::Emissive))),
            (
                "/materials/2/extensions/KHR_materials_emissive_strength/emissiveStrength",
                Some((2, P::EmissiveStrength)),
            ),
            ("/materials/-1/emissiveFactor", None),
            ("/materials/2/emissiveFactor/0", None),
            ("/materials/2/normalTexture/scale", None),
        ] {
            assert_eq!(material_path(p), want, "{p}");
        }
    }

    #[test]
    fn the_scan_finds_the_name() {
        assert!(mentions(br#"{"extensionsUsed":["KHR_animation_pointer"]}"#));
        assert!(!mentions(br#"{"asset":{"version":"2.0"}}"#));
    }
}
