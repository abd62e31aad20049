//! The error-against-time plot (plotters, drawn into memory and saved with `png`), and the
//! Pareto front: the settings no other setting beats on both time and error.
use glview::image_out::RgbaFiles;
use glview::{Error, Result};
use plotters::prelude::*;
use std::path::Path;

/// One setting on the plot.
#[derive(Clone, Debug)]
pub struct Point {
    pub label: String,
    /// The knob group (off, size_pcf, bias, shading, pbr): decides the colour.
    pub group: &'static str,
    pub x: f64,
    pub y: f64,
    pub default: bool,
}

/// Whether each point is Pareto-optimal for minimising both coordinates: no other point is
/// at least as good in both and better in one. Points with a NaN are never on the front.
pub fn pareto(points: &[(f64, f64)]) -> Vec<bool> {
    points
        .iter()
        .map(|&(x, y)| {
            !x.is_nan()
                && !y.is_nan()
                && !points
                    .iter()
                    .any(|&(a, b)| a <= x && b <= y && (a < x || b < y))
        })
        .collect()
}

/// One chart: a y-axis title and its points.
#[derive(Clone, Debug)]
pub struct Panel {
    pub x_title: String,
    pub y_title: String,
    pub points: Vec<Point>,
}

const FONT: &str = "sans-serif";

/// Fonts tried for the labels; Debian's fonts-dejavu-core installs the first.
const FONT_FILES: &[&str] = &[
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/TTF/DejaVuSans.ttf",
    "/usr/share/fonts/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/truetype/liberation/LiberationSans-Regular.ttf",
];

fn register_font() -> Result<()> {
    static REGISTERED: std::sync::OnceLock<std::result::Result<(), String>> =
        std::sync::OnceLock::new();
    REGISTERED
        .get_or_init(|| {
            let path = FONT_FILES
                .iter()
                .find(|p| Path::new(p).is_file())
                .ok_or("no TrueType font found (apt-get install fonts-dejavu-core)")?;
            let bytes = std::fs::read(path).map_err(|e| format!("{path}: {e}"))?;
            // plotters keeps fonts for the life of the process.
            let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
            plotters::style::register_font(FONT, FontStyle::Normal, bytes)
                .map_err(|_| format!("{path}: not a usable font"))
        })
        .clone()
        .map_err(Error::Unsupported)
}

fn colour(p: &Point) -> RGBColor {
    let pcf = p.label.split('/').nth(1).unwrap_or("");
    match (p.group, pcf) {
        ("off", _) => RGBColor(0, 0, 0),
        ("bias", _) => RGBColor(127, 127, 127),
        ("shading", _) => RGBColor(140, 86, 75),
        ("pbr", _) => RGBColor(23, 190, 207),
        (_, "1") => RGBColor(31, 119, 180),
        (_, "4") => RGBColor(44, 160, 44),
        (_, "9") => RGBColor(255, 127, 14),
        _ => RGBColor(148, 103, 189),
    }
}

const LEGEND: &[(&str, RGBColor)] = &[
    ("size/PCF 1", RGBColor(31, 119, 180)),
    ("size/PCF 4", RGBColor(44, 160, 44)),
    ("size/PCF 9", RGBColor(255, 127, 14)),
    ("size/PCF 16", RGBColor(148, 103, 189)),
    ("bias (2048/4)", RGBColor(127, 127, 127)),
    ("Gouraud (2048/4)", RGBColor(140, 86, 75)),
    ("shadows off", RGBColor(0, 0, 0)),
    ("PBR precompute setting", RGBColor(23, 190, 207)),
];

/// Draws the panels in a grid of two columns: x = mean frame time, the Pareto front as a red
/// line through red rings, the default setting in a large black ring.
pub fn error_vs_time(path: &Path, title: &str, panels: &[Panel]) -> Result<()> {
    register_font()?;
    let cols = panels.len().clamp(1, 2) as u32;
    let rows = (panels.len() as u32).div_ceil(cols).max(1);
    let (w, h) = (900 * cols, 40 + 660 * rows);
    let mut buf = vec![0u8; (w * h * 3) as usize];
    draw(&mut buf, (w, h), title, panels).map_err(|e| Error::Image {
        path: path.into(),
        message: format!("plot: {e}"),
    })?;
    let rgba: Vec<u8> = buf
        .chunks_exact(3)
        .flat_map(|p| [p[0], p[1], p[2], 255])
        .collect();
    glview::image_out::Rgba {
        width: w,
        height: h,
        data: rgba,
    }
    .save_png(
        path,
        &[("Software", format!("glview {}", env!("CARGO_PKG_VERSION")))],
    )
}

