//! Lights, in the scene's local (re-centred) coordinates.
use glam::{DVec3, Vec3};
pub use glview_scene::model::lights::{FileLight, FileLightKind};

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightKind {
    /// A point light at this position.
    Point(Vec3),
    /// A directional light travelling in this (unit) direction: `dir:0,-1,0` shines down.
    Directional(Vec3),
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Light {
    pub kind: LightKind,
    /// The colour at full strength: glview's own lights give it as typed; a file's light
    /// (KHR_lights_punctual) gives colour × intensity / π (`scene::gltf_lights`).
    pub color: Vec3,
    /// How the light weakens with distance and off its axis: none for glview's own lights.
    pub falloff: Falloff,
}

impl Light {
    /// A light that does not weaken (glview's own: `--light`, the kit, the headlight).
    pub fn new(kind: LightKind, color: Vec3) -> Light {
        Light {
            kind,
            color,
            falloff: Falloff::NONE,
        }
    }

    /// The colour arriving at `p` (local coordinates): [`Light::color`] times
    /// [`Light::falloff_at`] there.
    pub fn color_at(&self, p: DVec3) -> DVec3 {
        self.color.as_dvec3() * self.falloff_at(p)
    }

    /// The falloff at `p` (local coordinates), in f64: the reference renderer's copy of
    /// falloff.glsl's `glviewFalloff`; 1 for a directional light.
    pub fn falloff_at(&self, p: DVec3) -> f64 {
        match self.kind {
            LightKind::Point(q) => self.falloff.at(q.as_dvec3() - p),
            LightKind::Directional(_) => 1.0,
        }
    }
}

pub use glview_scene::model::lights::{Falloff, Spot, MIN_DISTANCE2};

/// The default kit (no `--light`): key (casts the shadow), fill and headlight colours.
pub(crate) const KIT_KEY: f32 = 0.75;
pub(crate) const KIT_FILL: f32 = 0.3;
pub(crate) const KIT_HEAD: f32 = 0.3;

/// The most lights a frame draws (each may cast a shadow); more is an error at the CLI.
pub use glview_scene::model::lights::MAX_LIGHTS;

/// A light as given on the command line: positions in the file's coordinates, in f64 so a
/// model far from the origin keeps its light exactly where it was put.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightSpec {
    Point(DVec3),
    Directional(DVec3),
}

impl LightSpec {
    /// A placed light's words (`point:X,Y,Z`, `dir:X,Y,Z`), or `none`; through
    /// [`LightOpt`]'s parser, so the messages are one.
    pub fn parse(s: &str) -> Result<Option<LightSpec>, String> {
        match s.parse::<LightOpt>()? {
            LightOpt::Head | LightOpt::Kit | LightOpt::File => Err(format!(
                "light {s:?}: expected point:X,Y,Z, dir:X,Y,Z or none"
            )),
            light => Ok(light.spec()),
        }
    }

    /// The default light when none is given: from above, in front and to the left of the default view.
    pub(crate) fn default_light() -> LightSpec {
        LightSpec::Directional(DVec3::new(0.3, -0.8, -0.55).normalize())
    }

    /// The default light kit's fill: from the other side and a little below the key, so
    /// what the key leaves dark is still readable.
    pub(crate) fn fill_light() -> LightSpec {
        LightSpec::Directional(DVec3::new(-0.45, 0.25, 0.6).normalize())
    }

    pub fn to_local(self, origin: DVec3, color: Vec3) -> Light {
        let kind = match self {
            LightSpec::Point(p) => LightKind::Point((p - origin).as_vec3()),
            LightSpec::Directional(d) => LightKind::Directional(d.as_vec3().normalize()),
        };
        Light::new(kind, color)
    }
}

