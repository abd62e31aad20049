//! A viewer's frame as a render thread's job: its view lent with its waiting inputs
//! ([`Scheduler::dispatch`]), given back when drawn ([`Scheduler::done`]); and which thread
//! draws a viewer ([`Scheduler::place`]).
use super::{Kind, Scheduler};
use crate::serve::pool::{Done, Job, Outcome, Work};
use std::path::Path;
use std::time::Instant;

impl Scheduler {
    /// Gives `id`'s next frame to render thread `thread`: a preview while input arrives, the
    /// still once it stops. Its encode counts from now (it may end before the job's news).
    pub(super) fn dispatch(&mut self, id: u64, thread: usize) {
        let frame = self.next_frame;
        self.next_frame += 1;
        let (drag_scale, drag_quality) = (self.config.drag_scale, self.config.drag_quality);
        let pictures = self.needs_pictures(id, &self.viewers[&id]);
        let state = self.needs_state(id, &self.viewers[&id]);
        let v = self.viewers.get_mut(&id).expect("ready");
        // A playing view moves on by the time since its last frame; its frames are
        // previews, and the still follows once it pauses.
        let mut advance = 0.0;
        if v.view.playing() {
            let now = Instant::now();
            advance = v.played_at.map_or(0.0, |t| (now - t).as_secs_f64());
            v.played_at = Some(now);
            v.changed();
        }
        let kind = if !pictures {
            Kind::State
        } else if v.dirty && !v.fresh {
            Kind::Preview {
                scale: drag_scale,
                quality: drag_quality,
            }
        } else {
            Kind::Still
        };
        let job = Job {
            id,
            frame,
            kind,
            view: v.view.clone(),
            pending: std::mem::take(&mut v.pending),
            seq: v.seq,
            presenter: v.presenter,
            out: v.out.clone(),
            advance,
            state,
        };
        (v.rendering, v.encoding) = (true, true);
        self.turns[thread].busy = true;
        if !self.pool.send(thread, Work::Draw(Box::new(job))) {
            log::error!("render thread {thread} is gone");
        }
    }

    /// A job done: the view back, the viewer charged, a load started when the scene was
    /// not there, and the inputs that came meanwhile taken.
    pub(super) fn done(&mut self, d: Done) {
        self.turns[d.thread].busy = false;
        let thread = d.thread;
        // The job's viewer may have left while it drew: the others' messages that waited
        // for the thread are taken all the same (returning early left them waiting for good).
        if self.viewers.contains_key(&d.id) {
            self.take_back(d);
        }
        self.wake_waiting(thread);
    }

    /// The job's view and outcome back into its viewer (present: checked by the caller).
    fn take_back(&mut self, d: Done) {
        let still_delay = self.config.still_delay;
        let v = self.viewers.get_mut(&d.id).expect("checked by the caller");
        v.rendering = false;
        v.view = *d.view;
        // Inputs that came during the job follow those it did not apply.
        let later = std::mem::replace(&mut v.pending, d.pending);
        v.pending.extend(later);
        if d.screenshot {
            v.last_input = Instant::now() - still_delay;
        }
        let mut need = None;
        match d.outcome {
            Outcome::Drawn => {
                (v.dirty, v.fresh) = (false, false);
                // A state owes no still: the page draws its own.
                if matches!(d.kind, Kind::Still | Kind::State) {
                    v.still_owed = false;
                }
            }
            Outcome::NeedScene(o) => {
                v.encoding = false;
                need = Some(o);
            }
            Outcome::Failed { drawn } => {
                v.encoding = false;
                // The viewer was told once; a playing view would fail at every frame.
                v.view.pause();
                (v.dirty, v.still_owed) = (false, false);
                if drawn {
                    v.fresh = false;
                }
            }
        }
        // Started playing in this job: its time moves on from now.
        if v.view.playing() {
            v.played_at.get_or_insert_with(Instant::now);
        } else {
            v.played_at = None;
        }
        match need {
            Some(o) => self.load(d.id, d.thread, *o),
            None => self.charge_frame(d.id, d.cost),
        }
    }

    /// The messages of `thread`'s viewers that waited for its job.
    fn wake_waiting(&mut self, thread: usize) {
        let woken: Vec<u64> = self
            .viewers
            .iter_mut()
            .filter(|(_, v)| v.thread == thread && v.woken)
            .map(|(id, v)| {
                v.woken = false;
                *id
            })
            .collect();
        for id in woken {
            self.wake(id);
        }
    }

    /// The thread for a viewer of `model` (`me`: the viewer moving, not counted): one that
    /// has viewers of it while it holds no more than its share of all the viewers (they
    /// share its scene), otherwise the one with the fewest viewers (which loads the model:
    /// a class on one model spreads over every thread, each with its own copy).
    pub(super) fn place(&self, model: Option<&Path>, me: Option<u64>) -> usize {
        let n = self.turns.len();
        let mut count = vec![0usize; n];
        let mut same = vec![0usize; n];
        for (id, v) in &self.viewers {
            if Some(*id) == me {
                continue;
            }
            count[v.thread] += 1;
            if v.view.options().load.model.as_deref() == model {
                same[v.thread] += 1;
            }
        }
        let share = (count.iter().sum::<usize>() + 1).div_ceil(n);
        let least =
            |ok: &dyn Fn(usize) -> bool| (0..n).filter(|&t| ok(t)).min_by_key(|&t| count[t]);
        least(&|t| same[t] > 0 && count[t] < share)
            .or_else(|| least(&|_| true))
            .unwrap_or(0)
    }
}
