//! The choice-valued options (clap value enums; their names are the CLI's words).
use clap::ValueEnum;

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Diffuse {
    /// max(N·L, 0)
    Lambert,
    /// Half-Lambert: (1 + N·L)/2.
    Wrap,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum AaMode {
    None,
    Msaa,
    Fxaa,
    Ssaa,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum DepthMode {
    Standard,
    /// The seed's logarithmic depth (2.10), C = 1.
    Log,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Show {
    /// The lit scene.
    Scene,
    /// Light 0's shadow depth map as grey (near = dark); a point light inside the scene
    /// shows its six-face atlas.
    ShadowMap,
    /// The PBR irradiance cube (E_d) as an unfolded cross.
    Irradiance,
    /// One PBR specular cube (E_s) as a cross: level --show-level.
    Specular,
    /// The PBR BRDF lookup table (A red, B green).
    Lut,
    /// Surface normals (eye space, n·0.5 + 0.5), normal maps applied.
    Normals,
    /// Texture coordinates (u red, v green).
    Uvs,
    /// PBR roughness as grey.
    Roughness,
    /// PBR metallic as grey.
    Metallic,
    /// The bloom buffer: the blurred bright parts alone (strength 1 unless --bloom).
    Bloom,
}
