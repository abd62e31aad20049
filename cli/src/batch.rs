//! `glview batch JOBS`: many pictures in one process. Every job is a command line of the
//! headless mode; all of them share one GL context (so one compiled-program cache), the
//! environment-map cache and the mesh cache. A failing job is reported with its line and
//! the others still render.
use crate::cli::{Args, BatchCommand};
use glview::error::{Error, Result};
use glview::session::Session;
use std::io::Read;
use std::path::Path;
use std::time::Instant;

/// Jobs files are lists of command lines; anything larger is not one.
const MAX_JOBS_BYTES: u64 = 16 << 20;

/// One job: its 1-based line in the jobs file and its words (the program name excluded).
pub struct Job {
    pub line: usize,
    pub words: Vec<String>,
}

/// Splits a jobs file into jobs: one per non-empty line, `#` starts a comment line, words
/// split as a POSIX shell would (quotes and backslashes). Unbalanced quotes fail the file.
pub fn parse_jobs(text: &str, file: &Path) -> Result<Vec<Job>> {
    let mut jobs = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let line = raw.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let words = shlex::split(line)
            .ok_or_else(|| Error::model(file, Some(i + 1), "unbalanced quotes"))?;
        jobs.push(Job { line: i + 1, words });
    }
    Ok(jobs)
}

fn read_jobs(path: &Path) -> Result<String> {
    let mut text = String::new();
    let r = if path == Path::new("-") {
        std::io::stdin()
            .take(MAX_JOBS_BYTES + 1)
            .read_to_string(&mut text)
    } else {
        std::fs::File::open(path).and_then(|f| f.take(MAX_JOBS_BYTES + 1).read_to_string(&mut text))
    };
    r.map_err(|e| Error::io(path, e))?;
    if text.len() as u64 > MAX_JOBS_BYTES {
        return Err(Error::model(
            path,
            None,
            "larger than 16 MiB: not a jobs file",
        ));
    }
    Ok(text)
}

/// The job's arguments, refused unless they ask for exactly one headless picture.
fn job_args(job: &Job) -> std::result::Result<Args, String> {
    let args = Args::from_words(&job.words).map_err(|e| {
        // clap's message is several lines with usage; its first line says what is wrong.
        let s = e.to_string();
        s.lines()
            .next()
            .unwrap_or_default()
            .trim_start_matches("error: ")
            .to_string()
    })?;
    args.options().map_err(|e| e.to_string())?;
    let other_mode = args.command.is_some()
        || args.reference
        || args.compare.is_some()
        || args.diff.is_some()
        || args.diff_against.is_some()
        || args.info
        || args.compile_shaders
        || args.check;
    if other_mode {
        return Err(
            "a batch job renders one GPU picture (no subcommand, --reference, \
                    --compare, --diff, --info, --check)"
                .into(),
        );
    }
    if args.output.is_none() {
        return Err("a batch job needs --output FILE".into());
    }
    Ok(args)
}

pub fn run(cmd: &BatchCommand) -> Result<()> {
    let jobs = parse_jobs(&read_jobs(&cmd.jobs)?, &cmd.jobs)?;
    let name = cmd.jobs.display().to_string();
    let bar = indicatif::ProgressBar::new(jobs.len() as u64);
    if let Ok(style) = indicatif::ProgressStyle::with_template("batch [{bar:30}] {pos}/{len} {msg}")
    {
        bar.set_style(style);
    }
    let start = Instant::now();
    let mut session = Session::new();
    let mut failed = Vec::new();
    for job in &jobs {
        let result = job_args(job).and_then(|args| {
            let out = args.output.clone().unwrap_or_default();
            bar.set_message(out.display().to_string());
            session.write(&args, &out).map_err(|e| e.to_string())
        });
        if let Err(e) = result {
            bar.suspend(|| eprintln!("error: {name}:{}: {e}", job.line));
            failed.push(job.line);
        }
        bar.inc(1);
    }
    bar.finish_and_clear();
    let secs = start.elapsed().as_secs_f64();
    let done = jobs.len() - failed.len();
    eprintln!(
        "batch: {done} pictures in {secs:.2} s ({:.2} per second), {} failed",
        done as f64 / secs.max(1e-9),
        failed.len()
    );
    if cmd.compare_processes {
        compare_processes(&jobs, secs)?;
    }
    if failed.is_empty() {
        Ok(())
    } else {
        Err(Error::Batch {
            file: cmd.jobs.clone(),
            failed: failed.len(),
            total: jobs.len(),
            lines: failed
                .iter()
                .map(|l| l.to_string())
                .collect::<Vec<_>>()
                .join(", "),
        })
    }
}

/// The same jobs, one `glview` process each (what a CI script without `batch` does), timed.
fn compare_processes(jobs: &[Job], batch_secs: f64) -> Result<()> {
    let exe = std::env::current_exe().map_err(|e| Error::io("glview", e))?;
    let start = Instant::now();
    for job in jobs {
        // Failures were reported by the batch run; this only times the same work.
        let _ = std::process::Command::new(&exe)
            .args(&job.words)
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .status();
    }
    let secs = start.elapsed().as_secs_f64();
    eprintln!(
        "one process per picture: {} jobs in {secs:.2} s ({:.2} per second); batch is {:.2}x \
         faster",
        jobs.len(),
        jobs.len() as f64 / secs.max(1e-9),
        secs / batch_secs.max(1e-9)
    );
    Ok(())
}
