//! The interactive window loop: winit events → the [`View`] (the options the keys and drags
//! change, as the server's viewers hold them) → a redraw only when the frame settings derived
//! from it, the window size or the OS (expose) asks for one. Between events the loop sleeps
//! (`ControlFlow::Wait`), so an idle viewer draws nothing and uses no CPU; a playing
//! animation ([`play`]) wakes it for each frame.
mod play;

use crate::cli::Args;
use crate::window::WindowContext;
use glview::frame::{FrameSettings, Shading};
use glview::gpu::{Gpu, GpuRef};
use glview::image_out::RgbaFiles;
use glview::keys::{self, Action, Effect};
use glview::render::aa::{AaTarget, WindowAa};
use glview::render::{Renderer, Target};
use glview::scene::Scene;
use glview::session::View;
use glview::{session, Error, Result};
use std::path::{Path, PathBuf};
use winit::application::ApplicationHandler;
use winit::dpi::{PhysicalPosition, PhysicalSize};
use winit::event::{ElementState, KeyEvent, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{Key, KeyCode, NamedKey, PhysicalKey};
use winit::window::{Window, WindowId};

/// Pixels of a touchpad scroll that count as one wheel notch.
const PIXELS_PER_NOTCH: f64 = 40.0;

/// Whether a display server is reachable (X11 or Wayland). Windows always has its desktop.
pub fn display_available() -> bool {
    cfg!(windows)
        || std::env::var_os("DISPLAY").is_some_and(|d| !d.is_empty())
        || std::env::var_os("WAYLAND_DISPLAY").is_some_and(|d| !d.is_empty())
}

/// Opens the window and runs until Esc/Q or the window closes. A window or context that
/// cannot be made is `Error::Context` (the caller then renders headless); a render error or a
/// lost context later ends the loop with that error.
pub fn run_window(args: &Args) -> Result<()> {
    glview::platform::keep_freed_heap();
    // With the cache's clusters and levels of detail when it had them (or built them for the
    // entry): a window rebuilds nothing (the levels of the 2M-triangle sphere cost 1.6 s).
    // Clusters without levels get them from the renderer before a frame would draw them.
    let (scene, prepared) = session::load_scene_prepared(args)?;
    // `--time` or `--animation` the file cannot show is the command's one error, not a
    // window that opens to print it.
    session::moment(args, &scene)?;
    let settings = session::frame_settings(args, &scene)?.0;
    let event_loop = EventLoop::new()
        .map_err(|e| Error::Context(format!("window: cannot connect to the display: {e}")))?;
    event_loop.set_control_flow(ControlFlow::Wait);
    let mut app = App {
        args,
        view: View::new((**args).clone()),
        scene: Some(scene),
        prepared,
        settings,
        live: None,
        size: PhysicalSize::new(args.picture.size.0, args.picture.size.1),
        cursor: None,
        left_down: false,
        screenshot: false,
        overlay: false,
        last_ms: 0.0,
        clock: None,
        error: None,
    };
    event_loop
        .run_app(&mut app)
        .map_err(|e| Error::Window(format!("event loop failed: {e}")))?;
    app.error.map_or(Ok(()), Err)
}

/// The window, its context and the scene on the GPU. Field order is drop order: GL objects
/// go while the context is still current, the context before the window.
struct Live {
    /// MSAA or SSAA: the offscreen target frames are drawn into before the window.
    aa: AaTarget,
    renderer: Renderer,
    gpu: GpuRef,
    window: WindowContext,
}

struct App<'a> {
    args: &'a Args,
    /// What the keys and drags change: the options every frame is derived from (its size
    /// is the window's), and whether `C` shows Phong | PBR side by side.
    view: View,
    /// The scene until the renderer takes it.
    scene: Option<Scene>,
    /// Its clusters and levels from the mesh cache, if it had or wrote them.
    prepared: Option<Vec<Option<glview::scene::lod::clusters::Clusters>>>,
    /// Derived from `view` ([`session::frame_settings`]) whenever it changes.
    settings: FrameSettings,
    live: Option<Live>,
    /// The framebuffer size; 0×0 while minimised.
    size: PhysicalSize<u32>,
    /// The last cursor position in the window: where the next drag step starts.
    cursor: Option<PhysicalPosition<f64>>,
    left_down: bool,
    /// F12 was pressed: the next frame is also saved.
    screenshot: bool,
    /// `H`: the overlay with model, tier, toggles, frame time and the key table.
    overlay: bool,
    /// The last frame's time, for the overlay.
    last_ms: f64,
    /// While playing: when the view's time last moved on.
    clock: Option<std::time::Instant>,
    error: Option<Error>,
}

