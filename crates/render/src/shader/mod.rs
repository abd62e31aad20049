//! Shader assembly: a dialect header (`#version` plus a few macros), feature `#define`s, then
//! the body from `shaders_gl/` with `#include "x.glsl"` resolved. One body serves GLSL 1.20,
//! GLSL ES 3.00, GLSL 3.30 and GLSL ES 1.00 (WebGL 1). Sources are compiled into the binary.
use crate::gpu::Dialect;

pub mod cache;

/// (name, source) of every shader file, embedded at build time.
pub(crate) const SOURCES: &[(&str, &str)] = &[
    ("lit.vert", include_str!("../../../../shaders_gl/lit.vert")),
    ("lit.frag", include_str!("../../../../shaders_gl/lit.frag")),
    (
        "depth.vert",
        include_str!("../../../../shaders_gl/depth.vert"),
    ),
    (
        "depth.frag",
        include_str!("../../../../shaders_gl/depth.frag"),
    ),
    (
        "show_depth.vert",
        include_str!("../../../../shaders_gl/show_depth.vert"),
    ),
    (
        "show_depth.frag",
        include_str!("../../../../shaders_gl/show_depth.frag"),
    ),
    (
        "instance.glsl",
        include_str!("../../../../shaders_gl/include/instance.glsl"),
    ),
    (
        "skin.glsl",
        include_str!("../../../../shaders_gl/include/skin.glsl"),
    ),
    (
        "lighting.glsl",
        include_str!("../../../../shaders_gl/include/lighting.glsl"),
    ),
    (
        "falloff.glsl",
        include_str!("../../../../shaders_gl/include/falloff.glsl"),
    ),
    (
        "shadow.glsl",
        include_str!("../../../../shaders_gl/include/shadow.glsl"),
    ),
    (
        "output.glsl",
        include_str!("../../../../shaders_gl/include/output.glsl"),
    ),
    (
        "material.glsl",
        include_str!("../../../../shaders_gl/include/material.glsl"),
    ),
    (
        "normalmap.glsl",
        include_str!("../../../../shaders_gl/include/normalmap.glsl"),
    ),
    (
        "rgbm.glsl",
        include_str!("../../../../shaders_gl/include/rgbm.glsl"),
    ),
    (
        "brdf.glsl",
        include_str!("../../../../shaders_gl/include/brdf.glsl"),
    ),
    (
        "iridescence.glsl",
        include_str!("../../../../shaders_gl/include/iridescence.glsl"),
    ),
    (
        "anisotropy.glsl",
        include_str!("../../../../shaders_gl/include/anisotropy.glsl"),
    ),
    (
        "ibl.glsl",
        include_str!("../../../../shaders_gl/include/ibl.glsl"),
    ),
    ("pbr.vert", include_str!("../../../../shaders_gl/pbr.vert")),
    ("pbr.frag", include_str!("../../../../shaders_gl/pbr.frag")),
    (
        "skybox.vert",
        include_str!("../../../../shaders_gl/skybox.vert"),
    ),
    (
        "fill.frag",
        include_str!("../../../../shaders_gl/fill.frag"),
    ),
    (
        "edges.vert",
        include_str!("../../../../shaders_gl/edges.vert"),
    ),
    (
        "edges.frag",
        include_str!("../../../../shaders_gl/edges.frag"),
    ),
    (
        "grid.vert",
        include_str!("../../../../shaders_gl/grid.vert"),
    ),
    (
        "grid.frag",
        include_str!("../../../../shaders_gl/grid.frag"),
    ),
    (
        "prefilter.frag",
        include_str!("../../../../shaders_gl/prefilter.frag"),
    ),
    (
        "overlay.frag",
        include_str!("../../../../shaders_gl/overlay.frag"),
    ),
    (
        "logdepth.glsl",
        include_str!("../../../../shaders_gl/include/logdepth.glsl"),
    ),
    (
        "skybox.frag",
        include_str!("../../../../shaders_gl/skybox.frag"),
    ),
    (
        "bright.frag",
        include_str!("../../../../shaders_gl/post/bright.frag"),
    ),
    (
        "down.frag",
        include_str!("../../../../shaders_gl/post/down.frag"),
    ),
    (
        "blur.frag",
        include_str!("../../../../shaders_gl/post/blur.frag"),
    ),
    (
        "composite.frag",
        include_str!("../../../../shaders_gl/post/composite.frag"),
    ),
    (
        "fxaa.frag",
        include_str!("../../../../shaders_gl/post/fxaa.frag"),
    ),
    (
        "box.frag",
        include_str!("../../../../shaders_gl/post/box.frag"),
    ),
    (
        "packdepth.glsl",
        include_str!("../../../../shaders_gl/include/packdepth.glsl"),
    ),
    (
        "stereo.frag",
        include_str!("../../../../shaders_gl/post/stereo.frag"),
    ),
    (
        "attributes.vert",
        include_str!("../../../../shaders_gl/attributes.vert"),
    ),
    (
        "attributes.frag",
        include_str!("../../../../shaders_gl/attributes.frag"),
    ),
];

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Stage {
    Vertex,
    Fragment,
}

fn source(name: &str) -> &'static str {
    SOURCES
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, s)| *s)
        .unwrap_or_else(|| panic!("shader {name} is not embedded (add it to shader::SOURCES)"))
}

