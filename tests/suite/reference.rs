//! The CPU reference renderer against analytic truths: a finely tessellated sphere against
//! the exact sphere (perspective, orthographic, Gouraud, Ns = 0 and 10,000), a box's shadow on
//! a floor against its analytic footprint, translucent layers against hand-blended colours,
//! and degenerate input against NaN. Scenes are built in code.
use glam::{DMat4, DVec3, DVec4, Vec3};
use glview::camera::OrbitCamera;
use glview::frame::LightingParams;
use glview::light::{Light, LightKind};
use glview::reference::{render_with_info, PixelInfo};
use glview::render::{FrameSettings, Shading, ShadowSettings};
use glview::scene::model::material::PhongTerms;
use glview::scene::model::texture_slot::{ColorSpace, TextureSlot};
use glview::scene::{Material, Mesh, Scene, Vertex};
use glview::shading::{shade, to_light};

const BACKGROUND: Vec3 = Vec3::new(0.25, 0.5, 0.75);

fn vertex(p: DVec3, n: DVec3) -> Vertex {
    Vertex {
        position: p.as_vec3().to_array(),
        normal: n.as_vec3().to_array(),
        uv: [0.0; 2],
    }
}

fn scene(meshes: Vec<Mesh>, materials: Vec<Material>) -> Scene {
    Scene::from_meshes("test", meshes, materials)
}

/// A UV sphere with exact unit normals, counter-clockwise seen from outside. The pole rows
/// contain zero-area triangles, which the renderer must never hit.
fn sphere(center: DVec3, segments: u32, material: usize) -> Mesh {
    let rings = segments / 2;
    let mut vertices = Vec::new();
    for j in 0..=rings {
        let theta = std::f64::consts::PI * f64::from(j) / f64::from(rings);
        for i in 0..=segments {
            let phi = std::f64::consts::TAU * f64::from(i) / f64::from(segments);
            let n = DVec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            );
            vertices.push(vertex(center + n, n));
        }
    }
    let mut indices = Vec::new();
    let at = |i: u32, j: u32| j * (segments + 1) + i;
    for j in 0..rings {
        for i in 0..segments {
            // East × south points outwards.
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i, j + 1), at(i + 1, j + 1));
            indices.extend([a, b, c, b, d, c]);
        }
    }
    Mesh {
        name: "sphere".into(),
        vertices,
        indices,
        material,
        ..Default::default()
    }
}

/// Quads given as four corners counter-clockwise seen from the side their normal faces.
fn quads(faces: &[[DVec3; 4]], material: usize) -> Mesh {
    let mut m = Mesh {
        name: "quads".into(),
        material,
        ..Default::default()
    };
    for f in faces {
        let n = (f[1] - f[0]).cross(f[2] - f[0]).normalize();
        let base = m.vertices.len() as u32;
        m.vertices.extend(f.iter().map(|&p| vertex(p, n)));
        m.indices
            .extend([base, base + 1, base + 2, base, base + 2, base + 3]);
    }
    m
}

fn floor(half: f64, y: f64, material: usize) -> Mesh {
    let p = |x: f64, z: f64| DVec3::new(x, y, z);
    quads(
        &[[
            p(-half, -half),
            p(-half, half),
            p(half, half),
            p(half, -half),
        ]],
        material,
    )
}

/// An axis-aligned box with outward faces.
fn cuboid(min: DVec3, max: DVec3, material: usize) -> Mesh {
    let c = |x: bool, y: bool, z: bool| {
        DVec3::new(
            if x { max.x } else { min.x },
            if y { max.y } else { min.y },
            if z { max.z } else { min.z },
        )
    };
    let (f, t) = (false, true);
    quads(
        &[
            [c(f, t, f), c(f, t, t), c(t, t, t), c(t, t, f)], // +y
            [c(f, f, f), c(t, f, f), c(t, f, t), c(f, f, t)], // -y
            [c(t, f, f), c(t, t, f), c(t, t, t), c(t, f, t)], // +x
            [c(f, f, f), c(f, f, t), c(f, t, t), c(f, t, f)], // -x
            [c(f, f, t), c(t, f, t), c(t, t, t), c(f, t, t)], // +z
            [c(f, f, f), c(f, t, f), c(t, t, f), c(t, f, f)], // -z
        ],
        material,
    )
}

