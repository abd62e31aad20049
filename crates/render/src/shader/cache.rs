//! Programs keyed by what they compute, compiled on first use and reused. A key is a shader
//! pair plus feature flags; the `#define`s and the label `--stats` prints are generated from
//! the flags, so a new pass declares its flags and needs no table here. There is one cache per
//! GL context, shared by every renderer on it (see [`ProgramCache::for_context`]).
use super::{assemble, Stage};
use crate::gpu::program::Program;
use crate::gpu::{Gpu, GpuRef};
use crate::Result;
use std::cell::RefCell;
use std::collections::HashMap;
use std::rc::{Rc, Weak};

/// How a flag becomes a `#define` and a part of the label.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) enum FlagKind {
    /// `#define NAME value`; label `short` + value (e.g. `l2`).
    Count,
    /// `#define NAME 1` when non-zero, nothing otherwise; label `short` when set.
    Switch,
    /// `#define NAME value`; not in the label (derived from other flags).
    Hidden,
    /// `#define NAME value.0` (a float constant); not in the label.
    HiddenFloat,
    /// `#define NAME value`; label `short` + value in binary when non-zero.
    Mask,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) struct Flag {
    pub(crate) define: &'static str,
    pub(crate) short: &'static str,
    pub(crate) kind: FlagKind,
    pub(crate) value: i32,
}

/// Everything that changes a program's source; the cache key.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct ProgramKey {
    /// Label prefix, e.g. `lit`.
    pub(crate) name: &'static str,
    pub(crate) vertex: &'static str,
    pub(crate) fragment: &'static str,
    pub(crate) flags: Vec<Flag>,
}

impl ProgramKey {
    /// A program from `NAME.vert` + `NAME.frag` without flags.
    pub(crate) fn new(name: &'static str, vertex: &'static str, fragment: &'static str) -> Self {
        ProgramKey {
            name,
            vertex,
            fragment,
            flags: Vec::new(),
        }
    }

    fn with(mut self, define: &'static str, short: &'static str, kind: FlagKind, v: i32) -> Self {
        self.flags.push(Flag {
            define,
            short,
            kind,
            value: v,
        });
        self
    }

    pub(crate) fn count(self, define: &'static str, short: &'static str, v: i32) -> Self {
        self.with(define, short, FlagKind::Count, v)
    }

    pub(crate) fn switch(self, define: &'static str, short: &'static str, on: bool) -> Self {
        self.with(define, short, FlagKind::Switch, i32::from(on))
    }

    pub(crate) fn hidden(self, define: &'static str, v: i32) -> Self {
        self.with(define, "", FlagKind::Hidden, v)
    }

    pub(crate) fn hidden_float(self, define: &'static str, v: i32) -> Self {
        self.with(define, "", FlagKind::HiddenFloat, v)
    }

    pub(crate) fn mask(self, define: &'static str, short: &'static str, v: i32) -> Self {
        self.with(define, short, FlagKind::Mask, v)
    }

    /// A short name for stats and errors, e.g. `lit[l1,s1,pcf4,tex]`; flagless keys are just
    /// the name.
    pub(crate) fn label(&self) -> String {
        let parts: Vec<String> = self
            .flags
            .iter()
            .filter_map(|f| match f.kind {
                FlagKind::Count => Some(format!("{}{}", f.short, f.value)),
                FlagKind::Switch => (f.value != 0).then(|| f.short.to_string()),
                FlagKind::Mask => (f.value != 0).then(|| format!("{}{:b}", f.short, f.value)),
                FlagKind::Hidden | FlagKind::HiddenFloat => None,
            })
            .collect();
        if self.flags.is_empty() {
            self.name.to_string()
        } else {
            format!("{}[{}]", self.name, parts.join(","))
        }
    }

    pub(crate) fn defines(&self) -> Vec<(&'static str, String)> {
        self.flags
            .iter()
            .filter_map(|f| match f.kind {
                FlagKind::Switch => (f.value != 0).then(|| (f.define, "1".to_string())),
                FlagKind::HiddenFloat => Some((f.define, format!("{}.0", f.value))),
                _ => Some((f.define, f.value.to_string())),
            })
            .collect()
    }
}

pub struct ProgramCache {
    gpu: GpuRef,
    programs: HashMap<ProgramKey, Rc<Program>>,
    /// Programs compiled and linked by this cache, and the milliseconds that took (for the
    /// start-up profile of `--stats`).
    compiled: usize,
    compile_ms: f64,
}

/// Shared handle to a context's cache.
pub type SharedPrograms = Rc<RefCell<ProgramCache>>;

type CacheEntry = (*const Gpu, Weak<RefCell<ProgramCache>>);

thread_local! {
    /// GL contexts are current on one thread; each has at most one live cache, found by the
    /// address of its `Gpu`. Entries are weak: the cache goes (and deletes its programs) with
    /// the last renderer that uses it, so dropping every renderer leaves no GL object behind.
    static CACHES: RefCell<Vec<CacheEntry>> = const { RefCell::new(Vec::new()) };
}

impl ProgramCache {
    pub fn new(gpu: &GpuRef) -> Self {
        ProgramCache {
            gpu: gpu.clone(),
            programs: HashMap::new(),
            compiled: 0,
            compile_ms: 0.0,
        }
    }

    /// The context's cache, created on first use: programs compiled for one scene are reused
    /// by the next scene loaded into the same context.
    pub fn for_context(gpu: &GpuRef) -> SharedPrograms {
        let key = Rc::as_ptr(gpu);
        CACHES.with(|c| {
            let mut caches = c.borrow_mut();
            caches.retain(|(_, w)| w.strong_count() > 0);
            if let Some(p) = caches
                .iter()
                .find(|(k, _)| *k == key)
                .and_then(|(_, w)| w.upgrade())
            {
                return p;
            }
            let p = Rc::new(RefCell::new(ProgramCache::new(gpu)));
            caches.push((key, Rc::downgrade(&p)));
            p
        })
    }

    pub fn get(&mut self, key: &ProgramKey) -> Result<Rc<Program>> {
        if let Some(p) = self.programs.get(key) {
            return Ok(p.clone());
        }
        let start = crate::clock::Mark::now();
        let dialect = self.gpu.caps.dialect;
        let mut defines = key.defines();
        // A fact of the context, not of the key: every program on it keeps shadow maps the
        // one way (shadow.glsl, depth.frag, show_depth.frag).
        if self.gpu.caps.packed_shadow() {
            defines.push(("SHADOW_PACKED", "1".into()));
        }
        let p = Rc::new(Program::new(
            &self.gpu,
            &key.label(),
            &assemble(dialect, Stage::Vertex, &defines, key.vertex),
            &assemble(dialect, Stage::Fragment, &defines, key.fragment),
        )?);
        self.programs.insert(key.clone(), p.clone());
        self.compiled += 1;
        self.compile_ms += start.ms();
        Ok(p)
    }

    /// Programs compiled so far and the milliseconds spent compiling and linking them (the
    /// driver may finish linking lazily at first use, which this cannot see).
    pub fn compiled(&self) -> (usize, f64) {
        (self.compiled, self.compile_ms)
    }

    pub fn len(&self) -> usize {
        self.programs.len()
    }

    /// Whether no program is compiled yet (clippy's `len_without_is_empty`: `len` is public).
    pub fn is_empty(&self) -> bool {
        self.programs.is_empty()
    }
}
