//! Per-stage load times, measured inside the loader: read (file → bytes), repair (the
//! byte-level pre-pass), parse (tobj, MTL libraries included; on the fast path,
//! `scene::fast`'s one pass, and repair is 0), textures (decoding),
//! meshes (re-centring, vertex building; normals excluded), normals (generation and repair),
//! finish (redundant faces, texture notes). Recorded per thread; [`last`] returns the most
//! recent load's profile (for `--stats` and `--check`).
use serde::Serialize;
use std::cell::RefCell;
use std::time::Duration;
// std's Instant natively; the browser's clock on wasm32, where std's panics.
use web_time::Instant;

/// A loader stage; see the module comment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Stage {
    Read,
    Repair,
    Parse,
    Textures,
    Meshes,
    Normals,
    Finish,
}

/// Milliseconds per stage of one load. `cached` = the scene came from the mesh cache (then
/// only `read` and `total` are set).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct LoadProfile {
    pub(crate) bytes: u64,
    pub(crate) cached: bool,
    /// With `cached`: the bytes of the entry read at load (payload; the header apart).
    pub(crate) entry_bytes: u64,
    pub(crate) read_ms: f64,
    pub(crate) repair_ms: f64,
    pub(crate) parse_ms: f64,
    pub(crate) textures_ms: f64,
    pub(crate) meshes_ms: f64,
    pub(crate) normals_ms: f64,
    pub(crate) finish_ms: f64,
    pub(crate) total_ms: f64,
    /// The one-pass parser ran (`scene::fast`): `repair_ms` is 0, `parse_ms` is that pass.
    pub fast_path: bool,
}

impl LoadProfile {
    fn slot(&mut self, s: Stage) -> &mut f64 {
        match s {
            Stage::Read => &mut self.read_ms,
            Stage::Repair => &mut self.repair_ms,
            Stage::Parse => &mut self.parse_ms,
            Stage::Textures => &mut self.textures_ms,
            Stage::Meshes => &mut self.meshes_ms,
            Stage::Normals => &mut self.normals_ms,
            Stage::Finish => &mut self.finish_ms,
        }
    }
}

impl std::fmt::Display for LoadProfile {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{:.1} MB{}: read {:.0} ms, repair {:.0} ms, parse{} {:.0} ms, textures {:.0} ms, \
             meshes {:.0} ms, normals {:.0} ms, finish {:.0} ms, total {:.0} ms",
            self.bytes as f64 / 1e6,
            if self.cached { " (mesh cache)" } else { "" },
            self.read_ms,
            self.repair_ms,
            if self.fast_path { " (one pass)" } else { "" },
            self.parse_ms,
            self.textures_ms,
            self.meshes_ms,
            self.normals_ms,
            self.finish_ms,
            self.total_ms
        )
    }
}

struct Recorder {
    start: Instant,
    mark: Instant,
    current: LoadProfile,
    last: Option<LoadProfile>,
}

thread_local! {
    static REC: RefCell<Recorder> = RefCell::new(Recorder {
        start: Instant::now(),
        mark: Instant::now(),
        current: LoadProfile::default(),
        last: None,
    });
}

fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

/// Starts a load of `bytes` bytes (before the file is read, when it is).
pub fn begin(bytes: u64) {
    REC.with_borrow_mut(|r| {
        let now = Instant::now();
        (r.start, r.mark) = (now, now);
        r.current = LoadProfile {
            bytes,
            ..Default::default()
        };
    });
}

/// Ends the stage that began at the previous mark (or at [`begin`]).
pub(crate) fn mark(stage: Stage) {
    REC.with_borrow_mut(|r| {
        let now = Instant::now();
        *r.current.slot(stage) += ms(now - r.mark);
        r.mark = now;
    });
}

/// Sets the input size once it is known (after reading).
pub(crate) fn set_bytes(bytes: u64) {
    REC.with_borrow_mut(|r| r.current.bytes = bytes);
}

#[cfg_attr(not(feature = "native"), allow(dead_code))]
/// The bytes of the mesh cache entry a hit read (its header and first section).
pub(crate) fn set_entry_bytes(bytes: u64) {
    REC.with_borrow_mut(|r| r.current.entry_bytes = bytes);
}

/// Time spent inside a stage nested in another (normals inside meshes, textures inside
/// materials): added to `stage`, and taken out of the enclosing stage by moving its mark.
pub(crate) struct Nested {
    stage: Stage,
    start: Instant,
}

pub(crate) fn nested(stage: Stage) -> Nested {
    Nested {
        stage,
        start: Instant::now(),
    }
}

impl Drop for Nested {
    fn drop(&mut self) {
        let d = self.start.elapsed();
        REC.with_borrow_mut(|r| {
            *r.current.slot(self.stage) += ms(d);
            r.mark += d;
        });
    }
}

/// Notes whether this load took the fast OBJ path.
pub(crate) fn set_fast_path(fast: bool) {
    REC.with_borrow_mut(|r| r.current.fast_path = fast);
}

/// Ends the load: the profile becomes [`last`].
pub(crate) fn end(cached: bool) {
    REC.with_borrow_mut(|r| {
        r.current.cached = cached;
        r.current.total_ms = ms(r.start.elapsed());
        r.last = Some(r.current);
    });
}

/// The profile of this thread's most recent load.
pub fn last() -> Option<LoadProfile> {
    REC.with_borrow(|r| r.last)
}

/// The most recent load's profile, forgotten here (so the next call says whether another
/// load happened since).
pub fn take_last() -> Option<LoadProfile> {
    REC.with_borrow_mut(|r| r.last.take())
}

#[cfg(test)]
mod tests {
    use super::*;
    use {crate::load, crate::load::options::LoadOptions};

    #[test]
    fn a_load_records_every_stage_and_they_add_up() {
        let dir = std::env::temp_dir().join(format!("glview-profile-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("t.obj");
        let mut text = String::new();
        for i in 0..2000 {
            text.push_str(&format!("v {i} 0 0\nv {i} 1 0\nv {i} 0 1\n"));
            let k = 3 * i + 1;
            text.push_str(&format!("f {} {} {}\n", k, k + 1, k + 2));
        }
        std::fs::write(&p, &text).unwrap();
        load(&p, &LoadOptions::default()).unwrap();
        let prof = last().unwrap();
        assert_eq!(prof.bytes, text.len() as u64);
        assert!(!prof.cached);
        let parts = prof.read_ms
            + prof.repair_ms
            + prof.parse_ms
            + prof.textures_ms
            + prof.meshes_ms
            + prof.normals_ms
            + prof.finish_ms;
        assert!(
            prof.parse_ms > 0.0 && prof.fast_path && prof.normals_ms > 0.0,
            "{prof}"
        );
        assert!(parts <= prof.total_ms + 1e-6, "{prof}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
