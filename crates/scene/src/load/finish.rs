//! The loader's last step, after the meshes are built: redundant faces dropped
//! ([`crate::geometry::dedup`]) and a warning for every texture decoded smaller than its file
//! ([`crate::textures`]). One call from `obj.rs`, so the parser's code stays apart.
use crate::model::texture_slot::Slot;
use std::path::Path;
use {
    crate::geometry::dedup, crate::model::material::Material, crate::model::Mesh,
    crate::model::Warning, crate::textures,
};

pub(crate) fn finish(
    path: &Path,
    meshes: &mut Vec<Mesh>,
    materials: &[Material],
    warnings: &mut Vec<Warning>,
) {
    dedup::drop_redundant_faces(path, meshes, warnings);
    texture_warnings(materials, warnings);
    crate::profile::mark(crate::profile::Stage::Finish);
    crate::profile::end(false);
}

/// One warning per downscaled texture, naming the image file.
pub(crate) fn texture_warnings(materials: &[Material], warnings: &mut Vec<Warning>) {
    let mut seen = std::collections::HashSet::new();
    for m in materials {
        let Some(t) = m.image(Slot::BaseColor) else {
            continue;
        };
        if !seen.insert(t.path.clone()) {
            continue;
        }
        if let Some(note) = textures::downscale_note(t) {
            warnings.push(Warning {
                file: t.path.clone(),
                line: None,
                message: format!("material {}: {note}", m.name),
            });
        }
    }
}
