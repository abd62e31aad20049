//! Materials from MTL, with the fixed-function GL defaults where a value is not given, and
//! diffuse textures decoded to RGBA8 (no GL here; the renderer uploads them).
use super::Warning;
use std::path::{Path, PathBuf};

/// A decoded texture, RGBA8, row 0 at the top (image order).
#[derive(Clone, Debug)]
pub struct Texture {
    /// The image file, or the glTF file that holds the image.
    pub path: PathBuf,
    /// Which image of the container at `path` (a glTF image index); `None` for an image file.
    /// Part of the texture's identity: every image inside one `.glb` has the same `path`.
    pub image: Option<usize>,
    pub width: u32,
    pub height: u32,
    pub rgba: Vec<u8>,
}

#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Material {
    pub name: String,
    pub ambient: [f32; 3],
    pub diffuse: [f32; 3],
    pub specular: [f32; 3],
    pub emissive: [f32; 3],
    /// Phong exponent; Ns <= 0 means "specular factor 1 wherever N·L > 0" (the limit x^0 = 1
    /// of the fixed-function formula), evaluated without calling pow.
    pub shininess: f32,
    /// Opacity (`d`, or 1 - `Tr`).
    pub opacity: f32,
    pub illum: Option<u8>,
    /// Decoded pixels are not cached (see `scene::cache`): they are decoded again from the
    /// resolved path.
    #[serde(skip)]
    pub diffuse_map: Option<std::sync::Arc<Texture>>,
    /// `map_Kd` as written in the MTL, whether or not it could be loaded.
    pub diffuse_map_spec: Option<String>,
    /// The PBR tier's inputs (`Pr`, `Pm`, their maps, normal, AO and emissive maps).
    #[serde(default)]
    pub pbr_inputs: super::pbr_material::PbrInputs,
}

impl PartialEq for Texture {
    fn eq(&self, other: &Self) -> bool {
        self.path == other.path && self.image == other.image
    }
}

impl Default for Material {
    /// The fixed-function OpenGL material defaults.
    fn default() -> Self {
        Material {
            name: "default".into(),
            ambient: [0.2; 3],
            diffuse: [0.8; 3],
            specular: [0.0; 3],
            emissive: [0.0; 3],
            shininess: 0.0,
            opacity: 1.0,
            illum: None,
            diffuse_map: None,
            diffuse_map_spec: None,
            pbr_inputs: Default::default(),
        }
    }
}

impl Material {
    /// Drawn blended: an opacity below 1, or glTF's BLEND (whose texture alpha may be below 1
    /// where the factor is 1).
    pub fn is_translucent(&self) -> bool {
        self.opacity < 1.0
            || self.pbr_inputs.model.alpha_mode == super::material_model::AlphaMode::Blend
    }
}

/// Options that make texture loading safe; see `--allow-outside-paths`.
#[derive(Clone, Copy, Debug, Default)]
pub struct TextureOptions {
    pub allow_outside_paths: bool,
    /// Largest width/height accepted from a file header; larger images are refused before
    /// decoding (decompression bombs) and images above the driver limit are downscaled later.
    pub max_dimension: u32,
}

fn to_rgb(v: Option<[f64; 3]>, default: [f32; 3]) -> [f32; 3] {
    v.map(|c| c.map(|x| if x.is_finite() { x as f32 } else { 0.0 }))
        .unwrap_or(default)
}