impl App<'_> {
    fn start(&mut self, event_loop: &ActiveEventLoop) -> Result<()> {
        let Some(scene) = self.scene.take() else {
            return Ok(());
        };
        let attributes = Window::default_attributes()
            .with_title(format!("glview — {} — loading", scene.name))
            .with_inner_size(self.size);
        let quad = self.args.stereo.mode == glview::stereo::StereoMode::QuadBuffer;
        let window = WindowContext::new(event_loop, attributes, self.args.context.gl, quad)?;
        glview::native_hooks();
        let es2 = self.args.context.gl == glview::platform::GlRequest::Es2;
        let gpu = Gpu::with_es2_ceiling(window.glow_context(), es2);
        glview::platform::require_gl21(&gpu.caps)?;
        let mut renderer = match self.prepared.take() {
            Some(clusters) => Renderer::prepared(&gpu, scene, clusters)?,
            None => Renderer::new(&gpu, scene)?,
        };
        renderer.time_post = self.args.picture.stats;
        renderer.cull_clusters = self.args.render.culling;
        renderer.lod = glview::render::Lod {
            mode: self.args.render.lod,
            error: self.args.render.lod_error,
        };
        self.size = window.window.inner_size();
        window.resize(self.size.width, self.size.height);
        let aa = AaTarget::new(&gpu, window_aa(self.args))?;
        let live = Live {
            aa,
            renderer,
            gpu,
            window,
        };
        live.window.window.request_redraw();
        self.live = Some(live);
        // The first frame shows `--time`'s moment, framed by its animation's bounds.
        self.pose()?;
        let scene = self.live.as_ref().map(|l| l.renderer.scene());
        if let Some(scene) = scene {
            self.settings = session::frame_settings(self.view.options(), scene)?.0;
        }
        // The window manager may not give the size asked for: frames are of the window's.
        let size = (self.size.width, self.size.height);
        if size.0 > 0 && size.1 > 0 {
            self.change(|view, _| {
                view.resize(size);
                Ok(Effect::Redraw)
            });
        }
        self.update_title();
        Ok(())
    }

    fn update_title(&self) {
        if let Some(live) = &self.live {
            let shading = match self.settings.shading {
                Shading::Phong => "legacy Phong",
                Shading::Gouraud => "legacy Gouraud",
                Shading::Pbr => "PBR",
            };
            let shading = if self.view.compare() {
                "compare Phong | PBR"
            } else {
                shading
            };
            let title = format!(
                "glview — {} — {shading} — {}",
                live.renderer.scene().name,
                live.gpu.caps.version
            );
            live.window.window.set_title(&title);
        }
    }

    fn request_redraw(&self) {
        if let Some(live) = &self.live {
            live.window.window.request_redraw();
        }
    }

    /// Applies `change` to the view and derives the frame settings again; a redraw only
    /// when they changed (or `C` toggled the panes).
    fn change(&mut self, change: impl FnOnce(&mut View, &Scene) -> Result<Effect>) -> Effect {
        let scene = match (&self.live, &self.scene) {
            (Some(live), _) => live.renderer.scene(),
            (None, Some(scene)) => scene,
            (None, None) => return Effect::Redraw,
        };
        let compare = self.view.compare();
        let load = self.view.options().load.clone();
        let motion = (self.view.options().motion.clone(), self.view.playing());
        let effect = match change(&mut self.view, scene) {
            Ok(e) => e,
            Err(e) => {
                eprintln!("error: {e}");
                return Effect::Redraw;
            }
        };
        // A new scene (`V`) is drawn even when the frame settings stay the same.
        let reloaded = self.view.options().load != load && {
            let done = self.reload();
            if let Err(e) = &done {
                eprintln!("error: {e}");
            }
            done.is_ok()
        };
        // Posed before the settings are derived: the camera fits the animation's bounds.
        if let Err(e) = self.pose() {
            eprintln!("error: {e}");
            // Once: a playing view would fail again at every frame.
            self.view.pause();
        }
        let scene = match (&self.live, &self.scene) {
            (Some(live), _) => live.renderer.scene(),
            (None, Some(scene)) => scene,
            (None, None) => return Effect::Redraw,
        };
        let changed = session::frame_settings(self.view.options(), scene).map(|s| (effect, s.0));
        let (effect, settings) = match changed {
            Ok(x) => x,
            Err(e) => {
                eprintln!("error: {e}");
                return Effect::Redraw;
            }
        };
        // The moment is drawn even when the frame settings stay the same (the label shows
        // the play state too).
        if reloaded || motion != (self.view.options().motion.clone(), self.view.playing()) {
            self.request_redraw();
        }
        if settings != self.settings || compare != self.view.compare() {
            let retitle =
                settings.shading != self.settings.shading || compare != self.view.compare();
            self.settings = settings;
            if retitle {
                self.update_title();
            }
            self.request_redraw();
        }
        effect
    }

    /// Poses the uploaded scene at the view's moment (`--animation`, `--time`; nothing when
    /// it is posed there already).
    fn pose(&mut self) -> Result<()> {
        let Some(live) = &mut self.live else {
            return Ok(());
        };
        let at = session::moment(self.view.options(), live.renderer.scene())?;
        live.renderer.pose(at)
    }

    /// A load option changed (`V`, the material variant): the scene is loaded again and
    /// replaces the uploaded one (the renderer keeps its switches).
    fn reload(&mut self) -> Result<()> {
        let (scene, prepared) = session::load_scene_prepared(self.view.options())?;
        let Some(live) = &mut self.live else {
            (self.scene, self.prepared) = (Some(scene), prepared);
            return Ok(());
        };
        let mut renderer = match prepared {
            Some(clusters) => Renderer::prepared(&live.gpu, scene, clusters)?,
            None => Renderer::new(&live.gpu, scene)?,
        };
        renderer.time_post = live.renderer.time_post;
        renderer.cull_clusters = live.renderer.cull_clusters;
        renderer.lod = live.renderer.lod;
        live.renderer = renderer;
        Ok(())
    }

    fn act(&mut self, event_loop: &ActiveEventLoop, action: Action) {
        match self.change(|view, scene| view.act(action, scene)) {
            Effect::Redraw | Effect::Camera | Effect::Compare => {}
            Effect::Screenshot => {
                self.screenshot = true;
                self.request_redraw();
            }
            Effect::Help => {
                print!("{}", keys::help_text());
                self.overlay = !self.overlay;
                self.request_redraw();
            }
            Effect::Quit => event_loop.exit(),
        }
    }

    fn key(&mut self, event_loop: &ActiveEventLoop, event: &KeyEvent) {
        if event.state != ElementState::Pressed {
            return;
        }
        let Some(action) = key_name(event).and_then(|n| keys::action_for(&n)) else {
            return;
        };
        // Held keys repeat camera moves (smooth turning) and frame steps (scrubbing), but
        // not toggles or screenshots.
        if event.repeat && !matches!(action, Action::Camera(_) | Action::Step(_)) {
            return;
        }
        self.act(event_loop, action);
    }

    fn draw(&mut self) -> Result<()> {
        let (w, h) = (self.size.width, self.size.height);
        let Some(live) = &mut self.live else {
            return Ok(());
        };
        if w == 0 || h == 0 {
            if std::mem::take(&mut self.screenshot) {
                eprintln!("screenshot: the window is minimised, nothing to save");
            }
            return Ok(());
        }
        let window = Target {
            fbo: None,
            width: w,
            height: h,
        };
        // MSAA/SSAA draw offscreen (SSAA k times larger), then into the window.
        let target = live.aa.target(&live.gpu, window)?;
        let k = live.aa.scale();
        // Interlaced stereo follows the screen's rows and columns: where the window is.
        let mut settings = self.settings.clone();
        settings.stereo.parity = screen_parity(&live.window.window);
        let stats = if self.view.compare() {
            glview::compare::split::draw(&mut live.renderer, &settings, &target, w * k, h * k)?
        } else if settings.stereo.mode == glview::stereo::StereoMode::QuadBuffer {
            live.renderer.render_quad_buffer(&settings, &target)?
        } else {
            live.renderer.render(&settings, &target)?
        };
        live.aa.present(&mut live.renderer, &window)?;
        let target = window;
        self.last_ms = stats.ms;
        let moment = play::label(&self.view, live.renderer.scene());
        if self.overlay {
            let mut lines = overlay_lines(
                &self.settings,
                &live.renderer.scene().name,
                self.view.compare(),
                stats.ms,
            );
            lines.splice(1..1, moment.clone());
            live.renderer.draw_overlay(&text_image(&lines), &target)?;
        }
        if std::mem::take(&mut self.screenshot) {
            let img = WindowContext::read_back_buffer(&live.gpu, w, h);
            let backend = format!("window ({})", live.window.platform);
            let gpu = session::Drawer::Gpu {
                caps: &live.gpu.caps,
                backend: &backend,
            };
            let repro = session::Repro {
                args: self.view.options(),
                size: (w, h),
            };
            let text = session::png_text(gpu, &self.settings, live.renderer.scene(), &repro);
            match next_screenshot_path(&self.args.screenshot_dir)
                .and_then(|p| img.save_png(&p, &text).map(|_| p))
            {
                Ok(p) => println!("screenshot: {}", p.display()),
                Err(e) => eprintln!("error: screenshot not saved: {e}"),
            }
        }
        // After the screenshot: a window's still is the picture of its options.
        if let (false, Some(m)) = (self.overlay, moment) {
            live.renderer.draw_overlay(&text_image(&[m]), &target)?;
        }
        live.window.swap_buffers()?;
        if self.args.picture.stats {
            println!("{}", serde_json::to_string(&stats).unwrap_or_default());
        }
        Ok(())
    }

    fn fail(&mut self, event_loop: &ActiveEventLoop, e: Error) {
        self.error.get_or_insert(e);
        event_loop.exit();
    }
}

