//! What crosses the socket (docs/serve.md, "Protocol") and what the connections tell the
//! render thread.
use super::queues::{Inbox, Outbox};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// The protocol's version, in the hello: 2 added local mode (`local`, state frames).
pub const PROTOCOL: u32 = 2;

/// Client messages are small JSON objects: anything larger is refused.
pub const MAX_MESSAGE: usize = 4096;
/// The largest view a client may ask for, per axis.
pub const MAX_SIZE: u32 = 4096;

#[derive(Debug, PartialEq, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum ClientMsg {
    Key {
        key: String,
        seq: Option<u64>,
    },
    Drag {
        dx: f32,
        dy: f32,
        seq: Option<u64>,
    },
    Wheel {
        notches: f32,
        seq: Option<u64>,
    },
    Ack {
        frame: u64,
    },
    Model {
        name: String,
        seq: Option<u64>,
    },
    Size {
        width: u32,
        height: u32,
    },
    /// The camera absolutely (a shared link's view): `glview --yaw --pitch [--distance]
    /// [--target] [--fov]`; what is not given fits or takes the default.
    Camera {
        yaw: f32,
        pitch: f32,
        distance: Option<f32>,
        target: Option<[f64; 3]>,
        fov: Option<f32>,
        seq: Option<u64>,
    },
    /// The page's camera or variant picker: look through the file's camera `index` or draw
    /// its variant `index` (none: the orbit camera, the file's own materials), as K and V do.
    Pick {
        what: Pickable,
        index: Option<usize>,
        seq: Option<u64>,
    },
    /// Play (from the time shown; 0 from the static pose) or pause the view's glTF animation,
    /// as Space does.
    Play {
        on: bool,
        seq: Option<u64>,
    },
    /// Show animation `animation` (none: the one shown) at `seconds` (wrapped into its
    /// duration), playing or not as before: the page's time slider and animation picker.
    Time {
        seconds: f32,
        animation: Option<usize>,
        seq: Option<u64>,
    },
    /// The page's stereo picker: `--stereo`'s modes but quad-buffer (a window's).
    Stereo {
        mode: String,
        seq: Option<u64>,
    },
    Still,
    Follow {
        on: bool,
    },
    /// The page draws the view itself (local mode): from now on its frames carry the view's
    /// state and no picture; `false` asks for the stream again.
    Local {
        on: bool,
    },
    Ping,
}

/// What the page's pickers choose among: the file's cameras or its material variants.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Pickable {
    Camera,
    Variant,
}

impl ClientMsg {
    /// Parses and checks a message; the error is the line the client is sent.
    pub fn parse(text: &str) -> Result<ClientMsg, String> {
        // serde's message may quote the client's text: clipped, never echoed whole.
        let m: ClientMsg = serde_json::from_str(text)
            .map_err(|e| format!("bad message: {}", super::http::clip(&e.to_string())))?;
        let finite = |v: f32, what: &str| {
            if v.is_finite() && v.abs() <= 1e5 {
                Ok(())
            } else {
                Err(format!(
                    "bad message: {what} must be a number within ±100000"
                ))
            }
        };
        match &m {
            ClientMsg::Drag { dx, dy, .. } => {
                finite(*dx, "dx")?;
                finite(*dy, "dy")?;
            }
            ClientMsg::Wheel { notches, .. } => finite(*notches, "notches")?,
            ClientMsg::Time { seconds, .. } if !(*seconds >= 0.0 && *seconds <= 1e5) => {
                return Err("bad message: seconds must be a number from 0 to 100000".into())
            }
            ClientMsg::Camera {
                yaw,
                pitch,
                distance,
                target,
                fov,
                ..
            } => {
                finite(*yaw, "yaw")?;
                finite(*pitch, "pitch")?;
                if distance.is_some_and(|d| !(d > 0.0 && d <= 1e5)) {
                    return Err("bad message: distance must be in (0, 100000]".into());
                }
                if target.is_some_and(|t| t.iter().any(|v| !(v.is_finite() && v.abs() <= 1e9))) {
                    return Err("bad message: target must be 3 numbers within ±1e9".into());
                }
                if fov.is_some_and(|f| !(f > 0.0 && f < 180.0)) {
                    return Err("bad message: fov must be between 0 and 180".into());
                }
            }
            ClientMsg::Stereo { mode, .. } => {
                let m: glview::stereo::StereoMode = mode.parse().map_err(|e: String| {
                    format!("bad message: stereo: {}", super::http::clip(&e))
                })?;
                if m == glview::stereo::StereoMode::QuadBuffer {
                    return Err(
                        "bad message: stereo: quad-buffer is a window's, not a page's".into(),
                    );
                }
            }
            ClientMsg::Size { width, height }
                if !(16..=MAX_SIZE).contains(width) || !(16..=MAX_SIZE).contains(height) =>
            {
                return Err(format!(
                    "bad message: the size must be 16 to {MAX_SIZE} pixels a side"
                ))
            }
            _ => {}
        }
        Ok(m)
    }

