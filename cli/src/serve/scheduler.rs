//! The scheduler: every viewer's state, and whose view each render thread ([`pool`]) draws
//! next: of a thread's viewers, the one charged least render time. Inputs (taken from each
//! viewer's bounded inbox) only change a view (the latest wins); a view is drawn when it
//! changed, or at most `--fps` times a second while its animation plays (its time moved on
//! by the wall clock on the render thread), and its last frame was acknowledged: small and
//! JPEG while input arrives or it plays, full-size PNG once it stops, encoded on a worker.
//! A presenter's frames go to every follower. Viewers of one model are kept on one thread
//! while it has no more than its share of viewers ([`jobs`]); a model not yet uploaded on a
//! thread is loaded on a worker ([`loads`]) while the others are drawn.
//!
//! [`pool`]: super::pool
mod jobs;
mod loads;

use super::models::Models;
use super::pool::Pool;
use super::protocol::{error_json, state_only, ClientMsg, Event, Outgoing, ServerMsg, PROTOCOL};
use super::queues::{Inbox, Outbox};
use super::render::{options_for, Kind};
use glview::keys;
use glview::options::Options;
use glview::session::View;
use serde_json::json;
use std::collections::BTreeMap;
use std::sync::mpsc::{Receiver, RecvTimeoutError, Sender};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Inputs waiting for their scene (the first frame of a model) are bounded.
const MAX_PENDING: usize = 256;
/// A frame costing more than this holds its viewer back for twice the excess while others
/// are active, so an expensive view takes at most about a third of the render thread's time
/// (half left the cheap viewers too little margin: a frame cannot be cut short, and the one
/// in progress delays theirs).
const CHEAP: Duration = Duration::from_millis(40);
/// A viewer served this recently counts as active.
const ACTIVE: Duration = Duration::from_secs(1);

pub struct Config {
    pub still_delay: Duration,
    pub drag_scale: f32,
    pub drag_quality: u8,
    /// The context cannot change size (OSMesa): size messages are refused.
    pub fixed_size: bool,
    /// `--size`: the largest view a viewer may ask for.
    pub max_size: (u32, u32),
    /// Pages that can draw may do so (the browser build is served: local mode).
    pub local: bool,
}

struct Viewer {
    out: Arc<Outbox>,
    inbox: Arc<Inbox>,
    view: View,
    presenter: bool,
    following: bool,
    /// Its page draws the view itself (local mode): it is sent the view's state, and a
    /// picture is drawn for it only when a streaming follower needs one.
    local: bool,
    /// Inputs not yet applied (they need the scene: applied just before a frame).
    pending: Vec<ClientMsg>,
    /// The latest input's sequence number, echoed in the frame that shows it.
    seq: Option<u64>,
    /// The picture changed since the last frame.
    dirty: bool,
    /// A lossless still is owed (input stopped, or asked for).
    still_owed: bool,
    /// No frame sent yet: the first one is a still.
    fresh: bool,
    last_input: Instant,
    /// The frame sent and not yet acknowledged.
    in_flight: Option<u64>,
    /// A follower's newest frame, sent when the one in flight is acknowledged.
    owed: Option<(u64, tungstenite::Bytes)>,
    /// The newest frame sent (a new follower starts with it), and whether it is a still.
    last_frame: Option<(u64, tungstenite::Bytes)>,
    last_was_still: bool,
    /// Render time charged to this viewer (virtual time: the least charged is served first).
    used: Duration,
    /// An expensive frame's viewer waits until then while others are active.
    not_before: Instant,
    /// When its last frame was drawn.
    served_at: Option<Instant>,
    /// Its frame is being encoded on a worker: the next one waits.
    encoding: bool,
    /// Its scene is being loaded on a worker (or waits for a worker): it waits.
    loading: bool,
    /// The render thread that draws it.
    thread: usize,
    /// A render thread has its view (the one here is stale): its inbox waits until the
    /// view comes back.
    rendering: bool,
    /// Its inbox had messages while its render thread drew.
    woken: bool,
    /// While its view plays: when its time last moved on (None: at its next frame).
    played_at: Option<Instant>,
}