impl ApplicationHandler for App<'_> {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if let Err(e) = self.start(event_loop) {
            self.fail(event_loop, e);
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        match event {
            WindowEvent::CloseRequested | WindowEvent::Destroyed => event_loop.exit(),
            WindowEvent::RedrawRequested => {
                if let Err(e) = self.draw() {
                    self.fail(event_loop, e);
                }
            }
            WindowEvent::Resized(size) => {
                self.size = size;
                if size.width > 0 && size.height > 0 {
                    self.change(|view, _| {
                        view.resize((size.width, size.height));
                        Ok(Effect::Redraw)
                    });
                }
                if let Some(live) = &self.live {
                    live.window.resize(size.width, size.height);
                }
                self.request_redraw();
            }
            // Moved by one row, an interlaced picture swaps which eye each row shows.
            WindowEvent::Moved(_) if self.settings.stereo.mode.interlaced() => {
                self.request_redraw()
            }
            WindowEvent::KeyboardInput {
                event,
                is_synthetic: false,
                ..
            } => self.key(event_loop, &event),
            WindowEvent::MouseInput {
                state,
                button: MouseButton::Left,
                ..
            } => {
                self.left_down = state == ElementState::Pressed;
            }
            WindowEvent::CursorLeft { .. } => self.cursor = None,
            WindowEvent::CursorMoved { position, .. } => {
                let last = self.cursor.replace(position);
                if let (true, Some(last)) = (self.left_down, last) {
                    let (dx, dy) = ((position.x - last.x) as f32, (position.y - last.y) as f32);
                    self.change(|view, scene| {
                        view.drag(dx, dy, scene)?;
                        Ok(Effect::Redraw)
                    });
                }
            }
            WindowEvent::MouseWheel { delta, .. } => {
                let notches = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y as f64,
                    MouseScrollDelta::PixelDelta(p) => p.y / PIXELS_PER_NOTCH,
                };
                if notches != 0.0 {
                    self.change(|view, scene| {
                        view.wheel(notches as f32, scene)?;
                        Ok(Effect::Redraw)
                    });
                }
            }
            WindowEvent::Focused(false) => self.left_down = false,
            _ => {}
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        self.play(event_loop);
    }

    fn exiting(&mut self, _event_loop: &ActiveEventLoop) {
        // The display connection closes when `run_app` returns: GL objects, the context and
        // the window must go while it is still open.
        self.live = None;
    }
}

