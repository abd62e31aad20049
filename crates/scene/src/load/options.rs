//! What every loader is asked: [`LoadOptions`] (the mesh cache, textures, creases, the up
//! axis, a glTF scene or variant) and a progress callback.
use crate::geometry::normals::Creases;
use crate::model::material::TextureOptions;
use crate::model::UpAxis;

/// Called with (bytes scanned, total bytes) while a file is read.
pub type ProgressFn = std::sync::Arc<dyn Fn(u64, u64) + Send + Sync>;

#[derive(Clone, Default)]
pub struct LoadOptions {
    pub textures: TextureOptions,
    pub progress: Option<ProgressFn>,
    /// Use the mesh cache (`scene::cache`) for large files.
    pub cache: bool,
    /// Keep fully transparent materials (`d 0`, `Tr 1`) invisible instead of opaque.
    pub honor_transparency: bool,
    /// How generated normals treat sharp edges (`--crease`, `--flat`).
    pub creases: Creases,
    /// Which file axis is up (`--up`).
    pub up: UpAxis,
    /// A base-colour texture for meshes without a material of their own (`--texture`).
    pub texture: Option<std::path::PathBuf>,
    /// The glTF scene to draw (`--scene N|NAME`; default: the file's default scene).
    pub scene: Option<String>,
    /// The `KHR_materials_variants` variant to draw (`--variant N|NAME`).
    pub variant: Option<String>,
}

impl LoadOptions {
    /// Whether these options give the scene the mesh cache stores (it keys on the file only).
    /// A chosen scene or variant is not it: the entry holds the default scene with its
    /// default materials, and those choices load the file (variant files are small; a
    /// cache of every scene and every variant's materials would multiply the entry).
    pub fn cacheable(&self) -> bool {
        !self.honor_transparency
            && self.creases == Creases::default()
            && self.up == UpAxis::PosY
            && self.texture.is_none()
            && self.scene.is_none()
            && self.variant.is_none()
    }
}