    /// The input's sequence number, echoed in the frame that shows it.
    pub fn seq(&self) -> Option<u64> {
        match self {
            ClientMsg::Key { seq, .. }
            | ClientMsg::Drag { seq, .. }
            | ClientMsg::Wheel { seq, .. }
            | ClientMsg::Camera { seq, .. }
            | ClientMsg::Pick { seq, .. }
            | ClientMsg::Play { seq, .. }
            | ClientMsg::Time { seq, .. }
            | ClientMsg::Stereo { seq, .. }
            | ClientMsg::Model { seq, .. } => *seq,
            _ => None,
        }
    }
}

/// To a connection's writer.
pub enum Outgoing {
    /// A frame (shared by every follower of a presenter: one encode; `Bytes` clones share
    /// the buffer, and tungstenite sends it as it is).
    Frame(tungstenite::Bytes),
    Text(String),
    /// Close with this code and reason, then stop.
    Close(u16, String),
}

/// To the scheduler, from the connections, the render threads and the encoders: a bounded
/// stream (one `Wake` per viewer until the scheduler takes its inbox; a join and a leave
/// per viewer; one `Drawn` and one `Encoded` per viewer at a time).
pub enum Event {
    Join {
        id: u64,
        out: Arc<Outbox>,
        inbox: Arc<Inbox>,
        presenter: bool,
    },
    /// The viewer's inbox has messages.
    Wake {
        id: u64,
    },
    Leave {
        id: u64,
    },
    /// From an encoding worker: a frame's bytes (or the encoder's error).
    Encoded {
        id: u64,
        frame: u64,
        still: bool,
        bytes: Result<tungstenite::Bytes, String>,
    },
    /// From a loading worker: load `load`'s scene, for pictures of `options`, ready to upload
    /// (or the loader's panic).
    Loaded {
        load: u64,
        options: Box<glview::Options>,
        prepared: Result<Box<glview::session::Prepared>, String>,
    },
    /// From a render thread: a viewer's job done, its view given back.
    Drawn(Box<super::pool::Done>),
    /// From render thread `thread`: load `load`'s scene uploaded (or why not, scrubbed).
    Adopted {
        load: u64,
        thread: usize,
        options: Box<glview::Options>,
        failed: Option<String>,
    },
}

/// The server's text messages (docs/serve.md, "Protocol"); its frames are binary
/// ([`frame_bytes`]).
#[derive(Debug, Serialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum ServerMsg<'a> {
    /// First, on every socket.
    Hello {
        /// [`PROTOCOL`].
        protocol: u32,
        /// The browser build is here: a page that can draw may (local mode).
        local: bool,
        models: Vec<String>,
        model: &'a str,
        size: [u32; 2],
        presenter: bool,
        presenter_online: bool,
        max_size: [u32; 2],
        resizable: bool,
        /// The window's key table less quit, help and screenshot.
        keys: serde_json::Value,
    },
    /// The socket stays open unless `closing`.
    Error { message: &'a str, closing: bool },
    /// The presenter came or went.
    Presenter { online: bool },
}

impl ServerMsg<'_> {
    pub fn text(&self) -> String {
        // Strings, numbers and a JSON value: serialising cannot fail.
        serde_json::to_string(self).unwrap_or_default()
    }
}

/// An `error` message's text.
pub fn error_json(message: &str, closing: bool) -> String {
    ServerMsg::Error { message, closing }.text()
}

