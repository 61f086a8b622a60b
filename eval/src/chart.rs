//! Charts of a report (plotters): frame time against shimmer (log scale) and against colour
//! error (in a report without the raster, coverage error), one labelled point per method ×
//! face resolution (averaged over paths); and per
//! path, bars of shimmer by method. Written as PNG (text through a bundled font, so no
//! system font is needed) and SVG.

use std::collections::BTreeMap;
use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::report::Report;

/// Why a chart could not be drawn.
#[derive(Debug, thiserror::Error)]
#[error("chart {0}: {1}")]
pub struct ChartError(String, String);

const METHODS: [&str; 8] = [
    "raster",
    "naive",
    "snap",
    "cubemap",
    "splat-paper",
    "splat",
    "march",
    "splat-facing",
];
const COLOURS: [RGBColor; 8] = [
    RGBColor(120, 120, 120),
    RGBColor(214, 96, 77),
    RGBColor(244, 165, 60),
    RGBColor(102, 166, 30),
    RGBColor(117, 112, 179),
    RGBColor(31, 120, 180),
    RGBColor(231, 41, 138),
    RGBColor(166, 206, 227),
];
/// Methods run on a few paths only (a variant to compare there): in the per-path bars, not
/// in the scatter plots, whose points average over every path.
const BARS_ONLY: [&str; 1] = ["splat-facing"];
const FONT: &str = "sans-serif";
const SHIMMER_FLOOR: f64 = 1e-4;

fn colour(method: &str) -> RGBColor {
    METHODS
        .iter()
        .position(|m| *m == method)
        .map_or(BLACK, |i| COLOURS[i])
}

/// One point of the scatter plots.
#[derive(Debug, Clone, PartialEq)]
pub struct Point {
    /// Method name.
    pub method: String,
    /// Face resolution (0 for raster, which has none).
    pub face_res: u32,
    /// Mean over paths of the median frame time, ms.
    pub frame_ms: f64,
    /// Mean over paths of the mean shimmer.
    pub shimmer: f64,
    /// Mean over paths of the coverage error.
    pub coverage_error: f64,
    /// Mean over paths of the mean colour error (none when no run has one).
    pub colour_error: Option<f64>,
}

/// The scatter points of `report`: one per method × face resolution, averaged over paths.
pub fn points(report: &Report) -> Vec<Point> {
    let mut groups: BTreeMap<(usize, u32, String), Vec<[f64; 4]>> = BTreeMap::new();
    for r in report
        .runs
        .iter()
        .filter(|r| !BARS_ONLY.contains(&r.method.as_str()))
    {
        let order = METHODS.iter().position(|m| *m == r.method).unwrap_or(99);
        // Raster does not depend on the face resolution: one point.
        let face_res = if r.method == "raster" { 0 } else { r.face_res };
        groups
            .entry((order, face_res, r.method.clone()))
            .or_default()
            .push([
                r.frame_ms.median,
                r.shimmer.mean,
                r.coverage_error,
                r.colour_error.map_or(f64::NAN, |c| c.mean),
            ]);
    }
    groups
        .into_iter()
        .map(|((_, face_res, method), v)| {
            let mean = |k: usize| v.iter().map(|x| x[k]).sum::<f64>() / v.len() as f64;
            let colours: Vec<f64> = v.iter().map(|x| x[3]).filter(|c| !c.is_nan()).collect();
            Point {
                method,
                face_res,
                frame_ms: mean(0),
                shimmer: mean(1),
                coverage_error: mean(2),
                colour_error: (!colours.is_empty())
                    .then(|| colours.iter().sum::<f64>() / colours.len() as f64),
            }
        })
        .collect()
}

/// Writes `<stem>.png` and `<stem>.svg` into `dir`.
pub fn write_charts(report: &Report, dir: &Path, stem: &str) -> Result<(), ChartError> {
    // The PNG backend draws text with fonts registered here; egui's bundled font is pure data.
    let _ =
        plotters::style::register_font(FONT, FontStyle::Normal, epaint_default_fonts::UBUNTU_LIGHT);
    // The bar panels' rows (three panels a row) each get room for readable axes.
    let rows = bar_paths(report).len().div_ceil(3) as u32;
    let size = (1400, (480 + 40 + rows * BAR_ROW_PX).max(1100));
    let png = dir.join(format!("{stem}.png"));
    let svg = dir.join(format!("{stem}.svg"));
    let err = |file: &Path| {
        let f = file.display().to_string();
        move |e: String| ChartError(f.clone(), e)
    };
    let mut rgb = vec![0u8; (size.0 * size.1 * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, size).into_drawing_area();
        draw(&root, report).map_err(err(&png))?;
        root.present().map_err(|e| err(&png)(e.to_string()))?;
    }
    image::save_buffer(&png, &rgb, size.0, size.1, image::ColorType::Rgb8)
        .map_err(|e| err(&png)(e.to_string()))?;
    let root = SVGBackend::new(&svg, size).into_drawing_area();
    draw(&root, report).map_err(err(&svg))?;
    root.present().map_err(|e| err(&svg)(e.to_string()))?;
    Ok(())
}

