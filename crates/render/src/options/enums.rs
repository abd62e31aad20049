//! The choice-valued options (clap value enums; their names are the CLI's words).

crate::choice! {
    pub enum Diffuse {
        /// max(N·L, 0)
        Lambert = "lambert",
        /// Half-Lambert: (1 + N·L)/2.
        Wrap = "wrap",
    }
}

crate::choice! {
    pub enum AaMode {
        None = "none",
        Msaa = "msaa",
        Fxaa = "fxaa",
        Ssaa = "ssaa",
    }
}

crate::choice! {
    pub enum DepthMode {
        Standard = "standard",
        /// The seed's logarithmic depth (2.10), C = 1.
        Log = "log",
    }
}

crate::choice! {
    pub enum Show {
        /// The lit scene.
        Scene = "scene",
        /// Light 0's shadow depth map as grey (near = dark); a point light inside the scene
        /// shows its six-face atlas.
        ShadowMap = "shadow-map",
        /// The PBR irradiance cube (E_d) as an unfolded cross.
        Irradiance = "irradiance",
        /// One PBR specular cube (E_s) as a cross: level --show-level.
        Specular = "specular",
        /// The PBR BRDF lookup table (A red, B green).
        Lut = "lut",
        /// Surface normals (eye space, n·0.5 + 0.5), normal maps applied.
        Normals = "normals",
        /// Texture coordinates (u red, v green).
        Uvs = "uvs",
        /// PBR roughness as grey.
        Roughness = "roughness",
        /// PBR metallic as grey.
        Metallic = "metallic",
        /// The bloom buffer: the blurred bright parts alone (strength 1 unless --bloom).
        Bloom = "bloom",
    }
}

crate::choice! {
    pub enum LodMode {
        /// Coarser levels for meshes with more triangles than the view has pixels.
        Auto = "auto",
        /// Coarser levels for every mesh that has them.
        On = "on",
        /// Every triangle.
        Off = "off",
    }
}
