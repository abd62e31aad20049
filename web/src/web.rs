//! The page's viewer: a canvas, its WebGL context as a `glow::Context`, a scene (the built-in
//! one, or a model from the files the page hands over: [`Inputs`]) uploaded once, and a
//! [`View`] steered by the window's key names. A picture is `glview -o`
//! with the same options: the same option words, frame settings, passes and shader bodies;
//! only the rasteriser differs (the browser's, e.g. SwiftShader, against llvmpipe).
use glview_render::frame::FrameSettings;
use glview_render::gpu::{Gpu, GpuRef};
use glview_render::image::differences::Differences;
use glview_render::keys::{self, Effect};
use glview_render::passes::{Renderer, Target};
use glview_render::pbr::store::{bytes as map_bytes, set_store, Given};
use glview_render::scene::geometry::normals::Creases;
use glview_render::scene::load::resources::{self, Memory};
use glview_render::scene::model::material::TextureOptions;
use glview_render::scene::LoadOptions;
use glview_render::view::settings::{adjust_scene, env_request};
use glview_render::view::View;
use glview_render::Options;
use wasm_bindgen::prelude::*;
use wasm_bindgen::JsCast;
use web_sys::WebGlRenderingContext;
use web_sys::{HtmlCanvasElement, WebGl2RenderingContext, WebGlContextAttributes};

/// Milliseconds from the page's clock: the renderer's time (`--stats`' durations).
fn now() -> f64 {
    web_sys::window()
        .and_then(|w| w.performance())
        .map_or(0.0, |p| p.now())
}

fn js(e: impl std::fmt::Display) -> JsValue {
    JsValue::from_str(&e.to_string())
}

/// Panics reach the console with their message (wasm32's default is an opaque trap).
fn panic_to_console() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        std::panic::set_hook(Box::new(|info| {
            web_sys::console::error_1(&JsValue::from_str(&format!("glview: {info}")));
        }));
    });
}

/// What the headless target is: single-sampled RGBA8 with depth and stencil, opaque. The
/// drawing buffer is kept after compositing so that a test (or a screenshot) can read it.
/// With `caveat`, the browser is asked for no context where it would be slow
/// (`failIfMajorPerformanceCaveat`: a software rasteriser, a blocklisted GPU).
fn attributes(caveat: bool) -> WebGlContextAttributes {
    let a = WebGlContextAttributes::new();
    a.set_fail_if_major_performance_caveat(caveat);
    a.set_alpha(false);
    a.set_antialias(false);
    a.set_depth(true);
    a.set_stencil(true);
    a.set_premultiplied_alpha(false);
    a.set_preserve_drawing_buffer(true);
    a
}

/// The canvas's context: WebGL 2 unless `webgl` is 1 or the browser has none, then WebGL 1.
/// Returns the context and which WebGL it is.
fn context(
    canvas: &HtmlCanvasElement,
    webgl: u32,
    caveat: bool,
) -> Result<(glow::Context, u32), JsValue> {
    let attrs = attributes(caveat);
    if webgl != 1 {
        if let Some(c) = canvas.get_context_with_context_options("webgl2", &attrs)? {
            let gl: WebGl2RenderingContext = c.dyn_into()?;
            return Ok((glow::Context::from_webgl2_context(gl), 2));
        }
    }
    match canvas.get_context_with_context_options("webgl", &attrs)? {
        Some(c) => {
            let gl: WebGlRenderingContext = c.dyn_into()?;
            Ok((glow::Context::from_webgl1_context(gl), 1))
        }
        None if caveat => Err(js(
            "the browser offers WebGL only with a major performance caveat (software drawing or a blocklisted GPU)",
        )),
        None => Err(js("this browser gives the canvas no WebGL context")),
    }
}

/// The loader's options from the picture's (as the native library's `load_options`, without
/// the mesh cache: a browser has no disk).
fn load_options(o: &Options) -> LoadOptions {
    LoadOptions {
        textures: TextureOptions {
            allow_outside_paths: false,
            max_dimension: 0,
        },
        progress: None,
        cache: false,
        honor_transparency: o.load.honor_transparency,
        creases: match (o.load.flat, o.load.crease) {
            (true, _) => Creases::Flat,
            (false, Some(d)) => Creases::Angle(d),
            (false, None) => Creases::default(),
        },
        up: o.load.up,
        texture: None,
        scene: o.load.scene.clone(),
        variant: o.load.variant.clone(),
    }
}

