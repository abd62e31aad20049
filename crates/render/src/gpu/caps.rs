//! What the driver actually gave, read from the context (never from what was requested).
//! Every feature decision in the renderer gates on this.
use glow::HasContext;
use serde::Serialize;

/// The GLSL dialect shaders are assembled for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
pub enum Dialect {
    /// GLSL 1.20 (OpenGL 2.1 and compatibility profiles).
    Glsl120,
    /// GLSL ES 3.00 (OpenGL ES 3.0).
    Glsl300Es,
    /// GLSL 3.30 (OpenGL 3.3 core).
    Glsl330,
    /// GLSL ES 1.00 (OpenGL ES 2.0, WebGL 1): both tiers (PBR as GL 2.1 draws it), shadows
    /// compared in the shader (ES 2.0 has no shadow samplers).
    Glsl100Es,
}

impl Dialect {
    pub fn name(self) -> &'static str {
        match self {
            Dialect::Glsl120 => "GLSL 1.20",
            Dialect::Glsl300Es => "GLSL ES 3.00",
            Dialect::Glsl330 => "GLSL 3.30",
            Dialect::Glsl100Es => "GLSL ES 1.00",
        }
    }
}

#[derive(Clone, Debug, Serialize)]
pub struct Caps {
    pub version: String,
    pub(crate) glsl_version: String,
    pub renderer: String,
    pub(crate) vendor: String,
    pub major: u32,
    pub minor: u32,
    pub embedded: bool,
    pub(crate) core_profile: bool,
    pub(crate) glsl: (u32, u32),
    pub dialect: Dialect,
    /// OpenGL ES 2.0 rules (WebGL 1): unsized texture formats, no draw/read buffer selection,
    /// no blits or multisampled renderbuffers, shadows compared in the shader. Also set on a
    /// later ES context asked to behave as ES 2.0 (`--gl es2`: Mesa answers an ES 2.0
    /// request with its newest ES, which runs every ES 2.0 program unchanged).
    pub(crate) es2: bool,
    /// 24-bit depth renderbuffers: everything but ES 2.0 without OES_depth24 (WebGL 1 has
    /// DEPTH_COMPONENT16 only).
    pub(crate) depth24: bool,
    /// Screen-space derivatives (dFdx, fwidth): everything but ES 2.0 without
    /// OES_standard_derivatives.
    pub(crate) derivatives: bool,
    /// A fragment shader can write its depth (gl_FragDepth): everything but ES 2.0 without
    /// EXT_frag_depth.
    pub(crate) frag_depth: bool,
    /// Framebuffer objects: GL >= 3.0, ES, ARB_ or EXT_framebuffer_object.
    pub fbo: bool,
    pub(crate) vao: bool,
    pub(crate) depth_texture: bool,
    pub(crate) shadow_compare: bool,
    pub(crate) float_textures: bool,
    pub(crate) texture_lod: bool,
    pub(crate) uint_indices: bool,
    /// Instanced arrays and draws (`glVertexAttribDivisor`, `glDrawElementsInstanced`: GL 3.3,
    /// ES 3.0): `EXT_mesh_gpu_instancing` nodes drawn as instances of one uploaded mesh.
    pub(crate) instancing: bool,
    /// `samplerCubeShadow` lookups (GLSL 1.30+ / ES 3.00; not in GLSL 1.20).
    pub(crate) cube_shadow: bool,
    pub generate_mipmap: bool,
    /// GL_TIME_ELAPSED queries (desktop GL 3.3 or ARB_timer_query).
    pub(crate) timer_query: bool,
    pub(crate) max_texture_size: u32,
    /// Texture units a fragment shader can sample (GL_MAX_TEXTURE_IMAGE_UNITS).
    pub(crate) max_texture_units: u32,
    /// 16-bit float textures (RGBA16F, RG16F): GL 3.0, ES 3.0, ARB_texture_float with
    /// ARB_half_float_pixel.
    pub(crate) half_float_textures: bool,
    /// Two-channel textures (RG8, RG16F): GL 3.0, ES 3.0 or ARB_texture_rg.
    pub(crate) rg_textures: bool,
    /// sRGB textures decoded by the sampler: GL 2.1, ES 3.0, EXT_texture_sRGB.
    pub(crate) srgb_textures: bool,
    /// Filtering across cube faces (GL_TEXTURE_CUBE_MAP_SEAMLESS): GL 3.2 or ARB_seamless_cube_map.
    pub(crate) seamless_cube: bool,
    /// Packed depth + stencil formats: GL 3.0, ES 3.0 or EXT/OES_packed_depth_stencil.
    pub depth_stencil: bool,
    /// `glReadPixels` can return rows top first (GL_MESA_pack_invert): no flip afterwards.
    pub(crate) pack_invert: bool,
    /// 32-bit float colour render targets read back as floats: GL 3.0, or ES 3.0 with
    /// EXT_color_buffer_float.
    pub(crate) float_render: bool,
    /// Samples a multisampled renderbuffer may have (GL_MAX_SAMPLES; 0 without them).
    pub max_samples: u32,
    pub max_renderbuffer_size: u32,
    pub max_viewport: (u32, u32),
    pub(crate) max_varying_floats: u32,
    /// Uniform components (floats) a vertex / fragment shader may use: GL 2.1 only promises
    /// 512 / 64, which the lit shader's per-light uniforms can exceed; the renderer falls
    /// back on these.
    pub(crate) max_vertex_uniform_components: u32,
    pub(crate) max_fragment_uniform_components: u32,
    /// `GL_MAX_VERTEX_ATTRIBS` (16 at least on GL 2.1 and ES 3.0): what is left above the
    /// fixed layout (attributes 0–11) carries GPU morph targets' deltas.
    pub(crate) max_vertex_attribs: u32,
    pub(crate) extension_count: usize,
}

