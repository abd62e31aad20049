//! Context creation: on Linux EGL headless (device platform, surfaceless) and OSMesa (loaded
//! at run time), on Windows WGL on a hidden window; and, for the binary's window (winit +
//! glutin-winit), the attributes of a context request. Each gives a `glow::Context`; the same
//! renderer draws in all of them.
#[cfg(not(windows))]
pub(crate) mod egl;
#[cfg(not(windows))]
pub(crate) mod osmesa;
pub mod turbojpeg;
#[cfg(windows)]
pub(crate) mod wgl;

use crate::gpu::Caps;
use crate::{Error, Result};

/// glview draws with OpenGL 2.1 at least (GLSL 1.20). A context below it is refused with
/// what it is, and on Windows with the usual cure: a PC without a GL driver gets Microsoft's
/// GDI renderer, OpenGL 1.1 only, and Mesa's llvmpipe for Windows (mesa-dist-win's
/// `opengl32.dll` and `libgallium_wgl.dll` beside glview.exe) gives it GL 4.5 in software.
pub fn require_gl21(caps: &Caps) -> Result<()> {
    gl21_floor(
        (caps.major, caps.minor, caps.embedded),
        &caps.version,
        &caps.renderer,
        cfg!(windows),
    )
}

fn gl21_floor(
    (major, minor, embedded): (u32, u32, bool),
    version: &str,
    renderer: &str,
    windows: bool,
) -> Result<()> {
    if embedded || (major, minor) >= (2, 1) {
        return Ok(());
    }
    let cure = if windows {
        "; this PC has no usable OpenGL driver (Windows' own is OpenGL 1.1): install the \
         graphics vendor's driver, or put Mesa's llvmpipe (opengl32.dll and \
         libgallium_wgl.dll from mesa-dist-win) beside glview.exe (docs/windows.md)"
    } else {
        ""
    };
    Err(Error::Unsupported(format!(
        "glview needs OpenGL 2.1 or later; this context is OpenGL {version} ({renderer}){cure}"
    )))
}

pub use crate::options::context::{Backend, GlRequest};

/// What glutin is asked for, per request; shared by the EGL headless and the window paths.
pub fn context_attributes(
    request: GlRequest,
    window: Option<raw_window_handle::RawWindowHandle>,
) -> glutin::context::ContextAttributes {
    use glutin::context::{ContextApi, ContextAttributesBuilder, GlProfile, Version};
    let b = ContextAttributesBuilder::new();
    match request {
        GlRequest::Es3 => b.with_context_api(ContextApi::Gles(Some(Version::new(3, 0)))),
        GlRequest::Es2 => b.with_context_api(ContextApi::Gles(Some(Version::new(2, 0)))),
        GlRequest::Core => b
            .with_context_api(ContextApi::OpenGl(Some(Version::new(3, 3))))
            .with_profile(GlProfile::Core),
        GlRequest::Gl21 | GlRequest::Auto => b
            .with_context_api(ContextApi::OpenGl(Some(Version::new(2, 1))))
            .with_profile(GlProfile::Compatibility),
    }
    .build(window)
}

/// Keeps freed heap memory for reuse instead of handing it back to the kernel at once.
///
/// llvmpipe allocates its vertex buffers per frame (4.7 MB for the 69k-triangle bunny) and
/// frees them at the flush; glibc's default trims the heap on that free (madvise) and the
/// next frame faults every page in again. That was 40 % of a 64×48 frame's time on this
/// machine (12.5 → 6.4 ms a picture from Python, batch 110 → 138 pictures/s). Raising the
/// trim threshold to 256 MB, and fixing the mmap threshold at glibc's maximum (setting one
/// turns off glibc's adaptive raising of the other), keeps those pages; it is
/// process-wide, so a program that needs its freed memory back at once should not use
/// glview in the same process. Called where a context is made; later calls change nothing.
pub fn keep_freed_heap() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        static ONCE: std::sync::Once = std::sync::Once::new();
        ONCE.call_once(|| {
            // SAFETY: mallopt only sets allocator parameters; both values are in range
            // (M_MMAP_THRESHOLD's maximum on 64-bit is 32 MiB).
            unsafe {
                libc::mallopt(libc::M_MMAP_THRESHOLD, 32 << 20);
                libc::mallopt(libc::M_TRIM_THRESHOLD, 256 << 20);
            }
        });
    }
}

#[cfg(test)]
mod tests {
    use super::gl21_floor;

    /// GDI's OpenGL 1.1 (a Windows PC without a driver) is refused with the cure named; 2.1,
    /// later versions and GL ES pass; on Linux the message names no Windows DLL.
    #[test]
    fn below_gl21_is_refused_with_the_cure() {
        let e = gl21_floor((1, 1, false), "1.1.0", "GDI Generic", true)
            .unwrap_err()
            .to_string();
        assert!(e.contains("OpenGL 1.1.0 (GDI Generic)"), "{e}");
        assert!(
            e.contains("mesa-dist-win") && e.contains("opengl32.dll"),
            "{e}"
        );
        assert!(!e.contains('\n'), "one line: {e}");
        let e = gl21_floor((2, 0, false), "2.0", "old", false)
            .unwrap_err()
            .to_string();
        assert!(!e.contains("mesa-dist-win"), "{e}");
        assert!(gl21_floor((2, 1, false), "2.1", "x", true).is_ok());
        assert!(gl21_floor((4, 5, false), "4.5", "x", true).is_ok());
        assert!(gl21_floor((2, 0, true), "OpenGL ES 2.0", "x", true).is_ok());
    }
}
