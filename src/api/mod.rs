//! The library API: load a [`Model`] (a file in any format glview reads, or arrays), make a
//! [`Renderer`] (a [`Session`] on a thread of its own, as `glview batch` keeps one) and render [`Options`]
//! into buffers: the colour picture, and on request depth, normals and object/material ids.
//!
//! A GL context is current on one thread, so a renderer draws on a thread of its own and
//! its methods send it work: a `Renderer` may be used from any thread, but not from two at
//! once (the second call is refused with [`Error::Busy`](crate::Error) instead of waiting).
pub(crate) mod arrays;

pub(crate) use crate::image_out::Rgba;
pub(crate) use crate::options::Options;
pub use crate::render::attributes::{Attributes, Outputs};
pub use arrays::Arrays;

use crate::error::{Error, Result};
use crate::scene::Scene;
use crate::session::{Given, Profile, Session};
use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc;
use std::sync::{Arc, Mutex};

/// A loaded model, kept on the CPU; renderers upload it when they first draw it.
#[derive(Clone, Debug)]
pub struct Model {
    scene: Arc<Scene>,
    /// Names this model among the ones a renderer has drawn (kept uploaded while it is).
    key: String,
}

static NEXT_MODEL: AtomicU64 = AtomicU64::new(1);

impl Model {
    fn new(scene: Scene) -> Model {
        Model {
            scene: Arc::new(scene),
            key: format!("model#{}", NEXT_MODEL.fetch_add(1, Ordering::Relaxed)),
        }
    }

    /// Loads a model file with the loading options of `opts` (`up`, `crease`, `flat`,
    /// `texture`, `honor-transparency`, the mesh cache, ...); its warnings are logged.
    ///
    /// ```
    /// use glview::api::{Model, Outputs, Renderer};
    /// let model = Model::load("models/sphere.obj".as_ref(), &glview::Options::default())?;
    /// assert!(model.scene().triangle_count() > 0);
    /// let mut o = glview::Options::default();
    /// o.picture.size = (64, 48);
    /// let mut r = Renderer::new(o.clone())?;
    /// r.load(model);
    /// for yaw in [0.0, 90.0] {
    ///     o.camera.yaw = yaw; // the same scene: uploaded once
    ///     let frame = r.render(&o, Outputs::default())?;
    ///     assert_eq!((frame.color.width, frame.color.height), (64, 48));
    /// }
    /// # Ok::<(), glview::Error>(())
    /// ```
    pub fn load(path: &Path, opts: &Options) -> Result<Model> {
        let mut o = opts.clone();
        o.load.model = Some(path.to_path_buf());
        Ok(Model::new(crate::session::load_scene_with(&o, false)?).warned())
    }

    /// A model from arrays: the same scene as the same data in an OBJ file.
    pub fn from_arrays(a: &Arrays, opts: &Options) -> Result<Model> {
        let obj = a.to_obj()?;
        let scene = crate::scene::loaders::obj::load_embedded(
            Path::new("<arrays>.obj"),
            obj.as_bytes(),
            b"",
            &crate::session::load_options(opts, None),
        )?;
        Ok(Model::new(scene).warned())
    }

    fn warned(self) -> Model {
        for w in &self.scene.warnings {
            log::warn!("{w}");
        }
        self
    }

    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// Object names by object id (the scene's meshes: OBJ objects/groups, glTF meshes).
    pub fn object_names(&self) -> Vec<String> {
        self.scene.meshes.iter().map(|m| m.name.clone()).collect()
    }

    /// Material names by material id.
    pub fn material_names(&self) -> Vec<String> {
        self.scene
            .materials
            .iter()
            .map(|m| m.name.clone())
            .collect()
    }
}

/// One rendered picture.
#[derive(Clone, Debug)]
pub struct Frame {
    /// RGBA8, straight alpha, top row first: the pixels `glview -o x.png` writes.
    pub color: Rgba,
    /// What the PNG text chunks are made of ([`Frame::text`]).
    pub repro: crate::session::PictureText,
    pub attributes: Option<Attributes>,
    /// With [`Outputs::linear`]: the colour before bloom, exposure, tone mapping and sRGB
    /// (linear, unclamped), RGB per pixel, top row first.
    pub linear: Option<Vec<[f32; 3]>>,
    /// The frame's `--stats` line, with the picture's `profile` (what was uploaded and
    /// made for it, and where the time went).
    pub stats: serde_json::Value,
}

impl Frame {
    /// The PNG text chunks (renderer, camera, the reproducing command line), made now: a
    /// picture used as arrays never pays for them.
    pub fn text(&self) -> Vec<(String, String)> {
        self.repro
            .text()
            .into_iter()
            .map(|(k, v)| (k.to_string(), v))
            .collect()
    }

