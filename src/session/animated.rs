//! Animated pictures (`-o` ending in .gif, .apng or .webp): frame k is the still of the
//! options at that moment (`--time k/fps` when an animation plays; with `--turntable` the
//! yaw turned by 360°·k/N), drawn by [`super::draw`], the path every still takes, in one
//! kept context with the scene uploaded once, and handed to the encoder as soon as it is
//! drawn (`crate::anim_out`): memory is one frame plus the encoded file, whatever the
//! frame count.
use super::profile::ms;
use super::{draw, prepare, KeptContext, Profile};
use crate::anim_out::{AnimFormat, AnimWriter, MAX_FRAMES};
use crate::error::{Error, Result};
use crate::options::Options;
use crate::scene::Scene;
use std::io::{BufWriter, Seek, Write};
use std::path::Path;
use std::time::Instant;

/// A turntable without an animation to time it lasts this long unless `--duration` says.
const TURNTABLE_SECONDS: f64 = 4.0;

/// What the frames show: how many, at what rate, whether an animation plays and the
/// camera turns.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Plan {
    pub(crate) frames: u32,
    pub(crate) fps: f32,
    /// The played animation's index in [`Scene::animations`].
    pub(crate) animation: Option<usize>,
    pub(crate) turntable: bool,
}

impl Plan {
    /// The plan of an animated picture of `args` into `path`: one-line errors for a model
    /// with nothing to play and no `--turntable`, and for too many frames.
    pub(crate) fn new(args: &Options, scene: &Scene, path: &Path) -> Result<Plan> {
        let m = &args.motion;
        let err = |message: String| Error::Image {
            path: path.into(),
            message,
        };
        if let Some(f) = AnimFormat::of(path) {
            f.check_fps(m.fps).map_err(err)?;
        }
        // A turntable at `--time` turns around that moment, frozen; an animation plays from
        // its start, so `--time` alone would be ignored: refused instead.
        let animation = match (m.time, m.turntable) {
            (Some(_), true) => None,
            (Some(t), false) => {
                return Err(err(format!(
                    "--time {t}: an animated picture plays the animation from 0 s; drop --time, or add --turntable to turn around that moment"
                )))
            }
            (None, _) => played(args, scene)?,
        };
        let seconds = match (m.duration, animation) {
            (Some(d), _) => f64::from(d),
            (None, Some(a)) if scene.animations()[a].duration > 0.0 => {
                scene.animations()[a].duration
            }
            (None, _) if m.turntable => TURNTABLE_SECONDS,
            (None, Some(a)) => {
                return Err(err(format!(
                    "animation {a} lasts 0 seconds: give --duration"
                )))
            }
            (None, None) => {
                return Err(err(format!(
                    "an animated picture plays an animation or turns the camera, and {} has no animation: add --turntable",
                    model_name(args)
                )))
            }
        };
        let frames = (seconds * f64::from(m.fps)).round().max(1.0);
        if frames > f64::from(MAX_FRAMES) {
            return Err(err(format!(
                "{seconds} s at --fps {} is {frames} frames; an animated picture has at most {MAX_FRAMES} (shorten --duration or lower --fps)",
                m.fps
            )));
        }
        Ok(Plan {
            frames: frames as u32,
            fps: m.fps,
            animation,
            turntable: m.turntable,
        })
    }

    /// The options of frame `k`: the still of the same moment.
    pub(crate) fn frame(&self, args: &Options, k: u32) -> Options {
        let mut o = args.clone();
        if self.animation.is_some() {
            o.motion.time = Some(k as f32 / self.fps);
        }
        if self.turntable {
            o.camera.yaw = turntable_yaw(args.camera.yaw, k, self.frames);
        }
        o.motion.turntable = false;
        o
    }
}

/// The yaw of frame `k` of `n` of a turntable starting at `yaw`: one turn over the picture,
/// frame n (the first again) left out so that the loop does not stutter.
pub fn turntable_yaw(yaw: f32, k: u32, n: u32) -> f32 {
    yaw + 360.0 * k as f32 / n as f32
}