/// What a page hands a viewer beside its options: the model's files by path (the bytes the
/// loader reads from disk natively: the model, its MTL libraries, images, glTF buffers, an
/// HDR environment), the precomputed environment maps (`glview export --live` ships the
/// native ones, so the page computes none), and whether a slow context is refused.
#[wasm_bindgen]
#[derive(Default)]
pub struct Inputs {
    files: Memory,
    maps: Option<glview_render::pbr::precompute::IblData>,
    /// The model as scene bytes (`cache::to_bytes`), in place of its files.
    prepared: Option<Prepared>,
    caveat: bool,
}

type Prepared = (
    glview_render::scene::Scene,
    Vec<Option<glview_render::scene::lod::clusters::Clusters>>,
);

#[wasm_bindgen]
impl Inputs {
    #[wasm_bindgen(constructor)]
    pub fn new() -> Inputs {
        Inputs::default()
    }

    /// Holds `bytes` as the file `path` (absolute, `/`-separated, as the options name it).
    pub fn file(&mut self, path: &str, bytes: Vec<u8>) {
        self.files.insert(path, bytes);
    }

    /// The environment maps as `pbr::store::bytes` wrote them; an error for anything else.
    pub fn maps(&mut self, bytes: &[u8]) -> Result<(), JsValue> {
        let d = map_bytes::decode(bytes).ok_or_else(|| {
            js("the environment maps given are not glview's maps (pbr::store::bytes)")
        })?;
        self.maps = Some(d);
        Ok(())
    }

    /// The model the options name as scene bytes (`glview export --live`'s and serve's
    /// `prepared`: parsed, normals made, levels of detail built, textures decoded), read in
    /// place of its files; an error for bytes that are not such a scene of this glview.
    pub fn prepared(&mut self, bytes: Vec<u8>) -> Result<(), JsValue> {
        let p = glview_render::scene::cache::from_bytes(bytes).ok_or_else(|| {
            js("the scene given is not a scene of this glview's (cache::to_bytes), or is damaged")
        })?;
        self.prepared = Some(p);
        Ok(())
    }

    /// Refuse a context the browser would draw slowly (`failIfMajorPerformanceCaveat`).
    pub fn refuse_slow_context(&mut self, on: bool) {
        self.caveat = on;
    }
}

/// glview on one canvas.
#[wasm_bindgen]
pub struct Viewer {
    view: View,
    renderer: Renderer,
    gpu: GpuRef,
    canvas: HtmlCanvasElement,
    webgl: u32,
    frames: u64,
    /// The load options the scene was loaded with: a view whose load options move on (`V`,
    /// a variant picked; a class's state) loads it again from the page's files.
    loaded: glview_render::options::Load,
}

/// The scene `options` name, from the page's files (the built-in one without a model), as
/// `glview -o` loads it.
fn load_scene(options: &Options) -> Result<glview_render::scene::Scene, JsValue> {
    let load = load_options(options);
    let mut scene = match &options.load.model {
        Some(path) => glview_render::scene::load::load(path, &load).map_err(js)?,
        None => glview_render::scene::builtin::load(&load).map_err(js)?,
    };
    adjust_scene(options, &mut scene).map_err(js)?;
    Ok(scene)
}

/// A renderer of the scene `options` name, with the environment they ask for: from the
/// model's scene bytes where the page gave them (as a native mesh cache hit makes one), else
/// loaded from its files.
fn renderer_for(
    gpu: &GpuRef,
    options: &Options,
    prepared: Option<Prepared>,
) -> Result<Renderer, JsValue> {
    let mut renderer = match prepared {
        Some((mut scene, clusters)) => {
            adjust_scene(options, &mut scene).map_err(js)?;
            Renderer::prepared(gpu, scene, clusters)
        }
        None => Renderer::new(gpu, load_scene(options)?),
    }
    .map_err(js)?;
    renderer.set_environment(env_request(options).map_err(js)?);
    Ok(renderer)
}

