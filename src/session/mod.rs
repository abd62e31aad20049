//! The session: one headless context, kept, with its program cache and the last picture's
//! renderer (uploaded scene, environment maps, shadow maps), and what it does with them:
//! load, draw (options and the outputs asked for → colour, depth, normals, ids), write.
//! The library API, `glview batch`, the tests' fixture and the server draw through a
//! [`Session`]; nothing here calls back up. What a picture is made of comes from
//! `settings` (no GL), its PNG text from `text`, the other headless modes are `modes`.
//!
//! ```no_run
//! let mut session = glview::session::Session::new();
//! let mut o = glview::Options::default();
//! o.picture.size = (320, 240);
//! session.write(&o, std::path::Path::new("builtin.png"))?;
//! o.camera.yaw = 60.0; // same scene: the upload and the maps are kept
//! session.write(&o, std::path::Path::new("builtin-60.png"))?;
//! # Ok::<(), glview::Error>(())
//! ```
pub(crate) mod animated;
pub(crate) mod modes;
mod profile;
pub(crate) mod settings;
pub(crate) mod text;

pub use animated::{turntable_yaw, AnimTimes};
pub(crate) use glview_render::view::settings::env_request;
pub use glview_render::view::settings::frame_settings;
pub use glview_render::view::{moment, pose_scene, View};
pub use modes::{compile_shaders, print_info, render_headless, render_reference};
pub use profile::Profile;
pub(crate) use settings::reference_env;
pub use settings::{load_options, load_scene, load_scene_prepared, load_scene_with};
pub use text::{png_text, Drawer, PictureText, Repro};

use crate::error::Result;
use crate::headless::Headless;
use crate::image_out::RgbaFiles;
use crate::options::{AaMode, Options};
use crate::platform::{Backend, GlRequest};
use crate::render::attributes::{FrameDepth, Outputs};
use crate::render::ibl::{Environments, SharedEnvironments};
use crate::render::Renderer;
use crate::repro::SceneKey;
use crate::scene::lod::clusters::Clusters;
use crate::scene::profile::LoadProfile;
use crate::shader::cache::{ProgramCache, SharedPrograms};
use profile::ms;
use std::path::Path;
use std::time::Instant;

/// A headless context kept between pictures, with what it was asked for; the context's
/// program cache (held so that programs outlive the renderers that compiled them); and the
/// last picture's renderer (its uploaded scene, environment maps and shadow maps) with the
/// options it was made for. Field order is drop order: GL objects before their context.
struct KeptContext {
    /// Least recently drawn first; at most [`Session::keep_scenes`] of them. Keyed by the
    /// model and its load options only ([`SceneKey`]).
    renderers: Vec<(SceneKey, Renderer)>,
    /// The environment maps every renderer of the context shares (one copy of each).
    envs: SharedEnvironments,
    programs: SharedPrograms,
    hl: Headless,
    request: (Backend, GlRequest),
}

/// Makes sure `kept` is a context for `args` (made, or re-targeted to `size`), multisampled
/// when `msaa`.
fn context(
    args: &Options,
    size: (u32, u32),
    msaa: bool,
    kept: &mut Option<KeptContext>,
    profile: &mut Profile,
) -> Result<()> {
    let request = (args.context.backend, args.context.gl);
    let reused = match kept {
        Some(c) if c.request == request => c.hl.reset_target(size.0, size.1).is_ok(),
        _ => false,
    };
    if !reused {
        // The old context goes first: one context alive at a time.
        *kept = None;
        let t = Instant::now();
        let hl = Headless::new(args.context.backend, args.context.gl, size.0, size.1)?;
        profile.context_ms = ms(t);
        *kept = Some(KeptContext {
            renderers: Vec::new(),
            envs: Environments::shared(),
            programs: ProgramCache::for_context(&hl.gpu),
            hl,
            request,
        });
    }
    let kept = kept.as_mut().expect("context made above");
    if msaa {
        kept.hl.enable_msaa(args.post.aa_samples)?;
    }
    Ok(())
}

/// Whether a picture of `args` is drawn into a multisampled target.
fn msaa(args: &Options) -> bool {
    args.post.aa == AaMode::Msaa
}

