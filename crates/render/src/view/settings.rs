//! The frame settings a view's options describe (camera, lights, tiers, post) and the PBR
//! environment they ask for; no GL, no file. The native session, the window, the reference
//! renderer, the tools and the browser build all start here, so `--keys` headless and the
//! keys in a window give the same view.
use super::View;
use crate::camera::OrbitCamera;
use crate::error::{Error, Result};
use crate::frame::LightingParams;
use crate::frame::{AttributeView, Translucency};
use crate::frame::{FrameSettings, ShadowSettings};
use crate::light::{LightOpt, LightSpec, MAX_LIGHTS};
use crate::options::{Diffuse, Options, Ortho, Show};
use crate::pbr::precompute::IblSettings;
use crate::pbr::{EnvRequest, EnvSource, OutputParams, PbrParams};
use crate::scene::Scene;
use crate::stereo::{Stereo, StereoMode};
use glam::Vec3;

/// What the options change in a loaded scene (a file's, or one a program passed in): the
/// x-rayed materials and objects, and `--single-sided`.
pub fn adjust_scene(args: &Options, s: &mut crate::scene::Scene) -> Result<()> {
    if !args.load.xray.is_empty() {
        let opacity = args
            .render
            .opacity
            .unwrap_or(crate::scene::model::xray::XRAY_OPACITY);
        s.xray(&args.load.xray, opacity.clamp(0.0, 1.0))
            .map_err(Error::Usage)?;
    }
    if args.load.single_sided {
        for m in &mut s.materials {
            m.double_sided = false;
        }
    }
    Ok(())
}

/// The frame settings the options describe, with `--keys` applied (replayed on the
/// options by a [`View`], as the window and the server apply them: `View::settled`), and
/// the camera before the keys (where `R` returns).
pub fn frame_settings(args: &Options, scene: &Scene) -> Result<(FrameSettings, OrbitCamera)> {
    let mut plain = args.clone();
    plain.camera.keys = None;
    let home = FrameSettings::new(&plain, scene)?.camera;
    let settled = View::settled(args, scene)?;
    Ok((FrameSettings::new(&settled, scene)?, home))
}

impl FrameSettings {
    /// The frame settings `args` describe, derived from them alone (every default is the
    /// option's: nothing here has one of its own); `--keys` is not replayed here
    /// ([`frame_settings`] does). The options are typed and checked
    /// ([`Options::validate`]); this only places them in the scene.
    pub fn new(args: &Options, scene: &Scene) -> Result<FrameSettings> {
        derive(args, scene)
    }
}

fn derive(args: &Options, scene: &Scene) -> Result<FrameSettings> {
    let (w, h) = args.picture.size;
    let aspect = w as f32 / h as f32;
    let cam = &super::file_camera::resolve(args, scene)?;
    let mut camera = OrbitCamera::fit(&scene.bounds, cam.fov, aspect);
    camera.yaw_deg = cam.yaw;
    camera.pitch_deg = cam.pitch;
    if let Some(t) = cam.target {
        camera.target = scene.to_local(glam::DVec3::from_array(t));
    }
    if let Some(d) = cam.distance {
        camera.distance = d;
    }
    camera.near = cam.near;
    match cam.ortho {
        Some(Ortho::Height(h)) => camera.ortho_height = Some(h),
        Some(Ortho::Fit) => {
            camera.ortho_height = Some(OrbitCamera::fit_ortho_height(&scene.bounds, aspect))
        }
        None => {}
    }
    camera.shift_x = args.camera.lens_shift;
    let stereo = stereo_of(args, &mut camera)?;
    let (lights, headlight, kit) = lights(args, scene)?;
    let pbr = PbrParams::from(args);
    let post = &args.post;
    let point_px = point_size(args, scene, &camera, h);
    let settings = FrameSettings {
        camera,
        lights,
        lighting: LightingParams {
            ambient: crate::options::convert::ambient(&args.light),
            wrap: args.light.diffuse == Diffuse::Wrap,
            terms: args.render.legacy_terms,
            pbr,
            pbr_terms: args.render.terms,
            output: OutputParams::from(&args.pbr),
            headlight,
            shadow_casters: match args.shadow.lights {
                Some(n) => n.min(MAX_LIGHTS as u8),
                None if kit => 1,
                None => MAX_LIGHTS as u8,
            },
            translucency: Translucency {
                mode: args.render.translucency,
                blend: args.render.blend,
                opacity: args.render.opacity,
                log_depth: args.render.depth == crate::options::DepthMode::Log,
            },
            post: crate::frame::Post {
                bloom: crate::frame::Bloom::from(post),
                fxaa: post.aa == crate::options::AaMode::Fxaa,
                transparent: post.transparent,
                show_bloom: args.render.show == Show::Bloom,
                linear_out: false,
            },
            attribute_view: match args.render.show {
                Show::Normals => AttributeView::Normals,
                Show::Uvs => AttributeView::Uvs,
                Show::Roughness => AttributeView::Roughness,
                Show::Metallic => AttributeView::Metallic,
                _ => AttributeView::None,
            },
            point_size: (point_px, h),
            edges: edges(args),
            guides: crate::frame::Guides {
                grid: args.render.grid,
                axes: args.render.axes,
                scale: ssaa_factor(args) as f32,
                up: args.load.up,
            },
        },
        shading: args.render.shading,
        background: Vec3::from_array(args.background()),
        shadows: ShadowSettings::from(&args.shadow),
        show_shadow_map: args.render.show == Show::ShadowMap,
        stereo,
    };
    Ok(settings)
}

