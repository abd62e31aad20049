//! The two bounded queues between a viewer's socket and the render thread. Inbound, a
//! client's messages wait in a short queue that merges what the latest value replaces
//! (drags and wheels add up, sizes and acks replace): when it is full the socket is not read,
//! so TCP pushes back on the client and nothing grows here. Outbound, what the render thread
//! sends waits in a queue with a byte cap: a client that does not take its frames is closed,
//! not buffered for.
use super::protocol::{ClientMsg, Outgoing};
use std::collections::VecDeque;
use std::sync::{Mutex, MutexGuard};
use tokio::sync::Notify;

/// Messages waiting for the render thread, per socket (after merging).
pub const INBOX_LEN: usize = 64;
/// Bytes waiting to go out to one client beyond the message being sent: past it the socket
/// is closed. A single message is always taken when nothing waits (a still may be large).
pub const OUTBOX_BYTES: usize = 16 << 20;

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    // A panic elsewhere leaves the data as it was: the queue goes on.
    m.lock().unwrap_or_else(|e| e.into_inner())
}

/// A sum that stays within the protocol's ±100000 (protocol.rs checks each message).
fn add(a: f32, b: f32) -> f32 {
    (a + b).clamp(-1e5, 1e5)
}

#[derive(Default)]
struct InState {
    msgs: VecDeque<ClientMsg>,
    /// The render thread has been told (one wake per drain, whatever arrives meanwhile).
    signaled: bool,
}

#[derive(Default)]
pub struct Inbox {
    state: Mutex<InState>,
    room: Notify,
}

/// What [`Inbox::push`] did.
#[derive(Debug, PartialEq)]
pub enum Pushed {
    /// Queued or merged; `wake`: the render thread must be told (it was not yet).
    Queued { wake: bool },
    /// No room: wait for [`Inbox::room`] and push again.
    Full(Box<ClientMsg>),
}

/// `next` folded into `last` when the latest value is all that counts.
fn merge(last: &mut ClientMsg, next: ClientMsg) -> Option<ClientMsg> {
    use ClientMsg as M;
    match (last, next) {
        (
            M::Drag { dx, dy, seq },
            M::Drag {
                dx: x,
                dy: y,
                seq: s,
            },
        ) => {
            (*dx, *dy) = (add(*dx, x), add(*dy, y));
            *seq = s.or(*seq);
            None
        }
        (M::Wheel { notches, seq }, M::Wheel { notches: n, seq: s }) => {
            *notches = add(*notches, n);
            *seq = s.or(*seq);
            None
        }
        (l @ M::Ack { .. }, n @ M::Ack { .. })
        | (l @ M::Size { .. }, n @ M::Size { .. })
        | (l @ M::Follow { .. }, n @ M::Follow { .. })
        | (l @ M::Still, n @ M::Still) => {
            *l = n;
            None
        }
        (_, n) => Some(n),
    }
}

impl Inbox {
    pub fn push(&self, msg: ClientMsg) -> Pushed {
        let mut s = lock(&self.state);
        let rest = match s.msgs.back_mut() {
            Some(last) => merge(last, msg),
            None => Some(msg),
        };
        if let Some(m) = rest {
            if s.msgs.len() >= INBOX_LEN {
                return Pushed::Full(Box::new(m));
            }
            s.msgs.push_back(m);
        }
        let wake = !s.signaled;
        s.signaled = true;
        Pushed::Queued { wake }
    }

    /// Everything waiting (the render thread's side); the reader may go on.
    pub fn take(&self) -> Vec<ClientMsg> {
        let mut s = lock(&self.state);
        s.signaled = false;
        let out = s.msgs.drain(..).collect();
        drop(s);
        self.room.notify_one();
        out
    }

    /// Resolves when [`Inbox::take`] made room.
    pub async fn room(&self) {
        self.room.notified().await;
    }
}

#[derive(Default)]
struct OutState {
    msgs: VecDeque<Outgoing>,
    bytes: usize,
    /// Over the cap, or the writer stopped: nothing more is queued.
    closed: bool,
}

#[derive(Default)]
pub struct Outbox {
    state: Mutex<OutState>,
    ready: Notify,
}

fn size_of(m: &Outgoing) -> usize {
    match m {
        Outgoing::Frame(b) => b.len(),
        Outgoing::Text(t) => t.len(),
        Outgoing::Close(_, r) => r.len(),
    }
}

impl Outbox {
    /// Queues `m` for the writer; past [`OUTBOX_BYTES`] the socket is closed instead (the
    /// writer finds the box closed and drops the connection). False when closed, or closing now.
    pub fn push(&self, m: Outgoing) -> bool {
        let mut s = lock(&self.state);
        if s.closed {
            return false;
        }
        let n = size_of(&m);
        if !s.msgs.is_empty() && s.bytes + n > OUTBOX_BYTES {
            log::info!(
                "a client took no frames while {} bytes waited: closed",
                s.bytes
            );
            drop(s);
            self.close();
            return false;
        }
        s.bytes += n;
        s.msgs.push_back(m);
        drop(s);
        self.ready.notify_one();
        true
    }

    /// The next message for the writer; None once closed (what waited is dropped).
    pub async fn next(&self) -> Option<Outgoing> {
        loop {
            {
                let mut s = lock(&self.state);
                if s.closed {
                    return None;
                }
                if let Some(m) = s.msgs.pop_front() {
                    s.bytes -= size_of(&m);
                    return Some(m);
                }
            }
            self.ready.notified().await;
        }
    }

    /// Nothing more goes out.
    pub fn close(&self) {
        let mut s = lock(&self.state);
        s.closed = true;
        s.msgs.clear();
        s.bytes = 0;
        drop(s);
        self.ready.notify_one();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn drag(dx: f32, seq: u64) -> ClientMsg {
        ClientMsg::Drag {
            dx,
            dy: 1.0,
            seq: Some(seq),
        }
    }

    #[test]
    fn drags_merge_and_the_queue_is_bounded() {
        let inbox = Inbox::default();
        assert_eq!(inbox.push(drag(1.0, 1)), Pushed::Queued { wake: true });
        assert_eq!(inbox.push(drag(2.5, 2)), Pushed::Queued { wake: false });
        let got = inbox.take();
        assert_eq!(got.len(), 1);
        assert!(matches!(
            got[0],
            ClientMsg::Drag { dx, dy, seq: Some(2) } if dx == 3.5 && dy == 2.0
        ));
        // Keys do not merge: the queue fills, then refuses until taken.
        let key = || ClientMsg::Key {
            key: "Right".into(),
            seq: None,
        };
        for i in 0..INBOX_LEN {
            assert_eq!(inbox.push(key()), Pushed::Queued { wake: i == 0 });
        }
        assert!(matches!(inbox.push(key()), Pushed::Full(_)));
        assert_eq!(inbox.take().len(), INBOX_LEN);
        assert_eq!(inbox.push(key()), Pushed::Queued { wake: true });
    }

    #[test]
    fn the_outbox_closes_past_its_cap() {
        let out = Outbox::default();
        let big = || Outgoing::Frame(vec![0u8; OUTBOX_BYTES / 2 + 1].into());
        // One message is taken whatever its size; the queue past the cap closes.
        assert!(out.push(Outgoing::Frame(vec![0u8; OUTBOX_BYTES + 1].into())));
        let out = Outbox::default();
        assert!(out.push(big()));
        assert!(!out.push(big()));
        assert!(!out.push(Outgoing::Text("x".into())));
    }
}
