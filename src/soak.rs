//! `glview bench --soak N`: load, upload, render and drop a model N times in one context and
//! report live GL objects and resident memory, to show nothing leaks (the test runs a
//! smaller count).
use crate::headless::Headless;
use crate::options::Options;
use crate::render::Renderer;
use crate::Result;

/// Resident memory of this process in KiB (0 where /proc is missing).
pub fn rss_kib() -> u64 {
    std::fs::read_to_string("/proc/self/statm")
        .ok()
        .and_then(|s| {
            s.split_whitespace()
                .nth(1)
                .and_then(|v| v.parse::<u64>().ok())
        })
        .map_or(0, |pages| pages * 4)
}

/// Least-squares slope of `samples` against their index: resident memory on llvmpipe jumps
/// between levels 16 MiB apart from round to round, so a before/after pair says nothing and a
/// trend over every round does.
pub fn trend_per_round(samples: &[u64]) -> f64 {
    let n = samples.len() as f64;
    if samples.len() < 2 {
        return 0.0;
    }
    let mx = (n - 1.0) / 2.0;
    let my = samples.iter().map(|&v| v as f64).sum::<f64>() / n;
    let (mut sxy, mut sxx) = (0.0, 0.0);
    for (i, &v) in samples.iter().enumerate() {
        sxy += (i as f64 - mx) * (v as f64 - my);
        sxx += (i as f64 - mx).powi(2);
    }
    sxy / sxx
}

pub fn run(args: &Options, rounds: u32) -> Result<()> {
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

#[cfg(test)]
mod tests {
    #[test]
    fn trend() {
        assert_eq!(super::trend_per_round(&[5, 7, 9, 11]), 2.0);
        assert!(super::trend_per_round(&[3, 9, 3, 9, 3, 9, 3, 9]).abs() < 1.0);
        assert_eq!(super::trend_per_round(&[1]), 0.0);
    }
}
