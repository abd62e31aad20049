//! The quality benchmark's results: rows per scene × setting, means over scenes with their
//! Pareto fronts, the tables printed, and `quality.csv`, `quality.json`, `quality.png`.
use super::knobs::Knob;
use super::metrics::ImageError;
use super::plot::{self, Panel, Point};
use super::table::{csv_line, num, Table};
use super::write_file;
use glview::{Error, Result};
use serde::Serialize;
use std::path::Path;

/// One scene × setting.
#[derive(Clone, Debug, Serialize)]
pub struct Row {
    pub scene: String,
    pub knob: Knob,
    pub default: bool,
    /// Median frame time with the shadow pass run (ms).
    pub ms: f64,
    pub ms_min: f64,
    /// Median frame time with the shadow map reused (ms).
    pub ms_reused: f64,
    /// `ms` relative to the same scene's frame without shadows.
    pub ms_vs_off: f64,
    /// Against the reference at pixel centres.
    pub error: ImageError,
    /// Against the supersampled (anti-aliased) reference.
    pub error_aa: ImageError,
}

#[derive(Clone, Debug, Serialize)]
pub struct SceneInfo {
    pub name: String,
    pub command: String,
    pub triangles: usize,
    pub reference_ms: f64,
    pub reference_aa_ms: f64,
    /// Share of pixels left out of every metric (translucent layers).
    pub ignored: f64,
}

/// A setting's figures averaged over the scenes.
#[derive(Clone, Debug, Serialize)]
pub struct Summary {
    pub label: String,
    pub group: &'static str,
    pub options: String,
    pub default: bool,
    pub ms: f64,
    pub ms_reused: f64,
    pub ms_vs_default: f64,
    pub error: ImageError,
    pub error_aa: ImageError,
    /// On the Pareto front of time against: share > 8/255, 1 − SSIM, and both against the
    /// anti-aliased reference.
    pub pareto: [bool; 4],
}

#[derive(Serialize)]
pub struct Report {
    pub renderer: String,
    pub gl_version: String,
    pub backend: &'static str,
    pub size: (u32, u32),
    pub warmup_rounds: usize,
    pub timed_rounds: usize,
    pub supersample: u32,
    pub wrong_threshold: u8,
    pub load_average: String,
    pub scenes: Vec<SceneInfo>,
    pub summary: Vec<Summary>,
    pub rows: Vec<Row>,
}