/// Vertex array objects before GL 3.0 / ES 3.0 (ES 2.0 and WebGL 1: OES_; glow calls
/// whichever the context has).
const VAO_EXTENSIONS: &[&str] = &[
    "GL_ARB_vertex_array_object",
    "GL_APPLE_vertex_array_object",
    "GL_OES_vertex_array_object",
];

/// Depth textures before GL 1.4 / ES 3.0 (WebGL 1: WEBGL_depth_texture).
const DEPTH_TEXTURE_EXTENSIONS: &[&str] = &[
    "GL_ARB_depth_texture",
    "GL_OES_depth_texture",
    "GL_WEBGL_depth_texture",
];

fn parse_version(s: &str) -> Option<(u32, u32)> {
    let start = s.find(|c: char| c.is_ascii_digit())?;
    let mut it = s[start..].split(|c: char| !c.is_ascii_digit());
    let major = it.next()?.parse().ok()?;
    // "1.20" → 20, "2.1" → 1, "3.00" → 0: at most two digits of minor version.
    let minor = it.next().unwrap_or("0");
    let minor = minor[..minor.len().min(2)].parse().unwrap_or(0);
    Some((major, minor))
}

/// The context's version and dialect: the first facts [`Caps::probe`] reads.
struct Level {
    major: u32,
    minor: u32,
    embedded: bool,
    es2: bool,
    core_profile: bool,
    glsl_version: String,
    glsl: (u32, u32),
    dialect: Dialect,
}