fn material(kd: f32, ks: f32, ns: f32) -> Material {
    Material::with_phong(PhongTerms {
        diffuse: [kd; 3],
        specular: [ks; 3],
        shininess: ns,
        ..Default::default()
    })
}

fn settings(sc: &Scene, yaw: f32, pitch: f32, lights: Vec<Light>, aspect: f32) -> FrameSettings {
    let mut camera = OrbitCamera::fit(&sc.bounds, 45.0, aspect);
    camera.yaw_deg = yaw;
    camera.pitch_deg = pitch;
    FrameSettings {
        camera,
        lights,
        lighting: LightingParams::default(),
        shading: Shading::Phong,
        background: BACKGROUND,
        shadows: ShadowSettings::default(),
        show_shadow_map: false,
        stereo: Default::default(),
    }
}

fn point(x: f32, y: f32, z: f32) -> Light {
    Light::new(LightKind::Point(Vec3::new(x, y, z)), Vec3::splat(0.7))
}

fn directional(x: f32, y: f32, z: f32) -> Light {
    Light::new(
        LightKind::Directional(Vec3::new(x, y, z).normalize()),
        Vec3::splat(0.6),
    )
}

/// Pixel-centre rays computed independently of the renderer: from the f32 matrices the GPU
/// gets, inverted in f64. Returns (origin, direction) with the far plane at t = 1.
fn rays(sc: &Scene, s: &FrameSettings, w: u32, h: u32) -> impl Fn(i64, i64) -> (DVec3, DVec3) {
    let vp = s.camera.projection(&sc.bounds, w as f32 / h as f32) * s.camera.view();
    let inv: DMat4 = vp.as_dmat4().inverse();
    move |x, y| {
        let nx = 2.0 * (x as f64 + 0.5) / f64::from(w) - 1.0;
        let ny = 1.0 - 2.0 * (y as f64 + 0.5) / f64::from(h);
        let un = |z: f64| {
            let p = inv * DVec4::new(nx, ny, z, 1.0);
            p.truncate() / p.w
        };
        (un(-1.0), un(1.0) - un(-1.0))
    }
}

fn unit_sphere_hit(o: DVec3, d: DVec3) -> Option<DVec3> {
    let (a, b, c) = (d.dot(d), o.dot(d), o.dot(o) - 1.0);
    let disc = b * b - a * c;
    let t = (-b - disc.sqrt()) / a;
    (disc >= 0.0 && (0.0..=1.0).contains(&t)).then(|| o + t * d)
}

/// How a render of the tessellated unit sphere compares with the exact sphere.
#[derive(Debug, Default)]
struct SphereError {
    /// Largest error in 1/255 units (including the final rounding) away from the silhouette.
    worst: f64,
    worst_at: (i64, i64),
    /// Interior pixels compared, and those that missed the mesh (a coarse polygon).
    compared: usize,
    missed: usize,
    /// Pixels left out at a discontinuity of the formula (see below).
    skipped: usize,
}

