//! KHR_lights_punctual: the lights a glTF file places with its nodes, read from the JSON by
//! hand (the `gltf` crate's typed reader would refuse the whole file over one bad light).
//! Each light is placed by its node's world transform (position, −Z direction; the node's
//! scale does not change the light, as the extension says) and turned to the up axis like the
//! geometry. A malformed light is a warning, never an error: a negative or non-finite
//! intensity, an unknown type or a bad light index skips it; a bad range is dropped (the light
//! reaches everywhere); cone angles out of order or out of 0..π/2 are clamped; a colour
//! outside 0..1 is clamped. More than [`MAX_LIGHTS`] lights: the brightest at the model's
//! centre are kept, and the others named in a warning.
use crate::model::lights::{FileLight, FileLightKind, MAX_LIGHTS};
use crate::model::UpAxis;
use glam::{DMat4, DVec3};
use serde_json::Value;

const EXT: &str = "KHR_lights_punctual";

/// [`read`] for the loader: the warnings as the file's.
pub(crate) fn read_into(
    doc: &gltf::Document,
    nodes: &[(usize, DMat4)],
    (up, centre): (UpAxis, DVec3),
    path: &std::path::Path,
    warnings: &mut Vec<crate::model::Warning>,
) -> Vec<FileLight> {
    let mut notes = Vec::new();
    let lights = read(doc, nodes, up, centre, &mut notes);
    warnings.extend(notes.into_iter().map(|message| crate::model::Warning {
        file: path.to_path_buf(),
        line: None,
        message,
    }));
    lights
}

/// The lights of the scene's `nodes` (`gltf_graph::nodes`: index and world transform, the
/// walk the meshes and cameras are read from) in file coordinates (the up axis turned), at
/// most [`MAX_LIGHTS`], brightest at `centre` first; problems as warning messages.
pub(crate) fn read(
    doc: &gltf::Document,
    nodes: &[(usize, DMat4)],
    up: UpAxis,
    centre: DVec3,
    warnings: &mut Vec<String>,
) -> Vec<FileLight> {
    let Some(defs) = doc.extension_value(EXT).and_then(|v| v.get("lights")) else {
        return Vec::new();
    };
    let defs = defs.as_array().map_or(&[][..], Vec::as_slice);
    let all: Vec<gltf::Node> = doc.nodes().collect();
    let mut out = Vec::new();
    for &(n, world) in nodes {
        let Some(index) = all
            .get(n)
            .and_then(|node| node.extension_value(EXT))
            .and_then(|v| v.get("light"))
        else {
            continue;
        };
        let def = index
            .as_u64()
            .and_then(|i| defs.get(usize::try_from(i).ok()?));
        let Some(def) = def else {
            warnings.push(format!(
                "node {n}: {EXT} light {index} does not exist; ignored"
            ));
            continue;
        };
        let i = index.as_u64().unwrap_or_default();
        match light(def, i, n, world, up, warnings) {
            Ok(l) => out.push(l),
            Err(e) => warnings.push(format!("node {n}: {EXT} light {i}: {e}; ignored")),
        }
    }
    // In node order (the walk's is a stack's): the order `--check` lists and shadows take.
    out.sort_by_key(|l| l.node);
    keep_brightest(out, centre, warnings)
}

