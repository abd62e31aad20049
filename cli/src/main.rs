//! `glview`: the command line over the glview library. Parse, dispatch to one mode (the
//! modes import the library, never each other), print the one error, exit code; progress
//! bars for the library's long steps.
mod app;
mod batch;
mod cli;
mod export;
mod serve;
mod tools;
mod window;

use crate::cli::Args;
use glview::{session, Error, Result};
use std::process::ExitCode;

fn main() -> ExitCode {
    // Library warnings read like the loader's: `warning: ...`, one line each.
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn"))
        .format(|buf, record| {
            use std::io::Write;
            let level = match record.level() {
                log::Level::Error => "error",
                log::Level::Warn => "warning",
                log::Level::Info => "info",
                _ => "debug",
            };
            writeln!(buf, "{level}: {}", record.args())
        })
        .init();
    glview::progress::install(Box::new(progress_bar));
    let args = Args::from_words(std::env::args_os().skip(1)).unwrap_or_else(|e| e.exit());
    let result = dispatch(&args);
    // A first load of a large model writes its mesh cache entry (levels of detail built
    // while the picture was drawn) before the process ends.
    glview::scene::cache::wait_for_writes();
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// The library's long steps as indicatif bars on stderr (hidden when it is not a terminal).
fn progress_bar(
    what: &str,
    total: u64,
    unit: glview::progress::Unit,
) -> Box<dyn glview::progress::Task> {
    let template = match unit {
        glview::progress::Unit::Bytes => "{msg} [{bar:30}] {bytes}/{total_bytes} {elapsed}",
        glview::progress::Unit::Items => "{msg} [{bar:30}] {pos}/{len}",
    };
    let bar = indicatif::ProgressBar::new(total);
    bar.set_style(
        indicatif::ProgressStyle::with_template(template)
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    bar.set_message(what.to_string());
    Box::new(Bar(bar))
}

struct Bar(indicatif::ProgressBar);

impl glview::progress::Task for Bar {
    fn set(&self, done: u64) {
        self.0.set_position(done);
    }
    fn finish(&self, message: Option<String>) {
        match message {
            Some(m) => self.0.finish_with_message(m),
            None => self.0.finish_and_clear(),
        }
    }
}

/// The dispatch: one mode per invocation.
fn dispatch(args: &Args) -> Result<()> {
    args.options()?;
    match &args.command {
        Some(crate::cli::Command::Bench(b)) => return tools::run_bench(args, &b.words),
        Some(crate::cli::Command::Sheet(s)) => return s.run(),
        Some(crate::cli::Command::Batch(b)) => return crate::batch::run(b),
        Some(crate::cli::Command::Serve(s)) => return crate::serve::run(s),
        Some(crate::cli::Command::Export(e)) => return e.run(),
        None => {}
    }
    if args.options_reference {
        print!("{}", glview::options::reference_markdown());
        return Ok(());
    }
    if let Some(png) = &args.repro {
        let opts = glview::repro::options_of_png(png)?;
        let out = args
            .output
            .clone()
            .unwrap_or_else(|| "glview-repro.png".into());
        return session::render_headless(&opts, &out);
    }
    if args.reference && (args.compare.is_some() || args.diff.is_some()) {
        return Err(Error::Usage(
            "--reference renders one picture; use `reference` as a tier of --compare or --diff"
                .into(),
        ));
    }
    if let Some(tiers) = &args.compare {
        let out = args
            .output
            .clone()
            .unwrap_or_else(|| "glview-compare.png".into());
        return glview::compare::compare(args, tiers, &out);
    }
    if let Some(tiers) = &args.diff {
        let out = args
            .output
            .clone()
            .unwrap_or_else(|| "glview-diff.png".into());
        return glview::compare::diff::run_diff(args, tiers, &out);
    }
    if let Some(stored) = &args.diff_against {
        return glview::compare::diff::diff_against(
            args,
            args.output.as_deref(),
            stored,
            args.threshold,
        );
    }
    if args.info {
        return session::print_info(args);
    }
    if args.compile_shaders {
        return session::compile_shaders(args);
    }
    if args.reference {
        let out = args
            .output
            .clone()
            .unwrap_or_else(|| "glview-reference.png".into());
        return session::render_reference(args, &out);
    }
    if args.check {
        let scene = session::load_scene_with(args, false)?;
        let format = args
            .load
            .model
            .as_deref()
            .map(|p| glview::scene::loaders::formats::format_of(p).0);
        let crease = args
            .load
            .crease
            .unwrap_or(glview::scene::geometry::normals::DEFAULT_CREASE_DEG);
        print!("{}", glview::scene::report::report(&scene, format, crease));
        return Ok(());
    }
    if let Some(out) = &args.output {
        return session::render_headless(args, out);
    }
    if crate::app::display_available() {
        let quad = args.stereo.mode == glview::stereo::StereoMode::QuadBuffer;
        match crate::app::run_window(args) {
            // Quad buffers are a window's: a picture instead would not be what was asked.
            Err(Error::Context(e)) if quad => {
                return Err(Error::Context(format!("no quad-buffered window: {e}")));
            }
            Err(Error::Context(e)) => eprintln!("warning: no window ({e}); rendering headless"),
            other => return other,
        }
    }
    // Never overwrite silently: glview.png, else glview-1.png, glview-2.png, ...
    let out = std::iter::once("glview.png".to_string())
        .chain((1..).map(|i| format!("glview-{i}.png")))
        .map(std::path::PathBuf::from)
        .find(|p| !p.exists())
        .unwrap_or_else(|| "glview.png".into());
    session::render_headless(args, &out)?;
    eprintln!("no display: wrote {}", out.display());
    Ok(())
}
