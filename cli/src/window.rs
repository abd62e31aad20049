//! A window with a current GL context on its surface (winit + glutin, through glutin-winit's
//! `finalize_window`), for the event loop in `app`.
//!
//! On Windows the one platform is WGL, whose display loads its extension functions through a
//! window: there the window is made first and handed to the display.
//!
//! Every platform display (GLX, then EGL) is tried with every candidate context of the request
//! in order; the first pair that makes a context current wins, and a failure lists every
//! attempt. This is the same chain glutin-winit's `DisplayBuilder` runs, written out because
//! `DisplayBuilder` falls back from GLX to EGL only when the *display* fails, not when the
//! context does (Mesa can offer GL ES through EGL but not through an old GLX), and because
//! its config picker cannot report "no config" without panicking.
use glow::HasContext;
use glutin::config::{Api, Config, ConfigTemplateBuilder};
use glutin::context::{NotCurrentContext, PossiblyCurrentContext};
use glutin::display::{Display, DisplayApiPreference};
use glutin::prelude::*;
use glutin::surface::{Surface, SurfaceAttributesBuilder, SwapInterval, WindowSurface};
use glview::gpu::Gpu;
use glview::image_out::Rgba;
use glview::platform::GlRequest;
use glview::{Error, Result};
use raw_window_handle::{HasDisplayHandle, HasWindowHandle, RawWindowHandle};
use std::num::NonZeroU32;
use winit::event_loop::ActiveEventLoop;
use winit::window::{Window, WindowAttributes};

/// A window whose GL context is current on this thread. Field order is drop order: the
/// surface and context go before the window they draw into. Whatever was made with
/// [`WindowContext::glow_context`] must be dropped before this.
pub struct WindowContext {
    surface: Surface<WindowSurface>,
    context: PossiblyCurrentContext,
    display: Display,
    pub window: Window,
    /// "glx", "egl" or "wgl".
    pub platform: &'static str,
}

/// The platform displays tried, in order.
#[cfg(not(windows))]
const PLATFORMS: &[&str] = &["glx", "egl"];
#[cfg(windows)]
const PLATFORMS: &[&str] = &["wgl"];

/// The display of one platform (GLX's or EGL's; neither takes a window).
#[cfg(not(windows))]
fn preference(name: &str, _window: Option<RawWindowHandle>) -> DisplayApiPreference {
    if name == "glx" {
        DisplayApiPreference::Glx(Box::new(winit::platform::x11::register_xlib_error_hook))
    } else {
        DisplayApiPreference::Egl
    }
}

/// WGL's display, which takes the window made for it.
#[cfg(windows)]
fn preference(_name: &str, window: Option<RawWindowHandle>) -> DisplayApiPreference {
    DisplayApiPreference::Wgl(window)
}

fn api_of(request: GlRequest) -> Api {
    match request {
        GlRequest::Es3 => Api::GLES3,
        GlRequest::Es2 => Api::GLES2,
        _ => Api::OPENGL,
    }
}

/// A single-sampled config (so a screenshot matches a headless render) with a 24-bit depth
/// buffer (and preferably 8 stencil bits) that can run one of the candidates, preferring one
/// that runs them all.
fn pick_config(
    display: &Display,
    candidates: &[GlRequest],
    stereo: bool,
) -> Result<Config, String> {
    // An empty API set lets EGL list desktop-GL-only and ES-only configs alike.
    let template = ConfigTemplateBuilder::new()
        .with_depth_size(24)
        .with_api(Api::empty());
    if stereo {
        // `--stereo quad-buffer`: only configs with left and right back buffers (GLX, WGL;
        // EGL has none). What the driver offers otherwise is named in the error.
        // SAFETY: the template holds no raw window handle.
        let all = unsafe { display.find_configs(template.clone().build()) }
            .map(|c| c.count())
            .unwrap_or(0);
        let template = template.with_stereoscopy(Some(true)).build();
        // SAFETY: as above.
        let stereo: Vec<Config> = unsafe { display.find_configs(template) }
            .map(|c| c.collect())
            .unwrap_or_default();
        return stereo
            .into_iter()
            .find(|c| c.depth_size() >= 24)
            .ok_or_else(|| {
                format!(
                    "--stereo quad-buffer: the driver offers {all} configs, none with stereo \
                     (GL_STEREO) buffers; use another --stereo mode"
                )
            });
    }
    let template = template.build();
    // SAFETY: the template holds no raw window handle.
    let configs: Vec<Config> = unsafe { display.find_configs(template) }
        .map_err(|e| e.to_string())?
        .collect();
    let runs = |c: &Config| {
        candidates
            .iter()
            .filter(|r| c.api().contains(api_of(**r)))
            .count()
    };
    let score = |c: &Config| {
        (
            runs(c),
            c.num_samples() == 0,
            c.depth_size() == 24,
            c.alpha_size() == 0,
            // A stencil buffer for the nearest-layer translucency's background mask.
            c.stencil_size() >= 8,
        )
    };
    configs
        .into_iter()
        .filter(|c| c.depth_size() >= 24 && runs(c) > 0)
        .max_by_key(score)
        .ok_or_else(|| format!("no config with a 24-bit depth buffer for {candidates:?}"))
}