/// The frame's stereo from the options, and the camera an `--eye` picture looks through
/// (`camera` itself otherwise): the eyes' separation and convergence default to the orbit
/// distance / 30 and the orbit distance.
fn stereo_of(args: &Options, camera: &mut OrbitCamera) -> Result<Stereo> {
    let o = &args.stereo;
    let asked = o.mode != StereoMode::Off || o.eye.is_some();
    if asked && camera.ortho_height.is_some() {
        return Err(Error::Usage(
            "--stereo and --eye need a perspective view: an orthographic one has no parallax \
             (every depth shifts alike); drop --ortho"
                .into(),
        ));
    }
    let convergence = o.convergence.unwrap_or(camera.distance);
    let stereo = Stereo {
        mode: o.mode,
        method: o.anaglyph,
        glasses: o.glasses,
        swap: o.swap_eyes,
        separation: o
            .eye_separation
            .unwrap_or_else(|| crate::stereo::default_separation(convergence)),
        convergence,
        parity: (0, 0),
    };
    let Some(eye) = o.eye else {
        return Ok(stereo);
    };
    // One eye as a plain picture: the camera the composed picture's eye has.
    let eye = if o.swap_eyes { eye.other() } else { eye };
    let (w, h) = crate::stereo::output_size(o.mode, args.picture.size);
    *camera = crate::stereo::Layout::of(o.mode, w, h).eye_camera(camera, eye, &stereo);
    Ok(Stereo {
        mode: StereoMode::Off,
        ..stereo
    })
}

/// The size of the picture `args` draw: `--size`, except side-by-side-full's (twice as
/// wide) and one `--eye` of a squeezed mode (half the width or height).
pub fn output_size(args: &Options) -> (u32, u32) {
    let mode = args.stereo.mode;
    let (w, h) = crate::stereo::output_size(mode, args.picture.size);
    match args.stereo.eye {
        Some(_) => crate::stereo::Layout::of(mode, w, h).eye,
        None => (w, h),
    }
}

/// The default point diameter in mean nearest-neighbour spacings. Measured at 640×480 (the
/// share of the silhouette covered): a 150×150 lattice plane 78 % at 1, 100 % from 1.5
/// (√2 closes a lattice); 20,000 random points on a sphere 39 % at 1, 67 % at 1.5, 86 % at 2,
/// 99 % at 3. 1.5 closes a scanner's grid and leaves a random cloud's dots apart.
const POINT_SPACINGS: f32 = 1.5;

/// `--point-size`, else [`POINT_SPACINGS`] times the scene's point spacing as seen from
/// `camera` (at the target's distance, in a picture `h` pixels high), within
/// [`MIN_POINT_PX`, `MAX_POINT_PX`].
fn point_size(args: &Options, scene: &Scene, camera: &OrbitCamera, h: u32) -> f32 {
    use crate::frame::{MAX_POINT_PX, MIN_POINT_PX};
    if let Some(px) = args.render.point_size {
        return px;
    }
    if scene.wire.points.is_empty() {
        return MIN_POINT_PX;
    }
    let view_height = camera
        .ortho_height
        .unwrap_or_else(|| 2.0 * camera.distance * (camera.fov_y_deg.to_radians() * 0.5).tan());
    let px = scene.wire.spacing().map_or(MAX_POINT_PX, |d| {
        POINT_SPACINGS * d as f32 * h as f32 / view_height.max(1e-30)
    });
    px.clamp(MIN_POINT_PX, MAX_POINT_PX)
}

