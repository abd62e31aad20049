//! Exporters' MTL habits that would make a model render wrong, handled at load time with a
//! warning naming file and line: `Tr 1` / `d 0` meaning opaque, `Ns 0` with a specular colour
//! meaning matte. Also the `--check` account of every texture statement.
use crate::loaders::obj::repair::MtlLines;
use std::path::Path;
use {crate::model::material::Material, crate::model::Warning};

/// Where a material came from: its MTL file and the lines of its statements.
pub(crate) type Origin<'a> = Option<(&'a Path, &'a MtlLines)>;

fn warn(warnings: &mut Vec<Warning>, origin: Origin, line: Option<usize>, msg: String) {
    if let Some((file, _)) = origin {
        warnings.push(Warning {
            file: file.to_path_buf(),
            line,
            message: msg,
        });
    }
}

/// A material that would be fully invisible (`d 0`, `Tr 1`) is drawn opaque: many exporters
/// write those values meaning opaque, and a model vanishing without a word is never what a
/// user wants. `honor` keeps the file's value.
pub(crate) fn fix_invisible(m: &mut Material, origin: Origin, honor: bool, w: &mut Vec<Warning>) {
    if !matches!(m.opacity, Some(a) if a <= 0.0) || honor {
        return;
    }
    m.opacity = None;
    warn(
        w,
        origin,
        origin.and_then(|(_, l)| l.opacity),
        format!(
            "material {}: fully transparent (d 0 / Tr 1), which exporters often write meaning \
             opaque: drawn opaque (--honor-transparency keeps it invisible)",
            m.name
        ),
    );
}

/// `Ns 0` (or negative) with a specular colour: the formula's limit x⁰ = 1 turns every lit
/// point white. Exporters write it for the roughest surface (Blender's exporter maps
/// roughness 1 to Ns 0), so the material is made matte (Ks 0).
pub(crate) fn fix_ns_zero(m: &mut Material, origin: Origin, w: &mut Vec<Warning>) {
    let Some(p) = &mut m.phong else {
        return;
    };
    if p.shininess > 0.0 || p.specular.iter().all(|&k| k <= 0.0) || origin.is_none() {
        return;
    }
    p.specular = [0.0; 3];
    let shininess = p.shininess;
    warn(
        w,
        origin,
        origin.and_then(|(_, l)| l.shininess),
        format!(
            "material {}: Ns {} with a specular colour means the roughest surface: drawn matte \
             (Ks 0)",
            m.name, shininess
        ),
    );
}

/// What glview does with each texture statement.
fn map_outcome(keyword: &str) -> &'static str {
    match keyword {
        "map_Kd" => "base colour",
        "map_Bump" | "map_bump" | "bump" | "norm" => "not used (no bump or normal mapping)",
        "map_Ns" | "map_Pr" | "map_Pm" | "map_Ks" => "not used (specular/roughness maps)",
        "map_d" => "not used (opacity from d/Tr only)",
        "map_Ka" => "not used (ambient follows map_Kd)",
        "map_Ke" => "not used (emission from Ke only)",
        _ => "not used",
    }
}

/// One `--check` line per texture statement of the material.
pub(crate) fn map_report(m: &Material, origin: Origin) -> Vec<String> {
    let Some((file, lines)) = origin else {
        return Vec::new();
    };
    lines
        .maps
        .iter()
        .map(|(line, kw, arg)| {
            let what = if kw == "map_Kd" && m.base_color_texture.is_none() {
                "not loaded (see warnings)"
            } else {
                map_outcome(kw)
            };
            format!(
                "map: {}:{line}: material {}: {kw} {arg:?} -> {what}",
                file.display(),
                m.name
            )
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::material::PhongTerms;

    #[test]
    fn invisible_becomes_opaque_with_line() {
        let lines = MtlLines {
            opacity: Some(4),
            ..Default::default()
        };
        let mut m = Material {
            opacity: Some(0.0),
            ..Default::default()
        };
        let mut w = Vec::new();
        fix_invisible(&mut m, Some((Path::new("a.mtl"), &lines)), false, &mut w);
        assert_eq!(m.opacity, None);
        assert!(w[0].to_string().starts_with("a.mtl:4: material default"));
        let mut m = Material {
            opacity: Some(0.0),
            ..Default::default()
        };
        fix_invisible(&mut m, Some((Path::new("a.mtl"), &lines)), true, &mut w);
        assert_eq!(m.opacity, Some(0.0));
    }

    #[test]
    fn ns_zero_is_matte() {
        let lines = MtlLines {
            shininess: Some(2),
            ..Default::default()
        };
        let mut m = Material::with_phong(PhongTerms {
            specular: [0.5; 3],
            ..Default::default()
        });
        let mut w = Vec::new();
        fix_ns_zero(&mut m, Some((Path::new("a.mtl"), &lines)), &mut w);
        assert_eq!(m.phong_terms().specular, [0.0; 3]);
        assert_eq!(w[0].line, Some(2));
        // Materials built in code (no MTL) keep the formula's Ns 0 meaning.
        let mut m = Material::with_phong(PhongTerms {
            specular: [0.5; 3],
            ..Default::default()
        });
        fix_ns_zero(&mut m, None, &mut w);
        assert_eq!(m.phong_terms().specular, [0.5; 3]);
    }
}
