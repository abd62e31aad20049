//! The loaded scene: its meshes, materials, lines and points, bounds, the file's views and
//! lights, and its motion; made in one place ([`Scene::new`]).
use crate::loaders::gltf::instancing::Instancing;
use crate::model::material::Material;
use crate::model::meshes::Meshes;
use crate::model::{Bounds, Mesh, Warning, Wire};
use crate::{model, motion};
use glam::{DVec3, Vec3};

/// A loaded model, re-centred: vertex positions are relative to `origin` (the bounding-box
/// centre in file coordinates, kept in f64) so that far-from-origin models keep f32 precision.
#[derive(Clone, Debug)]
pub struct Scene {
    pub name: String,
    /// Here, or (after a mesh cache hit) partly still in the entry until first used.
    pub meshes: Meshes,
    pub materials: Vec<Material>,
    /// Bounds in local (re-centred) coordinates.
    pub bounds: Bounds,
    /// Where local (0,0,0) is in the file's coordinates.
    pub origin: DVec3,
    /// Bounds in the file's coordinates, exactly (f64): (min, max).
    pub file_bounds: (DVec3, DVec3),
    /// Other files the scene was built from (MTL libraries, textures): the mesh cache
    /// checks them too.
    pub dependencies: Vec<std::path::PathBuf>,
    pub warnings: Vec<Warning>,
    /// Lines (`l`) and points (`p`), in local coordinates; not triangles.
    pub wire: Wire,
    /// For `--check`: every texture statement of the MTL and what happens to it.
    pub(crate) maps: Vec<String>,
    /// glTF `EXT_mesh_gpu_instancing` nodes, whose instances `meshes` holds written out
    /// ([`Instancing`]); empty for other formats. The mesh cache keeps it.
    pub instancing: Vec<Instancing>,
    /// The file's cameras, scenes and material variants (glTF's; empty for other formats).
    pub views: model::views::Views,
    /// The lights the file places (glTF KHR_lights_punctual), in file coordinates; they
    /// replace the default light kit (the renderer's `--light file`).
    pub lights: Vec<crate::model::lights::FileLight>,
    /// glTF skins, morph targets and animations (None: nothing moves); shared by the
    /// scene's clones, which pose their own meshes.
    pub motion: Option<std::sync::Arc<motion::Rig>>,
    /// The moment [`Scene::pose`] posed the meshes at (None: the static pose, as loaded).
    pub posed: Option<motion::Moment>,
}

/// What a loader made of a file, for [`Scene::new`]; a part it has none of is its default
/// (no lines, no views, no lights, nothing that moves).
pub struct Parts {
    pub meshes: Meshes,
    pub materials: Vec<Material>,
    pub bounds: Bounds,
    pub origin: DVec3,
    pub file_bounds: (DVec3, DVec3),
    pub dependencies: Vec<std::path::PathBuf>,
    pub warnings: Vec<Warning>,
    pub wire: Wire,
    pub maps: Vec<String>,
    pub instancing: Vec<Instancing>,
    pub views: model::views::Views,
    pub lights: Vec<crate::model::lights::FileLight>,
    pub motion: Option<std::sync::Arc<motion::Rig>>,
}

impl Default for Parts {
    fn default() -> Parts {
        Parts {
            meshes: Vec::new().into(),
            materials: Vec::new(),
            bounds: Bounds::empty(),
            origin: DVec3::ZERO,
            file_bounds: (DVec3::ZERO, DVec3::ZERO),
            dependencies: Vec::new(),
            warnings: Vec::new(),
            wire: Wire::default(),
            maps: Vec::new(),
            instancing: Vec::new(),
            views: Default::default(),
            lights: Vec::new(),
            motion: None,
        }
    }
}

impl Scene {
    /// The one place a scene is made: named `name`, of what a loader (or the mesh cache, or
    /// code) made, in its static pose.
    pub fn new(name: String, parts: Parts) -> Scene {
        let Parts {
            meshes,
            materials,
            bounds,
            origin,
            file_bounds,
            dependencies,
            warnings,
            wire,
            maps,
            instancing,
            views,
            lights,
            motion,
        } = parts;
        Scene {
            name,
            meshes,
            materials,
            bounds,
            origin,
            file_bounds,
            dependencies,
            warnings,
            wire,
            maps,
            instancing,
            views,
            lights,
            motion,
            posed: None,
        }
    }

    /// A model file's scene name: its file name without the extension.
    pub(crate) fn name_of(path: &std::path::Path) -> String {
        path.file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "model".into())
    }

    /// A scene built in code (tests, generators): local coordinates are file coordinates.
    pub fn from_meshes(name: &str, meshes: Vec<Mesh>, materials: Vec<Material>) -> Scene {
        let bounds = Bounds::around(
            meshes
                .iter()
                .flat_map(|m| &m.vertices)
                .map(|v| Vec3::from(v.position)),
        );
        let parts = Parts {
            meshes: meshes.into(),
            materials,
            bounds,
            file_bounds: (bounds.min.as_dvec3(), bounds.max.as_dvec3()),
            ..Parts::default()
        };
        Scene::new(name.into(), parts)
    }

    /// Counted without reading meshes still in a cache entry.
    pub fn triangle_count(&self) -> usize {
        self.meshes.counts().0
    }
    pub fn vertex_count(&self) -> usize {
        self.meshes.counts().1
    }
    /// Converts a point in file coordinates to local coordinates, in f64 before rounding.
    pub fn to_local(&self, p: DVec3) -> Vec3 {
        (p - self.origin).as_vec3()
    }
}
