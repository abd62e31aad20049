//! `glview batch JOBS`: pictures from one process equal the pictures of one process each,
//! and failing jobs are reported by line without stopping the others.
use crate::common::*;
use glview::image_out::Rgba;
use glview::image_out::RgbaFiles;

#[test]
fn batch_equals_single_runs_and_reports_failures_by_line() {
    let dir = out_dir("batch");
    let p = |n: &str| dir.join(n).to_str().unwrap().to_string();
    let cube = dir.join("cube.obj");
    std::fs::write(&cube, box_obj([-1.0; 3], [1.0; 3], 0)).unwrap();
    let jobs = [
        // Two sizes and a reused size: the kept context's target is resized both ways.
        format!("--size 96x64 --yaw 30 --no-shadows -o {}", p("a.png")),
        // The words of the first job but for camera and size: its renderer is kept (uploaded
        // scene, maps) and must give what a fresh one gives.
        format!(
            "--size 80x80 --no-shadows --yaw 200 --keys 'Up W' -o {}",
            p("e.png")
        ),
        format!(
            "'{}' --size 64x80 --pitch 40 -o {}",
            cube.display(),
            p("b.png")
        ),
        "# a comment line, then a blank one".to_string(),
        String::new(),
        format!("{} -o {}", p("missing.obj"), p("c.png")),
        "--size 32x32".to_string(),
        format!("--size 96x64 --shading pbr --no-shadows -o {}", p("d.png")),
    ];
    let file = dir.join("jobs.txt");
    std::fs::write(&file, jobs.join("\n")).unwrap();
    let o = run(&["batch", file.to_str().unwrap()], &[]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "some jobs fail: exit 1\n{err}");
    let f = file.display();
    assert!(err.contains(&format!("error: {f}:6: ")), "{err}");
    assert!(err.contains("missing.obj"), "{err}");
    assert!(
        err.contains(&format!("error: {f}:7: a batch job needs --output")),
        "{err}"
    );
    assert!(
        err.contains(&format!("error: {f}: 2 of 6 jobs failed (lines 6, 7)")),
        "{err}"
    );
    assert!(!dir.join("c.png").exists());
    // Every good job: the same pixels as the same command line run alone.
    for (name, line) in [
        ("a", &jobs[0]),
        ("e", &jobs[1]),
        ("b", &jobs[2]),
        ("d", &jobs[7]),
    ] {
        let words = shlex::split(line).unwrap();
        let alone = dir.join(format!("{name}-alone.png"));
        let mut args: Vec<&str> = words.iter().map(String::as_str).collect();
        let at = args.iter().position(|w| *w == "-o").unwrap();
        let alone_s = alone.to_str().unwrap().to_string();
        args[at + 1] = &alone_s;
        let single = run(&args, &[]);
        assert!(single.status.success(), "{name}: {:?}", single);
        let a = Rgba::load_png(&dir.join(format!("{name}.png"))).unwrap();
        let b = Rgba::load_png(&alone).unwrap();
        check_frame(&a, name);
        assert_close(&dir, &format!("batch-{name}"), &a, &b, 0, 0, 0);
    }
}

#[test]
fn batch_refuses_a_file_with_unbalanced_quotes_naming_the_line() {
    let dir = out_dir("batch-quotes");
    let file = dir.join("jobs.txt");
    std::fs::write(&file, "--size 8x8 -o a.png\n'unclosed -o b.png\n").unwrap();
    let o = run(&["batch", file.to_str().unwrap()], &[]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(
        err.trim(),
        format!("error: {}:2: unbalanced quotes", file.display())
    );
}

/// `--animation` and `--time` on batch lines (issue 39's "batch: time=, animation="), on the
/// committed Khronos InterpolationTest.glb: its "Linear Translation" (animation 8) by index
/// and by name at one moment, and at another. Every picture is the very bytes `glview -o`
/// writes for the same words run alone; the name and the index draw the same pixels; the two
/// moments differ. Bad values fail their own line with one line naming the jobs file and the
/// line (never a panic), and the good lines still render.
#[test]
fn batch_renders_moments_by_time_and_animation() {
    let dir = out_dir("batch-motion");
    let p = |n: &str| dir.join(n).to_str().unwrap().to_string();
    let model = "tests/data/khronos/motion/InterpolationTest.glb";
    let job = |words: &str, out: &str| format!("{model} --size 64x48 {words} -o {}", p(out));
    let jobs = [
        job("--animation 8 --time 0.5", "index.png"),
        job("--animation 'Linear Translation' --time=0.5", "name.png"),
        job("--animation 8 --time 1.25", "later.png"),
        job("--time nan", "nan.png"),
        job("--time -1", "negative.png"),
        job("--animation nosuch --time 0.5", "nosuch.png"),
    ];
    let file = dir.join("jobs.txt");
    std::fs::write(&file, jobs.join("\n")).unwrap();
    let o = run(&["batch", file.to_str().unwrap()], &[]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "some jobs fail: exit 1\n{err}");
    assert!(!err.contains("panicked"), "{err}");
    let f = file.display();
    let errors: Vec<&str> = err.lines().filter(|l| l.starts_with("error: ")).collect();
    let want = [
        (4, "--time: NaN must be a finite number of seconds"),
        (5, "--time: -1 must be a finite number of seconds"),
        (6, "--animation nosuch: "),
    ];
    assert_eq!(errors.len(), want.len() + 1, "one line per bad job:\n{err}");
    for ((line, says), got) in want.iter().zip(&errors) {
        assert!(
            got.starts_with(&format!("error: {f}:{line}: ")) && got.contains(says),
            "line {line}: {got}\n{err}"
        );
    }
    assert!(
        err.contains(&format!("error: {f}: 3 of 6 jobs failed (lines 4, 5, 6)")),
        "{err}"
    );
    for bad in ["nan.png", "negative.png", "nosuch.png"] {
        assert!(!dir.join(bad).exists(), "{bad}");
    }
    // Every good job: the bytes of the same words run alone (the PNG's text included).
    for (name, line) in [("index", &jobs[0]), ("name", &jobs[1]), ("later", &jobs[2])] {
        let words = shlex::split(line).unwrap();
        let alone = p(&format!("{name}-alone.png"));
        let mut args: Vec<&str> = words.iter().map(String::as_str).collect();
        let at = args.iter().position(|w| *w == "-o").unwrap();
        args[at + 1] = &alone;
        let single = run(&args, &[]);
        assert!(single.status.success(), "{name}: {single:?}");
        let batch = std::fs::read(dir.join(format!("{name}.png"))).unwrap();
        assert!(
            batch == std::fs::read(&alone).unwrap(),
            "{name}: batch and alone differ"
        );
    }
    let load = |n: &str| Rgba::load_png(&dir.join(n)).unwrap();
    let (index, name, later) = (load("index.png"), load("name.png"), load("later.png"));
    check_frame(&index, "index");
    assert_close(&dir, "batch-motion-name", &name, &index, 0, 0, 0);
    assert!(
        index.data != later.data,
        "0.5 s and 1.25 s draw the same picture"
    );
}
