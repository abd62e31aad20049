//! `glview bench --soak N`: load, upload, render and drop a model N times in one context and
//! report live GL objects and resident memory, to show nothing leaks (the test runs a
//! smaller count).
use crate::cli::Args;
use crate::headless::Headless;
use crate::render::Renderer;
use crate::Result;

fn rss_kib() -> u64 {
    std::fs::read_to_string("/proc/self/statm")
        .ok()
        .and_then(|s| {
            s.split_whitespace()
                .nth(1)
                .and_then(|v| v.parse::<u64>().ok())
        })
        .map_or(0, |pages| pages * 4)
}

pub fn run(args: &Args, rounds: u32) -> Result<()> {
    let (w, h) = args.size;
    let hl = Headless::new(args.backend, args.gl, w, h)?;
    let base = hl.gpu.live_objects();
    let mut rss = Vec::with_capacity(rounds as usize);
    let start = std::time::Instant::now();
    for round in 1..=rounds {
        let scene = crate::run::load_scene(args)?;
        let (settings, _) = crate::run::frame_settings(args, &scene)?;
        let mut r = Renderer::new(&hl.gpu, scene)?;
        r.render(&settings, &hl.target())?;
        drop(r);
        let live = hl.gpu.live_objects() - base;
        rss.push(rss_kib());
        if live != 0 {
            return Err(crate::Error::Unsupported(format!(
                "round {round}: {live} GL objects leaked"
            )));
        }
        if round % 100 == 0 || round == rounds {
            println!(
                "round {round}: live GL objects {live}, RSS {} KiB",
                rss.last().unwrap_or(&0)
            );
        }
    }
    let warm = rss.get(rss.len() / 10).copied().unwrap_or(0);
    let last = rss.last().copied().unwrap_or(0);
    println!(
        "soak: {rounds} rounds in {:.1} s; live GL objects back to {base} every round; RSS after warm-up {warm} KiB, at the end {last} KiB ({:+} KiB)",
        start.elapsed().as_secs_f64(),
        last as i64 - warm as i64
    );
    Ok(())
}
