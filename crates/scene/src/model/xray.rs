//! `--xray NAME...`: makes the named materials, or the meshes of the named objects/groups,
//! translucent, to look at the parts inside a model; everything else is drawn opaque (the
//! seed's opaque inner mask: with nearest-layer translucency only opaque surfaces show
//! through the x-rayed shell, so a translucent glass inside a holder becomes solid).
use crate::model::Scene;

/// Opacity given to x-rayed surfaces unless `--opacity` says otherwise.
pub const XRAY_OPACITY: f32 = 0.3;

impl Scene {
    /// Applies `--xray`; a name that matches no material and no object is an error naming it
    /// and the names there are.
    pub fn xray(&mut self, names: &[String], opacity: f32) -> Result<(), String> {
        let mut rayed = vec![false; self.materials.len()];
        for name in names {
            let by_material: Vec<usize> = (0..self.materials.len())
                .filter(|&i| self.materials[i].name == *name)
                .collect();
            let by_mesh: Vec<usize> = (0..self.meshes.len())
                .filter(|&i| self.meshes[i].name == *name)
                .collect();
            if by_material.is_empty() && by_mesh.is_empty() {
                let mut known: Vec<&str> = self
                    .materials
                    .iter()
                    .map(|m| m.name.as_str())
                    .chain(self.meshes.iter().map(|m| m.name.as_str()))
                    .collect();
                known.sort_unstable();
                known.dedup();
                return Err(format!(
                    "--xray {name:?}: no material or object of that name (there are: {})",
                    known.join(", ")
                ));
            }
            for i in by_material {
                self.materials[i].set_opacity(opacity);
                rayed[i] = true;
            }
            for i in by_mesh {
                // A copy of the mesh's material, so other meshes sharing it stay opaque.
                let mut m = self.materials[self.meshes[i].material].clone();
                m.name = format!("{} (x-ray)", m.name);
                m.set_opacity(opacity);
                self.materials.push(m);
                rayed.push(true);
                self.meshes[i].material = self.materials.len() - 1;
            }
        }
        for (m, rayed) in self.materials.iter_mut().zip(rayed) {
            if !rayed {
                m.set_opacity(1.0);
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use {crate::model::material::Material, crate::model::Mesh, crate::model::Scene};

    #[test]
    fn by_object_copies_the_material() {
        let mesh = |name: &str| Mesh {
            name: name.into(),
            ..Default::default()
        };
        let glass = Material {
            opacity: Some(0.5),
            ..Default::default()
        };
        let mut s = Scene::from_meshes("t", vec![mesh("a"), mesh("b")], vec![glass]);
        s.xray(&["b".into()], 0.3).unwrap();
        // The inner mask: what is not x-rayed is opaque, even glass.
        assert_eq!(s.materials[s.meshes[0].material].opacity, None);
        assert_eq!(s.materials[s.meshes[1].material].opacity, Some(0.3));
        assert!(s.xray(&["nope".into()], 0.3).unwrap_err().contains("nope"));
    }
}
