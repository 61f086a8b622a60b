//! The chart of `texel-eval scale` (plotters, PNG and SVG): on the left each pass's median
//! and the whole frame against the number of entities (log–log), with the reference level's
//! frame and 1.5× it as dashed lines; on the right the peak resident memory and the GPU
//! bytes against the number of entities. Refused towns have no point.

use std::path::Path;

use anyhow::{Result, anyhow};
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::scale::{CHARTED_PASSES, ScaleReport, ScaleRow};

const FONT: &str = "sans-serif";
const SIZE: (u32, u32) = (1200, 520);
const COLOURS: [RGBColor; 5] = [
    RGBColor(20, 20, 20),
    RGBColor(31, 120, 180),
    RGBColor(214, 96, 77),
    RGBColor(102, 166, 30),
    RGBColor(117, 112, 179),
];

/// A line of the memory panel: its name, colour and value.
type Series = (&'static str, RGBColor, fn(&ScaleRow) -> u64);

type DrawResult<DB> = Result<(), DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;

/// Writes `scale.png` and `scale.svg` into `dir`.
pub fn write_chart(report: &ScaleReport, dir: &Path) -> Result<()> {
    let _ =
        plotters::style::register_font(FONT, FontStyle::Normal, epaint_default_fonts::UBUNTU_LIGHT);
    let png = dir.join("scale.png");
    let mut rgb = vec![0u8; (SIZE.0 * SIZE.1 * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, SIZE).into_drawing_area();
        draw(&root, report).map_err(|e| anyhow!("chart {}: {e}", png.display()))?;
    }
    image::save_buffer(&png, &rgb, SIZE.0, SIZE.1, image::ColorType::Rgb8)
        .map_err(|e| anyhow!("chart {}: {e}", png.display()))?;
    let svg = dir.join("scale.svg");
    let root = SVGBackend::new(&svg, SIZE).into_drawing_area();
    draw(&root, report).map_err(|e| anyhow!("chart {}: {e}", svg.display()))
}

fn draw<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, r: &ScaleReport) -> Result<(), String> {
    let s = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    root.fill(&WHITE).map_err(s)?;
    let (left, right) = root.split_horizontally(SIZE.0 * 3 / 5);
    let drawn: Vec<&ScaleRow> = r.towns.iter().filter(|t| t.frame_ms.is_some()).collect();
    times(&left, r, &drawn).map_err(s)?;
    memory(&right, &r.towns).map_err(s)?;
    root.present().map_err(s)
}

/// The x range of `rows` (entities), log scale, with some room.
fn x_range(rows: &[&ScaleRow]) -> std::ops::Range<f64> {
    let lo = rows
        .iter()
        .map(|t| t.entities as f64)
        .fold(f64::MAX, f64::min);
    let hi = rows.iter().map(|t| t.entities as f64).fold(1.0, f64::max);
    (lo.min(hi) / 1.5).max(1.0)..hi * 1.5
}

/// A chart over the entities (log) and `y_desc` (log, up to `y_hi`), captioned `caption`.
type LogLog<'a, DB> = ChartContext<'a, DB, Cartesian2d<LogCoord<f64>, LogCoord<f64>>>;

fn log_log<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    caption: &str,
    rows: &[&ScaleRow],
    y_hi: f64,
    y_desc: &str,
) -> Result<LogLog<'a, DB>, DrawingAreaErrorKind<DB::ErrorType>> {
    let mut chart = ChartBuilder::on(area)
        .caption(caption, (FONT, 20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(x_range(rows).log_scale(), (0.1..y_hi).log_scale())?;
    chart
        .configure_mesh()
        .x_desc("entities")
        .x_label_formatter(&|x| format!("{x:.0}"))
        .y_desc(y_desc)
        .label_style((FONT, 13))
        .draw()?;
    Ok(chart)
}

/// A labelled line through `points`, a dot at each.
fn line<'a, DB: DrawingBackend + 'a>(
    chart: &mut LogLog<'a, DB>,
    name: &str,
    c: RGBColor,
    points: Vec<(f64, f64)>,
) -> DrawResult<DB> {
    chart
        .draw_series(LineSeries::new(points.clone(), c.stroke_width(2)))?
        .label(name)
        .legend(move |(x, y)| PathElement::new([(x, y), (x + 16, y)], c.stroke_width(2)));
    chart.draw_series(points.iter().map(|&p| Circle::new(p, 4, c.filled())))?;
    Ok(())
}

/// The legend, bottom right.
fn legend<'a, DB: DrawingBackend + 'a>(chart: &mut LogLog<'a, DB>) -> DrawResult<DB> {
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::LowerRight)
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .label_font((FONT, 13))
        .draw()
}

fn times<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    r: &ScaleReport,
    rows: &[&ScaleRow],
) -> DrawResult<DB> {
    let reference = r.reference.as_ref().and_then(|b| b.frame_ms);
    let value = |t: &ScaleRow, k: usize| match k {
        0 => t.frame_ms,
        k => t.passes.get(CHARTED_PASSES[k - 1]).copied(),
    };
    let y_hi = (rows.iter())
        .filter_map(|t| t.frame_ms)
        .chain(reference.map(|f| f * 1.5))
        .fold(1.0, f64::max)
        * 2.0;
    let caption = format!("Median ms against entities ({}×{})", r.size[0], r.size[1]);
    let mut chart = log_log(area, &caption, rows, y_hi, "ms")?;
    for k in 0..=CHARTED_PASSES.len() {
        let name = if k == 0 {
            "frame"
        } else {
            CHARTED_PASSES[k - 1]
        };
        let points: Vec<(f64, f64)> = (rows.iter())
            .filter_map(|t| Some((t.entities as f64, value(t, k)?.max(0.1))))
            .collect();
        line(&mut chart, name, COLOURS[k], points)?;
    }
    if let Some(base) = reference {
        let x = x_range(rows);
        for (f, label) in [(1.0, "reference frame"), (1.5, "1.5× reference")] {
            let style = BLACK.mix(0.6).stroke_width(1);
            let dashed =
                DashedLineSeries::new([(x.start, base * f), (x.end, base * f)], 6, 4, style);
            chart
                .draw_series(dashed)?
                .label(label)
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 16, y)], style));
        }
    }
    legend(&mut chart)
}

fn memory<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, towns: &[ScaleRow]) -> DrawResult<DB> {
    let rows: Vec<&ScaleRow> = towns.iter().collect();
    let mb = |b: u64| (b as f64 / 1e6).max(0.1);
    let y_hi = (rows.iter())
        .map(|t| mb(t.peak_resident_bytes.max(t.gpu_bytes)))
        .fold(1.0, f64::max)
        * 2.0;
    let mut chart = log_log(area, "Memory against entities (MB)", &rows, y_hi, "MB")?;
    let series: [Series; 2] = [
        ("peak resident", COLOURS[0], |t| t.peak_resident_bytes),
        ("GPU buffers", COLOURS[1], |t| t.gpu_bytes),
    ];
    for (name, c, get) in series {
        let points: Vec<(f64, f64)> = (rows.iter())
            .filter(|t| get(t) > 0)
            .map(|t| (t.entities as f64, mb(get(t))))
            .collect();
        line(&mut chart, name, c, points)?;
    }
    legend(&mut chart)
}