/// A frame without its image: what a page that draws the view itself is sent (the
/// header's `state`; a frame that has no image is itself).
pub fn state_only(frame: &tungstenite::Bytes) -> tungstenite::Bytes {
    let n = frame
        .get(..4)
        .map_or(0, |b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize);
    frame.slice(..(4 + n).min(frame.len()))
}

/// A binary frame: a little-endian u32 header length, the JSON header, the image.
pub fn frame_bytes(header: &serde_json::Value, image: &[u8]) -> Vec<u8> {
    let h = header.to_string();
    let mut out = Vec::with_capacity(4 + h.len() + image.len());
    out.extend_from_slice(&(h.len() as u32).to_le_bytes());
    out.extend_from_slice(h.as_bytes());
    out.extend_from_slice(image);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_are_checked() {
        assert!(matches!(
            ClientMsg::parse(r#"{"type":"key","key":"Right","seq":3}"#),
            Ok(ClientMsg::Key { seq: Some(3), .. })
        ));
        assert!(matches!(
            ClientMsg::parse(r#"{"type":"time","seconds":0.5,"animation":1,"seq":5}"#),
            Ok(ClientMsg::Time {
                animation: Some(1),
                seq: Some(5),
                ..
            })
        ));
        assert_eq!(
            ClientMsg::parse(r#"{"type":"local","on":true}"#),
            Ok(ClientMsg::Local { on: true })
        );
        assert!(matches!(
            ClientMsg::parse(r#"{"type":"pick","what":"variant","index":null,"seq":4}"#),
            Ok(ClientMsg::Pick {
                what: Pickable::Variant,
                index: None,
                seq: Some(4)
            })
        ));
        for bad in [
            "not json",
            r#"{"type":"drag","dx":1e30,"dy":0}"#,
            r#"{"type":"size","width":100000,"height":10}"#,
            r#"{"type":"model","name":"x","path":"/etc/passwd"}"#,
            r#"{"type":"camera","yaw":0,"pitch":0,"fov":200}"#,
            r#"{"type":"camera","yaw":0,"pitch":0,"distance":-1}"#,
            r#"{"type":"camera","yaw":0,"pitch":0,"target":[0,1e300,0]}"#,
            r#"{"type":"camera","yaw":1e9,"pitch":0}"#,
            r#"{"type":"launch"}"#,
            r#"{"type":"pick","what":"scene","index":0}"#,
            r#"{"type":"pick","what":"camera","index":-1}"#,
            r#"{"type":"pick","what":"variant","index":1,"name":"/etc/passwd"}"#,
            r#"{"type":"time","seconds":-1}"#,
            r#"{"type":"time","seconds":1e39}"#,
            r#"{"type":"time","seconds":NaN}"#,
            r#"{"type":"time","seconds":"1"}"#,
            r#"{"type":"time","seconds":1,"animation":-1}"#,
            r#"{"type":"play","on":1}"#,
            r#"{"type":"local"}"#,
            r#"{"type":"local","on":true,"wasm":"x"}"#,
            r#"[1,2]"#,
        ] {
            let e = ClientMsg::parse(bad).unwrap_err();
            assert!(e.starts_with("bad message"), "{bad}: {e}");
        }
    }

    #[test]
    fn a_state_is_the_frame_without_its_image() {
        let header = serde_json::json!({"frame": 3, "state": {"compare": false}});
        let whole: tungstenite::Bytes = frame_bytes(&header, b"\x89PNG image bytes").into();
        let state = state_only(&whole);
        let n = u32::from_le_bytes(state[..4].try_into().unwrap()) as usize;
        assert_eq!(state.len(), 4 + n);
        let back: serde_json::Value = serde_json::from_slice(&state[4..]).unwrap();
        assert_eq!(back, header);
        assert_eq!(state_only(&state), state);
        assert_eq!(state_only(&tungstenite::Bytes::new()).len(), 0);
    }

    #[test]
    fn server_messages_are_tagged_objects() {
        let e: serde_json::Value = serde_json::from_str(&error_json("full", true)).unwrap();
        assert_eq!(
            e,
            serde_json::json!({"type": "error", "message": "full", "closing": true})
        );
        let p = ServerMsg::Presenter { online: false }.text();
        assert_eq!(p, r#"{"type":"presenter","online":false}"#);
    }
}
