//! `glview bench --khr`: the frame time of each glTF PBR extension's program permutation on
//! a sphere filling a 1280×720 frame (fragment-bound, PBR tier, the default lights and shadow
//! map; the fastest of 30 frames per material, measured in interleaved rounds after one
//! warm-up; transmission includes the frame's copy and its mip chain). The core row is the material without any
//! extension: its program carries none of the extensions' flags (listed), so it is the
//! program glview drew before issue 32 — what the extensions cost a material that does not
//! use them is nothing but the check that picks the program.
use super::table::{num, Table};
use glview::headless::Headless;
use glview::options::Options;
use glview::platform::{Backend, GlRequest};
use glview::render::Renderer;
use glview::scene::model::material_khr::{Clearcoat, Iridescence, Khr, Sheen, Specular, Volume};
use glview::Result;
use std::path::Path;

pub fn run_khr() -> Result<()> {
    let (w, h) = (1280, 720);
    let hl = Headless::new(Backend::Auto, GlRequest::Auto, w, h)?;
    let mut o = Options::default();
    o.picture.size = (w, h);
    let sphere = Path::new(env!("CARGO_MANIFEST_DIR")).join("../models/sphere.obj");
    o.load.model = Some(sphere);
    o.camera.distance = Some(1.6);
    o.render.shading = glview::frame::Shading::Pbr;
    let scene = glview::session::load_scene(&o)?;
    let (s, _) = glview::session::frame_settings(&o, &scene)?;
    let variants = variants();
    let mut table = Table::new(&["material", "program", "frame ms", "vs core"]);
    // One renderer per variant, measured in interleaved rounds, each variant's fastest
    // frame kept: on a shared machine the other processes only ever add time, and the
    // interleaving spreads their bursts over every variant.
    let mut runs = Vec::new();
    for (name, khr) in &variants {
        let mut sc = scene.clone();
        for m in &mut sc.materials {
            m.khr = khr.clone();
        }
        let mut r = Renderer::new(&hl.gpu, sc)?;
        let first = r.render(&s, &hl.target())?;
        let program = first
            .programs
            .iter()
            .find(|p| p.starts_with("pbr"))
            .cloned()
            .unwrap_or_default();
        runs.push((*name, program, r, f64::INFINITY));
    }
    for _round in 0..10 {
        for (_, _, r, best) in runs.iter_mut() {
            for _ in 0..3 {
                *best = best.min(r.render(&s, &hl.target())?.ms);
            }
        }
    }
    let core_ms = runs[0].3;
    for (name, program, _, ms) in &runs {
        table.row(vec![
            name.to_string(),
            program.clone(),
            num(*ms, 1),
            format!("{:.2}x", ms / core_ms),
        ]);
    }
    println!("{}", table.render());
    Ok(())
}

/// The materials measured: the core one, each extension alone, and three together.
fn variants() -> Vec<(&'static str, Khr)> {
    let cc = Clearcoat {
        factor: 1.0,
        roughness: 0.1,
        normal_scale: 1.0,
    };
    let sheen = Sheen {
        color: [1.0, 0.3, 0.3],
        roughness: 0.5,
    };
    let spec = Specular {
        factor: 0.8,
        color: [1.0, 0.8, 0.6],
    };
    vec![
        ("core (no extension)", Khr::default()),
        (
            "clearcoat",
            Khr {
                clearcoat: Some(cc),
                ..Default::default()
            },
        ),
        (
            "sheen",
            Khr {
                sheen: Some(sheen),
                ..Default::default()
            },
        ),
        (
            "specular + ior",
            Khr {
                specular: Some(spec),
                ior: Some(1.7),
                ..Default::default()
            },
        ),
        (
            "transmission (thin)",
            Khr {
                transmission: Some(1.0),
                ..Default::default()
            },
        ),
        (
            "transmission + volume",
            Khr {
                transmission: Some(1.0),
                volume: Some(Volume {
                    thickness: 0.5,
                    attenuation_color: [0.4, 0.7, 0.9],
                    attenuation_distance: Some(1.0),
                }),
                ..Default::default()
            },
        ),
        (
            "iridescence (400 nm)",
            Khr {
                iridescence: Some(Iridescence {
                    factor: 1.0,
                    ..Default::default()
                }),
                ..Default::default()
            },
        ),
        (
            "clearcoat + sheen + specular",
            Khr {
                clearcoat: Some(cc),
                sheen: Some(sheen),
                specular: Some(spec),
                ior: Some(1.7),
                ..Default::default()
            },
        ),
    ]
}
