//! Which terms of each tier's formula a frame draws: the legacy tier's ambient, diffuse and
//! specular (`--legacy-terms`, keys 1–3 in Phong) and the PBR tier's (`--terms`, keys 1–0 in
//! PBR). Both are sets of named switches, written and read as the same words. No GL.

/// A set of named on/off switches written as `all`, `none` or its words comma-separated.
trait Switches: Copy + Eq {
    const ALL: Self;
    const NONE: Self;
    /// Each switch's word, in the order the words are written.
    fn named(&mut self) -> Vec<(&'static str, &mut bool)>;
}

fn parse_switches<T: Switches>(s: &str) -> Result<T, String> {
    match s.trim() {
        "all" | "" => return Ok(T::ALL),
        "none" => return Ok(T::NONE),
        _ => {}
    }
    let mut t = T::NONE;
    for name in s.split(',').map(str::trim) {
        let mut named = t.named();
        let Some((_, on)) = named.iter_mut().find(|(n, _)| *n == name) else {
            // The words from the table itself, so a new term is listed with the rest.
            let words: Vec<&str> = named.iter().map(|(n, _)| *n).collect();
            return Err(format!(
                "unknown term {name:?} ({}, all, none)",
                words.join(", ")
            ));
        };
        **on = true;
    }
    Ok(t)
}

fn write_switches<T: Switches>(t: &T, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
    if *t == T::ALL {
        return f.write_str("all");
    }
    if *t == T::NONE {
        return f.write_str("none");
    }
    let mut t = *t;
    let on: Vec<&str> = t
        .named()
        .into_iter()
        .filter(|(_, b)| **b)
        .map(|(n, _)| n)
        .collect();
    f.write_str(&on.join(","))
}

/// `FromStr`, `Display` and the option value of a [`Switches`] set.
macro_rules! switch_words {
    ($t:ty, $expected:literal) => {
        impl std::str::FromStr for $t {
            type Err = String;
            fn from_str(s: &str) -> Result<Self, String> {
                parse_switches(s)
            }
        }
        impl std::fmt::Display for $t {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                write_switches(self, f)
            }
        }
        crate::word_value!($t, $expected);
    };
}

/// Which terms of the legacy formula are drawn (`--legacy-terms`; keys 1, 2, 3 in the legacy
/// tier).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Terms {
    pub ambient: bool,
    pub diffuse: bool,
    pub specular: bool,
}

impl Default for Terms {
    fn default() -> Self {
        Terms::ALL
    }
}

impl Switches for Terms {
    const ALL: Terms = Terms {
        ambient: true,
        diffuse: true,
        specular: true,
    };
    const NONE: Terms = Terms {
        ambient: false,
        diffuse: false,
        specular: false,
    };
    fn named(&mut self) -> Vec<(&'static str, &mut bool)> {
        vec![
            ("ambient", &mut self.ambient),
            ("diffuse", &mut self.diffuse),
            ("specular", &mut self.specular),
        ]
    }
}

switch_words!(Terms, "all, none or terms: ambient,diffuse,specular");

impl Terms {
    /// The switch the legacy tier's key `1`, `2` or `3` (index 0–2) toggles.
    pub(crate) fn key_switch(&mut self, i: u8) -> Option<&mut bool> {
        self.named().into_iter().nth(usize::from(i)).map(|(_, b)| b)
    }
}

/// Which terms of the PBR formula are drawn (`--terms`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PbrTerms {
    pub direct_diffuse: bool,
    pub direct_specular: bool,
    pub ibl_diffuse: bool,
    pub ibl_specular: bool,
    pub ao: bool,
    pub shadows: bool,
    pub emissive: bool,
    /// The material's normal map (both tiers); off: the interpolated normal.
    pub normal_map: bool,
    /// The glTF extensions' layers (KHR_materials_clearcoat, _sheen, _transmission,
    /// _iridescence, _anisotropy): off, the material is drawn without the layer (without
    /// anisotropy: the isotropic lobe).
    pub clearcoat: bool,
    pub sheen: bool,
    pub transmission: bool,
    pub iridescence: bool,
    pub anisotropy: bool,
}

impl Default for PbrTerms {
    fn default() -> Self {
        PbrTerms::ALL
    }
}

impl PbrTerms {
    /// The switch the PBR tier's key `1`–`9`, `0` (index 0–9) toggles: the terms in their
    /// written order, the normal map skipped (it has no key); the ten keys end at
    /// transmission, so iridescence and anisotropy are `--terms` only.
    pub(crate) fn key_switch(&mut self, i: u8) -> Option<&mut bool> {
        self.named()
            .into_iter()
            .filter(|(n, _)| *n != "normal-map")
            .take(10)
            .nth(usize::from(i))
            .map(|(_, b)| b)
    }
}

impl Switches for PbrTerms {
    const ALL: PbrTerms = PbrTerms {
        direct_diffuse: true,
        direct_specular: true,
        ibl_diffuse: true,
        ibl_specular: true,
        ao: true,
        shadows: true,
        emissive: true,
        normal_map: true,
        clearcoat: true,
        sheen: true,
        transmission: true,
        iridescence: true,
        anisotropy: true,
    };
    const NONE: PbrTerms = PbrTerms {
        direct_diffuse: false,
        direct_specular: false,
        ibl_diffuse: false,
        ibl_specular: false,
        ao: false,
        shadows: false,
        emissive: false,
        normal_map: false,
        clearcoat: false,
        sheen: false,
        transmission: false,
        iridescence: false,
        anisotropy: false,
    };
    fn named(&mut self) -> Vec<(&'static str, &mut bool)> {
        vec![
            ("direct-diffuse", &mut self.direct_diffuse),
            ("direct-specular", &mut self.direct_specular),
            ("ibl-diffuse", &mut self.ibl_diffuse),
            ("ibl-specular", &mut self.ibl_specular),
            ("ao", &mut self.ao),
            ("shadows", &mut self.shadows),
            ("emissive", &mut self.emissive),
            ("normal-map", &mut self.normal_map),
            ("clearcoat", &mut self.clearcoat),
            ("sheen", &mut self.sheen),
            ("transmission", &mut self.transmission),
            ("iridescence", &mut self.iridescence),
            ("anisotropy", &mut self.anisotropy),
        ]
    }
}

switch_words!(
    PbrTerms,
    "all, none or terms: direct-diffuse,ibl-specular,..."
);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words_round_trip() {
        for s in ["all", "none", "ambient,specular", "diffuse"] {
            let t: Terms = s.parse().unwrap();
            assert_eq!(t.to_string(), s);
        }
        for s in ["all", "none", "ao,sheen", "normal-map"] {
            let t: PbrTerms = s.parse().unwrap();
            assert_eq!(t.to_string(), s);
        }
        assert!("ambient".parse::<PbrTerms>().is_err());
        assert!("ao".parse::<Terms>().is_err());
    }

    #[test]
    fn keys_skip_the_normal_map() {
        let mut t = PbrTerms::ALL;
        *t.key_switch(7).unwrap() = false;
        assert!(!t.clearcoat && t.normal_map);
        assert!(t.key_switch(10).is_none());
        let mut l = Terms::ALL;
        *l.key_switch(2).unwrap() = false;
        assert!(!l.specular);
        assert!(l.key_switch(3).is_none());
    }
}