/// One light definition placed by `world`.
fn light(
    def: &Value,
    index: u64,
    node: usize,
    world: DMat4,
    up: UpAxis,
    warnings: &mut Vec<String>,
) -> Result<FileLight, String> {
    let what = format!("node {node}: {EXT} light {index}");
    let kind = match def.get("type").and_then(Value::as_str) {
        Some("directional") => FileLightKind::Directional,
        Some("point") => FileLightKind::Point,
        Some("spot") => spot_cone(def.get("spot"), &what, warnings),
        Some(t) => return Err(format!("unknown type {t:?}")),
        None => return Err("no type".into()),
    };
    let intensity = number(def.get("intensity"), 1.0).ok_or("intensity is not a number")?;
    if !(intensity.is_finite() && intensity >= 0.0) {
        return Err(format!("intensity {intensity} is not a finite number ≥ 0"));
    }
    let color = colour(def.get("color"), &what, warnings)?;
    let range = match def.get("range") {
        None => None,
        Some(r) => match r.as_f64() {
            Some(r) if r.is_finite() && r > 0.0 => Some(r as f32),
            _ => {
                warnings.push(format!(
                    "{what}: range {r} is not a number > 0; the light reaches everywhere"
                ));
                None
            }
        },
    };
    let position = up.rotate(world.transform_point3(DVec3::ZERO));
    let direction = up.rotate(world.transform_vector3(DVec3::NEG_Z));
    let direction = direction.try_normalize();
    if kind != FileLightKind::Point && direction.is_none() {
        return Err("its node's transform leaves it no direction".into());
    }
    if !position.is_finite() {
        return Err("its node's transform places it nowhere".into());
    }
    let name = match def.get("name").and_then(Value::as_str) {
        Some(n) => n.to_string(),
        None => format!("light {index}"),
    };
    Ok(FileLight {
        name,
        node,
        kind,
        position,
        direction: direction.unwrap_or(DVec3::NEG_Z),
        color,
        intensity: intensity as f32,
        range,
    })
}

/// A number member, or `default` when absent; None when present but not a number.
fn number(v: Option<&Value>, default: f64) -> Option<f64> {
    v.map_or(Some(default), Value::as_f64)
}

/// The spot's cone (defaults 0 and π/4), clamped to 0 ≤ inner ≤ outer ≤ π/2 with a warning.
fn spot_cone(spot: Option<&Value>, what: &str, warnings: &mut Vec<String>) -> FileLightKind {
    let get = |k, d| {
        number(spot.and_then(|s| s.get(k)), d)
            .filter(|a| a.is_finite())
            .unwrap_or(f64::NAN)
    };
    let (inner, outer) = (
        get("innerConeAngle", 0.0),
        get("outerConeAngle", 0.25 * std::f64::consts::PI),
    );
    let half = std::f64::consts::FRAC_PI_2;
    let o = if outer.is_nan() {
        0.25 * std::f64::consts::PI
    } else {
        outer.clamp(0.0, half)
    };
    let i = if inner.is_nan() {
        0.0
    } else {
        inner.clamp(0.0, o)
    };
    if (i, o) != (inner, outer) {
        warnings.push(format!(
            "{what}: cone angles {inner} and {outer} are not 0 ≤ inner ≤ outer ≤ π/2; \
             drawn with {i} and {o}"
        ));
    }
    FileLightKind::Spot {
        inner: i as f32,
        outer: o as f32,
    }
}

/// The light's linear colour (default white); components outside 0..1 clamped with a warning.
fn colour(v: Option<&Value>, what: &str, warnings: &mut Vec<String>) -> Result<[f32; 3], String> {
    let Some(v) = v else {
        return Ok([1.0; 3]);
    };
    let c: Vec<f64> = v
        .as_array()
        .map(|a| a.iter().filter_map(Value::as_f64).collect())
        .unwrap_or_default();
    let [r, g, b] = c[..] else {
        return Err("color is not three numbers".into());
    };
    if ![r, g, b].iter().all(|x| x.is_finite()) {
        return Err("color is not finite".into());
    }
    let k = [r, g, b].map(|x| x.clamp(0.0, 1.0));
    if k != [r, g, b] {
        warnings.push(format!("{what}: color {r},{g},{b} clamped to 0..1"));
    }
    Ok(k.map(|x| x as f32))
}