impl Viewer {
    /// The view into `target`, with a transparent background where asked (coverage): the
    /// whole target, with `C` both tiers side by side, each framed for its half (the
    /// window's split view), at the view's moment (`--time`, a playing animation; posed
    /// once per change).
    fn render_view(
        &mut self,
        target: &Target,
        transparent: bool,
    ) -> Result<glview_render::passes::FrameStats, JsValue> {
        self.reload_if_needed()?;
        self.render_loaded(target, transparent).map_err(js)
    }

    /// Loads the scene again when the view's load options are no longer the scene's.
    fn reload_if_needed(&mut self) -> Result<(), JsValue> {
        if self.view.options().load == self.loaded {
            return Ok(());
        }
        let options = self.view.options().clone();
        self.renderer = renderer_for(&self.gpu, &options, None)?;
        self.loaded = options.load;
        Ok(())
    }

    fn render_loaded(
        &mut self,
        target: &Target,
        transparent: bool,
    ) -> glview_render::Result<glview_render::passes::FrameStats> {
        let options = self.view.options();
        let at = glview_render::view::moment(options, self.renderer.scene())?;
        self.renderer.pose(at)?;
        let mut settings = FrameSettings::new(options, self.renderer.scene())?;
        settings.lighting.post.transparent = transparent;
        if self.view.compare() {
            let (w, h) = (target.width, target.height);
            glview_render::view::split::draw(&mut self.renderer, &settings, target, w, h)
        } else {
            self.renderer.render(&settings, target)
        }
    }
}

#[wasm_bindgen]
impl Viewer {
    /// A viewer of the built-in scene on `canvas`, with `words` the options of `glview -o`
    /// ("--size 400x300 --yaw 25 --shading pbr"; the canvas takes `--size`). `webgl`: 1
    /// forces WebGL 1; anything else takes WebGL 2 where the browser has it.
    #[wasm_bindgen(constructor)]
    pub fn new(canvas: HtmlCanvasElement, words: &str, webgl: u32) -> Result<Viewer, JsValue> {
        let words = words.split_whitespace().map(String::from).collect();
        Viewer::open(canvas, words, webgl, Inputs::default())
    }

    /// A viewer of what `words` name (one option word an element, so a path may hold
    /// spaces: a model among `inputs`' files, or the built-in scene) on `canvas`, as
    /// [`Viewer::new`]. Every viewer of a page reads the files and maps of the last one
    /// opened (the loaders' and the renderer's stores are the page's).
    pub fn open(
        canvas: HtmlCanvasElement,
        words: Vec<String>,
        webgl: u32,
        inputs: Inputs,
    ) -> Result<Viewer, JsValue> {
        panic_to_console();
        glview_render::clock::set(now);
        let options = Options::from_words(words).map_err(js)?;
        let Inputs {
            files,
            maps,
            prepared,
            caveat,
        } = inputs;
        resources::set(std::sync::Arc::new(files));
        if let Some(d) = maps {
            // Once per page (the renderer's store is set once): a compare's viewers share it.
            set_store(std::sync::Arc::new(Given(d)));
        }
        let (w, h) = options.picture.size;
        canvas.set_width(w);
        canvas.set_height(h);
        let (gl, webgl) = context(&canvas, webgl, caveat)?;
        // WebGL 1 reports "WebGL 1.0 (OpenGL ES 2.0 ...)": the ES 2.0 rules follow from it.
        let gpu = Gpu::new(gl);
        let prepared = prepared.filter(|_| options.load.model.is_some());
        let renderer = renderer_for(&gpu, &options, prepared)?;
        let settled = View::settled(&options, renderer.scene()).map_err(js)?;
        Ok(Viewer {
            view: View::new(settled),
            renderer,
            gpu,
            canvas,
            webgl,
            frames: 0,
            loaded: options.load,
        })
    }

    /// Sizes the canvas and the view (the camera keeps its angles). Draw again after it.
    pub fn resize(&mut self, width: u32, height: u32) {
        let (w, h) = (width.max(1), height.max(1));
        self.canvas.set_width(w);
        self.canvas.set_height(h);
        self.view.resize((w, h));
    }

