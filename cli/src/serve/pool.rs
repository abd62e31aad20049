//! The render threads (`--render-threads`): each holds a headless context and scenes of its
//! own (a [`Session`]; GL contexts are per thread, and nothing uploaded is shared between
//! them, so a model drawn on two threads is loaded and uploaded twice). The scheduler gives
//! a thread one [`Job`] at a time, a viewer's view with its waiting inputs; the thread
//! applies the inputs with its scene, draws, hands the pixels to the encoders and gives the
//! view back ([`Event::Drawn`]). A scene it does not hold is the scheduler's to load
//! ([`Outcome::NeedScene`]), on a worker, then uploaded here ([`Work::Adopt`]).
use super::models::Models;
use super::protocol::{error_json, frame_bytes, ClientMsg, Event, Outgoing, Pickable};
use super::queues::Outbox;
use super::render::{draw, encode, options_for, Kind, Picture};
use glview::keys::{self, Effect};
use glview::options::Options;
use glview::session::{Prepared, Session, View};
use std::sync::mpsc::{channel, Receiver, Sender};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// One frame of one viewer, for a render thread.
pub struct Job {
    pub id: u64,
    pub frame: u64,
    pub kind: Kind,
    pub view: View,
    /// Inputs not yet applied: they need the scene.
    pub pending: Vec<ClientMsg>,
    pub seq: Option<u64>,
    pub presenter: bool,
    pub out: Arc<Outbox>,
    /// Seconds the wall clock moved since the view's time last did (a playing view's
    /// frame; 0 otherwise).
    pub advance: f64,
    /// The header carries the view's state (a page, or a follower, draws it).
    pub state: bool,
}

/// What a render thread is asked to do.
pub enum Work {
    Draw(Box<Job>),
    /// Upload load `load`'s scene, loaded on a worker for pictures of `options`.
    Adopt {
        load: u64,
        options: Box<Options>,
        prepared: Result<Box<Prepared>, String>,
    },
}

/// How a job ended (the view, with what inputs were applied, goes back with it).
pub enum Outcome {
    /// Drawn; its bytes come as [`Event::Encoded`].
    Drawn,
    /// The scene of these options is not uploaded here: the inputs wait in `pending`.
    NeedScene(Box<Options>),
    /// The scene failed to load or the draw failed: the viewer was told.
    Failed { drawn: bool },
}

/// A finished job, to the scheduler.
pub struct Done {
    pub id: u64,
    pub thread: usize,
    pub kind: Kind,
    pub view: Box<View>,
    pub pending: Vec<ClientMsg>,
    pub outcome: Outcome,
    /// The render time the viewer is charged.
    pub cost: Duration,
    /// A key asked for the still now.
    pub screenshot: bool,
}

/// The scheduler's end of the pool.
pub struct Pool {
    senders: Vec<Sender<Work>>,
}

/// What every render thread shares.
pub struct Shared {
    pub models: Arc<Models>,
    pub encoders: Arc<rayon::ThreadPool>,
    pub events: Sender<Event>,
    /// Pictures drawn by every render thread so far (a state has none): in each frame's
    /// header, so a class in local mode can see that the server draws nothing for it.
    pub drawn: std::sync::atomic::AtomicU64,
}

impl Pool {
    /// Starts `n` render threads, each with its context made now (a machine without one
    /// fails here, not at the first viewer); the first loads `first`'s scene before anyone
    /// asks. Also says whether the contexts keep one size (OSMesa).
    pub fn start(
        n: usize,
        first: &Options,
        keep_scenes: usize,
        shared: &Arc<Shared>,
    ) -> glview::Result<(Pool, bool)> {
        let mut senders = Vec::new();
        let mut fixed = false;
        for t in 0..n {
            let (tx, rx) = channel();
            let (ready_tx, ready_rx) = channel();
            let (first, shared) = (first.clone(), shared.clone());
            std::thread::Builder::new()
                .name(format!("glview-render-{t}"))
                .spawn(move || {
                    let mut session = match Session::open(&first) {
                        Ok(s) => s,
                        Err(e) => return drop(ready_tx.send(Err(e))),
                    };
                    session.keep_scenes(keep_scenes);
                    // A broken first model is the viewers' error, not the server's.
                    if t == 0 {
                        if let Err(e) = session.scene(&first) {
                            log::warn!("{}: {e}", shared.models.first().0);
                        }
                    }
                    let _ = ready_tx.send(Ok(session.fixed_size()));
                    let run = std::panic::AssertUnwindSafe(|| serve(t, session, &rx, &shared));
                    if std::panic::catch_unwind(run).is_err() {
                        // As when the one GL thread was the main thread: the server ends,
                        // rather than keep viewers waiting for a thread that is gone.
                        log::error!("render thread {t} failed (a bug: please report it)");
                        std::process::exit(70);
                    }
                })
                .map_err(|e| {
                    glview::Error::Unsupported(format!("cannot start a render thread: {e}"))
                })?;
            let started = ready_rx.recv().map_err(|_| {
                glview::Error::Unsupported("a render thread failed to start".into())
            })?;
            fixed |= started?;
            senders.push(tx);
        }
        Ok((Pool { senders }, fixed))
    }

    pub fn len(&self) -> usize {
        self.senders.len()
    }

    /// Gives thread `t` work (false: it is gone).
    pub fn send(&self, t: usize, work: Work) -> bool {
        self.senders[t].send(work).is_ok()
    }
}