/// Pixels outside the exact silhouette must be background; those more than a pixel inside
/// are compared with the formula evaluated on the exact sphere.
fn sphere_error(s: &FrameSettings, m: Material, segments: u32) -> SphereError {
    let sc = scene(vec![sphere(DVec3::ZERO, segments, 0)], vec![m.clone()]);
    let (w, h) = (192, 160);
    let (img, info) = render_with_info(&sc, s, w, h);
    let ray = rays(&sc, s, w, h);
    let covered = |x: i64, y: i64| {
        let (o, d) = ray(x, y);
        unit_sphere_hit(o, d).is_some()
    };
    let eye = s.camera.eye().as_dvec3();
    let bg = glview::reference::to_unorm8(BACKGROUND.as_dvec3());
    let mut e = SphereError::default();
    for y in 0..h as i64 {
        for x in 0..w as i64 {
            let px = img.pixel(x as u32, y as u32);
            let pi: &PixelInfo = &info[(y as u32 * w + x as u32) as usize];
            let (o, d) = ray(x, y);
            let Some(p) = unit_sphere_hit(o, d) else {
                assert_eq!((&px[..3], pi.hit()), (&bg[..], false), "outside at {x},{y}");
                continue;
            };
            if (-1..=1).any(|j| (-1..=1).any(|i| !covered(x + i, y + j))) {
                continue;
            }
            if !pi.hit() {
                e.missed += 1;
                continue;
            }
            // With Ns = 0 the specular term jumps from 0 to Ks·Lc where N·L crosses 0. Near
            // that terminator a facet may face away from the light (and shadow itself) while
            // its interpolated normal still has N·L > 0, so within a facet's angular size
            // (2π / segments) of it a pixel may land on either side of the jump.
            let band = std::f64::consts::TAU / f64::from(segments);
            let step = s.lights.iter().any(|l| to_light(l, p).dot(p).abs() < band);
            if m.phong_terms().shininess <= 0.0 && step {
                e.skipped += 1;
                continue;
            }
            let vis = vec![1.0; s.lights.len()];
            let exact = shade(
                &m,
                glview::shading::Tex::WHITE,
                p,
                p,
                eye,
                &s.lights,
                &vis,
                &s.lighting,
            );
            for k in 0..3 {
                let err = (f64::from(px[k]) - exact[k] * 255.0).abs();
                if err > e.worst {
                    (e.worst, e.worst_at) = (err, (x, y));
                }
            }
            e.compared += 1;
        }
    }
    assert!(e.compared > 4000, "{e:?}");
    e
}

/// A fine sphere within `tolerance`, every interior pixel hit.
fn assert_close(e: &SphereError, tolerance: f64, what: &str) {
    println!("{what}: {e:?}");
    assert!(e.worst <= tolerance && e.missed == 0, "{what}: {e:?}");
}

fn sphere_settings(ortho: bool) -> FrameSettings {
    let sc = scene(vec![sphere(DVec3::ZERO, 8, 0)], vec![Material::default()]);
    let lights = vec![point(3.0, 2.5, 1.0), directional(-0.3, -0.2, -1.0)];
    let mut s = settings(&sc, 35.0, 25.0, lights, 192.0 / 160.0);
    if ortho {
        s.camera.ortho_height = Some(2.6);
    }
    s
}

/// Tolerances, in 1/255: 0.5 for the final rounding, plus the tessellation error of 256
/// segments (normals interpolated across facets, hit points up to 1 − cos(π/256) ≈ 7.5e-5
/// inside the sphere), measured at about 0.06 without shadows. With shadows, facets at the
/// terminator that face away from the light are shadowed by the sphere's lit side — exactly,
/// for the polygon mesh — while the exact sphere there still gets Kd·Lc·N·L with N·L up to
/// the facet angle: at most 0.7 · 0.7 · sin(2π/256) · 255 ≈ 3, measured ≈ 0.8.
const SPHERE_TOLERANCE: f64 = 0.75;
const SPHERE_SHADOW_TOLERANCE: f64 = 1.5;

#[test]
fn sphere_matches_exact_phong() {
    let mut s = sphere_settings(false);
    let e = sphere_error(&s, material(0.7, 0.5, 40.0), 256);
    assert_close(&e, SPHERE_SHADOW_TOLERANCE, "perspective Phong, shadows");
    s.shadows.enabled = false;
    let e = sphere_error(&s, material(0.7, 0.5, 40.0), 256);
    assert_close(&e, SPHERE_TOLERANCE, "perspective Phong, no shadows");
    // The comparison is sharp enough to see a coarse tessellation.
    let coarse = sphere_error(&s, material(0.7, 0.5, 40.0), 16);
    assert!(coarse.worst > 4.0, "16 segments: {coarse:?}");
}

