//! Local mode's files (docs/serve.md, "Local mode"): the browser build (`scripts/build_web.sh`),
//! read and gzipped once at the start, so no request reads it; and each model's scene for a
//! page that draws it — the view's option words, the model's files as the loader reads them,
//! the precomputed environment maps: what `glview export --live` embeds
//! ([`glview::export::live::scene`]) — made on a blocking thread at its first request and
//! kept for the next pages.
use super::http::{self, Answer};
use super::models::Models;
use glview::options::Options;
use glview::{Error, Result};
use hyper::body::Bytes;
use std::collections::VecDeque;
use std::io::Write;
use std::path::Path;
use std::sync::{Arc, Mutex, RwLock};

/// Scenes kept at once (each is a model's files, gzipped: a folder of many models must not
/// fill the memory): the oldest made goes first.
const MAX_SCENES: usize = 8;

/// The scheduler's loads read (`LOADING.read()`) while a scene is recorded (`write()`): the
/// loaders read through one process-wide source of files, and a recording must hold this
/// model's reads only.
pub static LOADING: RwLock<()> = RwLock::new(());

pub struct Web {
    /// `glview_web_bg.wasm`, gzipped.
    wasm: Bytes,
    /// wasm-bindgen's classic-script glue (`no-modules/glview_web.js`): it defines
    /// `wasm_bindgen` for the page's script.
    glue: Bytes,
    base: Options,
    models: Arc<Models>,
    scenes: Mutex<VecDeque<(String, Bytes)>>,
    /// One scene is made at a time: a page asking for every model takes one core, not all.
    making: tokio::sync::Mutex<()>,
}

fn gzip(bytes: &[u8]) -> Vec<u8> {
    let mut e = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
    // Writing to a Vec cannot fail.
    let _ = e.write_all(bytes);
    e.finish().unwrap_or_default()
}

impl Web {
    /// The browser build in `dir` (as `glview export --live --web-dir` finds it) for the
    /// models of `base`'s options; an error naming the folder when it is not there.
    pub fn open(dir: Option<&Path>, base: &Options, models: Arc<Models>) -> Result<Web> {
        let dir = glview::export::live::web_dir(dir)?;
        let read = |p: &Path| std::fs::read(p).map_err(|e| Error::io(p, e));
        let wasm = read(&dir.join("glview_web_bg.wasm"))?;
        if !wasm.starts_with(b"\0asm") {
            return Err(Error::Usage(format!(
                "{}: not a WebAssembly module (run `bash scripts/build_web.sh` again)",
                dir.join("glview_web_bg.wasm").display()
            )));
        }
        Ok(Web {
            wasm: gzip(&wasm).into(),
            glue: read(&dir.join("no-modules/glview_web.js"))?.into(),
            base: base.clone(),
            models,
            scenes: Mutex::new(VecDeque::new()),
            making: tokio::sync::Mutex::new(()),
        })
    }

    /// `GET /web/glview_web_bg.wasm` and `/web/glview_web.js`.
    pub fn file(&self, path: &str) -> Option<Answer> {
        let gz = [("Content-Encoding", "gzip".to_string())];
        match path {
            "/web/glview_web_bg.wasm" => Some(http::respond(
                200,
                "application/wasm",
                &gz,
                self.wasm.clone(),
            )),
            "/web/glview_web.js" => Some(http::respond(
                200,
                "text/javascript; charset=utf-8",
                &[],
                self.glue.clone(),
            )),
            _ => None,
        }
    }

    /// `GET /scene?model=NAME` (none: the first model): the scene's JSON, made now or kept.
    pub async fn scene(self: &Arc<Self>, name: Option<&str>) -> Answer {
        let name = name.unwrap_or(self.models.first().0).to_string();
        let path = match self.models.open(&name) {
            Ok(p) => p,
            Err(e) => return http::text(404, &e),
        };
        if let Some(b) = self.kept(&name) {
            return json(b);
        }
        let _one = self.making.lock().await;
        if let Some(b) = self.kept(&name) {
            return json(b);
        }
        let mut options = self.base.clone();
        options.load.model = path;
        let web = self.clone();
        let made = tokio::task::spawn_blocking(move || {
            let _alone = LOADING.write().unwrap_or_else(|e| e.into_inner());
            glview::export::live::scene(&options).map(|(data, _)| data.to_string())
        })
        .await;
        match made {
            Ok(Ok(text)) => {
                let bytes = Bytes::from(text);
                let mut kept = web.scenes.lock().unwrap_or_else(|e| e.into_inner());
                if kept.len() >= MAX_SCENES {
                    kept.pop_front();
                }
                kept.push_back((name, bytes.clone()));
                json(bytes)
            }
            Ok(Err(e)) => {
                let why = self.models.scrub(&e.to_string());
                log::warn!("scene {}: {why}", http::clip(&name));
                // The loader's errors name the model already.
                let named = why.starts_with(&format!("{name}:"));
                http::text(
                    422,
                    &if named {
                        why
                    } else {
                        format!("{}: {why}", http::clip(&name))
                    },
                )
            }
            Err(_) => http::text(500, "the scene could not be made (a bug: please report it)"),
        }
    }

    fn kept(&self, name: &str) -> Option<Bytes> {
        let kept = self.scenes.lock().unwrap_or_else(|e| e.into_inner());
        kept.iter().find(|(n, _)| n == name).map(|(_, b)| b.clone())
    }
}

fn json(body: Bytes) -> Answer {
    http::respond(200, "application/json", &[], body)
}
