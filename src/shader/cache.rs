//! Programs keyed by what they compute, compiled on first use and reused.
use super::{assemble, Stage};
use crate::gpu::program::Program;
use crate::gpu::GpuRef;
use crate::Result;
use serde::Serialize;
use std::collections::HashMap;
use std::rc::Rc;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
pub enum ProgramKind {
    Lit,
    Depth,
    ShowDepth,
}

/// Everything that changes a program's source; the cache key.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
pub struct ProgramKey {
    pub kind: ProgramKind,
    pub lights: u8,
    pub shadows: u8,
    pub pcf: u8,
    /// Bit i set: light i's shadow is a six-face atlas (point light inside the scene).
    pub cube_mask: u8,
    pub textured: bool,
    pub gouraud: bool,
}

impl ProgramKey {
    pub fn simple(kind: ProgramKind) -> Self {
        ProgramKey {
            kind,
            lights: 0,
            shadows: 0,
            pcf: 1,
            cube_mask: 0,
            textured: false,
            gouraud: false,
        }
    }

    /// A short name for stats and errors, e.g. `lit[l1,s1,pcf4,tex]`.
    pub fn label(&self) -> String {
        let mut s = format!("{:?}", self.kind).to_lowercase();
        if self.kind == ProgramKind::Lit {
            s += &format!("[l{},s{},pcf{}", self.lights, self.shadows, self.pcf);
            if self.cube_mask != 0 {
                s += &format!(",cube{:b}", self.cube_mask);
            }
            if self.textured {
                s += ",tex";
            }
            if self.gouraud {
                s += ",gouraud";
            }
            s += "]";
        }
        s
    }

    fn defines(&self) -> Vec<(&'static str, String)> {
        let mut d = vec![
            ("NUM_LIGHTS", self.lights.to_string()),
            ("NUM_SHADOWS", self.shadows.to_string()),
            ("PCF_TAPS", self.pcf.to_string()),
            (
                "SHADOW_STRIDE",
                if self.cube_mask != 0 { "6" } else { "1" }.into(),
            ),
        ];
        for (i, name) in [
            "SHADOW_CUBE0",
            "SHADOW_CUBE1",
            "SHADOW_CUBE2",
            "SHADOW_CUBE3",
        ]
        .iter()
        .enumerate()
        {
            d.push((
                name,
                if self.cube_mask & (1 << i) != 0 {
                    "1.0"
                } else {
                    "0.0"
                }
                .into(),
            ));
        }
        if self.textured {
            d.push(("HAS_TEXTURE", "1".into()));
        }
        if self.gouraud {
            d.push(("GOURAUD", "1".into()));
        }
        d
    }

    fn files(&self) -> (&'static str, &'static str) {
        match self.kind {
            ProgramKind::Lit => ("lit.vert", "lit.frag"),
            ProgramKind::Depth => ("depth.vert", "depth.frag"),
            ProgramKind::ShowDepth => ("show_depth.vert", "show_depth.frag"),
        }
    }
}

pub struct ProgramCache {
    gpu: GpuRef,
    programs: HashMap<ProgramKey, Rc<Program>>,
}

impl ProgramCache {
    pub fn new(gpu: &GpuRef) -> Self {
        ProgramCache {
            gpu: gpu.clone(),
            programs: HashMap::new(),
        }
    }

    pub fn get(&mut self, key: ProgramKey) -> Result<Rc<Program>> {
        if let Some(p) = self.programs.get(&key) {
            return Ok(p.clone());
        }
        let dialect = self.gpu.caps.dialect;
        let defines = key.defines();
        let (vs, fs) = key.files();
        let p = Rc::new(Program::new(
            &self.gpu,
            &key.label(),
            &assemble(dialect, Stage::Vertex, &defines, vs),
            &assemble(dialect, Stage::Fragment, &defines, fs),
        )?);
        self.programs.insert(key, p.clone());
        Ok(p)
    }

    pub fn len(&self) -> usize {
        self.programs.len()
    }

    pub fn is_empty(&self) -> bool {
        self.programs.is_empty()
    }
}

/// Every program key the renderer can ask for with up to `max_lights` lights: each light
/// count with and without shadows, every PCF size, single maps and six-face atlases,
/// textured or not, Phong or Gouraud, plus the depth and teaching-view programs.
pub fn all_keys(max_lights: u8) -> Vec<ProgramKey> {
    let mut keys = vec![
        ProgramKey::simple(ProgramKind::Depth),
        ProgramKey::simple(ProgramKind::ShowDepth),
    ];
    for lights in 0..=max_lights {
        let shadow_variants: Vec<(u8, u8, u8)> = if lights == 0 {
            vec![(0, 1, 0)]
        } else {
            let all = (1u8 << lights) - 1;
            let mut v = vec![(0, 1, 0)];
            for pcf in [1, 4, 9, 16] {
                for mask in [0, 1, all] {
                    v.push((lights, pcf, mask));
                }
            }
            v.dedup();
            v
        };
        for (shadows, pcf, cube_mask) in shadow_variants {
            for textured in [false, true] {
                for gouraud in [false, true] {
                    keys.push(ProgramKey {
                        kind: ProgramKind::Lit,
                        lights,
                        shadows,
                        pcf,
                        cube_mask,
                        textured,
                        gouraud,
                    });
                }
            }
        }
    }
    keys
}
