//! Headless WGL (Windows): a window that is never shown, a context current on it, and the
//! caller's own framebuffer object to render into — a PNG shows no window.
//!
//! WGL has no surfaceless contexts, and its pbuffers (WGL_ARB_pbuffer) need the same window
//! first: glutin loads WGL's extension functions (wglCreateContextAttribsARB, the pixel-format
//! queries) through a window's device context. A hidden window of the desktop's own style is
//! what glutin's examples and f3d's Windows path use; it costs one `CreateWindowExW`.
use super::GlRequest;
use crate::{Error, Result};
use glutin::config::{Api, ConfigTemplateBuilder};
use glutin::context::PossiblyCurrentContext;
use glutin::display::{Display, DisplayApiPreference};
use glutin::prelude::*;
use glutin::surface::{Surface, SurfaceAttributesBuilder, WindowSurface};
use raw_window_handle::{
    RawDisplayHandle, RawWindowHandle, Win32WindowHandle, WindowsDisplayHandle,
};
use std::num::{NonZeroIsize, NonZeroU32};
use windows_sys::Win32::Foundation::HWND;
use windows_sys::Win32::System::LibraryLoader::GetModuleHandleW;
use windows_sys::Win32::UI::WindowsAndMessaging as wm;

/// A current WGL context on a hidden window. Field order is drop order: the context, its
/// surface and the display go before the window they use.
pub(crate) struct WglHeadless {
    context: PossiblyCurrentContext,
    _surface: Surface<WindowSurface>,
    display: Display,
    _window: HiddenWindow,
}

/// A window of ours, destroyed on drop.
struct HiddenWindow(HWND);

impl Drop for HiddenWindow {
    fn drop(&mut self) {
        // SAFETY: the window was created by `hidden_window` and nothing else destroys it.
        unsafe { wm::DestroyWindow(self.0) };
    }
}

/// `"glview-headless"`, NUL-terminated UTF-16.
fn class_name() -> Vec<u16> {
    "glview-headless\0".encode_utf16().collect()
}

/// Registers the window class once per process (a second registration fails harmlessly).
fn hidden_window(width: u32, height: u32) -> Result<(HWND, isize)> {
    let class = class_name();
    // SAFETY: plain Win32 calls with valid, NUL-terminated strings; the class's procedure
    // is the system default, so the window needs no message loop of ours.
    unsafe {
        let instance = GetModuleHandleW(std::ptr::null());
        let wc = wm::WNDCLASSW {
            style: wm::CS_OWNDC,
            lpfnWndProc: Some(wm::DefWindowProcW),
            cbClsExtra: 0,
            cbWndExtra: 0,
            hInstance: instance,
            hIcon: 0,
            hCursor: 0,
            hbrBackground: 0,
            lpszMenuName: std::ptr::null(),
            lpszClassName: class.as_ptr(),
        };
        wm::RegisterClassW(&wc);
        let hwnd = wm::CreateWindowExW(
            0,
            class.as_ptr(),
            class.as_ptr(),
            wm::WS_OVERLAPPEDWINDOW,
            0,
            0,
            width.max(1) as i32,
            height.max(1) as i32,
            0,
            0,
            instance,
            std::ptr::null(),
        );
        if hwnd == 0 {
            return Err(Error::Context(format!(
                "WGL: cannot create the hidden window (error {})",
                windows_sys::Win32::Foundation::GetLastError()
            )));
        }
        Ok((hwnd, instance))
    }
}

impl WglHeadless {
    /// Tries each candidate context in order on one hidden window; the error lists every
    /// attempt, and names Mesa's llvmpipe for Windows where the driver offers only GDI's
    /// GL 1.1.
    pub(crate) fn new(request: GlRequest, width: u32, height: u32) -> Result<WglHeadless> {
        let (hwnd, instance) = hidden_window(width, height)?;
        let window = HiddenWindow(hwnd);
        let (context, surface, display) = Self::on(hwnd, instance, request)?;
        Ok(WglHeadless {
            context,
            _surface: surface,
            display,
            _window: window,
        })
    }

    fn on(
        hwnd: HWND,
        instance: isize,
        request: GlRequest,
    ) -> Result<(PossiblyCurrentContext, Surface<WindowSurface>, Display)> {
        let mut handle = Win32WindowHandle::new(NonZeroIsize::new(hwnd).expect("a window"));
        handle.hinstance = NonZeroIsize::new(instance);
        let raw_window = RawWindowHandle::Win32(handle);
        let raw_display = RawDisplayHandle::Windows(WindowsDisplayHandle::new());
        // SAFETY: the window is alive until Drop, after the display.
        let display =
            unsafe { Display::new(raw_display, DisplayApiPreference::Wgl(Some(raw_window))) }
                .map_err(|e| Error::Context(format!("WGL: {e}")))?;
        let template = ConfigTemplateBuilder::new()
            .with_depth_size(24)
            .compatible_with_native_window(raw_window)
            .build();
        // SAFETY: the template's window is alive.
        let config = unsafe { display.find_configs(template) }
            .map_err(|e| Error::Context(format!("WGL: {e}")))?
            .filter(|c| c.api().contains(Api::OPENGL))
            .min_by_key(|c| c.num_samples())
            .ok_or_else(|| {
                Error::Context("WGL: no pixel format with a 24-bit depth buffer".into())
            })?;
        let one = NonZeroU32::MIN;
        let attrs = SurfaceAttributesBuilder::<WindowSurface>::new().build(raw_window, one, one);
        // SAFETY: the window outlives the surface (field order, then Drop).
        let surface = unsafe { display.create_window_surface(&config, &attrs) }
            .map_err(|e| Error::Context(format!("WGL: cannot make the surface: {e}")))?;
        let mut tried = Vec::new();
        for &candidate in request.candidates() {
            // GL ES through WGL needs WGL_EXT_create_context_es2_profile, which old drivers
            // lack; EGL offers ES on Linux.
            // SAFETY: the attributes name the live window.
            let made = unsafe {
                display.create_context(
                    &config,
                    &super::context_attributes(candidate, Some(raw_window)),
                )
            }
            .map_err(|e| e.to_string())
            .and_then(|c| c.make_current(&surface).map_err(|e| e.to_string()));
            match made {
                Ok(context) => return Ok((context, surface, display)),
                Err(e) => tried.push(format!("{candidate:?}: {e}")),
            }
        }
        Err(Error::Context(format!("WGL: {}", tried.join("; "))))
    }

    pub(crate) fn glow_context(&self) -> glow::Context {
        // SAFETY: the context is current on this thread and its display lives in self.
        unsafe {
            glow::Context::from_loader_function_cstr(|name| self.display.get_proc_address(name))
        }
    }
}

impl Drop for WglHeadless {
    /// Releases the context from this thread before glutin deletes it (as EGL's does).
    fn drop(&mut self) {
        if self.context.is_current() {
            let _ = self.context.make_not_current_in_place();
        }
    }
}
