//! KHR_materials_transmission (thin-walled) and KHR_materials_volume (issue 32) against
//! exact expectations on every context. Helpers in `gltf_khr.rs`.
use crate::common::*;
use crate::gltf_khr::{material, shot, sphere, view, CONTEXTS, N};
use glview::image_out::Rgba;
use glview::image_out::RgbaFiles;

/// KHR_materials_transmission, thin-walled: a white, smooth, fully transmissive sphere over a
/// flat background B in a uniform environment of B's linear value shows nothing but B (what
/// the specular lobe reflects of the environment, the transmission lets through of the
/// frame behind: the two add up to the light arriving); over a red background in a grey
/// environment its centre is the red, less the 4 % the surface reflects (of the grey); with
/// KHR_materials_volume (thickness = attenuation distance) the centre keeps
/// attenuationColor of the light behind. On every context (OSMesa without a mip chain: a
/// smooth sphere reads level 0 anyway).
#[test]
fn a_transmissive_thin_sphere_shows_the_background() {
    let dir = out_dir("gltf-khr-transmission");
    let model = sphere(
        &dir,
        "thin",
        &material(
            [1.0; 3],
            0.0,
            0.0,
            r#""KHR_materials_transmission": {"transmissionFactor": 1}"#,
        ),
    );
    const ATT: [f64; 3] = [0.5, 0.8, 1.0];
    let volume = sphere(
        &dir,
        "volume",
        &material(
            [1.0; 3],
            0.0,
            0.0,
            &format!(
                r#""KHR_materials_transmission": {{"transmissionFactor": 1}},
                   "KHR_materials_volume": {{"thicknessFactor": 0.7, "attenuationDistance": 0.7,
                     "attenuationColor": [{}, {}, {}]}}"#,
                ATT[0], ATT[1], ATT[2]
            ),
        ),
    );
    let srgb = |v: f64| glview::pbr::srgb_decode(v);
    let bg = [0.6, 0.45, 0.3];
    let env = bg.map(|c| format!("{}", srgb(c))).join(",");
    let bg_arg = bg.map(|c| c.to_string()).join(",");
    let flat = plain(&env, &bg_arg);
    let red = plain("0.2,0.2,0.2", "0.9,0.1,0.1");
    for ctx in &CONTEXTS {
        // A uniform picture is the expectation here (`render` refuses those as blank).
        let out = dir.join(format!("flat-{}.png", ctx.0));
        let mut args = view(&model, &flat);
        args.extend(ctx.1.iter().map(|s| s.to_string()));
        args.extend(["--output".to_string(), out.to_str().unwrap().to_string()]);
        let all: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = run(&all, ctx.2);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let img = Rgba::load_png(&out).unwrap();
        let mut worst = 0.0f64;
        for p in img.data.chunks_exact(4) {
            for c in 0..3 {
                worst = worst.max((f64::from(p[c]) - bg[c] * 255.0).abs());
            }
        }
        eprintln!(
            "thin sphere over a flat background on {}: {worst:.1}/255",
            ctx.0
        );
        assert!(worst <= 2.0, "{}: {worst}/255 from the background", ctx.0);
        let img = shot(&dir, &format!("red-{}", ctx.0), &model, &red, ctx);
        let want = [0.9, 0.1, 0.1]
            .map(|b: f64| glview::pbr::srgb_encode(0.96 * srgb(b) + 0.04 * 0.2) * 255.0);
        let worst = centre_error(&img, 3, &want);
        eprintln!(
            "thin sphere over red on {}: centre {worst:.1}/255 from 0.96 red + 0.04 grey",
            ctx.0
        );
        assert!(worst <= 3.0, "{}: centre {worst}/255", ctx.0);
        // KHR_materials_volume: through a thickness of one attenuation distance the light
        // keeps attenuationColor of itself (Beer–Lambert); the centre's ray is not bent.
        let img = shot(&dir, &format!("volume-{}", ctx.0), &volume, &flat, ctx);
        let want: Vec<f64> = (0..3)
            .map(|c| {
                let l = srgb(bg[c]);
                glview::pbr::srgb_encode(0.04 * l + 0.96 * l * ATT[c]) * 255.0
            })
            .collect();
        let worst = centre_error(&img, 2, &want);
        eprintln!(
            "volume on {}: centre {worst:.1}/255 from Beer-Lambert",
            ctx.0
        );
        assert!(worst <= 3.0, "{}: volume centre {worst}/255", ctx.0);
    }
}

/// The view's options with neither tone mapping, exposure nor lights: a pixel is the light of
/// the uniform environment `env` and of the `background` as given, nothing else.
fn plain<'a>(env: &'a str, background: &'a str) -> [&'a str; 10] {
    [
        "--tonemap",
        "none",
        "--exposure",
        "0",
        "--light",
        "none",
        "--env-color",
        env,
        "--background",
        background,
    ]
}

/// The largest colour-channel difference (in 8-bit steps) from `want` over the 2h × 2h
/// pixels at the picture's centre, where the sphere's ray goes straight through.
fn centre_error(img: &Rgba, h: u32, want: &[f64]) -> f64 {
    let mut worst = 0.0f64;
    for y in N / 2 - h..N / 2 + h {
        for x in N / 2 - h..N / 2 + h {
            let p = img.pixel(x, y);
            for c in 0..3 {
                worst = worst.max((f64::from(p[c]) - want[c]).abs());
            }
        }
    }
    worst
}
