//! GPU timer queries (GL_TIME_ELAPSED): GPU time of a frame where the driver has them
//! (desktop GL 3.3, or ARB_timer_query); elsewhere the caller falls back to wall time.
use super::GpuRef;
use crate::{Error, Result};
use glow::HasContext;

pub(crate) struct TimerQuery {
    gpu: GpuRef,
    raw: glow::Query,
}

impl TimerQuery {
    /// None where the driver has no timer queries.
    pub(crate) fn new(gpu: &GpuRef) -> Result<Option<TimerQuery>> {
        if !gpu.caps.timer_query {
            return Ok(None);
        }
        // SAFETY: creating a query object on a context that supports them.
        let raw = unsafe { gpu.gl.create_query() }.map_err(Error::Unsupported)?;
        gpu.created();
        let q = TimerQuery {
            gpu: gpu.clone(),
            raw,
        };
        // llvmpipe answers the very first TIME_ELAPSED query of a context with the time since
        // boot; an empty query spent here makes the first frame's `gpu_ms` a real figure.
        q.begin();
        // SAFETY: plain state calls and a one-pixel depth clear on the current context; the
        // scissor state is restored, and every frame clears its target before drawing. The
        // clear goes to whatever framebuffer is bound: none at all on a surfaceless context
        // (the default framebuffer, bound back by `ibl_gpu::compute` for one), where it
        // would leave GL_INVALID_FRAMEBUFFER_OPERATION for the next pass's check.
        unsafe {
            let gl = &gpu.gl;
            if !gpu.caps.fbo
                || gl.check_framebuffer_status(glow::FRAMEBUFFER) == glow::FRAMEBUFFER_COMPLETE
            {
                let scissor = gl.is_enabled(glow::SCISSOR_TEST);
                gl.enable(glow::SCISSOR_TEST);
                gl.scissor(0, 0, 1, 1);
                gl.clear(glow::DEPTH_BUFFER_BIT);
                if !scissor {
                    gl.disable(glow::SCISSOR_TEST);
                }
            }
            gl.finish();
        }
        q.end();
        q.result_ns();
        Ok(Some(q))
    }

    pub(crate) fn begin(&self) {
        // SAFETY: our own query; no other TIME_ELAPSED query is active (one per renderer).
        unsafe { self.gpu.gl.begin_query(glow::TIME_ELAPSED, self.raw) }
    }

    pub(crate) fn end(&self) {
        // SAFETY: ends the query begun above.
        unsafe { self.gpu.gl.end_query(glow::TIME_ELAPSED) }
    }

    /// Nanoseconds between begin and end; waits for the result.
    pub(crate) fn result_ns(&self) -> u64 {
        let mut ns: u64 = 0;
        // SAFETY: glGetQueryObjectui64v writes one u64. glow passes its "offset" as the params
        // pointer, which GL reads as a client address because glview never binds a
        // GL_QUERY_BUFFER; so it is the address of `ns`, alive for the call. (The 32-bit getter
        // would saturate at 4.29 s.)
        unsafe {
            self.gpu.gl.get_query_parameter_u64_with_offset(
                self.raw,
                glow::QUERY_RESULT,
                &mut ns as *mut u64 as usize,
            )
        };
        ns
    }
}

impl Drop for TimerQuery {
    fn drop(&mut self) {
        // SAFETY: deleting our own query once.
        unsafe { self.gpu.gl.delete_query(self.raw) };
        self.gpu.deleted();
    }
}
