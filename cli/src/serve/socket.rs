//! A viewer's WebSocket: a reader that parses the client's messages into its bounded inbox
//! (at a limited rate; a full inbox stops the reading, so TCP pushes back), and a writer that
//! sends what the render thread put in its outbox, each message within a deadline. Whichever
//! ends first ends the viewer.
use super::conn::Shared;
use super::protocol::{error_json, ClientMsg, Event, Outgoing, MAX_MESSAGE};
use super::queues::{Inbox, Outbox, Pushed};
use futures_util::future::{select, Either};
use futures_util::{SinkExt, StreamExt};
use hyper::upgrade::Upgraded;
use hyper_util::rt::TokioIo;
use std::sync::atomic::Ordering;
use std::sync::Arc;
use std::time::{Duration, Instant};
use tokio::time::timeout;
use tokio_tungstenite::WebSocketStream;
use tungstenite::protocol::{frame::coding::CloseCode, CloseFrame, Role, WebSocketConfig};
use tungstenite::Message;

/// A whole message (a frame, however large) must be taken by the client within this: a
/// client that reads a trickle cannot hold the server's memory for longer.
pub const SEND_DEADLINE: Duration = Duration::from_secs(10);
/// Client messages a second, after a burst of [`BURST`]: the page sends at most one drag per
/// animation frame, an ack per frame and a ping per 20 s. Past it the socket is read slower.
pub const RATE: f64 = 240.0;
const BURST: f64 = 480.0;

type Ws = WebSocketStream<TokioIo<Upgraded>>;

/// Client messages over [`MAX_MESSAGE`] are refused; what the server sends is its own.
fn ws_config() -> WebSocketConfig {
    WebSocketConfig::default()
        .max_message_size(Some(MAX_MESSAGE))
        .max_frame_size(Some(MAX_MESSAGE))
}

/// Tokens for messages: a client past [`RATE`] waits (its socket unread meanwhile).
struct Bucket {
    tokens: f64,
    at: Instant,
}

impl Bucket {
    async fn take(&mut self) {
        let now = Instant::now();
        self.tokens = (self.tokens + (now - self.at).as_secs_f64() * RATE).min(BURST);
        self.at = now;
        if self.tokens < 1.0 {
            let wait = (1.0 - self.tokens) / RATE;
            tokio::time::sleep(Duration::from_secs_f64(wait)).await;
            self.tokens = 1.0;
            self.at = Instant::now();
        }
        self.tokens -= 1.0;
    }
}

/// A viewer's life on the upgraded connection.
pub async fn viewer(
    io: TokioIo<Upgraded>,
    shared: Arc<Shared>,
    presenter: bool,
    place: Option<super::conn::Slot>,
) {
    let mut ws = WebSocketStream::from_raw_socket(io, Role::Server, Some(ws_config())).await;
    if place.is_none() {
        // One address (one student's script) may not take every place in the class.
        let msg = format!(
            "this address has {} viewers open already (the server's \
             --max-viewers-per-address): close one first",
            shared.max_viewers_per_address
        );
        refuse(
            &mut ws,
            &msg,
            CloseCode::Policy,
            "too many viewers from this address",
        )
        .await;
        return;
    }
    // The viewer count is taken before the viewer exists, so two at once cannot both pass.
    let count = shared.viewers.fetch_add(1, Ordering::SeqCst) + 1;
    if count > shared.max_viewers {
        shared.viewers.fetch_sub(1, Ordering::SeqCst);
        let msg = format!(
            "the server is full ({} viewers): try again later",
            shared.max_viewers
        );
        refuse(&mut ws, &msg, CloseCode::Again, "server full").await;
        return;
    }
    let id = shared.next_id.fetch_add(1, Ordering::SeqCst);
    let inbox = Arc::new(Inbox::default());
    let outbox = Arc::new(Outbox::default());
    let join = Event::Join {
        id,
        out: outbox.clone(),
        inbox: inbox.clone(),
        presenter,
    };
    if shared.events.send(join).is_ok() {
        let (sink, stream) = ws.split();
        let writer = std::pin::pin!(write_loop(sink, &outbox));
        let reader = std::pin::pin!(read_loop(stream, id, &inbox, &outbox, &shared));
        if let Either::Left(((), writer)) = select(reader, writer).await {
            // What the reader queued last (an error, a close) still goes out.
            outbox.push(Outgoing::Close(1000, String::new()));
            let _ = timeout(SEND_DEADLINE, writer).await;
        }
        outbox.close();
        let _ = shared.events.send(Event::Leave { id });
    }
    shared.viewers.fetch_sub(1, Ordering::SeqCst);
}