    /// The split view's difference numbers over the model's pixels, as `glview --diff
    /// phong,pbr`'s "model" ones (without SSIM), as JSON `{mean, p99, over_8, pixels}`; null
    /// where neither half covers a pixel. Coverage is the view drawn once more with a
    /// transparent background into an offscreen target (as the native compare's); the
    /// canvas keeps its picture. An error outside the split view.
    pub fn compare_numbers(&mut self) -> Result<String, JsValue> {
        if !self.view.compare() {
            return Err(js("the difference numbers are the split view's (C)"));
        }
        let (width, height) = self.view.options().picture.size;
        let fb =
            glview_render::gpu::framebuffer::Framebuffer::color_depth(&self.gpu, width, height)
                .map_err(js)?;
        let offscreen = Target {
            fbo: Some(fb.raw),
            width,
            height,
        };
        self.render_view(&offscreen, true)?;
        self.gpu.bind_framebuffer(Some(fb.raw));
        let cover = self.gpu.read_rgba(width, height);
        let px = self.pixels();
        // Pixel i of the left half and its twin in the right one.
        let half = (width / 2) as usize;
        let pair = |i: usize| {
            let (y, x) = (i / half, i % half);
            let (l, r) = (y * width as usize + x, y * width as usize + x + half);
            let covered = cover[4 * l + 3] > 0 || cover[4 * r + 3] > 0;
            covered.then(|| (&px[4 * l..4 * l + 4], &px[4 * r..4 * r + 4]))
        };
        let d = Differences::of((0..half * height as usize).filter_map(pair));
        Ok(if d.pixels() == 0 {
            "null".into()
        } else {
            format!(
                "{{\"mean\":{},\"p99\":{},\"over_8\":{},\"pixels\":{}}}",
                d.mean(),
                d.percentile(0.99),
                d.wrong(),
                d.pixels()
            )
        })
    }

    /// Draws the view; the frame's milliseconds (to the end of the GL calls, not of the
    /// browser's rasterising: read the pixels or wait a frame for that).
    pub fn draw(&mut self) -> Result<f64, JsValue> {
        let (width, height) = self.view.options().picture.size;
        let canvas = Target {
            fbo: None,
            width,
            height,
        };
        let stats = self.render_view(&canvas, false)?;
        self.frames += 1;
        Ok(stats.ms)
    }

    /// A key of the window, by its name there ("Right", "Up", "P", "S", "+"; see `glview
    /// --help`). Returns whether the picture may have changed (draw again); an unknown name
    /// is an error.
    pub fn key(&mut self, name: &str) -> Result<bool, JsValue> {
        let action = keys::action_for(name).ok_or_else(|| js(format!("unknown key {name:?}")))?;
        let effect = self.view.act(action, self.renderer.scene()).map_err(js)?;
        Ok(matches!(effect, Effect::Redraw | Effect::Compare))
    }

    /// Waits for the GL calls so far to finish: a frame's end, for timings. WebGL's
    /// `finish()` need not wait (Chromium's returns at once), so one pixel is read back.
    pub fn finish(&self) {
        self.gpu.finish();
        self.gpu.bind_framebuffer(None);
        let _ = self.gpu.read_rgba(1, 1);
    }

    /// A left-drag of `dx`, `dy` pixels, as the window turns the view (dragging right
    /// turns the model right). Draw again after it.
    pub fn drag(&mut self, dx: f32, dy: f32) -> Result<(), JsValue> {
        self.view.drag(dx, dy, self.renderer.scene()).map_err(js)
    }

    /// `notches` of the mouse wheel (positive: away from the user, zooms in), as the window.
    pub fn wheel(&mut self, notches: f32) -> Result<(), JsValue> {
        self.view.wheel(notches, self.renderer.scene()).map_err(js)
    }

    /// The canvas's pixels as RGBA8, top row first (as glview's PNGs), read back now.
    pub fn pixels(&self) -> Vec<u8> {
        let (w, h) = self.view.options().picture.size;
        self.gpu.bind_framebuffer(None);
        self.gpu.read_rgba(w, h)
    }