/// The legacy tier's exposure for a file's lights: the factor on their colours that makes the
/// brightest give the kit's key light (`KIT_KEY`) at the model's centre (a point or spot
/// light as if at least `radius` away, its range and cone aside; a directional light its
/// colour). The tier has no exposure or tone mapping, and a file's photometric values
/// (LightsPunctualLamp's 180 cd lamps 1.5 m away: colour 25) would clip the model to white;
/// the lights keep their ratios and falloff. 1 when no light gives any.
pub fn legacy_scale(lights: &[FileLight], centre: DVec3, radius: f64) -> f32 {
    let brightest = lights
        .iter()
        .map(|l| {
            let c = f64::from(file_light(l, centre).color.max_element());
            match l.kind {
                FileLightKind::Directional => c,
                _ => c / (l.position - centre).length_squared().max(radius * radius),
            }
        })
        .fold(0.0f64, f64::max);
    if brightest > 0.0 && brightest.is_finite() {
        (f64::from(KIT_KEY) / brightest) as f32
    } else {
        1.0
    }
}

/// The frame's light of a file light: colour × intensity / π in both tiers (docs/gltf/lights.md): glview's
/// lights give the diffuse term `Kd · colour · N·L`, the specification's `Kd/π · E · N·L`
/// for an illuminance E, so a file light of E lux (or candela at 1 unit) equals a glview
/// light of colour E/π, and the PBR tier follows the specification exactly.
pub fn file_light(l: &FileLight, origin: DVec3) -> Light {
    let color = Vec3::from(l.color) * (l.intensity / std::f32::consts::PI);
    let at = (l.position - origin).as_vec3();
    let dir = l.direction.as_vec3().normalize_or_zero();
    let falloff = l.falloff();
    match l.kind {
        FileLightKind::Directional => Light::new(LightKind::Directional(dir), color),
        FileLightKind::Point | FileLightKind::Spot { .. } => Light {
            kind: LightKind::Point(at),
            color,
            falloff,
        },
    }
}

/// A `--light` value as given: a light, the camera's headlight, no lights at all, the
/// default kit or the model file's own lights. A direction is kept as typed (made unit when
/// the frame's lights are made), so the option writes back exactly as it was read.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightOpt {
    Point(DVec3),
    Dir(DVec3),
    Head,
    None,
    /// The default kit, even when the file has lights.
    Kit,
    /// The file's lights (glTF KHR_lights_punctual): the default when it has some.
    File,
}

impl std::str::FromStr for LightOpt {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "head" => return Ok(LightOpt::Head),
            "none" => return Ok(LightOpt::None),
            "kit" => return Ok(LightOpt::Kit),
            "file" => return Ok(LightOpt::File),
            _ => {}
        }
        let (kind, rest) = s.split_once(':').ok_or_else(|| {
            format!("light {s:?}: expected point:X,Y,Z, dir:X,Y,Z, head, none, kit or file")
        })?;
        let v = parse_vec3(rest).map_err(|e| format!("light {s:?}: {e}"))?;
        match kind {
            "point" => Ok(LightOpt::Point(v)),
            "dir" if v.length_squared() > 0.0 => Ok(LightOpt::Dir(v)),
            "dir" => Err(format!("light {s:?}: direction is zero")),
            _ => Err(format!("light {s:?}: kind must be point or dir")),
        }
    }
}

impl std::fmt::Display for LightOpt {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            LightOpt::Point(p) => write!(f, "point:{},{},{}", p.x, p.y, p.z),
            LightOpt::Dir(d) => write!(f, "dir:{},{},{}", d.x, d.y, d.z),
            LightOpt::Head => f.write_str("head"),
            LightOpt::None => f.write_str("none"),
            LightOpt::Kit => f.write_str("kit"),
            LightOpt::File => f.write_str("file"),
        }
    }
}

crate::word_value!(LightOpt, "point:X,Y,Z, dir:X,Y,Z, head, none, kit or file");

impl LightOpt {
    /// The light this value places, if it is one (not `head`, `none`, `kit` or `file`): a direction is
    /// made unit here, in f64, as the command line always did.
    pub fn spec(self) -> Option<LightSpec> {
        match self {
            LightOpt::Point(p) => Some(LightSpec::Point(p)),
            LightOpt::Dir(d) => Some(LightSpec::Directional(d.normalize())),
            LightOpt::Head | LightOpt::None | LightOpt::Kit | LightOpt::File => None,
        }
    }
}

