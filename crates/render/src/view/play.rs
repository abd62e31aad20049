//! Playing a view's glTF animation: the moment shown is options (`--animation`, `--time`),
//! so a still of a playing view is `glview -o --time T`; only whether the time runs is the
//! view's own. Space, `.`, `,` and `A` ([`View::act`]), the server's play and time messages
//! and the window's clock ([`View::advance`]) all move the same two options.
//!
//! Replayed headless (`--keys`), there is no clock: Space only sets the time to its current
//! value, or 0 from the static pose, and marks the view playing, which no picture shows.
use super::View;
use crate::error::{Error, Result};
use crate::scene::motion::AnimationInfo;
use crate::view::moment::{find, Missing};

/// A frame's time is snapped to the `--fps` grid when within this many frames of it (the
/// sum of f32 steps would otherwise drift off `--time k/fps`).
const ON_GRID: f32 = 1e-3;

impl View {
    /// Whether the view's time runs (the window's clock, the server's frames).
    pub fn playing(&self) -> bool {
        self.playing
    }

    /// The animation the view shows or would play (index into `all`): `--animation` by
    /// index, then by name, default the first. An error when the file has none or not that
    /// one.
    pub fn animation_index(&self, all: &[AnimationInfo]) -> Result<usize> {
        let asked = self.options.motion.animation.as_deref();
        find(all, asked).map_err(|missing| match missing {
            Missing::None => Error::Usage("this model has no animations to play".into()),
            Missing::NoSuch => Error::Usage(format!(
                "no animation {:?}: the model has {} (0 to {})",
                asked.unwrap_or_default(),
                all.len(),
                all.len() - 1
            )),
        })
    }

    /// Stops the clock, the moment stays (a frame that failed to draw is not drawn again and
    /// again at the frame rate).
    pub fn pause(&mut self) {
        self.playing = false;
    }

    /// Space: plays from the time shown (from 0 when the static pose is shown), or pauses.
    pub fn play_pause(&mut self, all: &[AnimationInfo]) -> Result<()> {
        let on = !self.playing;
        self.set_playing(on, all)
    }

    /// Plays (from the time shown, 0 from the static pose) or pauses.
    pub fn set_playing(&mut self, on: bool, all: &[AnimationInfo]) -> Result<()> {
        self.animation_index(all)?;
        let m = &mut self.options.motion;
        m.time = Some(m.time.unwrap_or(0.0));
        self.playing = on;
        Ok(())
    }

    /// `.` and `,`: `frames` frames of `--fps` forward or back (wrapping at the animation's
    /// end), paused. The time lands on the frame grid: k presses from the static pose show
    /// `--time k/fps` exactly.
    pub fn step(&mut self, frames: i32, all: &[AnimationInfo]) -> Result<()> {
        let a = self.animation_index(all)?;
        let m = &mut self.options.motion;
        let now = m.time.unwrap_or(0.0) * m.fps;
        let k = if frames >= 0 {
            (now + ON_GRID).floor() + frames as f32
        } else {
            (now - ON_GRID).ceil() + frames as f32
        };
        m.time = Some(wrap(k / m.fps, all[a].duration));
        self.playing = false;
        Ok(())
    }

    /// `A`: the file's next animation (after the last, the first), from its time 0.
    pub fn next_animation(&mut self, all: &[AnimationInfo]) -> Result<()> {
        let a = self.animation_index(all)?;
        let m = &mut self.options.motion;
        m.animation = Some(((a + 1) % all.len()).to_string());
        m.time = Some(0.0);
        Ok(())
    }

    /// The server's time message: animation `animation` (None: the one shown) at `seconds`
    /// (wrapped into its duration), play state unchanged.
    pub fn set_moment(
        &mut self,
        animation: Option<usize>,
        seconds: f32,
        all: &[AnimationInfo],
    ) -> Result<()> {
        if !(seconds.is_finite() && seconds >= 0.0) {
            return Err(Error::Usage(format!(
                "time {seconds}: a number of seconds, 0 or more"
            )));
        }
        let before = self.options.motion.animation.clone();
        if let Some(i) = animation {
            self.options.motion.animation = Some(i.to_string());
        }
        let a = match self.animation_index(all) {
            Ok(a) => a,
            Err(e) => {
                self.options.motion.animation = before;
                return Err(e);
            }
        };
        self.options.motion.time = Some(wrap(seconds, all[a].duration));
        Ok(())
    }

    /// The wall clock moved `seconds` on: a playing view's time moves with it (wrapping at
    /// the animation's end; a zero-length animation stays at 0). Paused, nothing changes.
    pub fn advance(&mut self, seconds: f64, all: &[AnimationInfo]) -> Result<()> {
        if !self.playing {
            return Ok(());
        }
        let a = self.animation_index(all)?;
        let m = &mut self.options.motion;
        let t = f64::from(m.time.unwrap_or(0.0)) + seconds.max(0.0);
        m.time = Some(wrap_f64(t, all[a].duration));
        Ok(())
    }

    /// The static pose again (another model: its animations are not this one's).
    pub(super) fn stop(&mut self) {
        self.playing = false;
        self.options.motion.time = None;
        self.options.motion.animation = None;
    }
}