#[test]
fn sphere_orthographic_and_extreme_shininess() {
    let mut s = sphere_settings(true);
    for ns in [40.0, 0.0, 10_000.0] {
        for (shadows, tol) in [(true, SPHERE_SHADOW_TOLERANCE), (false, SPHERE_TOLERANCE)] {
            s.shadows.enabled = shadows;
            let e = sphere_error(&s, material(0.6, 0.4, ns), 256);
            assert_close(&e, tol, &format!("ortho, Ns = {ns}, shadows {shadows}"));
        }
    }
}

#[test]
fn sphere_gouraud_is_close_at_fine_tessellation() {
    let mut s = sphere_settings(false);
    s.shading = Shading::Gouraud;
    let e = sphere_error(&s, material(0.7, 0.3, 10.0), 256);
    assert_close(&e, SPHERE_SHADOW_TOLERANCE, "Gouraud, 256 segments");
    // Coarse Gouraud visibly misses the per-pixel highlight.
    let coarse = sphere_error(&s, material(0.7, 0.8, 60.0), 12);
    assert!(coarse.worst > 10.0, "12 segments: {coarse:?}");
}

/// Floor at y = 0 (mesh 0), box over it from y = 1 to 2 (mesh 1). Checks every floor pixel's
/// shadow flag against `in_shadow` on the floor point its ray hits, except where a neighbour
/// pixel's classification differs (within 1 pixel of the shadow's edge), and checks the
/// colour of shadowed floor pixels (ambient only). Returns (shadowed, lit) pixel counts.
fn check_box_shadow(light: Light, in_shadow: impl Fn(DVec3) -> bool) -> (usize, usize) {
    let mats = vec![material(0.8, 0.0, 0.0), material(0.5, 0.2, 20.0)];
    let sc = scene(
        vec![
            floor(3.0, 0.0, 0),
            cuboid(DVec3::new(-0.5, 1.0, -0.5), DVec3::new(0.5, 2.0, 0.5), 1),
        ],
        mats,
    );
    let (w, h) = (240, 180);
    let s = settings(&sc, 30.0, 50.0, vec![light], w as f32 / h as f32);
    let (img, info) = render_with_info(&sc, &s, w, h);
    let ray = rays(&sc, &s, w, h);
    let floor_point = |x: i64, y: i64| {
        let (o, d) = ray(x, y);
        o - d * (o.y / d.y)
    };
    let ambient = glview::reference::to_unorm8(DVec3::splat(0.2 * 0.2));
    let (mut shadowed, mut lit) = (0, 0);
    for y in 0..h as i64 {
        for x in 0..w as i64 {
            let pi = &info[(y as u32 * w + x as u32) as usize];
            if pi.mesh != Some(0) {
                continue;
            }
            let inside = in_shadow(floor_point(x, y));
            let edge =
                (-1..=1).any(|j| (-1..=1).any(|i| in_shadow(floor_point(x + i, y + j)) != inside));
            if edge {
                continue;
            }
            assert_eq!(pi.shadowed[0], inside, "pixel {x},{y}");
            if inside {
                assert_eq!(img.pixel(x as u32, y as u32)[..3], ambient, "{x},{y}");
                shadowed += 1;
            } else {
                lit += 1;
            }
        }
    }
    assert!(
        shadowed > 100 && lit > 3000,
        "{shadowed} shadowed, {lit} lit"
    );
    (shadowed, lit)
}

#[test]
fn box_shadow_is_its_footprint() {
    // Straight down: the footprint is the box's own square.
    let down = check_box_shadow(directional(0.0, -1.0, 0.0), |p| {
        p.x.abs() <= 0.5 && p.z.abs() <= 0.5
    });
    // A point light above the centre: the top face (y = 2) is nearer the light and casts
    // the larger square, scaled by 5 / (5 − 2).
    let point = check_box_shadow(point(0.0, 5.0, 0.0), |p| {
        let half = 0.5 * 5.0 / 3.0;
        p.x.abs() <= half && p.z.abs() <= half
    });
    println!("shadowed/lit floor pixels: directional {down:?}, point {point:?}");
    assert!(point.0 > down.0);
}

