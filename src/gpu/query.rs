//! GPU timer queries (GL_TIME_ELAPSED): GPU time of a frame where the driver has them
//! (desktop GL 3.3, or ARB_timer_query); elsewhere the caller falls back to wall time.
use super::GpuRef;
use crate::{Error, Result};
use glow::HasContext;

pub struct TimerQuery {
    gpu: GpuRef,
    raw: glow::Query,
}

impl TimerQuery {
    /// None where the driver has no timer queries.
    pub fn new(gpu: &GpuRef) -> Result<Option<TimerQuery>> {
        if !gpu.caps.timer_query {
            return Ok(None);
        }
        // SAFETY: creating a query object on a context that supports them.
        let raw = unsafe { gpu.gl.create_query() }.map_err(Error::Unsupported)?;
        gpu.created();
        Ok(Some(TimerQuery {
            gpu: gpu.clone(),
            raw,
        }))
    }

    pub fn begin(&self) {
        // SAFETY: our own query; no other TIME_ELAPSED query is active (one per renderer).
        unsafe { self.gpu.gl.begin_query(glow::TIME_ELAPSED, self.raw) }
    }

    pub fn end(&self) {
        // SAFETY: ends the query begun above.
        unsafe { self.gpu.gl.end_query(glow::TIME_ELAPSED) }
    }

    /// Nanoseconds between begin and end; waits for the result.
    pub fn result_ns(&self) -> u64 {
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