/// Builds our material from tobj's, loading the diffuse map relative to `dir`.
pub fn from_tobj(
    m: &tobj::Material,
    dir: &Path,
    mtl_file: &Path,
    opts: TextureOptions,
    warnings: &mut Vec<Warning>,
) -> Material {
    let d = Material::default();
    let opacity = m
        .dissolve
        .map(|x| x as f32)
        .or_else(|| {
            m.unknown_param
                .get("Tr")
                .and_then(|t| t.trim().parse::<f32>().ok())
                .map(|t| 1.0 - t)
        })
        .filter(|x| x.is_finite())
        .unwrap_or(1.0)
        .clamp(0.0, 1.0);
    let shininess = m
        .shininess
        .map(|x| x as f32)
        .filter(|x| x.is_finite())
        .unwrap_or(d.shininess);
    let diffuse_map =
        m.diffuse_texture
            .as_deref()
            .and_then(|spec| match load_texture(spec, dir, opts) {
                Ok(t) => Some(std::sync::Arc::new(t)),
                Err(msg) => {
                    warnings.push(Warning {
                        file: mtl_file.to_path_buf(),
                        line: None,
                        message: format!(
                            "material {}: map_Kd {spec:?}: {msg}; using its colours",
                            m.name
                        ),
                    });
                    None
                }
            });
    Material {
        name: m.name.clone(),
        ambient: to_rgb(m.ambient, d.ambient),
        diffuse: to_rgb(m.diffuse, d.diffuse),
        specular: to_rgb(m.specular, d.specular),
        emissive: to_rgb(m.emissive, d.emissive),
        shininess,
        opacity,
        illum: m.illumination_model,
        diffuse_map,
        diffuse_map_spec: m.diffuse_texture.clone(),
        pbr_inputs: super::pbr_material::from_tobj(m, dir, mtl_file, opts, warnings),
    }
}

/// Options of MTL texture statements and how many arguments each takes.
fn option_arity(opt: &str) -> Option<usize> {
    Some(match opt {
        "-blendu" | "-blendv" | "-cc" | "-clamp" | "-imfchan" | "-type" | "-bm" | "-boost"
        | "-texres" | "-colorspace" => 1,
        "-mm" => 2,
        "-o" | "-s" | "-t" => 3,
        _ => return None,
    })
}

/// Strips MTL texture options (`-s 1 1 1 file.png`) and returns the file name. `-o`, `-s` and
/// `-t` take 1 to 3 numbers, so numeric words after them are consumed greedily.
pub fn strip_texture_options(spec: &str) -> String {
    let words: Vec<&str> = spec.split_whitespace().collect();
    let mut i = 0;
    while i < words.len() {
        let Some(n) = option_arity(words[i]) else {
            break;
        };
        i += 1;
        let mut taken = 0;
        while taken < n && i < words.len() - 1 {
            if n == 3 && taken > 0 && words[i].parse::<f64>().is_err() {
                break;
            }
            i += 1;
            taken += 1;
        }
    }
    words[i.min(words.len())..].join(" ")
}

/// Finds a texture file: as written, with backslashes as separators, then by case-insensitive
/// match of each component. Refuses paths that leave `dir` unless allowed (the rule every
/// format shares: [`super::uri`]).
pub fn resolve_texture_path(
    spec: &str,
    dir: &Path,
    allow_outside: bool,
) -> Result<PathBuf, String> {
    let name = strip_texture_options(spec).replace('\\', "/");
    super::uri::in_folder(&name, dir, allow_outside)
}

pub(crate) fn load_texture(
    spec: &str,
    dir: &Path,
    opts: TextureOptions,
) -> Result<Texture, String> {
    let path = resolve_texture_path(spec, dir, opts.allow_outside_paths)?;
    decode_texture(path, opts)
}

/// Decodes an image file already resolved (and checked against the folder rule), within the
/// memory bounds of [`super::texture`].
pub fn decode_texture(path: PathBuf, opts: TextureOptions) -> Result<Texture, String> {
    super::texture::decode(path, opts)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn options_are_stripped() {
        assert_eq!(strip_texture_options("-s 1 1 1 tex.png"), "tex.png");
        assert_eq!(
            strip_texture_options("-bm 2 -clamp on bump 01.png"),
            "bump 01.png"
        );
        assert_eq!(strip_texture_options("-o 0.1 tex.png"), "tex.png");
        assert_eq!(strip_texture_options("texture 01.png"), "texture 01.png");
    }

    #[test]
    fn defaults_are_fixed_function() {
        let m = Material::default();
        assert_eq!(
            (m.ambient, m.diffuse, m.specular, m.shininess),
            ([0.2; 3], [0.8; 3], [0.0; 3], 0.0)
        );
    }
}
