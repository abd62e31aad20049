//! Animated pictures (`-o` .apng, .gif, .webp; issue #39): frame k is the still of its
//! moment, drawn by the same path. A turntable of the built-in scene, 64×48, 6 frames
//! (0.4 s at 15 fps), in the tests' shared in-process session (one context). Decoded by
//! the `png` and `image` crates, not by glview.
use crate::common::*;
use glview::image_out::Rgba;
use image::AnimationDecoder;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

const SIZE: &str = "64x48";
const YAW: f32 = 30.0;
const FPS: f32 = 15.0;
const DURATION: &str = "0.4";
const FRAMES: u32 = 6;
/// Khronos's BoxAnimated (node translation and rotation), committed with its licence.
const BOX: &str = "tests/data/khronos/motion/BoxAnimated.glb";

fn dir() -> PathBuf {
    out_dir("animated_out")
}

/// Writes `dir/name` with the turntable's options and `extra`, in the shared session.
fn animated(name: &str, extra: &[&str]) -> PathBuf {
    let out = dir().join(name);
    let yaw = YAW.to_string();
    let mut args = vec!["-o", out.to_str().unwrap(), "--size", SIZE, "--yaw", &yaw];
    args.extend_from_slice(&["--turntable", "--duration", DURATION]);
    args.extend_from_slice(extra);
    match fixture::render(&args) {
        Some(Ok(())) => out,
        Some(Err(e)) => panic!("glview {args:?}: {e}"),
        None => panic!("glview {args:?} is not one picture"),
    }
}

/// The stills `-o still-k.png --yaw Y` with Y the turntable's yaw at frame k: what the
/// frames must show.
fn stills() -> &'static Vec<Rgba> {
    static STILLS: OnceLock<Vec<Rgba>> = OnceLock::new();
    STILLS.get_or_init(|| {
        (0..FRAMES)
            .map(|k| {
                let yaw = glview::session::turntable_yaw(YAW, k, FRAMES).to_string();
                render(
                    &dir(),
                    &format!("still-{k}"),
                    &["--size", SIZE, "--yaw", &yaw],
                    &[],
                )
            })
            .collect()
    })
}

/// The frames side by side, in the test's output folder, to look at.
fn sheet(frames: &[Rgba], name: &str) {
    let (w, h) = (frames[0].width, frames[0].height);
    let mut img = image::RgbaImage::new(w * frames.len() as u32, h);
    for (i, f) in frames.iter().enumerate() {
        let fi = image::RgbaImage::from_raw(w, h, f.data.clone()).unwrap();
        image::imageops::replace(&mut img, &fi, i as i64 * i64::from(w), 0);
    }
    img.save(dir().join(name)).unwrap();
}

fn rgba(f: image::Frame) -> Rgba {
    let b = f.into_buffer();
    Rgba {
        width: b.width(),
        height: b.height(),
        data: b.into_raw(),
    }
}

/// The APNG: 6 frames looping forever, each shown 1/15 s, each the whole picture and byte
/// for byte the still of its yaw (lossless).
#[test]
fn apng_frames_are_the_stills() {
    let path = animated("turn.apng", &[]);
    let file = std::io::BufReader::new(std::fs::File::open(&path).unwrap());
    let mut reader = png::Decoder::new(file).read_info().unwrap();
    let actl = reader.info().animation_control.unwrap();
    assert_eq!((actl.num_frames, actl.num_plays), (FRAMES, 0));
    let mut frames = Vec::new();
    for k in 0..FRAMES {
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        let out = reader.next_frame(&mut buf).unwrap();
        let fc = reader.info().frame_control.unwrap();
        assert_eq!(
            (fc.width, fc.height, fc.x_offset, fc.y_offset),
            (64, 48, 0, 0)
        );
        assert_eq!(f32::from(fc.delay_num) / f32::from(fc.delay_den), 1.0 / FPS);
        assert_eq!((out.width, out.height), (64, 48));
        let frame = Rgba {
            width: 64,
            height: 48,
            data: buf[..out.buffer_size()].to_vec(),
        };
        assert!(
            frame == stills()[k as usize],
            "APNG frame {k} differs from the still (frames: {})",
            dir().display()
        );
        frames.push(frame);
    }
    assert_ne!(frames[0], frames[1], "the camera turns");
    sheet(&frames, "apng-frames.png");
}