/// Pixels of the frame drawn per pixel of the picture: SSAA draws the frame k times larger,
/// so lines and labels k times larger keep their size.
/// How many times larger on each axis an SSAA picture is rendered (1 without SSAA).
pub fn ssaa_factor(args: &Options) -> u32 {
    if args.post.aa == crate::options::AaMode::Ssaa {
        args.post.aa_samples.clamp(1, 4)
    } else {
        1
    }
}

/// `--edges`, `--wireframe`, `--wireframe-only`, `--edge-color` and the loader's crease angle.
fn edges(args: &Options) -> crate::frame::Edges {
    use crate::frame::EdgeMode;
    let r = &args.render;
    let d = crate::frame::Edges::default();
    crate::frame::Edges {
        mode: if r.wireframe || r.wireframe_only {
            EdgeMode::Wireframe
        } else if r.edges {
            EdgeMode::Feature
        } else {
            EdgeMode::Off
        },
        crease_deg: args
            .load
            .crease
            .unwrap_or(crate::scene::geometry::normals::DEFAULT_CREASE_DEG),
        color: r.edge_color.unwrap_or(d.color),
        surface: !r.wireframe_only,
        only_color: r.edge_color.unwrap_or(d.only_color),
        width: r.line_width * ssaa_factor(args) as f32,
        method: r.edge_method,
    }
}

/// The frame's lights in the scene's coordinates, the headlight's colour, and whether they
/// are the default kit (no `--light` and no lights in the file, or `--light kit`): a key
/// light that casts the shadow, a fill from the other side and a headlight, so every side of
/// a model is readable from any orbit. A file's own lights replace the kit (`--light file`,
/// the default when it has some).
fn lights(args: &Options, scene: &Scene) -> Result<(Vec<crate::light::Light>, Option<Vec3>, bool)> {
    let given = &args.light.lights;
    let mut colors: Vec<Vec3> = args
        .light
        .colors
        .iter()
        .map(|c| Vec3::from_array(*c))
        .collect();
    let pick = |colors: &[Vec3], i: usize| {
        colors
            .get(i)
            .or(colors.last())
            .copied()
            .unwrap_or(Vec3::ONE)
    };
    let wants_file = match given[..] {
        [] => !scene.lights.is_empty(),
        [LightOpt::File] => true,
        _ => false,
    };
    if wants_file && scene.lights.is_empty() {
        return Err(Error::Usage(format!(
            "--light file: {} has no lights (glTF KHR_lights_punctual)",
            scene.name
        )));
    }
    if wants_file {
        // The file's lights replace the kit, headlight included; each may cast a shadow. The
        // PBR tier takes them as the specification says, the legacy tier exposed
        // (docs/gltf/lights.md).
        let scale = match args.render.shading {
            crate::frame::Shading::Pbr => 1.0,
            _ => {
                let (lo, hi) = scene.file_bounds;
                let centre = scene.origin + scene.bounds.center().as_dvec3();
                crate::light::legacy_scale(&scene.lights, centre, 0.5 * (hi - lo).length())
            }
        };
        let lights = scene.lights.iter().map(|l| {
            let mut light = crate::light::file_light(l, scene.origin);
            light.color *= scale;
            light
        });
        return Ok((lights.collect(), None, false));
    }
    let mut specs = Vec::new();
    let mut headlight = None;
    for l in given {
        if *l == LightOpt::Head {
            headlight = Some(pick(&colors, specs.len()));
        } else if let Some(spec) = l.spec() {
            specs.push(spec);
        }
    }
    let kit = given.is_empty() || given[..] == [LightOpt::Kit];
    if kit {
        specs.push(LightSpec::default_light());
        specs.push(LightSpec::fill_light());
        headlight = Some(Vec3::splat(crate::light::KIT_HEAD));
        if colors.is_empty() {
            colors = vec![
                Vec3::splat(crate::light::KIT_KEY),
                Vec3::splat(crate::light::KIT_FILL),
            ];
        }
    }
    let lights = specs
        .iter()
        .enumerate()
        .map(|(i, spec)| spec.to_local(scene.origin, pick(&colors, i)))
        .collect();
    Ok((lights, headlight, kit))
}

/// Where the PBR tier's environment comes from, and how its maps are made.
pub fn env_request(args: &Options) -> Result<EnvRequest> {
    let source = match (&args.pbr.env, args.pbr.env_color) {
        (Some(p), _) => EnvSource::File(p.clone()),
        (None, Some(c)) => EnvSource::Uniform(c),
        (None, None) => EnvSource::Builtin,
    };
    Ok(EnvRequest {
        source,
        settings: IblSettings::from(&args.pbr),
        encoding: args.pbr.ibl_encoding,
        cache: args.load.cache,
        precompute: args.pbr.ibl_precompute,
    })
}