/// The animation an animated picture of `args` plays: `--animation` (by index or name),
/// else the file's first, else none. Resolved by [`super::moment`] (as a still's moment is,
/// same errors) at time 0.
fn played(args: &Options, scene: &Scene) -> Result<Option<usize>> {
    if scene.animations().is_empty() && args.motion.animation.is_none() {
        return Ok(None);
    }
    let mut at = args.clone();
    at.motion.time = Some(0.0);
    Ok(super::moment(&at, scene)?.map(|m| m.animation))
}

fn model_name(args: &Options) -> String {
    args.load.model.as_deref().map_or_else(
        || "the built-in scene".to_string(),
        |p| p.display().to_string(),
    )
}

/// Time spent drawing the frames and encoding them, for `--stats` and the bench.
#[derive(Clone, Copy, Debug, Default, serde::Serialize)]
pub struct AnimTimes {
    pub frames: u32,
    pub render_ms: f64,
    pub encode_ms: f64,
}

/// [`super::Session::write`] for an animated `path`. A file left half-written by an error
/// is removed.
pub(super) fn write(
    args: &Options,
    path: &Path,
    format: AnimFormat,
    keep: usize,
    kept: &mut Option<KeptContext>,
) -> Result<()> {
    let start = Instant::now();
    // Made first: an unwritable path fails before anything is loaded or drawn.
    let file = std::fs::File::create(path).map_err(|e| Error::io(path, e))?;
    let mut out = BufWriter::new(file);
    let result = plan(args, path, keep, kept).and_then(|plan| {
        let t = frames(args, &plan, format, path, &mut out, keep, kept)?;
        out.flush().map_err(|e| Error::io(path, e))?;
        Ok((plan, t))
    });
    drop(out);
    let (plan, times) = match result {
        Ok(r) => r,
        Err(e) => {
            let _ = std::fs::remove_file(path);
            return Err(e);
        }
    };
    if args.picture.stats {
        let line = serde_json::json!({
            "animated": format.name(), "frames": times.frames, "fps": plan.fps,
            "render_ms": times.render_ms, "encode_ms": times.encode_ms, "total_ms": ms(start),
        });
        println!("{line}");
    }
    Ok(())
}

/// The plan of `args`, with their scene loaded and uploaded (kept for the frames).
fn plan(args: &Options, path: &Path, keep: usize, kept: &mut Option<KeptContext>) -> Result<Plan> {
    let size = crate::view::settings::output_size(args);
    let kept = prepare(args, keep, kept, None, size, &mut Profile::default())?;
    let scene = kept.renderers.last().expect("made by prepare").1.scene();
    Plan::new(args, scene, path)
}

/// Draws the frames of `plan` and encodes each into `out` as it comes.
pub(super) fn frames<W: Write + Seek>(
    args: &Options,
    plan: &Plan,
    format: AnimFormat,
    path: &Path,
    out: W,
    keep: usize,
    kept: &mut Option<KeptContext>,
) -> Result<AnimTimes> {
    let err = |message: String| Error::Image {
        path: path.into(),
        message,
    };
    let mut enc = AnimWriter::new(
        format,
        out,
        crate::view::settings::output_size(args),
        plan.fps,
        plan.frames,
    )
    .map_err(err)?;
    let bar = crate::progress::start(
        "frames",
        u64::from(plan.frames),
        crate::progress::Unit::Items,
    );
    let mut times = AnimTimes {
        frames: plan.frames,
        ..AnimTimes::default()
    };
    for k in 0..plan.frames {
        let t = Instant::now();
        let o = plan.frame(args, k);
        let drawn = draw(
            &o,
            keep,
            kept,
            None,
            Default::default(),
            &mut Profile::default(),
        )?;
        times.render_ms += ms(t);
        let t = Instant::now();
        enc.add(&drawn.image).map_err(err)?;
        times.encode_ms += ms(t);
        if let Some(b) = &bar {
            b.set(u64::from(k + 1));
        }
    }
    let t = Instant::now();
    enc.finish().map_err(err)?;
    times.encode_ms += ms(t);
    if let Some(b) = bar {
        b.finish(None);
    }
    Ok(times)
}
