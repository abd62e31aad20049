//! Which of a glTF file's scenes is drawn (`--scene N|NAME`, else the file's default, else
//! its first) and which material variant (`--variant N|NAME`), with the file's lists for
//! [`Views`]; its cameras are added once the chosen scene's nodes are walked
//! ([`crate::loaders::gltf::cameras`]).
use crate::load::options::LoadOptions;
use crate::model::views::{pick, Views};

/// The scene to draw and the views so far (scenes and variants, no cameras yet).
pub(crate) fn choose<'a>(
    doc: &'a gltf::Document,
    opts: &LoadOptions,
) -> Result<(gltf::Scene<'a>, Views), String> {
    let scenes: Vec<String> = doc
        .scenes()
        .map(|s| {
            s.name()
                .map_or_else(|| format!("scene {}", s.index()), str::to_string)
        })
        .collect();
    let names: Vec<&str> = scenes.iter().map(String::as_str).collect();
    let index = match &opts.scene {
        Some(q) => pick("scene", &names, q)?,
        None => doc
            .default_scene()
            .map(|s| s.index())
            .or((!scenes.is_empty()).then_some(0))
            .ok_or("no scene in the file")?,
    };
    let scene = doc.scenes().nth(index).ok_or("no scene in the file")?;
    let variants = crate::loaders::gltf::variants::names(doc);
    let variant = match &opts.variant {
        Some(q) => {
            let names: Vec<&str> = variants.iter().map(String::as_str).collect();
            Some(pick("variant", &names, q)?)
        }
        None => None,
    };
    Ok((
        scene,
        Views {
            cameras: Vec::new(),
            scenes,
            scene: index,
            variants,
            variant,
        },
    ))
}
