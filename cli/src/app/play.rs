//! The window playing a glTF animation: while the view plays, its time (the `--time`
//! option) follows the wall clock and a frame is drawn at most [`PLAY_HZ`] times a second;
//! paused, the loop waits for input as before and draws nothing. The time shown is a label
//! in the corner (or a line of the `H` overlay) whenever the file has animations.
use super::App;
use glview::scene::Scene;
use glview::session::View;
use std::time::{Duration, Instant};
use winit::event_loop::{ActiveEventLoop, ControlFlow};

/// Frames a second while playing: the display's usual rate (the swap does not wait for
/// vblank, so without a cap llvmpipe would draw as fast as it can).
const PLAY_HZ: f64 = 60.0;

impl App<'_> {
    /// Between events: a playing view's time moves on by the wall clock once a frame
    /// interval has passed (which asks for the frame), and the loop wakes for the next one.
    pub(super) fn play(&mut self, event_loop: &ActiveEventLoop) {
        if !self.view.playing() || self.live.is_none() {
            self.clock = None;
            event_loop.set_control_flow(ControlFlow::Wait);
            return;
        }
        let interval = Duration::from_secs_f64(1.0 / PLAY_HZ);
        let now = Instant::now();
        let last = *self.clock.get_or_insert(now);
        if now >= last + interval {
            self.clock = Some(now);
            let dt = (now - last).as_secs_f64();
            self.change(|view, scene| {
                view.advance(dt, scene.animations())?;
                Ok(glview::keys::Effect::Redraw)
            });
        }
        let next = self.clock.unwrap_or(now) + interval;
        event_loop.set_control_flow(ControlFlow::WaitUntil(next));
    }
}

/// The label of the moment shown: `Walk 1.27 / 2.00 s playing` (None: the file has no
/// animations). The static pose is `static pose (Space plays)`.
pub(super) fn label(view: &View, scene: &Scene) -> Option<String> {
    let all = scene.animations();
    if all.is_empty() {
        return None;
    }
    let Some(t) = view.options().motion.time else {
        return Some(format!(
            "static pose ({} animation{}: Space plays)",
            all.len(),
            if all.len() == 1 { "" } else { "s" }
        ));
    };
    let i = view.animation_index(all).ok()?;
    let a = &all[i];
    let name = if a.name.is_empty() {
        format!("animation {i}")
    } else {
        a.name.chars().take(40).collect()
    };
    let state = if view.playing() { "playing" } else { "paused" };
    Some(format!("{name}  {t:.2} / {:.2} s  {state}", a.duration))
}
