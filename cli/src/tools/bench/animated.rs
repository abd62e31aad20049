//! `glview bench --animated`: what a 3-second animated picture costs. The frames (45 at
//! 15 fps, 640×480: a turntable of the built-in scene, or `--animated-model`'s first
//! animation, a turntable where it has none) are
//! drawn once in one session, as `-o out.gif` draws them; then each encoder (GIF, APNG,
//! WebP) encodes the same frames three times and the median is printed beside the time the
//! frames took to draw and the file's size.
use super::median;
use super::table::{num, Table};
use glview::anim_out::{encode, AnimFormat};
use glview::image_out::Rgba;
use glview::session::{Profile, Session};
use glview::{Error, Options, Result};
use std::time::Instant;

const SIZE: (u32, u32) = (640, 480);
const FPS: f32 = 15.0;
const SECONDS: u32 = 3;
const ROUNDS: usize = 3;

pub fn run_animated(model: Option<&std::path::Path>) -> Result<()> {
    let mut args = Options::default();
    args.picture.size = SIZE;
    args.load.model = model.map(Into::into);
    let n = SECONDS * FPS as u32;
    let (frames, draw_ms) = draw(&args, n)?;
    println!(
        "glview bench --animated: {}, {n} frames ({SECONDS} s at {FPS} fps) of {}x{}; \
         frames drawn in {draw_ms:.0} ms ({:.1} ms each); encoding: median of {ROUNDS}",
        model.map_or("built-in scene".into(), |p| p.display().to_string()),
        SIZE.0,
        SIZE.1,
        draw_ms / f64::from(n),
    );
    let mut table = Table::new(&["format", "encode ms", "ms/frame", "vs drawing", "KiB"]);
    for format in [AnimFormat::Gif, AnimFormat::Apng, AnimFormat::Webp] {
        let mut times = Vec::new();
        let mut bytes = 0;
        for _ in 0..ROUNDS {
            let t = Instant::now();
            let out = encode(format, &frames, FPS).map_err(|message| Error::Image {
                path: format!("(bench {})", format.name()).into(),
                message,
            })?;
            times.push(t.elapsed().as_secs_f64() * 1e3);
            bytes = out.len();
        }
        let ms = median(&times);
        table.row(vec![
            format.name().into(),
            num(ms, 0),
            num(ms / f64::from(n), 1),
            format!("{:.2}x", ms / draw_ms),
            num(bytes as f64 / 1024.0, 0),
        ]);
    }
    print!("{}", table.render());
    Ok(())
}

/// The frames, drawn as an animated picture's are (the model's first animation from 0 s when
/// it has one, else a turntable), and the time they took (loading and the first frame's
/// compiles excluded: one frame is drawn first).
fn draw(args: &Options, n: u32) -> Result<(Vec<Rgba>, f64)> {
    let mut session = Session::new();
    let plays = !session.scene(args)?.animations().is_empty();
    session.draw(args, None, Default::default(), &mut Profile::default())?;
    let t = Instant::now();
    let mut frames = Vec::with_capacity(n as usize);
    for k in 0..n {
        let mut o = args.clone();
        if plays {
            o.motion.time = Some(k as f32 / FPS);
        } else {
            o.camera.yaw = glview::session::turntable_yaw(args.camera.yaw, k, n);
        }
        let drawn = session.draw(&o, None, Default::default(), &mut Profile::default())?;
        frames.push(drawn.image);
    }
    Ok((frames, t.elapsed().as_secs_f64() * 1e3))
}