impl Viewer {
    /// Sends a frame (its state only, to a page that draws), or owes it until the one in
    /// flight is acknowledged.
    fn send_frame(&mut self, id: u64, frame: &tungstenite::Bytes) {
        let frame = &if self.local {
            state_only(frame)
        } else {
            frame.clone()
        };
        if self.in_flight.is_none() {
            self.in_flight = Some(id);
            self.out.push(Outgoing::Frame(frame.clone()));
        } else {
            self.owed = Some((id, frame.clone()));
        }
    }

    fn error(&self, message: &str) {
        self.out.push(Outgoing::Text(error_json(message, false)));
    }

    /// A follower's own input leaves the class (a presenter coming later is not followed),
    /// from the class's view when there is one.
    fn leave_class(&mut self, presenter_view: Option<&View>) {
        if self.following {
            self.following = false;
            if let Some(pv) = presenter_view {
                self.view = pv.clone();
            }
        }
    }

    fn changed(&mut self) {
        self.dirty = true;
        self.still_owed = true;
        self.last_input = Instant::now();
    }
}

/// A render thread's turns.
#[derive(Default)]
struct Turns {
    /// It draws a job now.
    busy: bool,
    /// The viewer it served last: the next turn starts after it.
    last_served: u64,
    /// The charge of the viewer served last: no viewer's counts for less (an idle viewer
    /// does not bank time to spend in a burst).
    vclock: Duration,
}

pub struct Scheduler {
    pool: Pool,
    base: Options,
    models: Arc<Models>,
    config: Config,
    viewers: BTreeMap<u64, Viewer>,
    /// Per render thread.
    turns: Vec<Turns>,
    next_frame: u64,
    presenter: Option<u64>,
    presenter_online: Arc<std::sync::atomic::AtomicBool>,
    /// The loaders' way back (`Event::Loaded`).
    events: Sender<Event>,
    /// The scenes being loaded on workers, by load number, and the thread each is for.
    loads: BTreeMap<u64, (Options, usize)>,
    next_load: u64,
}

impl Scheduler {
    pub fn new(
        pool: Pool,
        base: Options,
        models: Arc<Models>,
        config: Config,
        presenter_online: Arc<std::sync::atomic::AtomicBool>,
        events: Sender<Event>,
    ) -> Scheduler {
        Scheduler {
            turns: (0..pool.len()).map(|_| Turns::default()).collect(),
            pool,
            base,
            models,
            config,
            viewers: BTreeMap::new(),
            next_frame: 1,
            presenter: None,
            presenter_online,
            events,
            loads: BTreeMap::new(),
            next_load: 1,
        }
    }

    /// Serves for the life of the process.
    pub fn run(&mut self, events: &Receiver<Event>) {
        loop {
            let now = Instant::now();
            let wait = if self.idle_threads().any(|t| self.ready(now, t).is_some()) {
                Duration::ZERO
            } else {
                self.next_deadline(now)
            };
            match events.recv_timeout(wait) {
                Ok(e) => self.event(e),
                Err(RecvTimeoutError::Timeout) => {}
                Err(RecvTimeoutError::Disconnected) => return,
            }
            // Everything that arrived is applied before drawing: only the latest view is drawn.
            while let Ok(e) = events.try_recv() {
                self.event(e);
            }
            let idle: Vec<usize> = self.idle_threads().collect();
            for t in idle {
                if let Some(id) = self.ready(Instant::now(), t) {
                    self.turns[t].last_served = id;
                    self.dispatch(id, t);
                }
            }
        }
    }