    /// The picture as a PNG file's bytes, text chunks included.
    pub fn png(&self) -> Vec<u8> {
        self.color.png_bytes(&self.repro.text())
    }
}

type Job = Box<dyn FnOnce(&mut Session) + Send>;

/// How long a thread polls before it sleeps: waking a sleeping thread took ~50 µs each way
/// here (a virtual machine's idle CPU), twice per picture, against a 6 ms picture.
const SPIN: std::time::Duration = std::time::Duration::from_micros(300);

/// The renderer thread's next job: polled for [`SPIN`] after the last one (a caller
/// rendering many pictures sends the next within microseconds), then waited for.
fn next_job(rx: &mpsc::Receiver<Job>) -> Option<Job> {
    let start = std::time::Instant::now();
    while start.elapsed() < SPIN {
        match rx.try_recv() {
            Ok(job) => return Some(job),
            Err(mpsc::TryRecvError::Disconnected) => return None,
            Err(mpsc::TryRecvError::Empty) => std::thread::yield_now(),
        }
    }
    rx.recv().ok()
}

/// A job's answer: slept for until [`SPIN`] before the time the last job took, then polled.
fn wait_answer<T>(
    answer: &mpsc::Receiver<T>,
    last: &Mutex<std::time::Duration>,
) -> std::result::Result<T, mpsc::RecvError> {
    let start = std::time::Instant::now();
    let expected = last.lock().map(|d| *d).unwrap_or_default();
    let r = (|| {
        if let Some(sleep) = expected.checked_sub(SPIN) {
            match answer.recv_timeout(sleep) {
                Ok(v) => return Ok(v),
                Err(mpsc::RecvTimeoutError::Disconnected) => return Err(mpsc::RecvError),
                Err(mpsc::RecvTimeoutError::Timeout) => {}
            }
        }
        while start.elapsed() < expected + SPIN {
            match answer.try_recv() {
                Ok(v) => return Ok(v),
                Err(mpsc::TryRecvError::Disconnected) => return Err(mpsc::RecvError),
                Err(mpsc::TryRecvError::Empty) => std::thread::yield_now(),
            }
        }
        answer.recv()
    })();
    if let Ok(mut d) = last.lock() {
        *d = start.elapsed();
    }
    r
}

/// A renderer held by one caller ([`Renderer::reserve`]).
pub struct Reserved<'a> {
    _guard: std::sync::MutexGuard<'a, Option<mpsc::Sender<Job>>>,
}

/// A kept GL context on a thread of its own, with the last model drawn kept uploaded.
pub struct Renderer {
    jobs: Mutex<Option<mpsc::Sender<Job>>>,
    thread: Option<std::thread::JoinHandle<()>>,
    model: Option<Model>,
    /// How long the last call took ([`wait_answer`]).
    last_job: Mutex<std::time::Duration>,
    /// Options every render starts from (size, backend, ...) unless it gives its own.
    pub(crate) defaults: Options,
}

impl Renderer {
    /// A renderer for pictures of `defaults.size` on `defaults.backend`/`gl`; the context
    /// is made now, so a machine without one fails here.
    pub fn new(defaults: Options) -> Result<Renderer> {
        let (tx, rx) = mpsc::channel::<Job>();
        let thread = std::thread::Builder::new()
            .name("glview-renderer".into())
            .spawn(move || {
                let mut session = Session::new();
                while let Some(job) = next_job(&rx) {
                    job(&mut session);
                }
            })
            .map_err(|e| Error::Context(format!("no renderer thread: {e}")))?;
        let r = Renderer {
            jobs: Mutex::new(Some(tx)),
            thread: Some(thread),
            model: None,
            last_job: Mutex::new(std::time::Duration::ZERO),
            defaults,
        };
        let opts = r.defaults.clone();
        r.call(move |session| {
            *session = Session::open(&opts)?;
            Ok(())
        })?;
        Ok(r)
    }