impl WindowContext {
    /// Creates the window (shown once a context works) and makes a context current on it.
    pub fn new(
        event_loop: &ActiveEventLoop,
        attributes: WindowAttributes,
        request: GlRequest,
        stereo: bool,
    ) -> Result<WindowContext> {
        let raw_display = event_loop
            .display_handle()
            .map_err(|e| Error::Context(format!("window: no display handle: {e}")))?
            .as_raw();
        let mut tried = Vec::new();
        for &name in PLATFORMS {
            // Shown once a context works.
            let attrs = attributes.clone().with_visible(false);
            // WGL's display needs its window first; the others make it from their config.
            let early = if cfg!(windows) {
                match event_loop.create_window(attrs.clone()) {
                    Ok(w) => Some(w),
                    Err(e) => {
                        tried.push(format!("{name}: cannot create the window: {e}"));
                        continue;
                    }
                }
            } else {
                None
            };
            let early_handle = early
                .as_ref()
                .and_then(|w| w.window_handle().ok())
                .map(|h| h.as_raw());
            // SAFETY: the handles come from the live event loop and window, which outlive
            // the display (field order in WindowContext).
            let display = match unsafe { Display::new(raw_display, preference(name, early_handle)) }
            {
                Ok(d) => d,
                Err(e) => {
                    tried.push(format!("{name}: {e}"));
                    continue;
                }
            };
            if stereo && name == "egl" {
                tried.push("egl: EGL has no stereo (quad-buffer) configs".into());
                continue;
            }
            let config = match pick_config(&display, request.candidates(), stereo) {
                Ok(c) => c,
                Err(e) => {
                    tried.push(format!("{name}: {e}"));
                    continue;
                }
            };
            let window = match early {
                Some(w) => w,
                None => match glutin_winit::finalize_window(event_loop, attrs, &config) {
                    Ok(w) => w,
                    Err(e) => {
                        tried.push(format!("{name}: cannot create the window: {e}"));
                        continue;
                    }
                },
            };
            let surface = match create_surface(&display, &config, &window) {
                Ok(s) => s,
                Err(e) => {
                    tried.push(format!("{name}: cannot create the window surface: {e}"));
                    continue;
                }
            };
            let raw_window = match window.window_handle() {
                Ok(h) => h.as_raw(),
                Err(e) => {
                    tried.push(format!("{name}: no window handle: {e}"));
                    continue;
                }
            };
            for &candidate in request.candidates() {
                if !config.api().contains(api_of(candidate)) {
                    tried.push(format!("{name} {candidate:?}: the config cannot run it"));
                    continue;
                }
                let made = create_context(&display, &config, candidate, raw_window)
                    .and_then(|c| c.make_current(&surface).map_err(|e| e.to_string()));
                match made {
                    Ok(context) => {
                        // Frames are drawn on demand, so waiting for vblank only adds latency;
                        // not every platform can change it, which is harmless.
                        let _ = surface.set_swap_interval(&context, SwapInterval::DontWait);
                        window.set_visible(true);
                        return Ok(WindowContext {
                            surface,
                            context,
                            display,
                            window,
                            platform: name,
                        });
                    }
                    Err(e) => tried.push(format!("{name} {candidate:?}: {e}")),
                }
            }
        }
        Err(Error::Context(format!("window: {}", tried.join("; "))))
    }

    pub fn glow_context(&self) -> glow::Context {
        // SAFETY: the context is current on this thread and its display lives in self.
        unsafe {
            glow::Context::from_loader_function_cstr(|name| self.display.get_proc_address(name))
        }
    }

    /// Follows a window resize; a 0×0 (minimised) window keeps its old surface size.
    pub fn resize(&self, width: u32, height: u32) {
        if let (Some(w), Some(h)) = (NonZeroU32::new(width), NonZeroU32::new(height)) {
            self.surface.resize(&self.context, w, h);
        }
    }

    /// Shows the back buffer. An error here usually means the context or window is gone.
    pub fn swap_buffers(&self) -> Result<()> {
        self.surface.swap_buffers(&self.context).map_err(|e| {
            Error::Window(format!(
                "cannot present the frame ({e}); the GL context or window was lost"
            ))
        })
    }

    /// Reads the back buffer of the default framebuffer (call before `swap_buffers`), top row
    /// first. Alpha is forced opaque: a screenshot shows what the window shows, whatever
    /// alpha the visual happens to store.
    pub fn read_back_buffer(gpu: &Gpu, width: u32, height: u32) -> Rgba {
        if gpu.caps.fbo {
            // SAFETY: binding framebuffer 0 (the window's) is always valid.
            unsafe { gpu.gl.bind_framebuffer(glow::FRAMEBUFFER, None) };
        }
        let mut data = gpu.read_rgba(width, height);
        for px in data.chunks_exact_mut(4) {
            px[3] = 255;
        }
        Rgba {
            width,
            height,
            data,
        }
    }
}

fn create_surface(
    display: &Display,
    config: &Config,
    window: &Window,
) -> Result<Surface<WindowSurface>, String> {
    let size = window.inner_size();
    let w = NonZeroU32::new(size.width.max(1)).unwrap_or(NonZeroU32::MIN);
    let h = NonZeroU32::new(size.height.max(1)).unwrap_or(NonZeroU32::MIN);
    let handle = window.window_handle().map_err(|e| e.to_string())?.as_raw();
    let attrs = SurfaceAttributesBuilder::<WindowSurface>::new().build(handle, w, h);
    // SAFETY: the window outlives the surface (field order in WindowContext).
    unsafe { display.create_window_surface(config, &attrs) }.map_err(|e| e.to_string())
}

fn create_context(
    display: &Display,
    config: &Config,
    request: GlRequest,
    window: RawWindowHandle,
) -> Result<NotCurrentContext, String> {
    // SAFETY: the attributes name a window that is alive for the whole call.
    unsafe {
        display.create_context(
            config,
            &glview::platform::context_attributes(request, Some(window)),
        )
    }
    .map_err(|e| e.to_string())
}