/// The key table's name for a key: the character it types (so `+` works however it is
/// reached), or for layouts whose letters are not ASCII, the key's US position.
fn key_name(event: &KeyEvent) -> Option<String> {
    let named = |k: &NamedKey| {
        Some(match k {
            NamedKey::ArrowLeft => "Left",
            NamedKey::ArrowRight => "Right",
            NamedKey::ArrowUp => "Up",
            NamedKey::ArrowDown => "Down",
            NamedKey::PageUp => "PageUp",
            NamedKey::PageDown => "PageDown",
            NamedKey::Home => "Home",
            NamedKey::Escape => "Escape",
            NamedKey::F1 => "F1",
            NamedKey::F12 => "F12",
            NamedKey::Space => "Space",
            _ => return None,
        })
    };
    match &event.logical_key {
        Key::Named(k) => named(k).map(String::from),
        Key::Character(c) if c.is_ascii() => Some(c.to_string()),
        _ => match event.physical_key {
            PhysicalKey::Code(code) => physical_name(code).map(String::from),
            PhysicalKey::Unidentified(_) => None,
        },
    }
}

fn physical_name(code: KeyCode) -> Option<&'static str> {
    Some(match code {
        KeyCode::KeyR => "R",
        KeyCode::KeyF => "F",
        KeyCode::KeyS => "S",
        KeyCode::KeyG => "G",
        KeyCode::KeyP => "P",
        KeyCode::KeyW => "W",
        KeyCode::KeyH => "H",
        KeyCode::KeyQ => "Q",
        KeyCode::Digit1 => "1",
        KeyCode::Digit2 => "2",
        KeyCode::Digit3 => "3",
        KeyCode::Digit4 => "4",
        KeyCode::Digit5 => "5",
        KeyCode::Digit6 => "6",
        KeyCode::Digit7 => "7",
        KeyCode::Digit8 => "8",
        KeyCode::Digit9 => "9",
        KeyCode::Digit0 => "0",
        KeyCode::KeyC => "C",
        KeyCode::KeyB => "B",
        KeyCode::KeyE => "E",
        KeyCode::KeyZ => "Z",
        KeyCode::KeyX => "X",
        KeyCode::KeyK => "K",
        KeyCode::KeyT => "T",
        KeyCode::KeyY => "Y",
        KeyCode::KeyV => "V",
        KeyCode::KeyA => "A",
        KeyCode::Period => ".",
        KeyCode::Comma => ",",
        _ => return None,
    })
}