    /// Runs `f` on the renderer's thread and waits for it; refuses a second caller.
    fn call<T: Send + 'static>(
        &self,
        f: impl FnOnce(&mut Session) -> Result<T> + Send + 'static,
    ) -> Result<T> {
        let guard = self.jobs.try_lock().map_err(|_| Error::Busy)?;
        let tx = guard.as_ref().ok_or(Error::Busy)?;
        let (back, answer) = mpsc::sync_channel(1);
        let job: Job = Box::new(move |session| {
            // A panic in a job must not take the thread (and the context) down with it.
            let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| f(session)))
                .unwrap_or_else(|_| Err(Error::Unsupported("the renderer panicked".into())));
            let _ = back.send(r);
        });
        tx.send(job)
            .map_err(|_| Error::Unsupported("the renderer thread has ended".into()))?;
        wait_answer(&answer, &self.last_job)
            .map_err(|_| Error::Unsupported("the renderer thread has ended".into()))?
    }

    /// Keeps every other caller out (they get [`Error::Busy`], as while a render runs)
    /// until the guard goes: a caller's way to hold the renderer across several steps, and a
    /// deterministic way to test that a second thread is refused.
    pub fn reserve(&self) -> Result<Reserved<'_>> {
        Ok(Reserved {
            _guard: self.jobs.try_lock().map_err(|_| Error::Busy)?,
        })
    }

    /// Draws `model` from now on instead of the options' model file.
    pub fn load(&mut self, model: Model) {
        self.model = Some(model);
    }

    /// Draws the options' model file (or the built-in scene) again instead of a loaded
    /// model, which is no longer kept.
    pub fn unload(&mut self) {
        self.model = None;
    }

    /// Renders `opts` (the loaded model, else `opts.model` or the built-in scene).
    pub fn render(&self, opts: &Options, outputs: Outputs) -> Result<Frame> {
        let opts = opts.clone();
        let model = self.model.clone();
        self.call(move |session| {
            let given = model.as_ref().map(|m| Given {
                key: &m.key,
                scene: &m.scene,
            });
            let mut profile = Profile::default();
            let drawn = session.draw(&opts, given, outputs, &mut profile)?;
            // As `--stats` prints it: the frame's line with the picture's profile (its
            // scene uploads and environments made among it).
            let mut stats = serde_json::to_value(&drawn.stats).unwrap_or_default();
            stats["profile"] = serde_json::to_value(&profile).unwrap_or_default();
            Ok(Frame {
                color: drawn.image,
                repro: drawn.repro,
                attributes: drawn.attributes,
                linear: drawn.linear,
                stats,
            })
        })
    }

    /// Ends the renderer's thread, releasing its context and everything uploaded.
    pub fn close(&mut self) {
        if let Ok(mut g) = self.jobs.lock() {
            g.take();
        }
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

impl Drop for Renderer {
    fn drop(&mut self) {
        self.close();
    }
}

/// The renderer one-shot [`render`] calls share, made by the first and kept until
/// [`release`]: a new context per picture cost 40-50 ms and compiled every program again.
static SHARED: Mutex<Option<Renderer>> = Mutex::new(None);

/// One picture: `render(&Options::from_words(["bunny.obj"])?, Outputs::default())`.
///
/// Calls share one process-wide renderer (made by the first call, kept warm until
/// [`release`]), so a picture costs what it costs on a kept [`Renderer`]: the context and
/// the compiled programs are reused, and so is the uploaded scene while the model file and
/// the options that make the scene stay the same. A call made while another thread's call
/// draws on it does not wait: it draws in a temporary renderer of its own, made and closed
/// for that picture (slower, as every call was before the renderer was shared).
///
/// ```
/// let mut o = glview::Options::default(); // the built-in scene
/// o.picture.size = (64, 48);
/// let frame = glview::api::render(&o, glview::api::Outputs { depth: true, ..Default::default() })?;
/// let depth = &frame.attributes.as_ref().expect("asked for").depth;
/// assert!(depth.iter().any(|d| d.is_finite()));
/// std::fs::write(std::env::temp_dir().join("glview-doc.png"), frame.png()).unwrap();
/// glview::api::release();
/// # Ok::<(), glview::Error>(())
/// ```
pub fn render(opts: &Options, outputs: Outputs) -> Result<Frame> {
    let mut shared = match SHARED.try_lock() {
        Ok(g) => g,
        // A panic while it was held: the renderer may be half made; make it anew.
        Err(std::sync::TryLockError::Poisoned(p)) => {
            let mut g = p.into_inner();
            *g = None;
            SHARED.clear_poison();
            g
        }
        Err(std::sync::TryLockError::WouldBlock) => {
            return Renderer::new(opts.clone())?.render(opts, outputs)
        }
    };
    if shared.is_none() {
        *shared = Some(Renderer::new(opts.clone())?);
    }
    shared.as_ref().expect("made above").render(opts, outputs)
}

/// Closes the renderer one-shot [`render`] calls share, releasing its context and what it
/// uploaded (the next call makes a new one). Waits for a call drawing on it to finish.
/// Without it the renderer lives until the process ends.
pub fn release() {
    let r = match SHARED.lock() {
        Ok(mut g) => g.take(),
        Err(p) => p.into_inner().take(),
    };
    drop(r);
}
