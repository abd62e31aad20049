//! `glview`: parse, run, print the one error, exit code.
use clap::Parser;
use glview::cli::Args;
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
    let args = Args::parse();
    match glview::run::main(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