/// The window's top-left pixel on the screen, modulo 2 (column, row): (0, 0) where the
/// platform does not say (Wayland).
fn screen_parity(window: &Window) -> (u32, u32) {
    window
        .inner_position()
        .map(|p| (p.x.rem_euclid(2) as u32, p.y.rem_euclid(2) as u32))
        .unwrap_or((0, 0))
}

/// The overlay's picture of `lines` (model, tier, toggles, frame time, the key table; or
/// the moment's label), light text on a translucent black box.
fn text_image(lines: &[String]) -> glview::image_out::Rgba {
    use glview::compare::canvas;
    let lines: Vec<String> = lines
        .iter()
        .map(|l| l.chars().map(canvas::substitute).collect())
        .collect();
    let width = lines.iter().map(|l| l.chars().count()).max().unwrap_or(1) as u32 * 8 + 8;
    let mut img = canvas::blank(width, lines.len() as u32 * 10 + 8, [0, 0, 0]);
    for p in img.data.chunks_exact_mut(4) {
        p[3] = 180;
    }
    for (i, l) in lines.iter().enumerate() {
        canvas::text_scaled(&mut img, 4, 4 + i as u32 * 10, l, [240, 240, 240], 1);
    }
    img
}

/// The overlay's lines, with the font's stand-ins for characters it lacks (`→` as `->`).
fn overlay_lines(s: &FrameSettings, name: &str, compare: bool, ms: f64) -> Vec<String> {
    let on = |b: bool| if b { "on" } else { "off" };
    let mut lines = vec![
        format!("{name}  {ms:.1} ms"),
        if compare {
            "compare: Phong | PBR".to_string()
        } else {
            format!("tier {} ({})", s.shading.tier(), s.shading)
        },
        format!(
            "shadows {}  lights {}  wrap {}  lines {}  grid {}  axes {}",
            on(s.shadows.enabled),
            glview::compare::light_count(s),
            on(s.lighting.wrap),
            match s.lighting.edges.mode {
                glview::frame::EdgeMode::Off => "off",
                glview::frame::EdgeMode::Feature => "edges",
                glview::frame::EdgeMode::Wireframe => "wireframe",
            },
            on(s.lighting.guides.grid),
            on(s.lighting.guides.axes)
        ),
    ];
    let st = &s.stereo;
    if st.mode != glview::stereo::StereoMode::Off {
        lines.push(format!(
            "stereo {}{}  separation {:.4}  convergence {:.4}{}",
            st.mode,
            if st.mode == glview::stereo::StereoMode::Anaglyph {
                format!(" ({} {})", st.method, st.glasses)
            } else {
                String::new()
            },
            st.separation,
            st.convergence,
            if st.swap { "  eyes swapped" } else { "" }
        ));
    }
    let t = &s.lighting.terms;
    let p = &s.lighting.pbr_terms;
    lines.push(format!(
        "legacy: ambient {} diffuse {} specular {}",
        on(t.ambient),
        on(t.diffuse),
        on(t.specular)
    ));
    lines.push(format!(
        "pbr: direct {}/{} ibl {}/{} ao {} shadows {} emissive {}",
        on(p.direct_diffuse),
        on(p.direct_specular),
        on(p.ibl_diffuse),
        on(p.ibl_specular),
        on(p.ao),
        on(p.shadows),
        on(p.emissive)
    ));
    lines.push(format!(
        "glTF layers: clearcoat {} sheen {} transmission {} iridescence {} anisotropy {}",
        on(p.clearcoat),
        on(p.sheen),
        on(p.transmission),
        on(p.iridescence),
        on(p.anisotropy)
    ));
    lines.push(String::new());
    lines.extend(keys::help_text().lines().map(str::to_string));
    lines
        .iter()
        .map(|l| {
            l.chars()
                .map(glview::compare::canvas::substitute)
                .collect::<String>()
        })
        .collect()
}

