//! Progress of long steps (loading a large file, a contact sheet), reported to whoever
//! installed a reporter: the command line shows bars (indicatif, in the binary); the library
//! alone, Python and tests report nothing. The library never draws on a terminal itself.
use std::sync::OnceLock;

/// One step under way.
pub trait Task: Send + Sync {
    /// `done` of the step's total so far.
    fn set(&self, done: u64);
    /// The step ended: with a message to leave on screen, or none (cleared).
    fn finish(&self, message: Option<String>);
}

/// Makes a [`Task`] for a step of `total` units (bytes, pictures) named `what`.
pub(crate) type Reporter = Box<dyn Fn(&str, u64, Unit) -> Box<dyn Task> + Send + Sync>;

/// What a step counts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Unit {
    Bytes,
    Items,
}

static REPORTER: OnceLock<Reporter> = OnceLock::new();

/// Installs the process's reporter (the first call wins).
pub fn install(r: Reporter) {
    let _ = REPORTER.set(r);
}

/// A task for this step, if a reporter is installed.
pub(crate) fn start(what: &str, total: u64, unit: Unit) -> Option<Box<dyn Task>> {
    REPORTER.get().map(|r| r(what, total, unit))
}
