//! `glview bench --soak N`: load, upload, render and drop a model N times in one context and
//! report live GL objects and resident memory, to show nothing leaks (the test runs a
//! smaller count).
use glview::headless::Headless;
use glview::metrics::{rss_kib, trend_per_round};
use glview::options::Options;
use glview::render::Renderer;
use glview::Result;

pub fn run(args: &Options, rounds: u32) -> Result<()> {
    let (w, h) = args.picture.size;
    let hl = Headless::new(args.context.backend, args.context.gl, w, h)?;
    let base = hl.gpu.live_objects();
    let mut rss = Vec::with_capacity(rounds as usize);
    let start = std::time::Instant::now();
    for round in 1..=rounds {
        let scene = glview::session::load_scene(args)?;
        let (settings, _) = glview::session::frame_settings(args, &scene)?;
        let mut r = Renderer::new(&hl.gpu, scene)?;
        r.render(&settings, &hl.target())?;
        drop(r);
        let live = hl.gpu.live_objects() - base;
        rss.push(rss_kib());
        if live != 0 {
            return Err(glview::Error::Unsupported(format!(
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
    let warm = rss.len() / 10;
    println!(
        "soak: {rounds} rounds in {:.1} s; live GL objects back to {base} every round; RSS {} KiB after warm-up, {} KiB at the end, trend {:+.1} KiB per round",
        start.elapsed().as_secs_f64(),
        rss.get(warm).copied().unwrap_or(0),
        rss.last().copied().unwrap_or(0),
        trend_per_round(&rss[warm..])
    );
    Ok(())
}