/// `DIR/glview-0001.png`, `-0002`, ...: the first name not taken. The file is created here
/// (create_new), so two viewers saving at once never write the same file.
fn next_screenshot_path(dir: &Path) -> Result<PathBuf> {
    for n in 1..=999_999u32 {
        let path = dir.join(format!("glview-{n:04}.png"));
        match std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&path)
        {
            Ok(_) => return Ok(path),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
            Err(e) => return Err(Error::io(path, e)),
        }
    }
    Err(Error::Unsupported(format!(
        "{}: no free screenshot name",
        dir.display()
    )))
}

/// The window's anti-aliasing from `--aa` (FXAA is a post pass of every frame: nothing here).
fn window_aa(args: &Args) -> WindowAa {
    match args.post.aa {
        crate::cli::AaMode::Msaa => WindowAa::Msaa(args.post.aa_samples),
        crate::cli::AaMode::Ssaa => WindowAa::Ssaa(args.post.aa_samples.clamp(1, 4)),
        crate::cli::AaMode::None | crate::cli::AaMode::Fxaa => WindowAa::None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn screenshot_names_never_overwrite() {
        let dir = std::env::temp_dir().join(format!("glview-shots-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("glview-0001.png"), b"taken").unwrap();
        std::fs::write(dir.join("glview-0003.png"), b"taken").unwrap();
        let names: Vec<_> = (0..3)
            .map(|_| next_screenshot_path(&dir).unwrap())
            .collect();
        let names: Vec<_> = names
            .iter()
            .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
            .collect();
        assert_eq!(
            names,
            ["glview-0002.png", "glview-0004.png", "glview-0005.png"]
        );
        assert_eq!(
            std::fs::read(dir.join("glview-0001.png")).unwrap(),
            b"taken"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn the_overlay_prints_only_glyphs_the_font_has() {
        use clap::Parser;
        let args = Args::try_parse_from(["glview"]).unwrap();
        let scene = session::load_scene(&args).unwrap();
        let (mut s, _) = session::frame_settings(&args, &scene).unwrap();
        for shading in [Shading::Phong, Shading::Gouraud, Shading::Pbr] {
            s.shading = shading;
            for compare in [false, true] {
                let lines = overlay_lines(&s, "modèle ünïcode", compare, 12.5);
                assert!(lines[2].contains("lights 3"), "{lines:?}");
                for l in &lines {
                    let missing = glview::compare::canvas::missing_glyphs(l);
                    assert!(missing.is_empty(), "{l:?} lacks {missing:?}");
                }
            }
        }
        // The key table's arrows and minus signs come out as ASCII stand-ins.
        let help = keys::help_text();
        assert!(help.contains('→') && help.contains('−'));
    }

    #[test]
    fn physical_fallback_covers_every_letter_key() {
        for (names, _, _) in keys::KEY_TABLE {
            for n in names
                .iter()
                .filter(|n| n.len() == 1 && n.chars().all(|c| c.is_ascii_alphanumeric()))
            {
                let found = [
                    KeyCode::KeyR,
                    KeyCode::KeyF,
                    KeyCode::KeyS,
                    KeyCode::KeyG,
                    KeyCode::KeyP,
                    KeyCode::KeyW,
                    KeyCode::KeyH,
                    KeyCode::KeyQ,
                    KeyCode::Digit1,
                    KeyCode::Digit2,
                    KeyCode::Digit3,
                    KeyCode::Digit4,
                    KeyCode::Digit5,
                    KeyCode::Digit6,
                    KeyCode::Digit7,
                    KeyCode::Digit8,
                    KeyCode::Digit9,
                    KeyCode::Digit0,
                    KeyCode::KeyC,
                    KeyCode::KeyB,
                    KeyCode::KeyE,
                    KeyCode::KeyZ,
                    KeyCode::KeyX,
                    KeyCode::KeyK,
                    KeyCode::KeyV,
                    KeyCode::KeyA,
                    KeyCode::KeyT,
                    KeyCode::KeyY,
                ]
                .iter()
                .any(|c| physical_name(*c) == Some(n));
                assert!(found, "key {n} has no physical fallback");
            }
        }
    }
}