/// An error measure: its title and how to read it from a summary.
type Measure = (&'static str, fn(&Summary) -> f64);

/// The four error measures the fronts are drawn for.
const MEASURES: [Measure; 4] = [
    ("pixels off by > 8/255 (%)", |s| 100.0 * s.error.wrong),
    ("1 - SSIM", |s| 1.0 - s.error.ssim),
    ("pixels off by > 8/255 (%), anti-aliased reference", |s| {
        100.0 * s.error_aa.wrong
    }),
    ("1 - SSIM, anti-aliased reference", |s| {
        1.0 - s.error_aa.ssim
    }),
];

fn mean(v: impl Iterator<Item = f64>) -> f64 {
    let (s, n) = v.fold((0.0, 0usize), |(s, n), x| (s + x, n + 1));
    if n == 0 {
        f64::NAN
    } else {
        s / n as f64
    }
}

fn mean_error(errors: &[ImageError]) -> ImageError {
    let m = |f: fn(&ImageError) -> f64| mean(errors.iter().map(f));
    ImageError {
        mae: m(|e| e.mae),
        p99: m(|e| e.p99),
        max: m(|e| e.max),
        wrong: m(|e| e.wrong),
        ssim: m(|e| e.ssim),
    }
}

/// Means over scenes per setting, and the Pareto fronts.
pub fn summarize(knobs: &[Knob], rows: &[Row]) -> Vec<Summary> {
    let mut out: Vec<Summary> = knobs
        .iter()
        .map(|k| {
            let of: Vec<&Row> = rows.iter().filter(|r| r.knob.label == k.label).collect();
            Summary {
                label: k.label.clone(),
                group: k.group,
                options: k.options(),
                default: k.is_default(),
                ms: mean(of.iter().map(|r| r.ms)),
                ms_reused: mean(of.iter().map(|r| r.ms_reused)),
                ms_vs_default: f64::NAN,
                error: mean_error(&of.iter().map(|r| r.error).collect::<Vec<_>>()),
                error_aa: mean_error(&of.iter().map(|r| r.error_aa).collect::<Vec<_>>()),
                pareto: [false; 4],
            }
        })
        .collect();
    let default_ms = out.iter().find(|s| s.default).map_or(f64::NAN, |s| s.ms);
    for (m, (_, f)) in MEASURES.iter().enumerate() {
        let front = plot::pareto(&out.iter().map(|s| (s.ms, f(s))).collect::<Vec<_>>());
        for (s, on) in out.iter_mut().zip(front) {
            s.pareto[m] = on;
        }
    }
    for s in &mut out {
        s.ms_vs_default = s.ms / default_ms;
    }
    out
}

/// The columns of both tables; `ratio` names the time ratio column.
fn columns(ratio: &'static str, pareto: bool) -> Vec<&'static str> {
    let mut c = vec![
        "setting",
        "ms",
        ratio,
        "reused",
        "MAE",
        "p99",
        ">8/255 %",
        "1-SSIM",
        "AA >8 %",
        "AA 1-SSIM",
    ];
    if pareto {
        c.push("Pareto");
    }
    c
}

/// One row: label, [ms, ratio, reused ms], then the exact and anti-aliased error measures.
fn cells(
    label: String,
    times: [f64; 3],
    e: &ImageError,
    aa: &ImageError,
    p99_digits: usize,
) -> Vec<String> {
    vec![
        label,
        num(times[0], 1),
        num(times[1], 2),
        num(times[2], 1),
        num(e.mae, 2),
        num(e.p99, p99_digits),
        num(100.0 * e.wrong, 2),
        num(1.0 - e.ssim, 4),
        num(100.0 * aa.wrong, 2),
        num(1.0 - aa.ssim, 4),
    ]
}

pub fn scene_table(info: &SceneInfo, rows: &[Row]) -> String {
    let mut t = Table::new(&columns("x off", false));
    for r in rows {
        let mark = if r.default { " *" } else { "" };
        let label = format!("{}{mark}", r.knob.label);
        t.row(cells(
            label,
            [r.ms, r.ms_vs_off, r.ms_reused],
            &r.error,
            &r.error_aa,
            0,
        ));
    }
    format!(
        "== {} ({} triangles): glview {}\n{}",
        info.name,
        info.triangles,
        info.command,
        t.render()
    )
}

pub fn summary_table(summary: &[Summary]) -> String {
    let mut t = Table::new(&columns("x default", true));
    for s in summary {
        let mark = if s.default { " *" } else { "" };
        let p: String = s
            .pareto
            .iter()
            .map(|&p| if p { 'P' } else { '.' })
            .collect();
        let mut row = cells(
            format!("{}{mark}", s.label),
            [s.ms, s.ms_vs_default, s.ms_reused],
            &s.error,
            &s.error_aa,
            1,
        );
        row.push(p);
        t.row(row);
    }
    let mut out = String::from("== mean over scenes\n");
    out.push_str(&t.render());
    for (m, (title, _)) in MEASURES.iter().enumerate() {
        let front: Vec<&str> = summary
            .iter()
            .filter(|s| s.pareto[m])
            .map(|s| s.label.as_str())
            .collect();
        out.push_str(&format!(
            "Pareto front, time against {title}: {}\n",
            front.join(", ")
        ));
    }
    out.push_str(
        "* = current default. ms = frame with the shadow pass, reused = shadow map kept (medians, \
         mean over scenes).\nPareto column: P where on the front of each measure, in the order \
         listed above.\n",
    );
    out
}

pub fn write_outputs(dir: &Path, report: &Report) -> Result<()> {
    let header = [
        "scene",
        "setting",
        "group",
        "default",
        "shadows",
        "shadow_size",
        "pcf",
        "bias",
        "shading",
        "ms_median",
        "ms_min",
        "ms_reused_median",
        "ms_vs_off",
        "mae",
        "p99",
        "max",
        "share_gt_8",
        "ssim",
        "aa_mae",
        "aa_p99",
        "aa_share_gt_8",
        "aa_ssim",
    ];
    let mut csv = csv_line(&header.map(String::from));
    for r in &report.rows {
        let k = &r.knob;
        let (e, a) = (&r.error, &r.error_aa);
        csv.push_str(&csv_line(&[
            r.scene.clone(),
            k.label.clone(),
            k.group.into(),
            r.default.to_string(),
            k.shadows.to_string(),
            k.size.to_string(),
            k.pcf.to_string(),
            k.bias.to_string(),
            k.shading.word().into(),
            num(r.ms, 3),
            num(r.ms_min, 3),
            num(r.ms_reused, 3),
            num(r.ms_vs_off, 4),
            num(e.mae, 4),
            num(e.p99, 0),
            num(e.max, 0),
            num(e.wrong, 6),
            num(e.ssim, 6),
            num(a.mae, 4),
            num(a.p99, 0),
            num(a.wrong, 6),
            num(a.ssim, 6),
        ]));
    }
    write_file(&dir.join("quality.csv"), &csv)?;
    let json =
        serde_json::to_string_pretty(report).map_err(|e| Error::Usage(format!("JSON: {e}")))?;
    write_file(&dir.join("quality.json"), &(json + "\n"))?;
    let panels: Vec<Panel> = MEASURES
        .iter()
        .map(|(title, f)| Panel {
            x_title: "frame time with the shadow pass (ms), mean over scenes".into(),
            y_title: format!("{title}, mean over scenes"),
            points: report
                .summary
                .iter()
                .map(|s| Point {
                    label: s.label.clone(),
                    group: s.group,
                    x: s.ms,
                    y: f(s),
                    default: s.default,
                })
                .collect(),
        })
        .collect();
    let title = format!(
        "glview bench: error against frame time, {} scenes at {}x{}, {} ({})",
        report.scenes.len(),
        report.size.0,
        report.size.1,
        report.renderer,
        report.backend
    );
    match plot::error_vs_time(&dir.join("quality.png"), &title, &panels) {
        Err(Error::Unsupported(msg)) => {
            eprintln!("warning: no plot: {msg}");
            Ok(())
        }
        other => other,
    }
}
