//! The time the renderer's measurements are in, given by its caller: the renderer has no
//! clock of its own (no picture depends on time; only the milliseconds `--stats` prints and
//! the profile's stages). The native library gives it `std::time::Instant`'s, the browser
//! build `performance.now()`; without one every duration is 0.
use std::sync::OnceLock;

/// Milliseconds since any fixed moment.
pub type Clock = fn() -> f64;

static CLOCK: OnceLock<Clock> = OnceLock::new();

/// Gives the renderer its time, once (later calls change nothing).
pub fn set(c: Clock) {
    let _ = CLOCK.set(c);
}

/// Now, in milliseconds (0 without a clock).
pub fn now() -> f64 {
    CLOCK.get().map_or(0.0, |c| c())
}

/// A moment measured from.
#[derive(Clone, Copy, Debug)]
pub struct Mark(f64);

impl Mark {
    pub fn now() -> Mark {
        Mark(now())
    }

    /// Milliseconds since the mark.
    pub fn ms(self) -> f64 {
        now() - self.0
    }
}