/// A headless context made on first use and kept between pictures (re-targeted to each
/// picture's size; made anew when a picture asks for another backend or GL request), its
/// program cache, and the last picture's renderer, kept while the scene's options stay the
/// same: a turntable or a camera sweep loads and uploads once.
pub struct Session {
    kept: Option<KeptContext>,
    /// How many scenes stay uploaded (least recently drawn goes first).
    keep: usize,
}

impl Default for Session {
    fn default() -> Session {
        Session {
            kept: None,
            keep: 1,
        }
    }
}

impl Session {
    /// A session without a context yet (the first picture makes it).
    pub fn new() -> Session {
        crate::native_hooks();
        Session::default()
    }

    /// Keeps up to `n` scenes uploaded instead of one (a server whose viewers look at
    /// different models draws each without loading it again); the least recently drawn
    /// goes first.
    pub fn keep_scenes(&mut self, n: usize) {
        self.keep = n.max(1);
        if let Some(k) = &mut self.kept {
            let excess = k.renderers.len().saturating_sub(self.keep);
            k.renderers.drain(..excess);
        }
    }

    /// Whether the context (once made) keeps one size: an OSMesa buffer, where a picture of
    /// another size makes a new context (and uploads every scene again).
    pub fn fixed_size(&self) -> bool {
        self.kept.as_ref().is_some_and(|k| !k.hl.resizable())
    }

    /// A session whose context is made now, for pictures of `args` (so a machine without
    /// one fails here, not at the first picture).
    pub fn open(args: &Options) -> Result<Session> {
        let mut s = Session::new();
        context(
            args,
            args.picture.size,
            msaa(args),
            &mut s.kept,
            &mut Profile::default(),
        )?;
        Ok(s)
    }

    /// Draws the picture of `args` (of `given`'s scene instead of the options' model where
    /// set) and returns it, with the buffers `outputs` asks for.
    pub fn draw(
        &mut self,
        args: &Options,
        given: Option<Given>,
        outputs: Outputs,
        profile: &mut Profile,
    ) -> Result<Drawn> {
        draw(args, self.keep, &mut self.kept, given, outputs, profile)
    }

    /// The scene of `args` (kept, or loaded and uploaded now): what inputs that depend on
    /// the model's size (zoom, fit) are applied with.
    pub fn scene(&mut self, args: &Options) -> Result<&crate::scene::Scene> {
        let size = args.picture.size;
        Ok(self.kept_renderer(args, size)?.1.scene())
    }

    /// Runs `f` with the renderer of `args`' scene (kept, or loaded and uploaded now) and
    /// the context re-targeted to `size`, single-sampled: for pictures made of several
    /// viewports of one target (the server's Phong | PBR panes).
    pub(crate) fn with_renderer<T>(
        &mut self,
        args: &Options,
        size: (u32, u32),
        f: impl FnOnce(&Headless, &mut Renderer) -> Result<T>,
    ) -> Result<T> {
        let mut single = args.clone();
        single.post.aa = AaMode::None;
        let (hl, renderer) = self.kept_renderer(&single, size)?;
        f(hl, renderer)
    }

    /// Renders the model of `args` into `path`: a still (PNG or JPEG; `--frames` times, the
    /// last one written; `--stats` printed) or, for .gif, .apng and .webp, an animated
    /// picture (docs/animated.md).
    pub fn write(&mut self, args: &Options, path: &Path) -> Result<()> {
        write(args, path, self.keep, &mut self.kept)
    }

    /// The context re-targeted to `size` and the renderer of `args`' scene ([`prepare`]).
    fn kept_renderer(
        &mut self,
        args: &Options,
        size: (u32, u32),
    ) -> Result<(&Headless, &mut Renderer)> {
        let profile = &mut Profile::default();
        let kept = prepare(args, self.keep, &mut self.kept, None, size, profile)?;
        let renderer = &mut kept.renderers.last_mut().expect("made by prepare").1;
        Ok((&kept.hl, renderer))
    }

