//! The interactive window loop.
use crate::cli::Args;
use crate::Result;

/// Whether a display server is reachable (X11 or Wayland).
pub fn display_available() -> bool {
    std::env::var_os("DISPLAY").is_some_and(|d| !d.is_empty())
        || std::env::var_os("WAYLAND_DISPLAY").is_some_and(|d| !d.is_empty())
}

pub fn run_window(_args: &Args) -> Result<()> {
    Err(crate::Error::Unsupported(
        "window not implemented yet".into(),
    ))
}