/// Tells the client why it has no viewer, and closes.
async fn refuse(ws: &mut Ws, msg: &str, code: CloseCode, reason: &'static str) {
    let _ = timeout(SEND_DEADLINE, async {
        ws.send(Message::text(error_json(msg, true))).await?;
        ws.close(Some(CloseFrame {
            code,
            reason: reason.into(),
        }))
        .await
    })
    .await;
}

/// Reads messages until the client closes, goes silent for the idle timeout, sends
/// something too large, or the connection fails; each good message goes to the inbox (the
/// render thread is woken once per batch), each malformed one is answered with an error.
async fn read_loop(
    mut stream: futures_util::stream::SplitStream<Ws>,
    id: u64,
    inbox: &Inbox,
    out: &Outbox,
    shared: &Shared,
) {
    let mut bucket = Bucket {
        tokens: BURST,
        at: Instant::now(),
    };
    loop {
        let text = match timeout(shared.idle_timeout, stream.next()).await {
            Err(_) => {
                let why = format!(
                    "closed after {} s without a message",
                    shared.idle_timeout.as_secs()
                );
                out.push(Outgoing::Text(error_json(&why, true)));
                out.push(Outgoing::Close(1001, "idle".into()));
                return;
            }
            Ok(None | Some(Ok(Message::Close(_)))) => return,
            Ok(Some(Ok(Message::Text(t)))) => t,
            Ok(Some(Ok(Message::Binary(_)))) => {
                let why = "bad message: the client sends JSON text";
                out.push(Outgoing::Text(error_json(why, false)));
                continue;
            }
            Ok(Some(Ok(_))) => continue,
            Ok(Some(Err(tungstenite::Error::Capacity(e)))) => {
                let why = format!("message refused: {e} (the limit is {MAX_MESSAGE} bytes)");
                out.push(Outgoing::Text(error_json(&why, true)));
                out.push(Outgoing::Close(1009, "message too big".into()));
                return;
            }
            Ok(Some(Err(_))) => return,
        };
        bucket.take().await;
        match ClientMsg::parse(&text) {
            Ok(ClientMsg::Ping) => {}
            Ok(msg) => {
                if !deliver(msg, id, inbox, shared).await {
                    return;
                }
            }
            Err(e) => {
                out.push(Outgoing::Text(error_json(&e, false)));
            }
        }
    }
}

/// Puts `msg` in the inbox, waiting for room (the socket is not read meanwhile); false when
/// the render thread is gone.
async fn deliver(mut msg: ClientMsg, id: u64, inbox: &Inbox, shared: &Shared) -> bool {
    loop {
        match inbox.push(msg) {
            Pushed::Queued { wake } => {
                return !wake || shared.events.send(Event::Wake { id }).is_ok();
            }
            Pushed::Full(m) => {
                msg = *m;
                inbox.room().await;
            }
        }
    }
}

/// Sends what the render thread queues until it says close, the box is closed (over its
/// cap), or the client does not take a message within [`SEND_DEADLINE`].
async fn write_loop(mut sink: futures_util::stream::SplitSink<Ws, Message>, out: &Outbox) {
    while let Some(m) = out.next().await {
        let (msg, last) = match m {
            Outgoing::Frame(bytes) => (Message::Binary(bytes), false),
            Outgoing::Text(t) => (Message::text(t), false),
            Outgoing::Close(code, reason) => {
                let frame = CloseFrame {
                    code: CloseCode::from(code),
                    reason: reason.into(),
                };
                (Message::Close(Some(frame)), true)
            }
        };
        if !matches!(timeout(SEND_DEADLINE, sink.send(msg)).await, Ok(Ok(()))) || last {
            break;
        }
    }
    out.close();
}