    /// Runs `draw` with this session's context, re-targeted to `size` and single-sampled (a
    /// comparison's panes and a sheet's cells are viewports of one target), and a renderer
    /// of `scene` with the environment of `args`, made for the call and dropped after it.
    /// `clusters` are the loader's ([`load_scene_prepared`]: a cache hit's carry the levels
    /// of detail); without them the clusters are made here without levels, which the
    /// renderer builds before a picture that draws them.
    pub(crate) fn with_scene<T>(
        &mut self,
        args: &Options,
        mut scene: crate::scene::Scene,
        clusters: Option<Vec<Option<Clusters>>>,
        size: (u32, u32),
        draw: impl FnOnce(&Headless, &mut Renderer) -> Result<T>,
    ) -> Result<T> {
        context(args, size, false, &mut self.kept, &mut Profile::default())?;
        let kept = self.kept.as_mut().expect("context made above");
        kept.renderers.clear();
        let clusters = clusters
            .unwrap_or_else(|| crate::scene::lod::clusters::prepare_without_lod(&mut scene));
        let mut renderer = Renderer::prepared(&kept.hl.gpu, scene, clusters)?;
        renderer.share_environments(kept.envs.clone());
        renderer.set_environment(env_request(args)?);
        posed(args, &mut renderer, &mut Profile::default())?;
        draw(&kept.hl, &mut renderer)
    }

    /// Whether a picture of `args` finds its scene uploaded (drawing it loads nothing).
    pub fn has_scene(&self, args: &Options) -> bool {
        let stamp = crate::repro::stamp(args);
        self.kept.as_ref().is_some_and(|c| {
            c.request == (args.context.backend, args.context.gl)
                && c.renderers
                    .iter()
                    .any(|(k, _)| k.matches(args, None, &stamp))
        })
    }

    /// Uploads a scene loaded off this thread ([`Prepared::load`]) for pictures of `args`:
    /// the GL half of a load, so a server's render thread spends only the upload on it.
    /// The least recently drawn of the kept scenes goes first, as for a load here.
    pub fn adopt(&mut self, args: &Options, prepared: Prepared) -> Result<()> {
        let Prepared { key, loaded } = prepared;
        let (scene, clusters) = loaded.0?;
        let request = (args.context.backend, args.context.gl);
        if self.kept.as_ref().is_none_or(|c| c.request != request) {
            let mut profile = Profile::default();
            context(
                args,
                args.picture.size,
                msaa(args),
                &mut self.kept,
                &mut profile,
            )?;
        }
        let kept = self.kept.as_mut().expect("context made above");
        // Another viewer's load of the same scene may have landed first: keep that one
        // rather than upload the same scene again.
        if kept.renderers.iter().any(|(k, _)| *k == key) {
            return Ok(());
        }
        let excess = (kept.renderers.len() + 1).saturating_sub(self.keep);
        kept.renderers.drain(..excess.min(kept.renderers.len()));
        let mut r = Renderer::prepared(&kept.hl.gpu, scene, clusters)?;
        r.share_environments(kept.envs.clone());
        kept.renderers.push((key, r));
        Ok(())
    }

    /// Drops the renderer and the context now (the session makes a new one if used again).
    pub fn close(&mut self) {
        self.kept = None;
    }
}

/// A scene loaded and prepared without GL (parsed, x-ray applied, large meshes' clusters
/// made), on any thread, for a [`Session`] to upload ([`Session::adopt`]): a server loads a
/// viewer's model on a worker while its render thread keeps drawing the others.
pub struct Prepared {
    key: SceneKey,
    loaded: Loaded,
}

impl Prepared {
    /// Loads the scene of `args` on the calling thread. The model file is stat'ed first, so
    /// a file rewritten during the load is seen as another scene and loaded again.
    pub fn load(args: &Options) -> Prepared {
        let key = SceneKey::new(args, None, crate::repro::stamp(args));
        Prepared {
            key,
            loaded: load(args),
        }
    }
}

/// Whether pictures of `a` and `b` draw the same scene (same model file, unchanged, and
/// load options): a server loads it once for both.
pub fn same_scene(a: &Options, b: &Options) -> bool {
    SceneKey::new(a, None, crate::repro::stamp(a)).matches(b, None, &crate::repro::stamp(b))
}