/// An animated picture's frames, each with the millisecond its display ends at, once the
/// picture is checked to loop forever, to hold [`FRAMES`] frames and to give each a whole
/// number of milliseconds.
fn timed_frames(looping: image::metadata::LoopCount, frames: image::Frames) -> Vec<(u32, Rgba)> {
    assert!(matches!(looping, image::metadata::LoopCount::Infinite));
    let frames: Vec<image::Frame> = frames.collect::<Result<_, _>>().unwrap();
    assert_eq!(frames.len(), FRAMES as usize);
    let mut elapsed = 0u32;
    frames
        .into_iter()
        .map(|f| {
            let (n, d) = f.delay().numer_denom_ms();
            assert_eq!(n % d, 0);
            elapsed += n / d;
            (elapsed, rgba(f))
        })
        .collect()
}

/// The GIF: 6 frames of 64×48 looping forever, delays in 1/100 s adding up to k/15 s, each
/// frame exactly the still reduced by glview's quantizer and, checked without it, within
/// the palette tolerance of the still: every pixel the nearest of its frame's colours (no
/// dithering) and the mean error within 6 levels, the quantizer's bound on a dense
/// gradient (`anim_out::gif` tests; these frames have fewer colours, measured 0.0–0.25).
#[test]
fn gif_frames_are_the_quantized_stills() {
    let path = animated("turn.gif", &[]);
    let file = std::io::BufReader::new(std::fs::File::open(&path).unwrap());
    let dec = image::codecs::gif::GifDecoder::new(file).unwrap();
    let looping = dec.loop_count();
    let mut decoded = Vec::new();
    for (k, (elapsed, frame)) in timed_frames(looping, dec.into_frames())
        .into_iter()
        .enumerate()
    {
        // The delays are whole 1/100 s and keep time: frames 0..=k end at (k+1)/15 s.
        assert_eq!(
            elapsed,
            ((k as f32 + 1.0) * 100.0 / FPS).round() as u32 * 10
        );
        let still = &stills()[k];
        let q = glview::anim_out::gif::quantize(still).to_rgba(64, 48);
        assert!(frame == q, "GIF frame {k} is not the quantized still");
        let colours: std::collections::BTreeSet<[u8; 3]> = frame
            .data
            .chunks_exact(4)
            .map(|p| [p[0], p[1], p[2]])
            .collect();
        assert!(colours.len() <= 256);
        let list: Vec<[u8; 3]> = colours.into_iter().collect();
        let dist = |a: &[u8], b: &[u8; 3]| -> u32 {
            (0..3).map(|i| u32::from(a[i].abs_diff(b[i])).pow(2)).sum()
        };
        let mut total = 0u64;
        for (p, s) in frame.data.chunks_exact(4).zip(still.data.chunks_exact(4)) {
            let got = dist(s, &[p[0], p[1], p[2]]);
            let best = list.iter().map(|c| dist(s, c)).min().unwrap();
            assert_eq!(got, best, "frame {k}: a pixel is not its nearest colour");
            total += (0..3).map(|i| u64::from(p[i].abs_diff(s[i]))).sum::<u64>();
        }
        let mean = total as f64 / (64.0 * 48.0 * 3.0);
        assert!(mean <= 6.0, "frame {k}: mean error {mean:.2} levels");
        decoded.push(frame);
    }
    sheet(&decoded, "gif-frames.png");
}

/// The WebP: an animated extended-format file (RIFF length right, VP8X with the animation
/// flag, ANIM looping forever, one ANMF per frame), whose frames the `image` crate decodes
/// byte for byte to the stills (lossless), with millisecond delays keeping time.
#[test]
fn webp_frames_are_the_stills() {
    let path = animated("turn.webp", &[]);
    let bytes = std::fs::read(&path).unwrap();
    assert_eq!(&bytes[..4], b"RIFF");
    assert_eq!(
        u32::from_le_bytes(bytes[4..8].try_into().unwrap()) as usize,
        bytes.len() - 8
    );
    assert_eq!(&bytes[8..16], b"WEBPVP8X");
    assert_eq!(bytes[20] & 0x02, 0x02, "VP8X animation flag");
    assert_eq!(&bytes[30..34], b"ANIM");
    let anmf = bytes.windows(4).filter(|w| w == b"ANMF").count();
    assert_eq!(anmf, FRAMES as usize);
    let dec = image::codecs::webp::WebPDecoder::new(std::io::Cursor::new(bytes)).unwrap();
    let looping = dec.loop_count();
    let mut decoded = Vec::new();
    for (k, (elapsed, frame)) in timed_frames(looping, dec.into_frames())
        .into_iter()
        .enumerate()
    {
        assert_eq!(elapsed, ((k as f32 + 1.0) * 1000.0 / FPS).round() as u32);
        assert!(
            frame == stills()[k],
            "WebP frame {k} differs from the still"
        );
        decoded.push(frame);
    }
    sheet(&decoded, "webp-frames.png");
}

