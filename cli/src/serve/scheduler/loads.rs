//! Models loaded off the render threads: a viewer whose scene is not uploaded on its
//! thread waits while a worker thread parses and prepares it ([`Prepared::load`], no GL);
//! the render threads draw everyone else meanwhile and the viewer's spends only the upload
//! on it ([`Session::adopt`](glview::session::Session::adopt)). Viewers of one scene on one
//! thread share its load; at most [`MAX_LOADS`] run at once (each holds a whole model in
//! memory), later ones wait for a free worker.
use super::{Event, Options, Scheduler};
use crate::serve::pool::Work;
use glview::session::{same_scene, Prepared};

/// Loads at once: more would only share the same cores and hold more models in memory.
const MAX_LOADS: usize = 2;

impl Scheduler {
    /// `id`'s frame needs the scene of `o` on render thread `thread`: a load is started
    /// or joined, and the viewer waits for it.
    pub(super) fn load(&mut self, id: u64, thread: usize, o: Options) {
        let v = self.viewers.get_mut(&id).expect("served");
        v.loading = true;
        let joined = self
            .loads
            .values()
            .any(|(l, t)| *t == thread && same_scene(l, &o));
        if joined || self.loads.len() >= MAX_LOADS {
            return;
        }
        let load = self.next_load;
        self.next_load += 1;
        let events = self.events.clone();
        let options = o.clone();
        let worker = std::thread::Builder::new()
            .name("glview-load".into())
            .spawn(move || {
                // A panic must still answer: its viewers would wait for ever, and its
                // slot of MAX_LOADS stay taken.
                let load_it = std::panic::AssertUnwindSafe(|| {
                    let load = || {
                        // Not while a page's scene is recorded (`serve::web::LOADING`).
                        let _shared = crate::serve::web::LOADING
                            .read()
                            .unwrap_or_else(|e| e.into_inner());
                        Box::new(Prepared::load(&options))
                    };
                    match loader_pool() {
                        Some(pool) => pool.install(load),
                        None => load(),
                    }
                });
                let prepared = std::panic::catch_unwind(load_it)
                    .map_err(|_| "the model loader failed (a bug: please report it)".to_string());
                let _ = events.send(Event::Loaded {
                    load,
                    options: Box::new(options),
                    prepared,
                });
            });
        match worker {
            Ok(_) => {
                self.loads.insert(load, (o, thread));
            }
            Err(e) => {
                log::warn!("cannot start a loading thread: {e}");
                v.loading = false;
                v.error("the server cannot load a model now: try again");
                (v.dirty, v.still_owed) = (false, false);
            }
        }
    }

    /// A worker's load done: to its render thread to upload (the load stays counted until
    /// then, so its viewers do not start it again).
    pub(super) fn loaded(
        &mut self,
        load: u64,
        options: Box<Options>,
        prepared: Result<Box<Prepared>, String>,
    ) {
        let Some((_, thread)) = self.loads.get(&load) else {
            return;
        };
        let work = Work::Adopt {
            load,
            options,
            prepared,
        };
        if !self.pool.send(*thread, work) {
            log::error!("render thread {thread} is gone");
        }
    }

    /// A load uploaded on `thread` (or failed): every waiting viewer tries again (those of
    /// this scene draw it; those of a scene still loading wait again; those held back by
    /// [`MAX_LOADS`] start theirs). A failed load is its viewers' error.
    pub(super) fn adopted(
        &mut self,
        load: u64,
        thread: usize,
        options: &Options,
        failed: Option<String>,
    ) {
        self.loads.remove(&load);
        for v in self.viewers.values_mut().filter(|v| v.loading) {
            v.loading = false;
            let o = super::options_for(&v.view, super::Kind::Still);
            let mine = v.thread == thread && same_scene(&o, options);
            if let Some(e) = failed.as_deref().filter(|_| mine) {
                v.error(e);
                v.pending.clear();
                (v.dirty, v.still_owed) = (false, false);
            }
        }
    }
}

/// The pool a load's parallel parts (parse, normals, clusters, levels) run in: half the
/// cores, so the render thread and the encoders keep the others (rayon's global pool would
/// take them all: a viewer's p95 reached 88-120 ms during a load on 2 busy cores).
fn loader_pool() -> Option<rayon::ThreadPool> {
    let cores = std::thread::available_parallelism().map_or(2, |n| n.get());
    rayon::ThreadPoolBuilder::new()
        .num_threads((cores / 2).max(1))
        .thread_name(|i| format!("glview-load-{i}"))
        .build()
        .ok()
}
