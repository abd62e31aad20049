//! The quality knobs the benchmark varies, and the settings it measures.
use glview::frame::{FrameSettings, Shading, ShadowSettings};
use serde::Serialize;

/// One setting of the quality knobs.
#[derive(Clone, Debug, Serialize)]
pub struct Knob {
    /// Which knob this setting varies: off, size_pcf, bias or shading.
    pub group: &'static str,
    pub label: String,
    pub shadows: bool,
    pub size: u32,
    pub pcf: u8,
    pub bias: f32,
    pub shading: Shading,
}

impl Knob {
    /// `base` with this setting's knobs.
    pub fn apply(&self, base: &FrameSettings) -> FrameSettings {
        let mut s = base.clone();
        s.shading = self.shading;
        s.shadows = ShadowSettings {
            enabled: self.shadows,
            size: self.size,
            pcf: self.pcf,
            bias: self.bias,
            ..base.shadows
        };
        s
    }

    /// Whether this is what glview renders without options.
    pub fn is_default(&self) -> bool {
        let d = ShadowSettings::default();
        self.shadows
            && self.shading == Shading::Phong
            && (self.size, self.pcf, self.bias) == (d.size, d.pcf, d.bias)
    }

    /// The options that select this setting on the command line.
    pub fn options(&self) -> String {
        if !self.shadows {
            return "--no-shadows".into();
        }
        let shading = match self.shading {
            Shading::Phong => "",
            Shading::Gouraud => " --shading gouraud",
            Shading::Pbr => " --shading pbr",
        };
        format!(
            "--shadow-size {} --pcf {} --shadow-bias {}{shading}",
            self.size, self.pcf, self.bias
        )
    }
}

/// The settings measured: shadows off; every map size with every PCF tap count; biases and
/// Gouraud at the default size and PCF. Labels read `size/pcf`.
pub fn knobs(quick: bool) -> Vec<Knob> {
    let d = ShadowSettings::default();
    let base = Knob {
        group: "size_pcf",
        label: String::new(),
        shadows: true,
        size: d.size,
        pcf: d.pcf,
        bias: d.bias,
        shading: Shading::Phong,
    };
    let mut out = vec![Knob {
        group: "off",
        label: "off".into(),
        shadows: false,
        ..base.clone()
    }];
    let (sizes, pcfs, biases): (&[u32], &[u8], &[f32]) = if quick {
        (&[512, 1024, 2048, 4096], &[1, 4, 9], &[0.0, 0.002])
    } else {
        (
            &[256, 512, 1024, 2048, 4096],
            &[1, 4, 9, 16],
            &[0.0, 0.0002, 0.001, 0.002],
        )
    };
    for &size in sizes {
        for &pcf in pcfs {
            out.push(Knob {
                label: format!("{size}/{pcf}"),
                size,
                pcf,
                ..base.clone()
            });
        }
    }
    for &bias in biases.iter().filter(|&&b| b != d.bias) {
        out.push(Knob {
            group: "bias",
            label: format!("bias {bias}"),
            bias,
            ..base.clone()
        });
    }
    out.push(Knob {
        group: "shading",
        label: "gouraud".into(),
        shading: Shading::Gouraud,
        ..base
    });
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_default_and_unique_labels() {
        for quick in [false, true] {
            let k = knobs(quick);
            assert_eq!(k.iter().filter(|k| k.is_default()).count(), 1);
            let mut labels: Vec<&str> = k.iter().map(|k| k.label.as_str()).collect();
            labels.sort();
            labels.dedup();
            assert_eq!(labels.len(), k.len());
        }
    }
}