/// The same command twice gives the same bytes, in every format.
#[test]
fn animated_pictures_are_deterministic() {
    for ext in ["apng", "gif", "webp"] {
        let a = std::fs::read(animated(&format!("again-a.{ext}"), &[])).unwrap();
        let b = std::fs::read(animated(&format!("again-b.{ext}"), &[])).unwrap();
        assert!(a == b, "{ext}: two runs differ");
    }
}

/// Bad values are one-line errors naming what is wrong, and leave no file behind.
#[test]
fn bad_values_are_one_line_errors() {
    let d = dir();
    let out = |n: &str| d.join(n).to_str().unwrap().to_string();
    let cases: &[(&[&str], &str)] = &[
        (
            &["-o", &out("fps0.gif"), "--turntable", "--fps", "0"],
            "--fps",
        ),
        (
            &["-o", "/nonexistent-dir/x.gif", "--turntable"],
            "/nonexistent-dir/x.gif",
        ),
        (
            &["-o", &out("long.apng"), "--turntable", "--duration", "600"],
            "at most 3600",
        ),
        (
            &["-o", &out("long.apng"), "--turntable", "--duration", "601"],
            "600 seconds",
        ),
        (&["-o", &out("still.webp"), "--size", SIZE], "--turntable"),
        (
            &["-o", &out("fast.gif"), "--turntable", "--fps", "60"],
            "50 frames per second",
        ),
        (&["-o", &out("turn.png"), "--turntable"], "animated picture"),
        (
            &["-o", &out("at.gif"), BOX, "--time", "1"],
            "add --turntable",
        ),
    ];
    for (args, says) in cases {
        let o = run(args, &[]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{args:?} succeeded");
        assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: {err}");
        assert!(
            err.starts_with("error: ") && err.contains(says),
            "{args:?}: {err}"
        );
        assert!(!Path::new(args[1]).exists(), "{args:?} left {}", args[1]);
    }
}

/// The truth on Khronos's BoxAnimated (node translation and rotation, committed
/// with its licence under tests/data/khronos/motion/): frame k of the animated picture is,
/// byte for byte, the still `--time t` with t = k/fps. The frames move (else the test
/// would pass on a renderer that ignored the time).
#[test]
fn a_moment_is_its_frame() {
    let model = repo().join(BOX);
    let model = model.to_str().unwrap();
    let out = dir().join("box.apng");
    let args = [
        model,
        "-o",
        out.to_str().unwrap(),
        "--size",
        SIZE,
        "--duration",
        "1.2",
    ];
    match fixture::render(&args) {
        Some(Ok(())) => {}
        other => panic!("glview {args:?}: {other:?}"),
    }
    let file = std::io::BufReader::new(std::fs::File::open(&out).unwrap());
    let mut reader = png::Decoder::new(file).read_info().unwrap();
    assert_eq!(reader.info().animation_control.unwrap().num_frames, 18);
    let mut frames = Vec::new();
    for _ in 0..18 {
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut buf).unwrap();
        buf.truncate(info.buffer_size());
        frames.push(buf);
    }
    let mut looked = Vec::new();
    for k in [0u32, 7, 17] {
        let t = (k as f32 / FPS).to_string();
        let still = render(
            &dir(),
            &format!("box-{k}"),
            &[model, "--size", SIZE, "--time", &t],
            &[],
        );
        assert!(
            still.data == frames[k as usize],
            "frame {k} is not the still --time {t}"
        );
        looked.push(still);
    }
    assert_ne!(looked[0], looked[1], "the box moves");
    sheet(&looked, "box-moments.png");
}

/// A stereo turntable (`--stereo side-by-side-full`, twice as wide): each APNG frame is the
/// stereo still of its yaw, byte for byte.
#[test]
fn stereo_turntable_frames_are_the_stereo_stills() {
    let path = animated("turn-stereo.apng", &["--stereo", "side-by-side-full"]);
    let file = std::io::BufReader::new(std::fs::File::open(&path).unwrap());
    let mut reader = png::Decoder::new(file).read_info().unwrap();
    for k in [0, 3] {
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        let mut out = reader.next_frame(&mut buf).unwrap();
        if k == 3 {
            for _ in 1..3 {
                out = reader.next_frame(&mut buf).unwrap();
            }
        }
        assert_eq!((out.width, out.height), (128, 48));
        let yaw = glview::session::turntable_yaw(YAW, k, FRAMES).to_string();
        let args = [
            "--size",
            SIZE,
            "--yaw",
            &yaw,
            "--stereo",
            "side-by-side-full",
        ];
        let still = render(&dir(), &format!("stereo-still-{k}"), &args, &[]);
        assert!(
            buf[..out.buffer_size()] == still.data[..],
            "stereo APNG frame {k} differs from the stereo still"
        );
    }
}