/// `t` (f32, as `--time` holds it) into `[0, duration)`; exact when already inside, so a
/// step's `k / fps` is the `--time` a user would type.
fn wrap(t: f32, duration: f64) -> f32 {
    if t >= 0.0 && f64::from(t) < duration {
        t
    } else {
        wrap_f64(f64::from(t), duration)
    }
}

fn wrap_f64(t: f64, duration: f64) -> f32 {
    // NaN durations count as zero-length.
    if duration.is_nan() || duration <= 0.0 || !t.is_finite() {
        return 0.0;
    }
    let w = t.rem_euclid(duration) as f32;
    // Rounding to f32 may land on the duration itself: that is the start again.
    if f64::from(w) >= duration {
        0.0
    } else {
        w
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::options::Options;

    fn anims(durations: &[f64]) -> Vec<AnimationInfo> {
        durations
            .iter()
            .enumerate()
            .map(|(i, d)| AnimationInfo {
                name: format!("a{i}"),
                duration: *d,
                channels: 1,
                together: false,
                default: false,
            })
            .collect()
    }

    fn view() -> View {
        View::new(Options::default())
    }

    /// k presses of `.` from the static pose are `--time k/fps` exactly (the f32 a user's
    /// `--time` parses to), paused; `,` goes back on the same grid and wraps at 0.
    #[test]
    fn steps_land_on_the_fps_grid() {
        let all = anims(&[10.0]);
        let mut v = view();
        for k in 1..=40 {
            v.step(1, &all).unwrap();
            let want: f32 = format!("{}", k as f32 / 15.0).parse().unwrap();
            assert_eq!(v.options().motion.time, Some(want), "press {k}");
        }
        assert!(!v.playing() && v.options().motion.animation.is_none());
        for k in (0..40).rev() {
            v.step(-1, &all).unwrap();
            assert_eq!(v.options().motion.time, Some(k as f32 / 15.0));
        }
        v.step(-1, &all).unwrap();
        assert_eq!(v.options().motion.time, Some(10.0 - 1.0 / 15.0));
        v.step(1, &all).unwrap();
        assert_eq!(v.options().motion.time, Some(0.0));
        // Off the grid (paused mid-play), a step goes to the next frame of the grid.
        v.options.motion.time = Some(0.1);
        v.step(1, &all).unwrap();
        assert_eq!(v.options().motion.time, Some(2.0 / 15.0));
        v.options.motion.time = Some(0.1);
        v.step(-1, &all).unwrap();
        assert_eq!(v.options().motion.time, Some(1.0 / 15.0));
    }

    /// Space from the static pose plays time 0 of the first animation (or `--animation`);
    /// the clock moves a playing view only, wrapping at the duration; a zero-length
    /// animation stays at 0.
    #[test]
    fn play_starts_at_zero_and_wraps() {
        let all = anims(&[2.0, 0.0]);
        let mut v = view();
        v.advance(1.0, &all).unwrap();
        assert_eq!(v.options().motion.time, None, "paused: no change");
        v.play_pause(&all).unwrap();
        assert!(v.playing());
        assert_eq!(v.options().motion.time, Some(0.0));
        v.advance(1.5, &all).unwrap();
        v.advance(1.0, &all).unwrap();
        assert_eq!(v.options().motion.time, Some(0.5));
        v.play_pause(&all).unwrap();
        v.advance(1.0, &all).unwrap();
        assert_eq!(v.options().motion.time, Some(0.5), "paused where it was");
        v.options.motion.animation = Some("a1".into());
        v.set_playing(true, &all).unwrap();
        v.advance(0.7, &all).unwrap();
        assert_eq!(v.options().motion.time, Some(0.0));
        v.step(1, &all).unwrap();
        assert_eq!(v.options().motion.time, Some(0.0));
    }

    /// `A` cycles the animations from their start; a moment names one by index; what the
    /// file lacks (no animations, an unknown one, a negative or NaN time) is an error that
    /// leaves the view as it was.
    #[test]
    fn animations_cycle_and_bad_values_are_errors() {
        let all = anims(&[1.0, 3.0]);
        let mut v = view();
        v.next_animation(&all).unwrap();
        assert_eq!(v.options().motion.animation.as_deref(), Some("1"));
        v.next_animation(&all).unwrap();
        assert_eq!(v.options().motion.animation.as_deref(), Some("0"));
        v.set_moment(Some(1), 2.5, &all).unwrap();
        let good = v.clone();
        assert_eq!(v.options().motion.time, Some(2.5));
        for (a, t) in [
            (Some(2), 1.0),
            (None, -1.0),
            (None, f32::NAN),
            (None, f32::INFINITY),
        ] {
            let e = v.set_moment(a, t, &all).unwrap_err().to_string();
            assert!(!e.contains('\n'), "{e}");
            assert_eq!(v, good);
        }
        v.options.motion.animation = Some("walk".into());
        let e = v.animation_index(&all).unwrap_err().to_string();
        assert!(
            e.ends_with("no animation \"walk\": the model has 2 (0 to 1)"),
            "{e}"
        );
        let mut s = view();
        for r in [s.play_pause(&[]), s.step(1, &[]), s.next_animation(&[])] {
            assert!(r.unwrap_err().to_string().contains("no animations"));
        }
        assert_eq!(s, view());
    }
}