/// A render thread's life: its work, in order, until the scheduler is gone.
fn serve(thread: usize, mut session: Session, rx: &Receiver<Work>, shared: &Shared) {
    while let Ok(work) = rx.recv() {
        match work {
            Work::Draw(job) => {
                let done = run(thread, &mut session, *job, shared);
                if shared.events.send(Event::Drawn(Box::new(done))).is_err() {
                    return;
                }
            }
            Work::Adopt {
                load,
                options,
                prepared,
            } => {
                let adopted =
                    prepared.and_then(|p| session.adopt(&options, *p).map_err(|e| e.to_string()));
                let failed = adopted.err().map(|e| shared.models.scrub(&e));
                let _ = shared.events.send(Event::Adopted {
                    load,
                    thread,
                    options,
                    failed,
                });
            }
        }
    }
}

/// One job: the inputs applied with the scene, the frame drawn and handed to an encoder.
fn run(thread: usize, session: &mut Session, mut job: Job, shared: &Shared) -> Done {
    let t = Instant::now();
    let mut screenshot = false;
    let outcome = 'o: {
        if let Some(o) = missing(session, &job.view, job.kind) {
            break 'o Outcome::NeedScene(o);
        }
        if let Err(e) = apply(session, &mut job, &shared.models, &mut screenshot) {
            job.out.push(Outgoing::Text(error_json(&e, false)));
            break 'o Outcome::Failed { drawn: false };
        }
        // A key may have changed the load options (x-ray, flat): another scene.
        if let Some(o) = missing(session, &job.view, job.kind) {
            break 'o Outcome::NeedScene(o);
        }
        draw_and_encode(thread, session, &job, shared)
    };
    Done {
        id: job.id,
        thread,
        kind: job.kind,
        view: Box::new(job.view),
        pending: job.pending,
        outcome,
        cost: t.elapsed(),
        screenshot,
    }
}

/// The options whose scene a frame of `view` needs, when it is not uploaded here.
fn missing(session: &Session, view: &View, kind: Kind) -> Option<Box<Options>> {
    let o = options_for(view, kind);
    (!session.has_scene(&o)).then(|| Box::new(o))
}

/// Applies the job's waiting inputs with its scene (an input's error is told to the viewer
/// and the others go on); the error returned is the scene's.
fn apply(
    session: &mut Session,
    job: &mut Job,
    models: &Models,
    screenshot: &mut bool,
) -> Result<(), String> {
    if job.pending.is_empty() && job.advance == 0.0 {
        return Ok(());
    }
    let pending = std::mem::take(&mut job.pending);
    let scene = session
        .scene(&options_for(&job.view, job.kind))
        .map_err(|e| models.scrub(&e.to_string()))?;
    let v = &mut job.view;
    // The clock first: a pause or a time set in this batch wins over it.
    if let Err(e) = v.advance(job.advance, scene.animations()) {
        job.out.push(Outgoing::Text(error_json(
            &models.scrub(&e.to_string()),
            false,
        )));
    }
    for m in pending {
        let r = match m {
            ClientMsg::Key { key, .. } => match keys::action_for(&key) {
                Some(a) => v
                    .act(a, scene)
                    .map(|e| *screenshot |= e == Effect::Screenshot),
                None => Err(glview::Error::Usage(format!(
                    "unknown key {:?} (the window's keys: glview --help)",
                    super::http::clip(&key)
                ))),
            },
            ClientMsg::Drag { dx, dy, .. } => v.drag(dx, dy, scene),
            ClientMsg::Wheel { notches, .. } => v.wheel(notches, scene),
            // The pickers' choices go the way K's and V's do: into the view's options.
            ClientMsg::Pick { what, index, .. } => match what {
                Pickable::Camera => v.pick_camera(index, scene),
                Pickable::Variant => v.pick_variant(index, scene),
            },
            ClientMsg::Play { on, .. } => v.set_playing(on, scene.animations()),
            ClientMsg::Time {
                seconds, animation, ..
            } => v.set_moment(animation, seconds, scene.animations()),
            _ => Ok(()),
        };
        if let Err(e) = r {
            let msg = models.scrub(&e.to_string());
            job.out.push(Outgoing::Text(error_json(&msg, false)));
        }
    }
    Ok(())
}

/// Draws the job's frame and gives it to an encoder (its bytes come as `Event::Encoded`).
fn draw_and_encode(thread: usize, session: &mut Session, job: &Job, shared: &Shared) -> Outcome {
    let picture = Picture {
        view: &job.view,
        models: &shared.models,
        kind: job.kind,
        state: job.state,
    };
    let mut drawn = match draw(session, &picture) {
        Ok(d) => d,
        Err(e) => {
            let msg = shared.models.scrub(&e.to_string());
            job.out.push(Outgoing::Text(error_json(&msg, false)));
            return Outcome::Failed { drawn: true };
        }
    };
    drawn.header["frame"] = job.frame.into();
    drawn.header["seq"] = job.seq.into();
    drawn.header["presenter"] = job.presenter.into();
    drawn.header["thread"] = thread.into();
    use std::sync::atomic::Ordering::Relaxed;
    let pictures = if job.kind == Kind::State {
        shared.drawn.load(Relaxed)
    } else {
        shared.drawn.fetch_add(1, Relaxed) + 1
    };
    drawn.header["drawn"] = pictures.into();
    let (events, id, frame) = (shared.events.clone(), job.id, job.frame);
    let still = job.kind == Kind::Still;
    let finish = move || {
        let bytes = encode(drawn)
            .map(|(header, image)| frame_bytes(&header, &image).into())
            .map_err(|e| e.to_string());
        let _ = events.send(Event::Encoded {
            id,
            frame,
            still,
            bytes,
        });
    };
    // A state has nothing to encode: sent from here, without a worker's turn.
    if job.kind == Kind::State {
        finish();
    } else {
        shared.encoders.spawn(finish);
    }
    Outcome::Drawn
}