/// The illuminance (weighted by the brightest channel) a light gives at `centre`: how the
/// lights kept are chosen when there are too many.
fn brightness(l: &FileLight, centre: DVec3) -> f64 {
    let c = l.color.iter().copied().fold(0.0f32, f32::max);
    let e = l.falloff().at(l.position - centre);
    let e = if l.kind == FileLightKind::Directional {
        1.0
    } else {
        e
    };
    f64::from(c) * f64::from(l.intensity) * e
}

/// At most [`MAX_LIGHTS`], the brightest first (stable: file order among equals).
fn keep_brightest(
    mut lights: Vec<FileLight>,
    centre: DVec3,
    warnings: &mut Vec<String>,
) -> Vec<FileLight> {
    if lights.len() <= MAX_LIGHTS {
        return lights;
    }
    lights.sort_by(|a, b| brightness(b, centre).total_cmp(&brightness(a, centre)));
    let dropped: Vec<String> = lights[MAX_LIGHTS..]
        .iter()
        .map(|l| format!("{:?}", l.name))
        .collect();
    warnings.push(format!(
        "{EXT}: {} lights, glview draws at most {MAX_LIGHTS}: the brightest at the model's \
         centre are drawn, not {}",
        lights.len(),
        dropped.join(", ")
    ));
    lights.truncate(MAX_LIGHTS);
    lights
}

#[cfg(test)]
mod tests {
    use super::*;

    fn light_json(json: &str) -> Result<FileLight, String> {
        let v: Value = serde_json::from_str(json).unwrap();
        let mut w = Vec::new();
        light(&v, 0, 0, DMat4::IDENTITY, UpAxis::PosY, &mut w)
    }

    #[test]
    fn malformed_lights_are_skipped_or_clamped() {
        assert!(light_json(r#"{"type": "point", "intensity": -1}"#).is_err());
        assert!(light_json(r#"{"type": "point", "intensity": "x"}"#).is_err());
        assert!(light_json(r#"{"type": "area"}"#).is_err());
        assert!(light_json(r#"{"intensity": 3}"#).is_err());
        assert!(light_json(r#"{"type": "point", "color": [1, 2]}"#).is_err());
        let l = light_json(r#"{"type": "point", "range": -2, "color": [2, 0.5, -1]}"#).unwrap();
        assert_eq!(
            (l.range, l.color, l.intensity),
            (None, [1.0, 0.5, 0.0], 1.0)
        );
        let s = light_json(
            r#"{"type": "spot", "spot": {"innerConeAngle": 1.0, "outerConeAngle": 0.5}}"#,
        )
        .unwrap();
        assert_eq!(
            s.kind,
            FileLightKind::Spot {
                inner: 0.5,
                outer: 0.5
            }
        );
        let s = light_json(r#"{"type": "spot"}"#).unwrap();
        assert_eq!(
            s.kind,
            FileLightKind::Spot {
                inner: 0.0,
                outer: std::f32::consts::FRAC_PI_4
            }
        );
        assert_eq!(s.direction, DVec3::NEG_Z);
    }

    #[test]
    fn node_transforms_place_and_aim_lights() {
        let v: Value = serde_json::from_str(r#"{"type": "spot"}"#).unwrap();
        // Turned 90° about +X (−Z becomes +Y), at (1,2,3), scaled 5 (which lights ignore).
        let world = DMat4::from_scale_rotation_translation(
            DVec3::splat(5.0),
            glam::DQuat::from_rotation_x(std::f64::consts::FRAC_PI_2),
            DVec3::new(1.0, 2.0, 3.0),
        );
        let l = light(&v, 0, 0, world, UpAxis::PosY, &mut Vec::new()).unwrap();
        assert_eq!(l.position, DVec3::new(1.0, 2.0, 3.0));
        assert!((l.direction - DVec3::Y).length() < 1e-12, "{}", l.direction);
        let z = light(&v, 0, 0, world, UpAxis::PosZ, &mut Vec::new()).unwrap();
        assert_eq!(z.position, UpAxis::PosZ.rotate(l.position));
    }
}