impl Level {
    /// `es2_ceiling` holds an ES 3.x context to ES 2.0 (its version then reads 2.0).
    fn probe(gl: &glow::Context, es2_ceiling: bool) -> Level {
        let v = gl.version();
        let embedded = v.is_embedded;
        let es2 = embedded && (v.major < 3 || es2_ceiling);
        let (major, minor) = if es2 && v.major >= 3 {
            (2, 0)
        } else {
            (v.major, v.minor)
        };
        // SAFETY: plain queries on a current context.
        let (glsl_version, profile_mask) = unsafe {
            let s = gl.get_parameter_string(glow::SHADING_LANGUAGE_VERSION);
            let core_possible = !embedded && (major, minor) >= (3, 2);
            let mask = if core_possible {
                gl.get_parameter_i32(glow::CONTEXT_PROFILE_MASK) as u32
            } else {
                0
            };
            (s, mask)
        };
        let glsl = parse_version(&glsl_version).unwrap_or((1, 10));
        let glsl = (glsl.0, if glsl.1 >= 10 { glsl.1 } else { glsl.1 * 10 });
        let glsl = if es2 { (1, 0) } else { glsl };
        let core_profile = profile_mask & glow::CONTEXT_CORE_PROFILE_BIT != 0;
        let dialect = if es2 {
            Dialect::Glsl100Es
        } else if embedded {
            Dialect::Glsl300Es
        } else if core_profile {
            Dialect::Glsl330
        } else {
            Dialect::Glsl120
        };
        Level {
            major,
            minor,
            embedded,
            es2,
            core_profile,
            glsl_version,
            glsl,
            dialect,
        }
    }
}

