//! `glview bench --motion`: what playing an animation costs a frame. A skinned figure
//! (docs/benchmarks.md uses Khronos' CesiumMan) at 1024×768 posed anew every frame — the
//! CPU pose ([`glview::scene::Scene::pose`]), the posed meshes uploaded again
//! ([`Renderer::pose`]) and the frame — against the same model standing still at one moment
//! (the frame alone); the target is a ratio of at most 1.3. Frames are measured in
//! interleaved rounds after a warm-up, medians reported, with the pose and upload apart.
use super::table::{num, Table};
use glview::options::Options;
use glview::render::Renderer;
use glview::scene::motion::Moment;
use glview::Result;
use std::path::Path;

/// Frames per round and file, and rounds.
const FRAMES: usize = 6;
const ROUNDS: usize = 10;

pub fn run_motion(model: &Path, size: (u32, u32)) -> Result<()> {
    let mut o = Options::default();
    o.picture.size = size;
    o.load.model = Some(model.to_path_buf());
    let mut scene = glview::session::load_scene(&o)?;
    let duration = match scene.animations().first() {
        Some(a) => a.duration,
        None => {
            return Err(glview::Error::Usage(format!(
                "bench --motion: {} has no animation to play",
                model.display()
            )))
        }
    };
    let at = |k: usize| Moment {
        animation: 0,
        // 30 frames a second, wrapping: every frame is another moment.
        seconds: (k as f64 / 30.0) % duration.max(1e-3),
    };
    // The camera frames the animation's bounds (the same at every moment of it).
    scene.pose(Some(at(0)))?;
    let (s, _) = glview::session::frame_settings(&o, &scene)?;
    let hl = super::open_headless(
        "motion",
        size,
        &format!(
            "{}: median of {} frames, posed anew each frame vs standing",
            model.display(),
            FRAMES * ROUNDS
        ),
    )?;
    let mut still = Renderer::new(&hl.gpu, scene.clone())?;
    still.pose(Some(at(0)))?;
    let mut playing = Renderer::new(&hl.gpu, scene)?;
    // Warm-up: programs compiled, shadow maps and textures made.
    still.render(&s, &hl.target())?;
    playing.pose(Some(at(1)))?;
    playing.render(&s, &hl.target())?;
    let (mut still_ms, mut frame_ms, mut pose_ms, mut upload_ms) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let mut k = 2;
    for _ in 0..ROUNDS {
        for _ in 0..FRAMES {
            still_ms.push(still.render(&s, &hl.target())?.ms);
        }
        for _ in 0..FRAMES {
            playing.pose(Some(at(k)))?;
            k += 1;
            let cost = playing.pose_cost();
            let frame = playing.render(&s, &hl.target())?.ms;
            pose_ms.push(cost.pose_ms);
            upload_ms.push(cost.upload_ms);
            frame_ms.push(cost.pose_ms + cost.upload_ms + frame);
        }
    }
    let cost = playing.pose_cost();
    let base = super::median(&still_ms);
    let mut table = Table::new(&[
        "model",
        "frame ms (median)",
        "pose ms",
        "upload ms",
        "meshes posed",
        "bytes uploaded",
        "vs still",
    ]);
    let name = model
        .file_stem()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    table.row(vec![
        format!("{name}, still"),
        num(base, 2),
        "-".into(),
        "-".into(),
        "0".into(),
        "0".into(),
        "1.00x".into(),
    ]);
    let played = super::median(&frame_ms);
    table.row(vec![
        format!("{name}, playing"),
        num(played, 2),
        num(super::median(&pose_ms), 2),
        num(super::median(&upload_ms), 2),
        cost.meshes.to_string(),
        cost.bytes.to_string(),
        format!("{:.2}x", played / base),
    ]);
    println!("{}", table.render());
    println!(
        "ratio playing/still {:.2} (target <= 1.3): {}",
        played / base,
        if played / base <= 1.3 {
            "met"
        } else {
            "NOT met"
        }
    );
    Ok(())
}
