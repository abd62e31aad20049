//! The load benchmark's results: the rows, the table printed, `load.csv` and `load.json`.
use super::child::Measured;
use super::table::{csv_line, num, Table};
use super::write_file;
use glview::{Error, Result};
use serde::Serialize;
use std::path::Path;

#[derive(Clone, Debug, Default, Serialize)]
pub struct LoadRow {
    pub file: String,
    pub bytes: u64,
    pub triangles: usize,
    pub parse_ms: f64,
    /// In-process load with the mesh cache warm (files of at least `cache::MIN_SIZE`).
    pub warm_load_ms: Option<f64>,
    pub upload_ms: f64,
    pub glview: Measured,
    /// With a warm mesh cache, where the glview binary has one (`--no-cache` in its help).
    pub glview_warm: Option<Measured>,
    pub f3d: Option<Measured>,
}

impl LoadRow {
    pub fn parse_mb_s(&self) -> f64 {
        self.bytes as f64 / 1e6 / (self.parse_ms / 1e3)
    }
    pub fn parse_mtri_s(&self) -> f64 {
        self.triangles as f64 / 1e6 / (self.parse_ms / 1e3)
    }
    pub fn ratio(&self, f: fn(&Measured) -> f64) -> f64 {
        self.f3d
            .as_ref()
            .map_or(f64::NAN, |p| f(&self.glview) / f(p))
    }
}

#[derive(Serialize)]
pub struct LoadReport {
    pub renderer: String,
    pub f3d: Option<String>,
    pub size: (u32, u32),
    pub runs: usize,
    pub memory: &'static str,
    pub glview_has_cache: bool,
    pub rows: Vec<LoadRow>,
    pub large_frame: FrameTime,
}

#[derive(Clone, Debug, Default, Serialize)]
pub struct FrameTime {
    pub file: String,
    pub triangles: usize,
    /// Median frame time with the shadow pass (ms), and with the map reused.
    pub ms_shadow_pass: f64,
    pub ms_reused: f64,
}

pub fn load_table(report: &LoadReport) -> String {
    let mut t = Table::new(&[
        "file",
        "MB",
        "triangles",
        "parse ms",
        "MB/s",
        "Mtri/s",
        "cached ms",
        "upload ms",
        "glview s",
        "f3d s",
        "time g/f",
        "glview MiB",
        "f3d MiB",
        "mem g/f",
        "warm s",
        "warm g/f",
    ]);
    for r in &report.rows {
        let f = r.f3d.unwrap_or(Measured {
            seconds: f64::NAN,
            peak_mib: f64::NAN,
        });
        t.row(vec![
            r.file.clone(),
            num(r.bytes as f64 / 1e6, 1),
            r.triangles.to_string(),
            num(r.parse_ms, 1),
            num(r.parse_mb_s(), 1),
            num(r.parse_mtri_s(), 2),
            r.warm_load_ms.map_or("-".into(), |m| num(m, 1)),
            num(r.upload_ms, 1),
            num(r.glview.seconds, 3),
            num(f.seconds, 3),
            num(r.ratio(|m| m.seconds), 2),
            num(r.glview.peak_mib, 0),
            num(f.peak_mib, 0),
            num(r.ratio(|m| m.peak_mib), 2),
            r.glview_warm.map_or("-".into(), |m| num(m.seconds, 3)),
            r.glview_warm
                .map_or("-".into(), |m| num(m.seconds / f.seconds, 2)),
        ]);
    }
    let lf = &report.large_frame;
    format!(
        "== load: glview vs {} at {}x{}, medians of {} runs; memory: {}\n{}\
         g/f = glview / f3d (below 1: glview is faster or smaller). glview s: --no-cache where \
         glview has a mesh cache; warm s: the cache warm; cached ms: in-process load from the \
         cache (files of 4 MiB or more).\nglview renders with its default shadows; f3d with its \
         defaults (no shadows).\n\
         {} ({} triangles) at {}x{}: frame {:.1} ms with the shadow pass, {:.1} ms with the \
         map reused (median of 7).\n",
        report.f3d.as_deref().unwrap_or("nothing"),
        report.size.0,
        report.size.1,
        report.runs,
        report.memory,
        t.render(),
        Path::new(&lf.file)
            .file_name()
            .map_or(String::new(), |n| n.to_string_lossy().into()),
        lf.triangles,
        report.size.0,
        report.size.1,
        lf.ms_shadow_pass,
        lf.ms_reused
    )
}

pub fn write_outputs(dir: &Path, report: &LoadReport) -> Result<()> {
    let header = [
        "file",
        "bytes",
        "triangles",
        "parse_ms",
        "parse_mb_per_s",
        "parse_mtri_per_s",
        "cached_load_ms",
        "upload_ms",
        "glview_png_s",
        "glview_peak_mib",
        "glview_warm_cache_png_s",
        "f3d_png_s",
        "f3d_peak_mib",
        "time_ratio_glview_f3d",
        "memory_ratio_glview_f3d",
        "warm_time_ratio_glview_f3d",
    ];
    let mut csv = csv_line(&header.map(String::from));
    for r in &report.rows {
        let opt = |m: Option<Measured>, f: fn(&Measured) -> f64| {
            m.map_or(String::new(), |m| num(f(&m), 4))
        };
        csv.push_str(&csv_line(&[
            r.file.clone(),
            r.bytes.to_string(),
            r.triangles.to_string(),
            num(r.parse_ms, 3),
            num(r.parse_mb_s(), 3),
            num(r.parse_mtri_s(), 4),
            r.warm_load_ms.map_or(String::new(), |m| num(m, 3)),
            num(r.upload_ms, 3),
            num(r.glview.seconds, 4),
            num(r.glview.peak_mib, 1),
            opt(r.glview_warm, |m| m.seconds),
            opt(r.f3d, |m| m.seconds),
            opt(r.f3d, |m| m.peak_mib),
            num(r.ratio(|m| m.seconds), 4),
            num(r.ratio(|m| m.peak_mib), 4),
            match (r.glview_warm, r.f3d) {
                (Some(w), Some(f)) => num(w.seconds / f.seconds, 4),
                _ => String::new(),
            },
        ]));
    }
    write_file(&dir.join("load.csv"), &csv)?;
    let json =
        serde_json::to_string_pretty(report).map_err(|e| Error::Usage(format!("JSON: {e}")))?;
    write_file(&dir.join("load.json"), &(json + "\n"))
}