impl Caps {
    /// What the current context can do; `es2_ceiling` holds an ES 3.x context to ES 2.0's
    /// rules (see [`Caps::es2`]).
    pub(crate) fn probe(gl: &glow::Context, es2_ceiling: bool) -> Caps {
        let Level {
            major,
            minor,
            embedded,
            es2,
            core_profile,
            glsl_version,
            glsl,
            dialect,
        } = Level::probe(gl, es2_ceiling);
        // SAFETY: plain queries on a current context.
        unsafe {
            let ext = gl.supported_extensions();
            // WebGL names its extensions without the "GL_" prefix.
            let has = |names: &[&str]| {
                names.iter().any(|n| {
                    ext.contains(*n) || n.strip_prefix("GL_").is_some_and(|s| ext.contains(s))
                })
            };
            let desktop_at_least = |a: u32, b: u32| !embedded && (major, minor) >= (a, b);
            let es3 = embedded && !es2;
            // Framebuffer objects are core in ES 2.0.
            let fbo = embedded
                || desktop_at_least(3, 0)
                || has(&["GL_ARB_framebuffer_object", "GL_EXT_framebuffer_object"]);
            let mut vp = [0i32; 2];
            gl.get_parameter_i32_slice(glow::MAX_VIEWPORT_DIMS, &mut vp);
            let max_varying_floats = if embedded || core_profile {
                gl.get_parameter_i32(glow::MAX_VARYING_VECTORS) as u32 * 4
            } else {
                gl.get_parameter_i32(glow::MAX_VARYING_FLOATS) as u32
            };
            // The COMPONENTS queries exist in GL 2.0+, 3.3 core and ES 3.0; where a driver
            // answers 0 (or an error), the VECTORS form (ES, GL 4.1+) times 4 is used.
            let uniforms = |components: u32, vectors: u32| {
                let c = gl.get_parameter_i32(components).max(0) as u32;
                if c > 0 {
                    c
                } else {
                    gl.get_parameter_i32(vectors).max(0) as u32 * 4
                }
            };
            let max_vertex_uniform_components = uniforms(
                glow::MAX_VERTEX_UNIFORM_COMPONENTS,
                glow::MAX_VERTEX_UNIFORM_VECTORS,
            );
            let max_fragment_uniform_components = uniforms(
                glow::MAX_FRAGMENT_UNIFORM_COMPONENTS,
                glow::MAX_FRAGMENT_UNIFORM_VECTORS,
            );
            let max_vertex_attribs = gl.get_parameter_i32(glow::MAX_VERTEX_ATTRIBS).max(0) as u32;
            let max_renderbuffer_size = if fbo {
                gl.get_parameter_i32(glow::MAX_RENDERBUFFER_SIZE) as u32
            } else {
                0
            };
            // Drain errors from queries a profile does not know (e.g. profile mask on 2.1).
            while gl.get_error() != glow::NO_ERROR {}
            Caps {
                version: gl.get_parameter_string(glow::VERSION),
                renderer: gl.get_parameter_string(glow::RENDERER),
                vendor: gl.get_parameter_string(glow::VENDOR),
                glsl_version,
                major,
                minor,
                embedded,
                core_profile,
                glsl,
                dialect,
                es2,
                depth24: !es2 || has(&["GL_OES_depth24"]),
                derivatives: !es2 || has(&["GL_OES_standard_derivatives"]),
                frag_depth: !es2 || has(&["GL_EXT_frag_depth"]),
                fbo,
                vao: es3 || desktop_at_least(3, 0) || has(VAO_EXTENSIONS),
                // Depth textures and shadow comparison are core since GL 1.4 (ARB_depth_texture,
                // ARB_shadow), so they are not always listed as extensions.
                depth_texture: es3 || desktop_at_least(1, 4) || has(DEPTH_TEXTURE_EXTENSIONS),
                // ES 2.0's shadow lookups compare in the shader (WebGL 1 has no shadow
                // samplers): the depth texture keeps no compare mode there.
                shadow_compare: !es2 && (es3 || desktop_at_least(1, 4) || has(&["GL_ARB_shadow"])),
                float_textures: es3 || desktop_at_least(3, 0) || has(&["GL_ARB_texture_float"]),
                // GLSL ES 1.00 spells explicit-LOD lookups texture2DLodEXT: not used there.
                texture_lod: !es2
                    && (es3
                        || glsl >= (1, 30)
                        || has(&["GL_ARB_shader_texture_lod", "GL_EXT_shader_texture_lod"])),
                uint_indices: !embedded || es3 || has(&["GL_OES_element_index_uint"]),
                instancing: es3 || desktop_at_least(3, 3),
                cube_shadow: es3 || (!embedded && glsl >= (1, 30)),
                generate_mipmap: fbo,
                timer_query: desktop_at_least(3, 3) || has(&["GL_ARB_timer_query"]),
                max_texture_size: gl.get_parameter_i32(glow::MAX_TEXTURE_SIZE) as u32,
                max_texture_units: gl.get_parameter_i32(glow::MAX_TEXTURE_IMAGE_UNITS).max(0)
                    as u32,
                half_float_textures: es3
                    || desktop_at_least(3, 0)
                    || (has(&["GL_ARB_texture_float"]) && has(&["GL_ARB_half_float_pixel"])),
                rg_textures: es3 || desktop_at_least(3, 0) || has(&["GL_ARB_texture_rg"]),
                srgb_textures: !es2
                    && (es3 || desktop_at_least(2, 1) || has(&["GL_EXT_texture_sRGB"])),
                seamless_cube: desktop_at_least(3, 2) || has(&["GL_ARB_seamless_cube_map"]),
                depth_stencil: es3
                    || desktop_at_least(3, 0)
                    || has(&["GL_EXT_packed_depth_stencil", "GL_OES_packed_depth_stencil"]),
                pack_invert: !embedded && has(&["GL_MESA_pack_invert"]),
                float_render: desktop_at_least(3, 0)
                    || (es3 && has(&["GL_EXT_color_buffer_float"])),
                max_samples: if es3 || desktop_at_least(3, 0) {
                    gl.get_parameter_i32(glow::MAX_SAMPLES).max(0) as u32
                } else {
                    0
                },
                max_renderbuffer_size,
                max_viewport: (vp[0] as u32, vp[1] as u32),
                max_varying_floats,
                max_vertex_uniform_components,
                max_fragment_uniform_components,
                max_vertex_attribs,
                extension_count: ext.len(),
            }
        }
    }

    /// Whether shadow maps can be drawn and looked up: depth textures, compared by the
    /// sampler or, on ES 2.0, in the shader; or, without depth textures, depth packed into
    /// RGBA8 ([`Caps::packed_shadow`]).
    pub(crate) fn shadow_maps(&self) -> bool {
        self.depth_texture_shadows() || self.packed_shadow()
    }