/// Loads the scene of `args` (on whatever thread calls it) with its time and the loader's
/// own profile, which is recorded per thread.
/// The scene with its large meshes' clusters prepared, load time (clusters included), the
/// loader's profile and the clusters' time.
type Loaded = (
    Result<(crate::scene::Scene, Vec<Option<Clusters>>)>,
    f64,
    Option<LoadProfile>,
    f64,
);

fn load(args: &Options) -> Loaded {
    let t = Instant::now();
    crate::scene::profile::take_last();
    let scene = load_scene_prepared(args);
    let profile = crate::scene::profile::take_last();
    let c = Instant::now();
    // A cache hit (or the miss that wrote the entry) brings them, levels of detail included;
    // else they are built here, without levels (the renderer builds those a picture draws).
    let scene = scene.map(|(mut s, prepared)| {
        let clusters =
            prepared.unwrap_or_else(|| crate::scene::lod::clusters::prepare_without_lod(&mut s));
        (s, clusters)
    });
    (scene, ms(t), profile, ms(c))
}

/// A scene given by the caller (the library API's in-memory models) instead of the
/// options' model file: `key` names it (equal keys are the same scene, kept uploaded).
pub struct Given<'a> {
    pub(crate) key: &'a str,
    pub(crate) scene: &'a crate::scene::Scene,
}

/// A drawn picture before it is written: the pixels (straight alpha), what its PNG text is
/// made of, the last frame's stats, and with `attributes` asked for, the attribute buffers
/// (normals too when `Some(true)`).
pub struct Drawn {
    pub image: crate::image_out::Rgba,
    /// The PNG text, built by [`Drawn::text`] for the pictures that need it.
    pub repro: PictureText,
    pub(crate) stats: crate::render::FrameStats,
    pub(crate) attributes: Option<crate::render::attributes::Attributes>,
    /// With `Outputs::linear`: the linear, unclamped colour, RGB per pixel, top row first.
    pub(crate) linear: Option<Vec<[f32; 3]>>,
    /// What the picture was drawn with (`--keys` applied): its tier and toggles.
    pub settings: crate::frame::FrameSettings,
}

impl Drawn {
    /// The picture's PNG text chunks (options as JSON, command line, camera words), made now.
    pub fn text(&self) -> Vec<(&'static str, String)> {
        self.repro.text()
    }
}

/// [`Session::write`]: `kept` is reused when it was made for the same backend and GL request
/// (its target is resized), else replaced.
fn write(args: &Options, path: &Path, keep: usize, kept: &mut Option<KeptContext>) -> Result<()> {
    if let Some(format) = crate::anim_out::AnimFormat::of(path) {
        return animated::write(args, path, format, keep, kept);
    }
    if args.motion.turntable {
        return Err(crate::Error::Image {
            path: path.into(),
            message: "--turntable makes an animated picture: -o ends in .gif, .apng or .webp"
                .into(),
        });
    }
    if args.stereo.eye.is_none() {
        if let Some(why) = crate::stereo::size_refusal(args.stereo.mode, args.picture.size) {
            return Err(crate::Error::Usage(why));
        }
    }
    let start = Instant::now();
    if let Some(img) = modes::map_view(args)? {
        return img.save_png(path, &text::map_view_text(args));
    }
    let mut profile = Profile::default();
    let drawn = draw(args, keep, kept, None, Default::default(), &mut profile)?;
    let t = Instant::now();
    // A JPEG carries no text: it is not made for one.
    let png = crate::image_out::OutputFormat::of(path) == Some(crate::image_out::OutputFormat::Png);
    let text = if png { drawn.text() } else { Vec::new() };
    drawn.image.save(path, &text)?;
    profile.encode_ms = ms(t);
    profile.total_ms = ms(start);
    if args.picture.stats {
        let mut line = serde_json::to_value(&drawn.stats).unwrap_or_default();
        line["profile"] = serde_json::to_value(&profile).unwrap_or_default();
        println!("{line}");
    }
    Ok(())
}

