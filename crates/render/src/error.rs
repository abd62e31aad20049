//! The one error type of the library; `main` prints it once as `error: ...`.
use std::path::PathBuf;

pub type Result<T, E = Error> = std::result::Result<T, E>;

#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A model or material file that cannot be used; `line` is 1-based where known.
    #[error("{}{}: {message}", path.display(), line.map(|l| format!(":{l}")).unwrap_or_default())]
    Model {
        path: PathBuf,
        line: Option<usize>,
        message: String,
    },
    #[error("{}: {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// A shader that the driver refused, with its log and the numbered source.
    #[error(
        "shader {name} ({dialect}) failed to {stage}:\n{log}\n--- source ---\n{numbered_source}"
    )]
    Shader {
        name: String,
        dialect: String,
        stage: &'static str,
        log: String,
        numbered_source: String,
    },
    /// The driver cannot do something glview needs, and there is no fallback.
    #[error("{0}")]
    Unsupported(String),
    /// Context creation failed on every path that was tried.
    #[error("could not create an OpenGL context: {0}")]
    Context(String),
    /// The window or its context failed after it was open (no headless fallback then).
    #[error("window: {0}")]
    Window(String),
    #[error("GL error {code:#06x} after {pass}")]
    Gl { code: u32, pass: String },
    /// A library renderer called from a second thread while it draws for the first.
    #[error("the renderer is in use by another thread (it draws one picture at a time: make one renderer per thread)")]
    Busy,
    #[error("invalid option: {0}")]
    Usage(String),
    /// OSMesa's context could not be made (the native library's message).
    #[error("{0}")]
    Osmesa(String),
    #[error("{}: {message}", path.display())]
    Image { path: PathBuf, message: String },
    /// Some jobs of `glview batch` failed (each was reported on its own line already).
    #[error("{}: {failed} of {total} jobs failed (lines {lines})", file.display())]
    Batch {
        file: PathBuf,
        failed: usize,
        total: usize,
        lines: String,
    },
}

impl Error {
    pub fn model(
        path: impl Into<PathBuf>,
        line: Option<usize>,
        message: impl Into<String>,
    ) -> Self {
        Error::Model {
            path: path.into(),
            line,
            message: message.into(),
        }
    }
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Error::Io {
            path: path.into(),
            source,
        }
    }
}

/// The scene crate's errors are the library's `Model` and `Io`, as they were before it was a
/// crate of its own.
impl From<crate::scene::error::Error> for Error {
    fn from(e: crate::scene::error::Error) -> Self {
        match e {
            crate::scene::error::Error::Model {
                path,
                line,
                message,
            } => Error::Model {
                path,
                line,
                message,
            },
            crate::scene::error::Error::Io { path, source } => Error::Io { path, source },
        }
    }
}