    /// Shadow maps in depth textures: compared by the sampler, or in the shader on ES 2.0.
    fn depth_texture_shadows(&self) -> bool {
        self.depth_texture && (self.shadow_compare || self.es2)
    }

    /// Shadow maps without depth textures (WebGL 1 without WEBGL_depth_texture): the light's
    /// depth is written into an RGBA8 colour texture, 8 bits a channel (`packdepth.glsl`),
    /// and compared in the shader as ES 2.0's depth textures are. Needs framebuffer objects
    /// (ES 2.0 core) to draw into the texture.
    pub(crate) fn packed_shadow(&self) -> bool {
        !self.depth_texture && self.fbo
    }

    /// Whether meshes keep their attribute bindings in vertex array objects (else they are
    /// bound per draw): for the web page's info.
    pub fn vertex_arrays(&self) -> bool {
        self.vao
    }

    /// How shadow maps are kept, for `--info` and the web page's info.
    pub fn shadow_store(&self) -> &'static str {
        if self.depth_texture_shadows() {
            "depth textures"
        } else if self.packed_shadow() {
            "depth packed into RGBA8 (no depth textures)"
        } else {
            "none"
        }
    }

    /// One line per fact, for `glview --info`.
    pub fn report(&self) -> String {
        let yes = |b: bool| if b { "yes" } else { "no" };
        format!(
            "GL_VERSION: {}\nGLSL: {} (dialect {})\nrenderer: {} ({})\nprofile: {}\n\
             framebuffer objects: {}\nvertex array objects: {}\ndepth textures: {}\n\
             shadow compare: {}\nshadow maps: {}\nfloat textures: {}\nexplicit-LOD lookups: {}\n\
             32-bit indices: {}\ninstanced arrays: {}\ncube shadow lookups: {}\ntimer queries: {}\n\
             max texture size: {}\ntexture units: {}\n16-bit float textures: {}\n\
             RG textures: {}\nsRGB textures: {}\nseamless cube maps: {}\n\
             depth+stencil: {}\nfloat render targets: {}\nmax samples (MSAA): {}\n\
             max viewport: {}x{}\nmax varying floats: {}\n\
             max vertex uniform components: {}\nmax fragment uniform components: {}\n\
             extensions: {}",
            self.version,
            self.glsl_version,
            self.dialect.name(),
            self.renderer,
            self.vendor,
            if self.es2 {
                "ES, held to ES 2.0's rules"
            } else if self.embedded {
                "ES"
            } else if self.core_profile {
                "core"
            } else {
                "compatibility"
            },
            yes(self.fbo),
            yes(self.vao),
            yes(self.depth_texture),
            yes(self.shadow_compare),
            self.shadow_store(),
            yes(self.float_textures),
            yes(self.texture_lod),
            yes(self.uint_indices),
            yes(self.instancing),
            yes(self.cube_shadow),
            yes(self.timer_query),
            self.max_texture_size,
            self.max_texture_units,
            yes(self.half_float_textures),
            yes(self.rg_textures),
            yes(self.srgb_textures),
            yes(self.seamless_cube),
            yes(self.depth_stencil),
            yes(self.float_render),
            self.max_samples,
            self.max_viewport.0,
            self.max_viewport.1,
            self.max_varying_floats,
            self.max_vertex_uniform_components,
            self.max_fragment_uniform_components,
            self.extension_count
        )
    }
}

#[cfg(test)]
mod tests {
    use super::parse_version;

    #[test]
    fn versions() {
        assert_eq!(parse_version("1.20"), Some((1, 20)));
        assert_eq!(parse_version("OpenGL ES GLSL ES 3.00"), Some((3, 0)));
        assert_eq!(parse_version("4.50"), Some((4, 50)));
        assert_eq!(parse_version("2.1 Mesa 22.3.6"), Some((2, 1)));
    }
}