/// The header that makes one body valid in each dialect. GLSL 1.20 rejects `precision`
/// statements, so they only appear for ES, where `highp` keeps llvmpipe from evaluating
/// fragments at half precision.
pub(crate) fn header(dialect: Dialect, stage: Stage) -> &'static str {
    match (dialect, stage) {
        (Dialect::Glsl120, Stage::Vertex) => {
            "#version 120\n#define IN attribute\n#define OUT varying\n"
        }
        (Dialect::Glsl120, Stage::Fragment) => {
            "#version 120\n#define IN varying\n#define FRAG_COLOR gl_FragColor\n\
             #define TEX2D texture2D\n#define TEXCUBE textureCube\n\
             #define SHADOW2D(s, c) shadow2D(s, c).r\n#define FRAG_DEPTH gl_FragDepth\n#define HAS_FRAG_DEPTH 1\n"
        }
        (Dialect::Glsl300Es, Stage::Vertex) => {
            "#version 300 es\nprecision highp float;\n#define IN in\n#define OUT out\n"
        }
        (Dialect::Glsl300Es, Stage::Fragment) => {
            "#version 300 es\n#ifdef GL_FRAGMENT_PRECISION_HIGH\nprecision highp float;\n\
             #else\nprecision mediump float;\n#endif\nprecision highp sampler2DShadow;\n\
             #define IN in\nout vec4 glviewFragColor;\n#define FRAG_COLOR glviewFragColor\n\
             #define TEX2D texture\n#define TEXCUBE texture\n\
             #define SHADOW2D(s, c) texture(s, c)\n#define FRAG_DEPTH gl_FragDepth\n#define HAS_FRAG_DEPTH 1\n"
        }
        (Dialect::Glsl100Es, Stage::Vertex) => {
            "#version 100\nprecision highp float;\n#define IN attribute\n#define OUT varying\n"
        }
        // ES 2.0 (WebGL 1) has no shadow samplers: the shadow map is a plain depth texture,
        // compared in the shader (shadow.glsl, SHADOW_COMPARE_IN_SHADER); dFdx is
        // OES_standard_derivatives', a written depth EXT_frag_depth's; uniform arrays are
        // indexed by constants and loop indices only (Appendix A, which WebGL enforces).
        // Samplers are highp where floats are: ES 1.00's default for them is lowp, and Mesa
        // then returns a depth texel at half-float precision (2^-11 steps near depth 1: a
        // point light's atlas, its depths crowded there, came out shadowed all over) and the
        // BRDF table's low byte is lost under the high byte's rounding.
        (Dialect::Glsl100Es, Stage::Fragment) => {
            "#version 100\n#extension GL_OES_standard_derivatives : enable\n\
             #extension GL_EXT_frag_depth : enable\n#define FRAG_DEPTH gl_FragDepthEXT\n\
             #ifdef GL_EXT_frag_depth\n#define HAS_FRAG_DEPTH 1\n#endif\n\
             #ifdef GL_FRAGMENT_PRECISION_HIGH\nprecision highp float;\n\
             precision highp sampler2D;\nprecision highp samplerCube;\n\
             #else\nprecision mediump float;\n#endif\n\
             #define IN varying\n#define FRAG_COLOR gl_FragColor\n\
             #define TEX2D texture2D\n#define TEXCUBE textureCube\n\
             #define SHADOW_SAMPLER sampler2D\n#define SHADOW_COMPARE_IN_SHADER 1\n\
             #define CONST_INDEX_ONLY 1\n"
        }
        (Dialect::Glsl330, Stage::Vertex) => "#version 330 core\n#define IN in\n#define OUT out\n",
        (Dialect::Glsl330, Stage::Fragment) => {
            "#version 330 core\n#define IN in\nout vec4 glviewFragColor;\n\
             #define FRAG_COLOR glviewFragColor\n#define TEX2D texture\n\
             #define TEXCUBE texture\n#define SHADOW2D(s, c) texture(s, c)\n\
             #define FRAG_DEPTH gl_FragDepth\n#define HAS_FRAG_DEPTH 1\n"
        }
    }
}

/// Replaces `#include "name"` lines by the named file, recursively; a file already included
/// is skipped (include guards for free, and no cycle can recurse forever).
fn resolve_includes(body: &str) -> String {
    fn walk(body: &str, seen: &mut Vec<String>, out: &mut String) {
        for line in body.lines() {
            let t = line.trim();
            if let Some(name) = t
                .strip_prefix("#include")
                .map(|r| r.trim().trim_matches('"'))
            {
                if !seen.iter().any(|s| s == name) {
                    seen.push(name.to_string());
                    walk(source(name), seen, out);
                }
            } else {
                out.push_str(line);
                out.push('\n');
            }
        }
    }
    let mut out = String::with_capacity(body.len() * 2);
    walk(body, &mut Vec::new(), &mut out);
    out
}

/// Header + `#define NAME VALUE` lines + body.
pub(crate) fn assemble(
    dialect: Dialect,
    stage: Stage,
    defines: &[(&str, String)],
    file: &str,
) -> String {
    let mut s = String::from(header(dialect, stage));
    for (name, value) in defines {
        s.push_str(&format!("#define {name} {value}\n"));
    }
    s.push_str(&resolve_includes(source(file)));
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_version_lines_in_bodies() {
        for (name, src) in SOURCES {
            assert!(!src.contains("#version"), "{name} must not carry #version");
        }
    }

    #[test]
    fn nested_includes_resolve_once() {
        let s = assemble(Dialect::Glsl330, Stage::Fragment, &[], "pbr.frag");
        assert!(!s.contains("#include"));
        // brdf.glsl is included by pbr.frag and by ibl.glsl: once in the output.
        assert_eq!(s.matches("float glviewD_GGX(").count(), 1, "{s}");
    }

    #[test]
    fn includes_resolve() {
        let s = assemble(
            Dialect::Glsl120,
            Stage::Fragment,
            &[("NUM_LIGHTS", "1".into())],
            "lit.frag",
        );
        assert!(s.starts_with("#version 120\n"));
        assert!(!s.contains("#include"));
        assert!(s.contains("#define NUM_LIGHTS 1\n"));
    }
}
