//! `glview bench --khr`: the frame time of each glTF PBR extension's program permutation on
//! a sphere filling a 1280×720 frame (fragment-bound, PBR tier, the default lights and shadow
//! map, median of 10 frames after one warm-up; transmission includes the frame's copy and
//! its mip chain). The core row is the material without any
//! extension: its program carries none of the extensions' flags (listed), so it is the
//! program glview drew before issue 32 — what the extensions cost a material that does not
//! use them is nothing but the check that picks the program.
use super::median;
use super::table::{num, Table};
use glview::headless::Headless;
use glview::options::Options;
use glview::platform::{Backend, GlRequest};
use glview::render::Renderer;
use glview::scene::material_khr::{Clearcoat, Khr, Sheen, Specular, Volume};
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
    let variants: Vec<(&str, Khr)> = vec![
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
            "clearcoat + sheen + specular",
            Khr {
                clearcoat: Some(cc),
                sheen: Some(sheen),
                specular: Some(spec),
                ior: Some(1.7),
                ..Default::default()
            },
        ),
    ];
    let mut table = Table::new(&["material", "program", "frame ms", "vs core"]);
    let mut core_ms = f64::NAN;
    for (name, khr) in variants {
        let mut sc = scene.clone();
        for m in &mut sc.materials {
            m.khr = khr.clone();
        }
        let mut r = Renderer::new(&hl.gpu, sc)?;
        let first = r.render(&s, &hl.target())?;
        let times: Vec<f64> = (0..10)
            .map(|_| r.render(&s, &hl.target()).map(|st| st.ms))
            .collect::<Result<_>>()?;
        let ms = median(&times);
        if core_ms.is_nan() {
            core_ms = ms;
        }
        let program = first
            .programs
            .iter()
            .find(|p| p.starts_with("pbr"))
            .cloned()
            .unwrap_or_default();
        table.row(vec![
            name.to_string(),
            program,
            num(ms, 1),
            format!("{:.2}x", ms / core_ms),
        ]);
    }
    println!("{}", table.render());
    Ok(())
}
