//! Window contexts (winit + glutin-winit); see `app` for the event loop.