type DrawResult = std::result::Result<(), Box<dyn std::error::Error>>;

fn draw(buf: &mut [u8], size: (u32, u32), title: &str, panels: &[Panel]) -> DrawResult {
    let root = BitMapBackend::with_buffer(buf, size).into_drawing_area();
    root.fill(&WHITE)?;
    let root = root.titled(title, (FONT, 22))?;
    let cols = panels.len().clamp(1, 2);
    let areas = root.split_evenly((panels.len().div_ceil(cols).max(1), cols));
    for (area, p) in areas.iter().zip(panels) {
        panel(area, &p.x_title, &p.y_title, &p.points)?;
    }
    root.present()?;
    Ok(())
}

fn panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    xtitle: &str,
    ytitle: &str,
    points: &[Point],
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let finite: Vec<&Point> = points
        .iter()
        .filter(|p| p.x.is_finite() && p.y.is_finite())
        .collect();
    let xmax = finite.iter().map(|p| p.x).fold(1.0, f64::max) * 1.08;
    let xmin = finite.iter().map(|p| p.x).fold(xmax, f64::min) * 0.9;
    let ymax = finite.iter().map(|p| p.y).fold(1e-9, f64::max) * 1.08;
    let mut chart = ChartBuilder::on(area)
        .margin(16)
        .x_label_area_size(46)
        .y_label_area_size(70)
        .build_cartesian_2d(xmin..xmax, 0.0..ymax)?;
    chart
        .configure_mesh()
        .x_desc(xtitle)
        .y_desc(ytitle)
        .label_style((FONT, 15))
        .axis_desc_style((FONT, 16))
        .draw()?;
    let on_front = pareto(&finite.iter().map(|p| (p.x, p.y)).collect::<Vec<_>>());
    let mut front: Vec<(f64, f64)> = finite
        .iter()
        .zip(&on_front)
        .filter(|(_, &f)| f)
        .map(|(p, _)| (p.x, p.y))
        .collect();
    front.sort_by(|a, b| a.0.total_cmp(&b.0));
    chart
        .draw_series(LineSeries::new(front.clone(), RED.stroke_width(2)))?
        .label("Pareto front")
        .legend(|(x, y)| PathElement::new(vec![(x - 8, y), (x + 8, y)], RED.stroke_width(2)));
    chart.draw_series(
        front
            .iter()
            .map(|&(x, y)| Circle::new((x, y), 8, RED.stroke_width(2))),
    )?;
    for &(name, c) in LEGEND {
        let members: Vec<&&Point> = finite.iter().filter(|p| colour(p) == c).collect();
        if members.is_empty() {
            continue;
        }
        chart
            .draw_series(members.iter().map(|p| {
                EmptyElement::at((p.x, p.y))
                    + Circle::new((0, 0), 4, c.filled())
                    + Text::new(p.label.clone(), (6, -14), (FONT, 12).into_font().color(&c))
            }))?
            .label(name)
            .legend(move |(x, y)| Circle::new((x, y), 4, c.filled()));
    }
    if let Some(d) = finite.iter().find(|p| p.default) {
        chart
            .draw_series(std::iter::once(Circle::new(
                (d.x, d.y),
                12,
                BLACK.stroke_width(2),
            )))?
            .label("current default")
            .legend(|(x, y)| Circle::new((x, y), 6, BLACK.stroke_width(2)));
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font((FONT, 14))
        .draw()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pareto_front() {
        let p = [
            (1.0, 5.0),
            (2.0, 3.0),
            (3.0, 4.0),
            (4.0, 1.0),
            (2.0, 3.0),
            (5.0, f64::NAN),
        ];
        assert_eq!(pareto(&p), [true, true, false, true, true, false]);
    }
}
