//! The lights a model file brings (glTF KHR_lights_punctual), as the file states them: the
//! renderer makes its frame lights from them (`glview_render`'s `light::file_light`).
use glam::{DVec3, Vec3};

/// The most lights a frame draws (each may cast a shadow); a file's further lights are
/// dropped with a warning, more `--light`s are an error at the CLI.
pub const MAX_LIGHTS: usize = 4;

/// A light a model file brings (glTF KHR_lights_punctual), in the file's coordinates (f64,
/// the up axis already turned, like the geometry), as the file states it: intensity in
/// candela (point, spot) or lux (directional).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FileLight {
    /// The light's name in the file, or `light N`.
    pub name: String,
    /// The node that places it.
    pub node: usize,
    pub kind: FileLightKind,
    /// World position (unused by a directional light).
    pub position: DVec3,
    /// Unit direction the light shines in (its node's −Z; unused by a point light).
    pub direction: DVec3,
    /// Linear RGB in 0..1.
    pub color: [f32; 3],
    pub intensity: f32,
    /// Where a point or spot light's reach ends; None: everywhere (inverse square only).
    pub range: Option<f32>,
}

/// A file light's kind; a spot's cone angles in radians, 0 ≤ inner ≤ outer ≤ π/2.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum FileLightKind {
    Directional,
    Point,
    Spot { inner: f32, outer: f32 },
}

impl FileLight {
    /// One line for `--check`: `spot "Lamp" (node 3): 40 cd, colour 1,0.9,0.8, range 5, cone 10°-30°, at X,Y,Z, towards X,Y,Z`.
    pub fn describe(&self) -> String {
        let c = self.color;
        let mut s = match self.kind {
            FileLightKind::Directional => format!(
                "directional {:?} (node {}): {} lux",
                self.name, self.node, self.intensity
            ),
            FileLightKind::Point | FileLightKind::Spot { .. } => format!(
                "{} {:?} (node {}): {} cd",
                if self.kind == FileLightKind::Point {
                    "point"
                } else {
                    "spot"
                },
                self.name,
                self.node,
                self.intensity
            ),
        };
        s += &format!(", colour {},{},{}", c[0], c[1], c[2]);
        if let (Some(r), false) = (self.range, self.kind == FileLightKind::Directional) {
            s += &format!(", range {r}");
        }
        if let FileLightKind::Spot { inner, outer } = self.kind {
            s += &format!(
                ", cone {:.4}°-{:.4}°",
                inner.to_degrees(),
                outer.to_degrees()
            );
        }
        let (p, d) = (self.position, self.direction);
        if self.kind != FileLightKind::Directional {
            s += &format!(", at {},{},{}", p.x, p.y, p.z);
        }
        if self.kind != FileLightKind::Point {
            s += &format!(", towards {:.4},{:.4},{:.4}", d.x, d.y, d.z);
        }
        s
    }
}

/// KHR_lights_punctual's attenuation of a point or spot light, the specification's formulas
/// (the Sample Viewer's `getRangeAttenuation` and the spec's informative spot formula):
/// `window / d²` with `window = clamp(1 − (d/range)⁴, 0, 1)` (1 without a range), times
/// `clamp(cos θ · scale + offset, 0, 1)²` off the spot's axis. A spot is a point light with
/// a cone: its shadow map is a point light's.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Falloff {
    /// 1/range² (0: no range, the light reaches everywhere).
    pub inv_range2: f32,
    /// Divide by the squared distance (photometric lights); glview's own lights do not.
    pub inverse_square: bool,
    /// The spot's cone, None for a point light.
    pub spot: Option<Spot>,
}

/// A spot light's cone: the unit direction it shines in (local coordinates) and the
/// specification's `lightAngleScale` / `lightAngleOffset`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spot {
    pub dir: Vec3,
    pub scale: f32,
    pub offset: f32,
}

impl Spot {
    /// The cone between `inner` and `outer` (radians, 0 ≤ inner < outer ≤ π/2, as the
    /// loader made them), as the specification's informative formula spells it.
    pub fn new(dir: Vec3, inner: f32, outer: f32) -> Spot {
        let scale = 1.0 / (inner.cos() - outer.cos()).max(0.001);
        Spot {
            dir,
            scale,
            offset: -outer.cos() * scale,
        }
    }
}

/// The squared distance below which a light is taken to be this far: the inverse square
/// stays finite at the light itself.
pub const MIN_DISTANCE2: f64 = 1e-8;

impl Falloff {
    pub const NONE: Falloff = Falloff {
        inv_range2: 0.0,
        inverse_square: false,
        spot: None,
    };

    /// The factor at offset `to_light` (from the lit point to the light). f32 inputs read
    /// in f64, the same steps as `glviewFalloff` in falloff.glsl.
    pub fn at(&self, to_light: DVec3) -> f64 {
        if *self == Falloff::NONE {
            return 1.0;
        }
        let d2 = to_light.length_squared();
        let r = d2 * f64::from(self.inv_range2);
        let window = (1.0 - r * r).clamp(0.0, 1.0);
        let inv = if self.inverse_square {
            1.0 / d2.max(MIN_DISTANCE2)
        } else {
            1.0
        };
        let spot = self.spot.map_or(1.0, |s| {
            let cd = if d2 > 0.0 {
                s.dir.as_dvec3().dot(-to_light) / d2.sqrt()
            } else {
                1.0
            };
            let a = (cd * f64::from(s.scale) + f64::from(s.offset)).clamp(0.0, 1.0);
            a * a
        });
        window * inv * spot
    }
}

impl FileLight {
    /// The attenuation the file's range and cone give it (directional lights: none).
    pub fn falloff(&self) -> Falloff {
        let spot = match self.kind {
            FileLightKind::Spot { inner, outer } => Some(Spot::new(
                self.direction.as_vec3().normalize_or_zero(),
                inner,
                outer,
            )),
            _ => None,
        };
        match self.kind {
            FileLightKind::Directional => Falloff::NONE,
            _ => Falloff {
                inv_range2: self.range.map_or(0.0, |r| 1.0 / (r * r)),
                inverse_square: true,
                spot,
            },
        }
    }
}