/// Lights off and ambient 1: every colour is Ka, so blending is checked exactly.
#[test]
fn translucent_layers_blend_far_to_near_and_cast_no_shadow() {
    let ka = |c: [f32; 3], opacity: f32| Material {
        opacity: (opacity < 1.0).then_some(opacity),
        ..Material::with_phong(PhongTerms {
            ambient: c,
            diffuse: [0.0; 3],
            ..Default::default()
        })
    };
    let mats = vec![
        ka([1.0, 0.0, 0.0], 1.0),
        ka([0.0, 0.0, 1.0], 0.25),
        ka([0.0, 1.0, 0.0], 0.5),
    ];
    let sc = scene(
        vec![floor(2.0, 0.0, 0), floor(1.0, 0.5, 1), floor(0.5, 1.0, 2)],
        mats,
    );
    let (w, h) = (101, 101);
    let mut s = settings(&sc, 0.0, 90.0, vec![], 1.0);
    // Looking straight down with +x to the right: pixel x sees world x = −2 + 4(x + ½)/101.
    s.camera.ortho_height = Some(4.0);
    s.lighting.ambient = DVec3::ONE;
    let (img, info) = render_with_info(&sc, &s, w, h);
    // Straight down the centre: red floor, then blue (0.25), then green (0.5) nearest.
    let under = DVec3::new(0.75, 0.0, 0.25);
    let expect = glview::reference::to_unorm8(DVec3::Y * 0.5 + under * 0.5);
    assert_eq!(img.pixel(50, 50)[..3], expect);
    assert_eq!(
        (info[50 * 101 + 50].layers, info[50 * 101 + 50].mesh),
        (2, Some(2))
    );
    // Off to the side only the blue layer covers the floor; at the corner only the floor.
    let i = 50 * 101 + 70;
    assert_eq!(info[i].layers, 1);
    assert_eq!(img.pixel(70, 50)[..3], glview::reference::to_unorm8(under));
    assert_eq!(img.pixel(98, 98)[..3], [255, 0, 0]);

    // A light straight down: glass above the floor casts no shadow.
    s.lights = vec![directional(0.0, -1.0, 0.0)];
    s.camera.pitch_deg = 60.0;
    s.camera.ortho_height = None;
    let (_, info) = render_with_info(&sc, &s, w, h);
    let floor_pixels = info.iter().filter(|p| p.mesh == Some(0)).count();
    assert!(floor_pixels > 1000);
    assert!(info.iter().all(|p| !p.shadowed[0]));
}

/// A textured quad seen straight down through an orthographic camera that maps pixel
/// centres onto texel centres: the render must be the texture itself, top row first (v = 0
/// samples row 0), through Ka · texture with ambient 1 and no lights.
#[test]
fn texture_maps_texel_for_pixel() {
    let (tw, th, rgba) = glview::scene::generate::checker_png_rgba();
    let mut quad = floor(1.0, 0.0, 0);
    for v in &mut quad.vertices {
        // Left edge u = 0; the far (−z) edge, at the top of the picture, v = 0.
        v.uv = [(v.position[0] + 1.0) / 2.0, (v.position[2] + 1.0) / 2.0];
    }
    quad.has_uv = true;
    let texture = glview::scene::Texture {
        path: "checker".into(),
        image: None,
        width: tw,
        height: th,
        rgba: rgba.clone(),
    };
    let m = Material {
        base_color_texture: Some(TextureSlot::plain(
            std::sync::Arc::new(texture),
            ColorSpace::Srgb,
        )),
        ..Material::with_phong(PhongTerms {
            ambient: [1.0; 3],
            diffuse: [0.0; 3],
            ..Default::default()
        })
    };
    let sc = scene(vec![quad], vec![m]);
    let mut s = settings(&sc, 0.0, 90.0, vec![], 1.0);
    s.camera.ortho_height = Some(2.0);
    s.lighting.ambient = DVec3::ONE;
    let (img, info) = render_with_info(&sc, &s, tw, th);
    assert!(info.iter().all(PixelInfo::hit));
    assert_eq!(img.data, rgba);
    assert_eq!(glview::reference::render(&sc, &s, tw, th), img);
    // Empty and single-pixel outputs.
    assert!(glview::reference::render(&sc, &s, 0, 7).data.is_empty());
    assert_eq!(glview::reference::render(&sc, &s, 1, 1).data.len(), 4);
    // At twice the resolution pixel x samples texel coordinate x/2 − 1/4: bilinear weights
    // 3/4 and 1/4, and row 0 blends with the last row (GL_REPEAT).
    let (img, _) = render_with_info(&sc, &s, 2 * tw, 2 * th);
    assert_eq!(img.pixel(3, 3)[..3], [255; 3]);
    // Texel column 7.75 (white 7, black 8) on row 3.75 (both in the top cell row).
    assert_eq!(img.pixel(16, 8)[..3], [64; 3]);
    // Column 7.25 on row −0.25: 3/4 of row 0 (white, black), 1/4 of row 63 (black, white).
    assert_eq!(img.pixel(15, 0)[..3], [159; 3]);
}