/// [`Session::draw`].
fn draw(
    args: &Options,
    keep: usize,
    kept: &mut Option<KeptContext>,
    given: Option<Given>,
    outputs: Outputs,
    profile: &mut Profile,
) -> Result<Drawn> {
    if args.stereo.mode == crate::stereo::StereoMode::QuadBuffer && args.stereo.eye.is_none() {
        return Err(crate::Error::Usage(
            "--stereo quad-buffer shows the eyes in a GL_STEREO window's own buffers, which \
             a picture has none of: draw --eye left and --eye right, or another mode"
                .into(),
        ));
    }
    let (w, h) = glview_render::view::settings::output_size(args);
    // SSAA renders k times larger on each axis and box-filters down.
    let k = glview_render::view::settings::ssaa_factor(args);
    let kept = prepare(args, keep, kept, given, (w * k, h * k), profile)?;
    let (hl, renderer) = (
        &kept.hl,
        &mut kept.renderers.last_mut().expect("made above").1,
    );
    renderer.time_post = args.picture.stats;
    renderer.cull_clusters = args.render.culling;
    // Depth, normals and ids come from the geometry the colour is drawn with: asking for
    // them never changes the picture (`--lod off` draws every triangle for all of them).
    renderer.lod = crate::render::Lod {
        mode: args.render.lod,
        error: args.render.lod_error,
    };
    let shown = View::settled(args, renderer.scene())?;
    let settings = crate::frame::FrameSettings::new(&shown, renderer.scene())?;
    let repro = PictureText::new(
        &hl.gpu.caps,
        hl.backend_name(),
        &settings,
        renderer.scene(),
        shown,
    );
    let compiled_before = kept.programs.borrow().compiled();
    let envs_before = kept.envs.borrow().made();
    let frames = args.picture.frames.max(1);
    let mut last = None;
    for i in 0..frames {
        let stats = renderer.render(&settings, &hl.target())?;
        profile.frames_ms.push(stats.ms);
        if args.picture.stats && i + 1 < frames {
            println!("{}", serde_json::to_string(&stats).unwrap_or_default());
        }
        last = Some(stats);
    }
    profile.textures = hl.gpu.take_texture_costs();
    let compiled = kept.programs.borrow().compiled();
    profile.programs_compiled = compiled.0 - compiled_before.0;
    profile.compile_ms = compiled.1 - compiled_before.1;
    profile.environments_made = kept.envs.borrow().made() - envs_before;
    let t = Instant::now();
    let mut image = crate::metrics::downsample(hl.read(), k);
    if args.post.transparent {
        crate::image_out::unpremultiply(&mut image);
    }
    profile.readback_ms = ms(t);
    let stats = last.unwrap_or_default();
    let direct = k == 1 && args.post.aa != AaMode::Msaa;
    let attributes = if outputs.any() {
        let depth = frame_depth(hl, &stats, direct);
        Some(renderer.attributes(&settings, w, h, &hl.target(), outputs, depth)?)
    } else {
        None
    };
    let linear = if outputs.linear {
        if !direct {
            return Err(crate::Error::Usage(
                "float linear colour is drawn without --aa ssaa or msaa".into(),
            ));
        }
        let mut s = settings.clone();
        s.lighting.post.linear_out = true;
        renderer.render(&s, &hl.target())?;
        let linear = renderer.read_linear(w, h)?;
        hl.gpu.bind_framebuffer(hl.target().fbo);
        Some(linear)
    } else {
        None
    };
    Ok(Drawn {
        image,
        repro,
        stats,
        attributes,
        linear,
        settings,
    })
}

