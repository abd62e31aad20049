//! Lights, in the scene's local (re-centred) coordinates.
use glam::{DVec3, Vec3};

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
    pub color: Vec3,
}

/// The default kit (no `--light`): key (casts the shadow), fill and headlight colours.
pub(crate) const KIT_KEY: f32 = 0.75;
pub(crate) const KIT_FILL: f32 = 0.3;
pub(crate) const KIT_HEAD: f32 = 0.3;

/// The most lights a frame draws (each may cast a shadow); more is an error at the CLI.
pub const MAX_LIGHTS: usize = 4;

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
            LightOpt::Head => Err(format!(
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
        Light { kind, color }
    }
}

/// A `--light` value as given: a light, the camera's headlight, or no lights at all. A
/// direction is kept as typed (made unit when the frame's lights are made), so the option
/// writes back exactly as it was read.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightOpt {
    Point(DVec3),
    Dir(DVec3),
    Head,
    None,
}

impl std::str::FromStr for LightOpt {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "head" => return Ok(LightOpt::Head),
            "none" => return Ok(LightOpt::None),
            _ => {}
        }
        let (kind, rest) = s
            .split_once(':')
            .ok_or_else(|| format!("light {s:?}: expected point:X,Y,Z, dir:X,Y,Z or none"))?;
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
        }
    }
}

crate::word_value!(LightOpt, "point:X,Y,Z, dir:X,Y,Z, head or none");

impl LightOpt {
    /// The light this value places, if it is one (not `head` or `none`): a direction is
    /// made unit here, in f64, as the command line always did.
    pub fn spec(self) -> Option<LightSpec> {
        match self {
            LightOpt::Point(p) => Some(LightSpec::Point(p)),
            LightOpt::Dir(d) => Some(LightSpec::Directional(d.normalize())),
            LightOpt::Head | LightOpt::None => None,
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
}