/// Zero-area triangles, zero and non-finite normals, Ns = 0 and 10,000, a point light
/// exactly on a surface and a grazing light: no NaN (the renderer debug-asserts finite values), and no pixel below the
/// ambient floor, which a NaN turned into 0 by the clamp would produce.
#[test]
fn degenerate_input_stays_finite() {
    let a = DVec3::new(0.0, 1.5, 0.0);
    let degenerate = Mesh {
        name: "degenerate".into(),
        vertices: vec![
            vertex(a, DVec3::ZERO),
            vertex(a, DVec3::ZERO),
            vertex(a + DVec3::X, DVec3::new(f64::NAN, 0.0, 0.0)),
            vertex(a + 2.0 * DVec3::X, DVec3::ZERO),
        ],
        indices: vec![0, 1, 2, 0, 2, 3, 1, 1, 1],
        material: 0,
        ..Default::default()
    };
    // Visible quads whose normals are all zero, or not finite, as a file may give them.
    let mut bad_normals = quads(
        &[
            [
                -2.5, -0.5, -2.0, 0.5, -0.5, -2.0, 0.5, 0.5, -2.0, -2.5, 0.5, -2.0,
            ],
            [
                0.5, -0.5, -2.0, 2.5, -0.5, -2.0, 2.5, 0.5, -2.0, 0.5, 0.5, -2.0,
            ],
        ]
        .map(|q| std::array::from_fn(|k| DVec3::new(q[3 * k], q[3 * k + 1], q[3 * k + 2]))),
        0,
    );
    for (k, v) in bad_normals.vertices.iter_mut().enumerate() {
        v.normal = if k < 4 {
            [0.0; 3]
        } else {
            [f32::NAN, 0.0, f32::INFINITY]
        };
    }
    let mats = vec![material(0.6, 0.8, 0.0), material(0.6, 0.8, 10_000.0)];
    let sc = scene(
        vec![
            sphere(DVec3::new(-1.2, 0.0, 0.0), 64, 0),
            sphere(DVec3::new(1.2, 0.0, 0.0), 64, 1),
            floor(3.0, -1.0, 1),
            degenerate,
            bad_normals,
        ],
        mats,
    );
    // The first light sits on a vertex of the left sphere, facing the camera; the second
    // grazes the floor.
    let lights = vec![point(-1.2, 0.0, 1.0), directional(1.0, -1e-6, 0.0)];
    for shading in [Shading::Phong, Shading::Gouraud] {
        let mut s = settings(&sc, 0.0, 10.0, lights.clone(), 1.0);
        s.shading = shading;
        let (img, info) = render_with_info(&sc, &s, 96, 96);
        let floor_value = glview::reference::to_unorm8(DVec3::splat(0.04))[0];
        for (px, pi) in img.data.chunks_exact(4).zip(&info) {
            if pi.hit() {
                assert!(pi.distance.is_finite());
                assert!(px[..3].iter().all(|&c| c >= floor_value), "{px:?} {pi:?}");
            }
        }
        let hits = info.iter().filter(|p| p.hit()).count();
        assert!(hits > 1200, "{hits} hits");
    }
}
