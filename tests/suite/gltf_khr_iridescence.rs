//! KHR_materials_iridescence (issue 37): a thin film over the base, the Sample Viewer's
//! formulas (docs/gltf/extensions.md). The GPU equals the CPU reference's Monte Carlo truth
//! in a uniform environment with the default light; a film of factor 0, or the layer
//! switched off by `--terms`, draws the core model, on every context; `--check` names it.
//! Helpers in `gltf_khr.rs`.
use crate::common::*;
use crate::gltf_khr::{gpu_matches_the_reference, material, max_diff, shot, sphere, CONTEXTS};

/// The brief's film: factor 1, 400 nm (the default maximum), ior 1.3.
const FILM: &str = r#""KHR_materials_iridescence": {"iridescenceFactor": 1,
    "iridescenceThicknessMaximum": 400}"#;

/// A film over a rough red dielectric, and over a smooth gold-like metal: the GPU's
/// permutation against the reference (1024 Monte Carlo samples per lobe, uniform
/// environment 0.5 plus the default light, no tone mapping) on the full-float path (GL 3.3,
/// ES 3.0) and the RGBM path of GL 2.1 and OSMesa, with `gpu_equals_the_reference_for_each_
/// extension`'s bounds (mean 0.5/255, max 3/255 over the sphere's pixels).
#[test]
fn iridescence_gpu_equals_the_reference() {
    let dir = out_dir("gltf-khr-iridescence-reference");
    let cases = [
        ("dielectric", [0.6, 0.1, 0.1], 0.0, 0.5),
        ("metal", [1.0, 0.78, 0.34], 1.0, 0.2),
    ];
    let furnace = ["--env-color", "0.5,0.5,0.5", "--tonemap", "none"];
    for (name, base, metal, rough) in cases {
        let model = sphere(&dir, name, &material(base, metal, rough, FILM));
        let contexts = [
            (&CONTEXTS[0], &[][..]),
            (&CONTEXTS[1], &[][..]),
            (&CONTEXTS[2], &["--ibl-encoding", "rgbm"][..]),
            (&CONTEXTS[3], &["--ibl-encoding", "rgbm"][..]),
        ];
        gpu_matches_the_reference(
            &dir,
            &format!("iridescence-{name}"),
            &model,
            &furnace,
            &contexts,
        );
    }
}

/// A film of factor 0 is the core model, and `--terms` without `iridescence` draws the
/// film's material as the core model (within 1/255), on every context; with the film on,
/// the picture differs (the test could not pass with the film ignored).
#[test]
fn iridescence_off_or_zero_equals_the_core_model_on_every_context() {
    let dir = out_dir("gltf-khr-iridescence-off");
    let (base, metal, rough) = ([0.6, 0.1, 0.1], 0.0, 0.3);
    let core = sphere(&dir, "core", &material(base, metal, rough, ""));
    let film = sphere(&dir, "film", &material(base, metal, rough, FILM));
    let zero = sphere(
        &dir,
        "zero",
        &material(
            base,
            metal,
            rough,
            r#""KHR_materials_iridescence": {"iridescenceFactor": 0}"#,
        ),
    );
    let off = "direct-diffuse,direct-specular,ibl-diffuse,ibl-specular,ao,shadows,emissive,\
               normal-map,clearcoat,sheen,transmission";
    for ctx in &CONTEXTS {
        let want = shot(&dir, &format!("core-{}", ctx.0), &core, &[], ctx);
        let on = shot(&dir, &format!("film-{}", ctx.0), &film, &[], ctx);
        assert!(
            max_diff(&on, &want) > 20,
            "{}: the film changes the picture",
            ctx.0
        );
        let got = shot(
            &dir,
            &format!("off-{}", ctx.0),
            &film,
            &["--terms", off],
            ctx,
        );
        assert_close(&dir, &format!("off-{}", ctx.0), &got, &want, 1, 0, 1);
        let got = shot(&dir, &format!("zero-{}", ctx.0), &zero, &[], ctx);
        assert_close(&dir, &format!("zero-{}", ctx.0), &got, &want, 1, 0, 1);
    }
}

/// `--check` prints the film's factors.
#[test]
fn check_lists_iridescence() {
    let dir = out_dir("gltf-khr-iridescence-check");
    let model = sphere(
        &dir,
        "check",
        &material(
            [1.0; 3],
            0.0,
            0.5,
            r#""KHR_materials_iridescence": {"iridescenceFactor": 0.5, "iridescenceIor": 1.8,
                "iridescenceThicknessMinimum": 200, "iridescenceThicknessMaximum": 600}"#,
        ),
    );
    let o = run(&[model.to_str().unwrap(), "--check"], &[]);
    let out = String::from_utf8_lossy(&o.stdout).to_string() + &String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{out}");
    let want = "KHR_materials_iridescence: iridescenceFactor 0.5, iridescenceIor 1.8, \
                iridescenceThicknessMinimum 200 nm, iridescenceThicknessMaximum 600 nm";
    assert!(out.contains(want), "--check lacks {want:?}:\n{out}");
}