    /// The render threads without a job.
    fn idle_threads(&self) -> impl Iterator<Item = usize> + '_ {
        (0..self.turns.len()).filter(|&t| !self.turns[t].busy)
    }

    /// Whether `id` draws its own view (not a follower of an online presenter).
    fn draws_own(&self, id: u64) -> bool {
        let v = &self.viewers[&id];
        !(v.following && self.presenter.is_some_and(|p| p != id))
    }

    /// Whether `id`'s frames need a picture: it streams, or it presents to a follower that
    /// streams (a page that draws itself gets the view's state: nothing is drawn for it).
    /// Whether `id`'s frames carry the view's state (`state` in the header, ~3 KB): for a page
    /// that draws itself, and for a presenter's frames while a follower draws itself. A page
    /// on the stream has no use for it.
    fn needs_state(&self, id: u64, v: &Viewer) -> bool {
        v.local
            || (self.presenter == Some(id) && self.viewers.values().any(|f| f.following && f.local))
    }

    /// Whether the presenter's frames carry the state now (see [`Self::needs_state`]).
    fn class_has_state(&self) -> bool {
        self.presenter
            .is_some_and(|p| self.needs_state(p, &self.viewers[&p]))
    }

    /// A follower that draws itself joined a class whose frames had no state: the
    /// presenter draws one now, for it (the last frame it was sent has none to take).
    fn state_for_class(&mut self, had_state: bool) {
        if had_state || !self.class_has_state() {
            return;
        }
        if let Some(pv) = self.presenter.and_then(|p| self.viewers.get_mut(&p)) {
            pv.changed();
        }
    }

    fn needs_pictures(&self, id: u64, v: &Viewer) -> bool {
        !v.local
            || (self.presenter == Some(id)
                && self.viewers.values().any(|f| f.following && !f.local))
    }

    /// When `v` wants a frame next (None: it waits for an ack, input, or its presenter).
    /// A page that draws itself is sent a state when its view changed, never a playing
    /// view's frames or a still: it plays and draws on its own.
    fn due_at(&self, id: u64, v: &Viewer) -> Option<Instant> {
        if v.in_flight.is_some() || v.encoding || v.loading || v.rendering || !self.draws_own(id) {
            return None;
        }
        let pictures = self.needs_pictures(id, v);
        let at = if v.dirty {
            v.not_before
        } else if !pictures {
            return None;
        } else if v.view.playing() {
            // A playing view's next frame, at most `--fps` a second (and after the last
            // one is acknowledged: the page's pace bounds it too).
            let fps = f64::from(v.view.options().motion.fps.max(1.0));
            let next = v.played_at.map(|t| t + Duration::from_secs_f64(1.0 / fps));
            v.not_before.max(next.unwrap_or(v.not_before))
        } else if v.still_owed {
            v.not_before.max(v.last_input + self.config.still_delay)
        } else {
            return None;
        };
        Some(at)
    }

    /// A viewer's charge as the turns count it.
    fn charge(&self, v: &Viewer) -> Duration {
        v.used.max(self.turns[v.thread].vclock)
    }

    /// The next viewer render thread `thread` draws: of its viewers due, the least charged
    /// with render time; among equals, in turn after the last one served.
    fn ready(&self, now: Instant, thread: usize) -> Option<u64> {
        let last = self.turns[thread].last_served;
        let after = self.viewers.range(last + 1..);
        let before = self.viewers.range(..=last);
        after
            .chain(before)
            .filter(|(_, v)| v.thread == thread)
            .filter(|(id, v)| self.due_at(**id, v).is_some_and(|t| t <= now))
            .min_by_key(|(_, v)| self.charge(v))
            .map(|(id, _)| *id)
    }

    /// How long nothing is due: until the nearest owed still or held-back frame of an idle
    /// thread's viewer (or a while: a busy thread's job ends with an event).
    fn next_deadline(&self, now: Instant) -> Duration {
        self.viewers
            .iter()
            .filter(|(_, v)| !self.turns[v.thread].busy)
            .filter_map(|(id, v)| self.due_at(*id, v))
            .map(|t| t.saturating_duration_since(now))
            .min()
            .unwrap_or(Duration::from_secs(3600))
    }

    /// Charges `id` with a frame that took `cost`: an expensive one holds it back while
    /// another viewer of its thread is active.
    fn charge_frame(&mut self, id: u64, cost: Duration) {
        let now = Instant::now();
        let thread = self.viewers[&id].thread;
        let others = self.viewers.iter().any(|(other, v)| {
            *other != id
                && v.thread == thread
                && (v.served_at.is_some_and(|t| now - t < ACTIVE)
                    || self.due_at(*other, v).is_some())
        });
        let start = self.charge(&self.viewers[&id]);
        self.turns[thread].vclock = start;
        let v = self.viewers.get_mut(&id).expect("served");
        v.used = start + cost;
        v.served_at = Some(now);
        if others && cost > CHEAP {
            v.not_before = now + 2 * (cost - CHEAP);
        }
    }

    fn event(&mut self, e: Event) {
        match e {
            Event::Join {
                id,
                out,
                inbox,
                presenter,
            } => self.join(id, out, inbox, presenter),
            Event::Leave { id } => self.leave(id),
            Event::Encoded {
                id,
                frame,
                still,
                bytes,
            } => self.encoded(id, frame, still, bytes),
            Event::Loaded {
                load,
                options,
                prepared,
            } => self.loaded(load, options, prepared),
            Event::Adopted {
                load,
                thread,
                options,
                failed,
            } => self.adopted(load, thread, &options, failed),
            Event::Drawn(done) => self.done(*done),
            Event::Wake { id } => self.wake(id),
        }
    }

    /// Takes `id`'s inbox, unless its render thread draws (then when the job ends): as when
    /// one thread both drew and read the inboxes between frames, a viewer's messages are
    /// taken in one batch a frame (its inbox wakes the scheduler once a batch), not one by
    /// one (30 viewers dragging at 60 inputs/s would wake it 1,800 times a second).
    fn wake(&mut self, id: u64) {
        let busy = |v: &Viewer, turns: &[Turns]| v.rendering || turns[v.thread].busy;
        let msgs = match self.viewers.get_mut(&id) {
            Some(v) if busy(v, &self.turns) => return v.woken = true,
            Some(v) => v.inbox.take(),
            None => return,
        };
        for msg in msgs {
            self.input(id, msg);
        }
    }

    fn join(&mut self, id: u64, out: Arc<Outbox>, inbox: Arc<Inbox>, want_presenter: bool) {
        let mut options = self.base.clone();
        options.load.model = self.models.first().1.map(Into::into);
        // The presenter's key is proof enough: a presenter coming back (a reload, a new
        // network) takes the role over from its old socket, which may not be closed yet.
        let presenter = want_presenter;
        if let Some(old) = self.presenter.filter(|_| presenter) {
            if let Some(o) = self.viewers.get_mut(&old) {
                o.presenter = false;
                o.error("the presenter's key opened another page: this one is an ordinary viewer");
            }
        }
        let hello = ServerMsg::Hello {
            protocol: PROTOCOL,
            local: self.config.local,
            models: self.models.names(),
            model: self.models.first().0,
            size: [options.picture.size.0, options.picture.size.1],
            presenter,
            presenter_online: self.presenter.is_some() || presenter,
            max_size: [self.config.max_size.0, self.config.max_size.1],
            resizable: !self.config.fixed_size,
            keys: keys::remote_table(),
        };
        out.push(Outgoing::Text(hello.text()));
        let thread = self.place(options.load.model.as_deref(), None);
        let v = Viewer {
            out,
            inbox,
            view: View::new(options),
            presenter,
            following: false,
            local: false,
            pending: Vec::new(),
            seq: None,
            dirty: true,
            still_owed: true,
            fresh: true,
            last_input: Instant::now(),
            in_flight: None,
            owed: None,
            last_frame: None,
            last_was_still: false,
            used: self.turns[thread].vclock,
            not_before: Instant::now(),
            served_at: None,
            encoding: false,
            loading: false,
            thread,
            rendering: false,
            woken: false,
            played_at: None,
        };
        self.viewers.insert(id, v);
        if presenter {
            self.presenter = Some(id);
            self.set_presenter_online(true);
        }
        log::info!(
            "viewer {id} joined ({} now), render thread {thread}",
            self.viewers.len()
        );
    }

    fn leave(&mut self, id: u64) {
        let Some(v) = self.viewers.remove(&id) else {
            return;
        };
        if self.presenter == Some(id) {
            self.presenter = None;
            // Followers go on from where the class was.
            let mut followers = Vec::new();
            for (fid, f) in self.viewers.iter_mut().filter(|(_, f)| f.following) {
                f.view = v.view.clone();
                f.changed();
                followers.push(*fid);
            }
            for fid in followers {
                self.place_again(fid);
            }
            self.set_presenter_online(false);
        }
        log::info!("viewer {id} left ({} now)", self.viewers.len());
    }

    fn set_presenter_online(&self, online: bool) {
        self.presenter_online
            .store(online, std::sync::atomic::Ordering::Relaxed);
        let note = ServerMsg::Presenter { online }.text();
        for v in self.viewers.values() {
            v.out.push(Outgoing::Text(note.clone()));
        }
    }

    /// A message of `id`'s; a view now of another model (picked, or the class's taken on
    /// leaving it) moves to the thread that has that model, or the least loaded one.
    fn input(&mut self, id: u64, msg: ClientMsg) {
        let before = self.viewers[&id].view.options().load.model.clone();
        self.apply_input(id, msg);
        if self
            .viewers
            .get(&id)
            .is_some_and(|v| v.view.options().load.model != before)
        {
            self.place_again(id);
        }
    }

    /// `id` to the thread [`Scheduler::place`] picks for its model now.
    fn place_again(&mut self, id: u64) {
        let model = self.viewers[&id].view.options().load.model.clone();
        let thread = self.place(model.as_deref(), Some(id));
        self.viewers.get_mut(&id).expect("present").thread = thread;
    }

    fn apply_input(&mut self, id: u64, msg: ClientMsg) {
        let presenter_view = self
            .presenter
            .filter(|&p| p != id)
            .map(|p| self.viewers[&p].view.clone());
        let v = self.viewers.get_mut(&id).expect("checked by the caller");
        if let Some(seq) = msg.seq() {
            v.seq = Some(seq);
        }
        match msg {
            ClientMsg::Ack { frame } => {
                if v.in_flight == Some(frame) {
                    v.in_flight = None;
                    if let Some((fid, f)) = v.owed.take() {
                        v.send_frame(fid, &f);
                    }
                }
            }
            ClientMsg::Local { on } => self.set_local(id, on),
            ClientMsg::Follow { on } => self.set_following(id, on, presenter_view),
            ClientMsg::Still => {
                let p = self.presenter.filter(|&p| p != id && v.following);
                // A follower's still is the presenter's: the last one, or one drawn now.
                let target = p.unwrap_or(id);
                let last = self.viewers[&target].last_frame.clone();
                let v = self.viewers.get_mut(&target).expect("present");
                match (p, last) {
                    (Some(_), Some((fid, f))) if v.last_was_still => {
                        self.viewers
                            .get_mut(&id)
                            .expect("present")
                            .send_frame(fid, &f);
                    }
                    _ => {
                        v.still_owed = true;
                        v.last_input = Instant::now() - self.config.still_delay;
                    }
                }
            }
            ClientMsg::Size { .. } if self.config.fixed_size => {
                v.error("this server's context (OSMesa) keeps one size: the view stays as it is")
            }
            ClientMsg::Size { width, height }
                if width > self.config.max_size.0 || height > self.config.max_size.1 =>
            {
                let (w, h) = self.config.max_size;
                v.error(&format!(
                    "the largest view here is {w}x{h} (the server's --size): asked {width}x{height}"
                ))
            }
            ClientMsg::Size { width, height } => {
                v.view.resize((width, height));
                v.changed();
            }
            ClientMsg::Stereo { mode, .. } => {
                v.leave_class(presenter_view.as_ref());
                // Checked by ClientMsg::parse.
                if let Ok(mode) = mode.parse() {
                    v.view.set_stereo(mode);
                    v.changed();
                }
            }
            ClientMsg::Camera {
                yaw,
                pitch,
                distance,
                target,
                fov,
                ..
            } => {
                v.leave_class(presenter_view.as_ref());
                let cam = json!({"yaw": yaw, "pitch": pitch, "distance": distance,
                    "target": target, "fov": fov.unwrap_or(self.base.camera.fov)});
                match set_camera(&v.view, cam) {
                    Some(view) => {
                        v.view = view;
                        v.changed();
                    }
                    None => v.error("the camera cannot be set on this view"),
                }
            }
            ClientMsg::Model { name, .. } => match self.models.open(&name) {
                Ok(path) => {
                    v.leave_class(presenter_view.as_ref());
                    v.pending.clear();
                    v.view.set_model(path);
                    v.changed();
                }
                Err(e) => v.error(&e),
            },
            m @ (ClientMsg::Key { .. }
            | ClientMsg::Drag { .. }
            | ClientMsg::Wheel { .. }
            | ClientMsg::Pick { .. }
            | ClientMsg::Play { .. }
            | ClientMsg::Time { .. }) => {
                v.leave_class(presenter_view.as_ref());
                if v.pending.len() >= MAX_PENDING {
                    v.error("too many inputs waiting for the model to load: dropped");
                    return;
                }
                v.pending.push(m);
                v.changed();
            }
            ClientMsg::Ping => {}
        }
    }

    /// The presenter `p`'s newest frame to follower `id` (as its page takes frames).
    fn send_last_frame(&mut self, p: u64, id: u64) {
        if let Some((fid, f)) = self.viewers[&p].last_frame.clone() {
            self.viewers
                .get_mut(&id)
                .expect("present")
                .send_frame(fid, &f);
        }
    }

    /// `id` follows the presenter (`on`) or leaves the class, orbiting on from its view
    /// (`presenter_view`: the online presenter's, when it is not `id`).
    fn set_following(&mut self, id: u64, on: bool, presenter_view: Option<View>) {
        let had_state = self.class_has_state();
        let v = self.viewers.get_mut(&id).expect("checked by the caller");
        v.following = on && !v.presenter;
        match (presenter_view, v.following) {
            (Some(pv), false) => {
                v.view = pv;
                v.changed();
            }
            (Some(_), true) => {
                let streams = !v.local;
                let p = self.presenter.expect("online");
                self.send_last_frame(p, id);
                // A presenter drawing itself drew no picture: one now, for this page.
                let pv = self.viewers.get_mut(&p).expect("present");
                if streams && pv.local {
                    pv.changed();
                }
                self.state_for_class(had_state);
            }
            (None, _) => {}
        }
    }

    /// `id`'s page draws the view itself (`on`: local mode) or takes the stream again.
    fn set_local(&mut self, id: u64, on: bool) {
        let had_state = self.class_has_state();
        let v = self.viewers.get_mut(&id).expect("checked by the caller");
        if on && !self.config.local {
            return v
                .error("this server has no browser build (--web-dir): the page keeps the stream");
        }
        v.local = on;
        // The state (or, back to the stream, a picture) now.
        v.changed();
        let following = v.following;
        let Some(p) = self.presenter.filter(|&p| p != id && following) else {
            return;
        };
        if on {
            // A follower drawing now: the class's view at once (its state), or, where the
            // class's frames had none, the presenter's next frame.
            self.send_last_frame(p, id);
            self.state_for_class(had_state);
        } else {
            // A follower back on the stream: the presenter's next frame is a picture.
            self.viewers.get_mut(&p).expect("present").changed();
        }
    }

    /// A frame encoded: sent to its viewer, and to the followers when it is the presenter.
    fn encoded(
        &mut self,
        id: u64,
        frame: u64,
        still: bool,
        bytes: Result<tungstenite::Bytes, String>,
    ) {
        let Some(v) = self.viewers.get_mut(&id) else {
            return;
        };
        v.encoding = false;
        let bytes = match bytes {
            Ok(b) => b,
            Err(e) => return v.error(&e),
        };
        v.send_frame(frame, &bytes);
        v.last_frame = Some((frame, bytes.clone()));
        v.last_was_still = still;
        if self.presenter == Some(id) {
            for f in self.viewers.values_mut().filter(|f| f.following) {
                f.send_frame(frame, &bytes);
            }
        }
    }
}

/// `view` with its camera's angles, distance, target and field of view set (the rest of
/// the view, its state and its home, as they were). Through the view's JSON form, which is
/// its options': no second way into them.
fn set_camera(view: &View, cam: serde_json::Value) -> Option<View> {
    let mut v = serde_json::to_value(view).ok()?;
    let c = v.get_mut("options")?.get_mut("camera")?.as_object_mut()?;
    for (k, val) in cam.as_object()? {
        if !c.contains_key(k) {
            return None;
        }
        c.insert(k.clone(), val.clone());
    }
    serde_json::from_value(v).ok()
}