fn draw<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, report: &Report) -> Result<(), String> {
    let s = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    root.fill(&WHITE).map_err(s)?;
    let (top, bottom) = root.split_vertically(480);
    let (left, right) = top.split_horizontally(700);
    let pts = points(report);
    scatter(&left, &pts, true).map_err(s)?;
    scatter(&right, &pts, false).map_err(s)?;
    bars(&bottom, report).map_err(s)?;
    Ok(())
}

type DrawResult<DB> = Result<(), DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;

fn scatter<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    pts: &[Point],
    shimmer: bool,
) -> DrawResult<DB> {
    let x_max = pts.iter().map(|p| p.frame_ms).fold(1.0, f64::max) * 1.15;
    // The right panel shows the colour error against the full-resolution raster when the
    // report has it (the raster ran), the coverage error otherwise.
    let by_colour = pts.iter().any(|p| p.colour_error.is_some());
    let title = match (shimmer, by_colour) {
        (true, _) => "Shimmer (mean flicker fraction, log) vs frame time",
        (false, true) => "Colour error (mean OKLab ΔE against the raster) vs frame time",
        (false, false) => "Coverage error vs frame time",
    };
    let mut builder = ChartBuilder::on(area);
    builder
        .caption(title, (FONT, 20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70);
    let label = |p: &Point| match p.face_res {
        0 => p.method.clone(),
        n => format!("{}@{n}", p.method),
    };
    let style = |p: &Point| colour(&p.method).filled();
    if shimmer {
        let y_max = pts.iter().map(|p| p.shimmer).fold(0.01, f64::max) * 2.0;
        let mut chart =
            builder.build_cartesian_2d(0.0..x_max, (SHIMMER_FLOOR..y_max).log_scale())?;
        chart
            .configure_mesh()
            .x_desc("median frame ms (lavapipe)")
            .y_desc("shimmer")
            .label_style((FONT, 13))
            .draw()?;
        chart.draw_series(pts.iter().map(|p| {
            let y = p.shimmer.max(SHIMMER_FLOOR);
            EmptyElement::at((p.frame_ms, y))
                + Circle::new((0, 0), 5, style(p))
                + Text::new(label(p), (7, -7), (FONT, 13))
        }))?;
    } else {
        let value = |p: &Point| {
            if by_colour {
                p.colour_error
            } else {
                Some(p.coverage_error)
            }
        };
        let y_max = pts.iter().filter_map(value).fold(0.01, f64::max) * 1.2;
        let mut chart = builder.build_cartesian_2d(0.0..x_max, 0.0..y_max)?;
        chart
            .configure_mesh()
            .x_desc("median frame ms (lavapipe)")
            .y_desc(if by_colour {
                "colour error (ΔE)"
            } else {
                "coverage error"
            })
            .label_style((FONT, 13))
            .draw()?;
        chart.draw_series(pts.iter().filter_map(|p| {
            Some(
                EmptyElement::at((p.frame_ms, value(p)?))
                    + Circle::new((0, 0), 5, style(p))
                    + Text::new(label(p), (7, -7), (FONT, 13)),
            )
        }))?;
    }
    Ok(())
}

/// Height of a row of bar panels, pixels.
const BAR_ROW_PX: u32 = 150;

/// One bar panel per level and path (the same path may fly through two levels), in report
/// order.
fn bar_paths(report: &Report) -> Vec<(&str, &str)> {
    let mut paths: Vec<(&str, &str)> = Vec::new();
    for r in &report.runs {
        let key = (r.level_name(), r.path_name());
        if !paths.contains(&key) {
            paths.push(key);
        }
    }
    paths
}

fn bars<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, report: &Report) -> DrawResult<DB> {
    let face_res = report.runs.iter().map(|r| r.face_res).max().unwrap_or(0);
    let paths = bar_paths(report);
    let first_level = |path: &str| paths.iter().find(|(_, p)| *p == path).map(|(l, _)| *l);
    let cols = 3;
    let rows = paths.len().div_ceil(cols).max(1);
    let title = format!(
        "Shimmer by method and path (face resolution {face_res}; outlined: sprite pixels alone)"
    );
    let area = area.titled(&title, (FONT, 20))?;
    let cells = area.split_evenly((rows, cols));
    for (cell, &(level, path)) in cells.iter().zip(&paths) {
        let runs: Vec<_> = report
            .runs
            .iter()
            .filter(|r| r.level_name() == level && r.path_name() == path)
            .filter(|r| r.face_res == face_res || r.method == "raster")
            .collect();
        // A path's first level names it alone; another level's runs say which.
        let caption = if first_level(path) == Some(level) {
            path.to_owned()
        } else {
            format!("{path} ({level})")
        };
        let y_max = (runs.iter())
            .map(|r| r.shimmer.mean.max(r.sprite_shimmer.unwrap_or(0.0)))
            .fold(0.01, f64::max)
            * 1.15;
        let mut chart = ChartBuilder::on(cell)
            .caption(caption, (FONT, 15))
            .margin(6)
            .x_label_area_size(22)
            .y_label_area_size(48)
            .build_cartesian_2d(0.0..METHODS.len() as f64, 0.0..y_max)?;
        chart
            .configure_mesh()
            .disable_x_mesh()
            .x_labels(METHODS.len() * 2 + 1)
            .x_label_formatter(&|x| {
                let i = (x - 0.5).round();
                if (x - 0.5 - i).abs() < 1e-6 && i >= 0.0 {
                    METHODS
                        .get(i as usize)
                        .map_or(String::new(), |m| m.replace("splat-", ""))
                } else {
                    String::new()
                }
            })
            .y_labels(4)
            .y_label_formatter(&|y| format!("{y:.3}"))
            .label_style((FONT, 12))
            .draw()?;
        chart.draw_series(runs.iter().filter_map(|r| {
            let i = METHODS.iter().position(|m| *m == r.method)? as f64;
            Some(Rectangle::new(
                [(i + 0.15, 0.0), (i + 0.85, r.shimmer.mean)],
                colour(&r.method).filled(),
            ))
        }))?;
        // Sprite pixels apart, as an outlined bar beside the whole image's.
        chart.draw_series(runs.iter().filter_map(|r| {
            let i = METHODS.iter().position(|m| *m == r.method)? as f64;
            Some(Rectangle::new(
                [(i + 0.55, 0.0), (i + 0.95, r.sprite_shimmer?)],
                BLACK.stroke_width(1),
            ))
        }))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::metrics::Summary;
    use crate::report::{RunRecord, Timing};

    fn run(method: &str, path: &str, face_res: u32, ms: f64, shimmer: f64) -> RunRecord {
        RunRecord {
            level: "l.ron".into(),
            path: format!("assets/paths/{path}.ron"),
            method: method.into(),
            face_res,
            frame_ms: Timing {
                median: ms,
                p90: ms,
            },
            shimmer: Summary {
                mean: shimmer,
                p95: shimmer,
                max: shimmer,
            },
            coverage_error: 0.01,
            ..Default::default()
        }
    }

    #[test]
    fn points_average_over_paths_and_charts_are_written() {
        let report = Report {
            runs: vec![
                run("splat", "yaw", 64, 10.0, 0.0),
                run("splat", "orbit", 64, 20.0, 0.02),
                run("naive", "yaw", 64, 4.0, 0.3),
                run("naive", "orbit", 32, 3.0, 0.2),
            ],
            ..Default::default()
        };
        let p = points(&report);
        assert_eq!(p.len(), 3);
        let splat = p.iter().find(|p| p.method == "splat").expect("splat point");
        assert_eq!((splat.frame_ms, splat.shimmer), (15.0, 0.01));
        let dir = tempfile::tempdir().expect("tempdir");
        write_charts(&report, dir.path(), "chart").expect("charts");
        let png = image::open(dir.path().join("chart.png")).expect("a PNG");
        assert_eq!((png.width(), png.height()), (1400, 1100));
        let svg = std::fs::read_to_string(dir.path().join("chart.svg")).expect("an SVG");
        assert!(svg.contains("splat@64") && svg.contains("orbit"));
    }
}