    /// What drew: the WebGL version, GL_VERSION, the renderer, the GLSL dialect, how shadow
    /// maps are kept (depth textures, or packed into RGBA8 without them) and whether vertex
    /// array objects are used (WebGL 1: OES_vertex_array_object), as JSON.
    pub fn info(&self) -> String {
        let c = &self.gpu.caps;
        format!(
            "{{\"webgl\":{},\"version\":{:?},\"renderer\":{:?},\"dialect\":{:?},\"shadow_maps\":{:?},\"vertex_arrays\":{},\"frames\":{}}}",
            self.webgl,
            c.version,
            c.renderer,
            c.dialect.name(),
            c.shadow_store(),
            c.vertex_arrays(),
            self.frames
        )
    }

    /// Compiles and links every program the renderer can ask for in this context (what
    /// `glview --compile-shaders` does natively): their count, or the first one the browser's
    /// compiler refuses, with its log and numbered source.
    pub fn compile_all(&self) -> Result<u32, JsValue> {
        let mut cache = glview_render::shader::cache::ProgramCache::new(&self.gpu);
        let max_lights = glview_render::light::MAX_LIGHTS as u8;
        let (keys, _) = glview_render::passes::programs::keys_for(&self.gpu.caps, max_lights);
        for key in &keys {
            cache.get(key).map_err(js)?;
        }
        Ok(keys.len() as u32)
    }

    /// The view's yaw in degrees (the page's record of the directions a student has seen).
    pub fn yaw(&self) -> f32 {
        self.view.options().camera.yaw
    }

    /// Whether the view's animation plays (Space): the page draws every animation frame then.
    pub fn playing(&self) -> bool {
        self.view.playing()
    }

    /// A playing view's time moved on by `seconds` (the page's clock between two frames);
    /// nothing when paused.
    pub fn advance(&mut self, seconds: f64) -> Result<(), JsValue> {
        let all = self.renderer.scene().animations().to_vec();
        self.view.advance(seconds, &all).map_err(js)
    }

    /// The moment shown (`--time`), or none: the static pose.
    pub fn time(&self) -> Option<f32> {
        self.view.options().motion.time
    }

    /// The view's pitch in degrees.
    pub fn pitch(&self) -> f32 {
        self.view.options().camera.pitch
    }

    /// Whether the view shows Phong | PBR side by side (`C`).
    pub fn compare(&self) -> bool {
        self.view.compare()
    }

    /// Draws `tier` ("phong", "gouraud", "pbr"), one pane (the page's tier buttons).
    pub fn set_shading(&mut self, tier: &str) -> Result<(), JsValue> {
        self.view.set_shading(tier.parse().map_err(js)?);
        Ok(())
    }

    /// Phong | PBR side by side, or one pane (the page's compare button; `C` toggles it).
    pub fn set_compare(&mut self, on: bool) {
        self.view.set_compare(on);
    }

    /// The shading tier drawn: "phong", "gouraud" or "pbr" (`P` cycles them).
    pub fn shading(&self) -> String {
        self.view.options().render.shading.word().to_string()
    }

    /// The options of the current view as `glview -o` words (what the keys led to).
    pub fn options(&self) -> String {
        self.view.picture().to_words().join(" ")
    }

    /// The view as JSON (`View`'s serde form: options, home camera, compare, playing): what
    /// `glview serve` sends a page that draws itself (the paths are the page's).
    pub fn view_json(&self) -> String {
        serde_json::to_string(&self.view).unwrap_or_default()
    }

    /// Takes the view `json` (as [`Viewer::view_json`] writes it: a presenter's, or the
    /// server's record of this page's) but keeps this canvas's size; a model other than the
    /// one loaded is an error (the page loads that one's files first). Draw again after it.
    pub fn set_view(&mut self, json: &str) -> Result<(), JsValue> {
        let mut view: View =
            serde_json::from_str(json).map_err(|e| js(format!("not a view: {e}")))?;
        if view.options().load.model != self.loaded.model {
            return Err(js("the view is of another model than the one loaded"));
        }
        view.resize(self.view.options().picture.size);
        self.view = view;
        self.reload_if_needed()?;
        self.view.settle_keys(self.renderer.scene()).map_err(js)
    }
}