/// Parses `X,Y,Z` of finite numbers.
pub(crate) fn parse_vec3(s: &str) -> Result<DVec3, String> {
    let parts: Vec<f64> = s
        .split(',')
        .map(|p| {
            p.trim()
                .parse::<f64>()
                .map_err(|_| format!("{p:?} is not a number"))
        })
        .collect::<Result<_, _>>()?;
    match parts[..] {
        [x, y, z] if parts.iter().all(|v| v.is_finite()) => Ok(DVec3::new(x, y, z)),
        [_, _, _] => Err("values must be finite".into()),
        _ => Err(format!("{s:?}: expected three comma-separated numbers")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parse_lights() {
        assert_eq!(LightSpec::parse("none").unwrap(), None);
        assert_eq!(
            LightSpec::parse("dir:0,-2,0").unwrap(),
            Some(LightSpec::Directional(DVec3::new(0.0, -1.0, 0.0)))
        );
        assert_eq!(
            LightSpec::parse("point:1,2,3").unwrap(),
            Some(LightSpec::Point(DVec3::new(1.0, 2.0, 3.0)))
        );
        assert!(LightSpec::parse("dir:0,0,0").is_err());
        assert!(LightSpec::parse("spot:0,0,0").is_err());
        assert!(LightSpec::parse("point:1,2").is_err());
        assert!(LightSpec::parse("point:1,nan,2").is_err());
    }

    /// The legacy tier's exposure: the brightest light gives the key light's colour at the
    /// centre (a point light as if at least `radius` away).
    #[test]
    fn legacy_scale_exposes_the_brightest_light_as_the_key() {
        let light = |kind, intensity, position| FileLight {
            name: String::new(),
            node: 0,
            kind,
            position,
            direction: DVec3::NEG_Y,
            color: [1.0, 0.5, 0.5],
            intensity,
            range: None,
        };
        let pi = std::f64::consts::PI;
        let sun = light(FileLightKind::Directional, 3.0, DVec3::ZERO);
        let near = light(FileLightKind::Point, 40.0, DVec3::X);
        let far = light(FileLightKind::Point, 40.0, DVec3::X * 4.0);
        let k = |ls: &[FileLight]| f64::from(legacy_scale(ls, DVec3::ZERO, 2.0));
        let close = |a: f64, b: f64| (a - b).abs() < 1e-5 * b;
        assert!(close(k(std::slice::from_ref(&sun)), 0.75 * pi / 3.0));
        assert!(close(k(&[sun.clone(), near]), 0.75 * pi / 10.0));
        assert!(close(k(&[sun, far]), 0.75 * pi / 3.0));
        assert_eq!(k(&[light(FileLightKind::Point, 0.0, DVec3::ZERO)]), 1.0);
    }

    /// The specification's range window and spot cone, at points where they are known.
    #[test]
    fn falloff_is_the_specification_formula() {
        let f = Falloff {
            inv_range2: 0.25,
            inverse_square: true,
            spot: None,
        };
        assert_eq!(f.at(DVec3::X), 1.0 - 0.5f64.powi(4));
        assert_eq!(f.at(DVec3::X * 0.5), (1.0 - 0.25f64.powi(4)) / 0.25);
        assert_eq!(f.at(DVec3::Y * 2.0), 0.0);
        assert_eq!(f.at(DVec3::Y * 3.0), 0.0);
        assert!(f.at(DVec3::ZERO).is_finite());
        assert_eq!(Falloff::NONE.at(DVec3::X * 7.0), 1.0);
        let (inner, outer) = (0.2f32, 0.6f32);
        let spot = Falloff {
            inv_range2: 0.0,
            inverse_square: false,
            spot: Some(Spot::new(Vec3::NEG_Y, inner, outer)),
        };
        // From the lit point to a light above it, at angle `a` off the spot's axis.
        let at = |a: f64| spot.at(DVec3::new(-a.sin(), a.cos(), 0.0));
        assert!((at(0.0) - 1.0).abs() < 1e-6);
        assert!((at(0.19) - 1.0).abs() < 1e-6);
        let (ci, co) = (f64::from(inner).cos(), f64::from(outer).cos());
        let want = ((0.4f64.cos() - co) / (ci - co)).powi(2);
        assert!((at(0.4) - want).abs() < 1e-5, "{} {want}", at(0.4));
        assert_eq!(at(0.61), 0.0);
        assert_eq!(at(2.0), 0.0);
    }
}
