//! `KHR_materials_variants`: the file names its variants once (the root extension) and each
//! primitive maps some of them to another material. A variant is applied at load: each
//! primitive takes the material its mapping gives for the chosen variant and keeps its own
//! otherwise, as the extension says. A mapping that is not well formed is ignored (the
//! primitive keeps its material) rather than refusing a file whose default look is fine.
use serde_json::Value;

pub(crate) const EXT: &str = "KHR_materials_variants";

/// The variants' names in the file's order (`variant N` when unnamed).
pub(crate) fn names(doc: &gltf::Document) -> Vec<String> {
    let Some(list) = doc
        .extension_value(EXT)
        .and_then(|e| e.get("variants"))
        .and_then(Value::as_array)
    else {
        return Vec::new();
    };
    list.iter()
        .enumerate()
        .map(|(i, v)| {
            v.get("name")
                .and_then(Value::as_str)
                .map_or_else(|| format!("variant {i}"), str::to_string)
        })
        .collect()
}

/// The material `variant` maps this primitive to, if its mappings name one.
pub(crate) fn material(p: &gltf::Primitive, variant: usize) -> Option<usize> {
    let mappings = p.extension_value(EXT)?.get("mappings")?.as_array()?;
    mappings.iter().find_map(|m| {
        let listed = m
            .get("variants")?
            .as_array()?
            .iter()
            .any(|v| v.as_u64() == Some(variant as u64));
        let material = usize::try_from(m.get("material")?.as_u64()?).ok()?;
        listed.then_some(material)
    })
}
