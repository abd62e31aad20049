//! `glview`: parse, dispatch to one mode (the modes import `run`, never each other), print
//! the one error, exit code.
mod tools;

use glview::cli::Args;
use glview::{run, Error, Result};
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
    let args = Args::from_words(std::env::args_os().skip(1)).unwrap_or_else(|e| e.exit());
    match dispatch(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// The dispatch: one mode per invocation.
fn dispatch(args: &Args) -> Result<()> {
    args.options()?;
    match &args.command {
        Some(glview::cli::Command::Bench(b)) => return tools::run_bench(args, &b.words),
        Some(glview::cli::Command::Sheet(s)) => return glview::compare::sheet::run(s),
        Some(glview::cli::Command::Batch(b)) => return glview::batch::run(b),
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
        return run::render_headless(&opts, &out);
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
        return glview::compare::diff::diff_against(args, stored, args.threshold);
    }
    if args.info {
        return run::print_info(args);
    }
    if args.compile_shaders {
        return run::compile_shaders(args);
    }
    if args.reference {
        let out = args
            .output
            .clone()
            .unwrap_or_else(|| "glview-reference.png".into());
        return run::render_reference(args, &out);
    }
    if args.check {
        let scene = run::load_scene_with(args, false)?;
        let format = args
            .load
            .model
            .as_deref()
            .map(|p| glview::scene::formats::format_of(p).0);
        print!("{}", glview::scene::report::report(&scene, format));
        return Ok(());
    }
    if let Some(out) = &args.output {
        return run::render_headless(args, out);
    }
    if glview::app::display_available() {
        match glview::app::run_window(args) {
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
    run::render_headless(args, &out)?;
    eprintln!("no display: wrote {}", out.display());
    Ok(())
}