/// The kept context re-targeted to `size`, with a renderer for the scene of `args` (or
/// `given`) last in its list: a kept one while the scene's options are the same (a
/// turntable, a camera sweep: the same scene, environment and lights), else the scene
/// loaded (on another thread while the context is made) and uploaded, the least recently
/// drawn of `keep` kept renderers dropped first.
fn prepare<'k>(
    args: &Options,
    keep: usize,
    kept: &'k mut Option<KeptContext>,
    given: Option<Given>,
    size: (u32, u32),
    profile: &mut Profile,
) -> Result<&'k mut KeptContext> {
    let name = given.as_ref().map(|g| g.key);
    let stamp = crate::repro::stamp(args);
    let found = kept.as_ref().and_then(|c| {
        (c.request == (args.context.backend, args.context.gl))
            .then(|| {
                c.renderers
                    .iter()
                    .position(|(k, _)| k.matches(args, name, &stamp))
            })
            .flatten()
    });
    let scene = if let Some(i) = found {
        let c = kept.as_mut().expect("found in it");
        let r = c.renderers.remove(i);
        c.renderers.push(r);
        context(args, size, msaa(args), kept, profile)?;
        None
    } else {
        // Renderers beyond `keep` go before a new context or scene is made.
        if let Some(c) = kept.as_mut() {
            let excess = (c.renderers.len() + 1).saturating_sub(keep);
            c.renderers.drain(..excess.min(c.renderers.len()));
        }
        // Loading needs no GL: it runs on another thread while this one makes the context
        // (which must stay current here), so start-up costs the longer of the two.
        let (made, loaded) = std::thread::scope(|s| {
            let loader = s.spawn(|| match &given {
                Some(g) => given_scene(args, g.scene),
                None => load(args),
            });
            let made = context(args, size, msaa(args), kept, profile);
            (made, loader.join())
        });
        made?;
        let (scene, load_ms, load_profile, clusters_ms) =
            loaded.map_err(|_| crate::Error::Unsupported("the model loader panicked".into()))?;
        profile.load_ms = load_ms;
        profile.load = load_profile;
        profile.clusters_ms = clusters_ms;
        Some(scene?)
    };
    let kept = kept.as_mut().expect("context made above");
    if let Some((scene, clusters)) = scene {
        let t = Instant::now();
        let mut r = Renderer::prepared(&kept.hl.gpu, scene, clusters)?;
        profile.upload_ms = ms(t);
        profile.scene_uploads += 1;
        r.share_environments(kept.envs.clone());
        kept.renderers.push((SceneKey::new(args, name, stamp), r));
    }
    // The environment is the view's: a kept scene takes another one without an upload,
    // and maps another scene of this context made are shared.
    let r = &mut kept.renderers.last_mut().expect("found or made above").1;
    r.set_environment(env_request(args)?);
    // Posed before anything reads the scene's bounds (the frame settings fit the camera to
    // the posed model); a kept renderer at the same moment does nothing here.
    posed(args, r, profile)?;
    Ok(kept)
}

/// Poses `r`'s scene at the moment `args` asks ([`moment`]) and records its cost when
/// something moved.
fn posed(args: &Options, r: &mut Renderer, profile: &mut Profile) -> Result<()> {
    let at = moment(args, r.scene())?;
    let before = r.posed();
    r.pose(at)?;
    if before != at {
        profile.pose = Some(r.pose_cost());
    }
    Ok(())
}

/// The target's depth is the picture's when the frame's passes drew straight into it at
/// the picture's size (`direct`: no MSAA or supersampling) and nothing came after them (no
/// post-processing or teaching view).
fn frame_depth(hl: &Headless, stats: &crate::render::FrameStats, direct: bool) -> FrameDepth {
    let plain = stats.post.is_empty()
        && stats.passes.iter().all(|p| {
            ["shadow", "background", "lit", "pbr"]
                .iter()
                .any(|n| p.starts_with(n))
        });
    if !(direct && plain) {
        FrameDepth::No
    } else if hl.stencil_bits() > 0 && hl.gpu.caps.depth_stencil {
        FrameDepth::WithStencil
    } else {
        FrameDepth::Depth
    }
}

/// A caller's scene as [`load`] returns a file's: cloned (the caller keeps it for later
/// pictures), x-ray applied, clusters prepared.
fn given_scene(args: &Options, scene: &crate::scene::Scene) -> Loaded {
    let t = Instant::now();
    let mut s = scene.clone();
    if let Err(e) = glview_render::view::settings::adjust_scene(args, &mut s) {
        return (Err(e), ms(t), None, 0.0);
    }
    let c = Instant::now();
    let clusters = crate::scene::lod::clusters::prepare_without_lod(&mut s);
    (Ok((s, clusters)), ms(t), None, ms(c))
}
