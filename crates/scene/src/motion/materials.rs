//! Materials animated by KHR_animation_pointer channels (`gltf_pointer`): base colour,
//! metallic, roughness, emissive factor and emissive strength. A pose sets the sampled
//! factors, the others the file's, through the loader's own [`Factors::apply`], so the
//! material at a moment is the one a file holding those factors loads as; the static pose
//! gives back the loaded values exactly. Nothing is uploaded: the renderer reads a
//! material's factors at every draw.
use crate::model::material::Factors;
use crate::model::material::Material;
use crate::motion::channels::Animation;
use crate::motion::Moment;

/// What a pose may change of a material, as loaded.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Values {
    base_color: [f32; 3],
    base_alpha: f32,
    opacity: Option<f32>,
    metallic: f32,
    roughness: f32,
    emissive: [f32; 3],
    emissive_strength: f32,
}

impl Values {
    fn of(m: &Material) -> Values {
        Values {
            base_color: m.base_color,
            base_alpha: m.base_alpha,
            opacity: m.opacity,
            metallic: m.metallic,
            roughness: m.roughness,
            emissive: m.emissive,
            emissive_strength: m.emissive_strength,
        }
    }

    fn restore(&self, m: &mut Material) {
        m.base_color = self.base_color;
        m.base_alpha = self.base_alpha;
        m.opacity = self.opacity;
        m.metallic = self.metallic;
        m.roughness = self.roughness;
        m.emissive = self.emissive;
        m.emissive_strength = self.emissive_strength;
    }
}

/// One animated material: its index, the file's factors and its loaded values.
#[derive(Debug)]
struct Animated {
    material: usize,
    factors: Factors,
    rest: Values,
}

/// The materials some animation animates.
#[derive(Debug, Default)]
pub(crate) struct Materials {
    animated: Vec<Animated>,
}

impl Materials {
    /// The animated materials (`factors`: each one's index and file factors, once), with
    /// their loaded values in `materials`.
    pub(crate) fn new(factors: &[(usize, Factors)], materials: &[Material]) -> Materials {
        let animated = factors
            .iter()
            .filter_map(|&(material, factors)| {
                Some(Animated {
                    material,
                    factors,
                    rest: Values::of(materials.get(material)?),
                })
            })
            .collect();
        Materials { animated }
    }

    /// Sets `materials` to `moment` of `animations` (None: as loaded).
    pub(crate) fn pose(
        &self,
        animations: &[Animation],
        moment: Option<Moment>,
        materials: &mut [Material],
    ) {
        for a in &self.animated {
            let Some(out) = materials.get_mut(a.material) else {
                continue;
            };
            a.rest.restore(out);
            let Some(m) = moment else { continue };
            let (mut f, mut sampled) = (a.factors, false);
            for k in &animations[m.animation].materials {
                if k.material == a.material {
                    set(&mut f, k.property, &k.keys.sample(m.seconds));
                    sampled = true;
                }
            }
            // A material this animation leaves alone keeps its loaded values.
            if sampled {
                f.apply(out);
            }
        }
    }
}

/// Factor `p` of `f` set to `v` (its width in floats).
fn set(f: &mut Factors, p: MaterialProperty, v: &[f32]) {
    match p {
        MaterialProperty::BaseColor => f.base_color.copy_from_slice(&v[..4]),
        MaterialProperty::Metallic => f.metallic = v[0],
        MaterialProperty::Roughness => f.roughness = v[0],
        MaterialProperty::Emissive => f.emissive.copy_from_slice(&v[..3]),
        MaterialProperty::EmissiveStrength => f.emissive_strength = v[0],
    }
}

/// A material factor a pointer channel may animate.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum MaterialProperty {
    /// `pbrMetallicRoughness/baseColorFactor` (4 floats).
    BaseColor,
    /// `pbrMetallicRoughness/metallicFactor`.
    Metallic,
    /// `pbrMetallicRoughness/roughnessFactor`.
    Roughness,
    /// `emissiveFactor` (3 floats).
    Emissive,
    /// `extensions/KHR_materials_emissive_strength/emissiveStrength`.
    EmissiveStrength,
}

impl MaterialProperty {
    /// Floats per value.
    pub(crate) fn width(self) -> usize {
        match self {
            MaterialProperty::BaseColor => 4,
            MaterialProperty::Emissive => 3,
            _ => 1,
        }
    }
}
