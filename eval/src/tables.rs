//! The results tables of the docs, written from reports, never typed.
//!
//! A Markdown file marks where a table goes, and which report it comes from:
//!
//! ```text
//! <!-- texel-eval table=shimmer report=docs/results/stability.json rows=stone_circle:yaw methods=naive,snap,splat -->
//! (the table, rewritten by `texel-eval tables FILE.md`)
//! <!-- /texel-eval -->
//! ```
//!
//! `report` is relative to the Markdown file's folder. `texel-eval tables` rewrites what lies
//! between the markers from the report (`--check` only says which blocks differ), and a test
//! in `tests/tests/docs.rs` fails when a block in the docs is not what its report gives, so
//! a number in such a table always comes from a command (the report holds its command line,
//! adapter, date, commit and machine; the table's last line repeats them).
//!
//! A bench's table (`cargo bench -p texel_runtime`, which writes `docs/results/benches/`)
//! comes in whole: `<!-- texel-eval include=../results/benches/moving.md -->`.
//!
//! Tables ([`TableKind`]):
//! - `shimmer`: a row per `level:path`, a column per method holding the mean shimmer at the
//!   report's largest face resolution, `naive ÷ splat` when both ran, and the mean coverage
//!   error over every path of the report.
//! - `colour`: the same rows and columns holding the mean colour error
//!   ([`crate::colour`]), for reports where the raster ran.
//! - `speed`: a row per run, the median frame and pass times (`passes`, default capture,
//!   shade, cull, splat) and the quads drawn and texels lit a frame.
//! - `crossings`: a row per `level:path`, splat's shimmer on its quiet and crossing frames
//!   against the baselines' and the paper schedule's, and whether issue 60's target holds
//!   there ([`crate::crossings`]).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::report::{Report, RunRecord};

/// The opening marker's start.
pub const OPEN: &str = "<!-- texel-eval ";
/// The closing marker.
pub const CLOSE: &str = "<!-- /texel-eval -->";

/// Why a file's tables cannot be written.
#[derive(Debug, thiserror::Error)]
#[error("{file}:{line}: {message}")]
pub struct TableError {
    /// The Markdown file.
    pub file: PathBuf,
    /// 1-based line of the block's opening marker.
    pub line: usize,
    /// What is wrong.
    pub message: String,
}

/// Which table a block holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TableKind {
    /// Mean shimmer per path and method.
    Shimmer,
    /// Mean colour error per path and method.
    Colour,
    /// Frame and pass times per run.
    Speed,
    /// Shimmer on crossing and quiet frames per path, against the target
    /// ([`crate::crossings`]).
    Crossings,
}

/// One block's request, parsed from its opening marker.
#[derive(Debug, Clone, PartialEq)]
pub struct Block {
    /// Which table.
    pub kind: TableKind,
    /// The report, as written in the marker (relative to the Markdown file's folder).
    pub report: String,
    /// `level:path` rows to show, in order (all of the report's when empty).
    pub rows: Vec<(String, String)>,
    /// Methods to show, in order (all of the report's when empty).
    pub methods: Vec<String>,
    /// Passes to show (`speed`).
    pub passes: Vec<String>,
}

impl Block {
    /// Parses the attributes of an opening marker (`table=... report=... rows=...`).
    pub fn parse(attributes: &str) -> Result<Block, String> {
        let (mut kind, mut report) = (None, None);
        let (mut rows, mut methods, mut passes) = (Vec::new(), Vec::new(), Vec::new());
        let list = |v: &str| -> Vec<String> {
            v.split(',')
                .filter(|s| !s.is_empty())
                .map(str::to_owned)
                .collect()
        };
        for pair in attributes.split_whitespace() {
            let Some((key, value)) = pair.split_once('=') else {
                return Err(format!("`{pair}` is not key=value"));
            };
            match key {
                "table" => {
                    kind = Some(match value {
                        "shimmer" => TableKind::Shimmer,
                        "colour" => TableKind::Colour,
                        "speed" => TableKind::Speed,
                        "crossings" => TableKind::Crossings,
                        other => {
                            return Err(format!(
                                "unknown table `{other}` (shimmer, colour, speed, crossings)"
                            ));
                        }
                    })
                }
                "report" => report = Some(value.to_owned()),
                "rows" => {
                    for row in list(value) {
                        let Some((level, path)) = row.split_once(':') else {
                            return Err(format!("row `{row}` is not level:path"));
                        };
                        rows.push((level.to_owned(), path.to_owned()));
                    }
                }
                "methods" => methods = list(value),
                "passes" => passes = list(value),
                other => {
                    return Err(format!(
                        "unknown attribute `{other}` (table, report, rows, methods, passes)"
                    ));
                }
            }
        }
        Ok(Block {
            kind: kind.ok_or("no table=")?,
            report: report.ok_or("no report=")?,
            rows,
            methods,
            passes,
        })
    }
}

/// `text` (the Markdown file `file`) with every block rewritten from its report.
pub fn refresh(text: &str, file: &Path) -> Result<String, TableError> {
    let dir = file.parent().unwrap_or(Path::new("."));
    let mut out = String::with_capacity(text.len());
    let mut lines = text.split_inclusive('\n').enumerate();
    while let Some((i, line)) = lines.next() {
        out.push_str(line);
        let trimmed = line.trim();
        let Some(attributes) = trimmed
            .strip_prefix(OPEN)
            .and_then(|r| r.strip_suffix("-->"))
        else {
            continue;
        };
        let fail = |message: String| TableError {
            file: file.to_owned(),
            line: i + 1,
            message,
        };
        let table = match attributes.trim().strip_prefix("include=") {
            Some(name) => included(&dir.join(name.trim())).map_err(fail)?,
            None => {
                let block = Block::parse(attributes).map_err(fail)?;
                let report =
                    Report::load(&dir.join(&block.report)).map_err(|e| fail(format!("{e:#}")))?;
                render(&block, &report).map_err(fail)?
            }
        };
        loop {
            match lines.next() {
                Some((_, l)) if l.trim() == CLOSE => {
                    out.push_str(&table);
                    out.push_str(l);
                    break;
                }
                Some(_) => {}
                None => return Err(fail(format!("no closing `{CLOSE}`"))),
            }
        }
    }
    Ok(out)
}

/// The Markdown a bench wrote (`include=`), as it is, ending in a newline.
fn included(path: &Path) -> Result<String, String> {
    let mut text = std::fs::read_to_string(path)
        .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    if text.contains(OPEN) || text.contains(CLOSE) {
        return Err(format!("{} holds a texel-eval marker", path.display()));
    }
    if !text.ends_with('\n') {
        text.push('\n');
    }
    Ok(text)
}

/// The table `block` asks for, from `report`, with its source line last.
pub fn render(block: &Block, report: &Report) -> Result<String, String> {
    let mut out = match block.kind {
        TableKind::Shimmer => per_path(block, report, &SHIMMER)?,
        TableKind::Colour => per_path(block, report, &COLOUR)?,
        TableKind::Speed => speed(block, report)?,
        TableKind::Crossings => crate::crossings::table(block, report)?,
    };
    // The command line without the binary's own path (`target/debug/texel-eval`).
    let command =
        (report.command.split_once(' ')).map_or(report.command.as_str(), |(_, rest)| rest);
    let _ = writeln!(
        out,
        "\n<sub>From [`{}`]({}): `texel-eval {command}`; {}; {}.</sub>",
        block.report,
        block.report,
        report.adapter,
        report.stamp.line(),
    );
    Ok(out)
}

pub(crate) fn methods_of<'a>(block: &'a Block, report: &'a Report) -> Result<Vec<&'a str>, String> {
    let mut all: Vec<&str> = Vec::new();
    for r in &report.runs {
        if !all.contains(&r.method.as_str()) {
            all.push(&r.method);
        }
    }
    if block.methods.is_empty() {
        return Ok(all);
    }
    for m in &block.methods {
        if !all.contains(&m.as_str()) {
            return Err(format!(
                "the report has no method `{m}` (it has {})",
                all.join(", ")
            ));
        }
    }
    Ok(block.methods.iter().map(String::as_str).collect())
}

pub(crate) fn rows_of<'a>(
    block: &'a Block,
    report: &'a Report,
) -> Result<Vec<(&'a str, &'a str)>, String> {
    let mut all: Vec<(&str, &str)> = Vec::new();
    for r in &report.runs {
        let key = (r.level_name(), r.path_name());
        if !all.contains(&key) {
            all.push(key);
        }
    }
    if block.rows.is_empty() {
        return Ok(all);
    }
    for (l, p) in &block.rows {
        if !all.contains(&(l.as_str(), p.as_str())) {
            return Err(format!("the report has no path `{p}` on level `{l}`"));
        }
    }
    Ok(block
        .rows
        .iter()
        .map(|(l, p)| (l.as_str(), p.as_str()))
        .collect())
}

/// The mean of the values that are numbers (a run without a colour error gives NaN).
fn mean(v: impl Iterator<Item = f64>) -> Option<f64> {
    let (sum, n) = v
        .filter(|x| !x.is_nan())
        .fold((0.0, 0usize), |(s, n), x| (s + x, n + 1));
    (n > 0).then(|| sum / n as f64)
}

/// `150×`, `16×`, `4.8×`.
pub(crate) fn ratio(x: f64) -> String {
    if x >= 9.95 {
        format!("{x:.0}×")
    } else {
        format!("{x:.1}×")
    }
}

/// What a per-path table shows in its cells.
struct Measure {
    /// A run's value (NaN: none).
    value: fn(&RunRecord) -> f64,
    /// The line under the table, before the faces and size.
    caption: &'static str,
}

const SHIMMER: Measure = Measure {
    value: |r| r.shimmer.mean,
    caption: "Mean shimmer",
};

const COLOUR: Measure = Measure {
    value: |r| r.colour_error.map_or(f64::NAN, |c| c.mean),
    caption: "Mean colour error (OKLab ΔE against the raster's frames, at the art-pixel scale)",
};

fn per_path(block: &Block, report: &Report, measure: &Measure) -> Result<String, String> {
    let methods = methods_of(block, report)?;
    let rows = rows_of(block, report)?;
    let top = report.runs.iter().map(|r| r.face_res).max().unwrap_or(0);
    // The mean of `f` over the method's runs (on one path, or all), at the largest faces.
    let mean_of = |m: &str, row: Option<(&str, &str)>, f: fn(&RunRecord) -> f64| {
        mean(
            (report.runs.iter())
                .filter(|r| {
                    r.method == m
                        && (r.face_res == top || m == "raster")
                        && row.is_none_or(|(l, p)| r.level_name() == l && r.path_name() == p)
                })
                .map(f),
        )
    };
    let with_ratio = methods.contains(&"naive") && methods.contains(&"splat");
    let mut out = String::from("| path (level) |");
    for m in &methods {
        let _ = write!(out, " {m} |");
    }
    out.push_str(if with_ratio {
        " naive ÷ splat |\n|---|"
    } else {
        "\n|---|"
    });
    out.push_str(&"---:|".repeat(methods.len() + usize::from(with_ratio)));
    out.push('\n');
    let cell = |v: Option<f64>| v.map_or("–".to_owned(), |x| format!("{x:.4}"));
    for &(level, path) in &rows {
        let _ = write!(out, "| `{path}` ({}) |", level.replace('_', " "));
        for m in &methods {
            let _ = write!(
                out,
                " {} |",
                cell(mean_of(m, Some((level, path)), measure.value))
            );
        }
        if with_ratio {
            let of = |m| mean_of(m, Some((level, path)), measure.value);
            let r = match (of("naive"), of("splat")) {
                (Some(n), Some(s)) if s > 0.0 => ratio(n / s),
                _ => "–".to_owned(),
            };
            let _ = write!(out, " {r} |");
        }
        out.push('\n');
    }
    let paths = report
        .runs
        .iter()
        .map(|r| (r.level_name(), r.path_name()))
        .collect::<std::collections::BTreeSet<_>>()
        .len();
    let _ = write!(out, "| *coverage error, mean of {paths} paths* |");
    for m in &methods {
        let _ = write!(out, " {} |", cell(mean_of(m, None, |r| r.coverage_error)));
    }
    out.push_str(if with_ratio { " |\n" } else { "\n" });
    if report.runs.iter().any(|r| r.colour_error.is_some()) {
        let _ = write!(out, "| *colour error, mean ΔE against the raster* |");
        for m in &methods {
            let colour = mean_of(m, None, |r| r.colour_error.map_or(f64::NAN, |c| c.mean));
            let _ = write!(out, " {} |", cell(colour));
        }
        out.push_str(if with_ratio { " |\n" } else { "\n" });
    }
    let _ = writeln!(
        out,
        "\n{} at faces of {top}, {}×{} pixels.",
        measure.caption,
        size(report).0,
        size(report).1
    );
    Ok(out)
}

fn size(report: &Report) -> (u32, u32) {
    report
        .runs
        .first()
        .map_or((0, 0), |r| (r.size[0], r.size[1]))
}

fn speed(block: &Block, report: &Report) -> Result<String, String> {
    let methods = methods_of(block, report)?;
    let rows = rows_of(block, report)?;
    let passes: Vec<&str> = if block.passes.is_empty() {
        vec!["capture", "shade", "cull", "splat"]
    } else {
        block.passes.iter().map(String::as_str).collect()
    };
    let several_paths = rows.len() > 1;
    let mut out = String::from("| run | frame |");
    for p in &passes {
        let _ = write!(out, " {p} |");
    }
    out.push_str(" quads drawn | texels lit |\n|---|");
    out.push_str(&"---:|".repeat(passes.len() + 3));
    out.push('\n');
    for &(level, path) in &rows {
        for m in &methods {
            for r in report
                .runs
                .iter()
                .filter(|r| r.method == *m && r.level_name() == level && r.path_name() == path)
            {
                let label = if several_paths {
                    format!("{m}, `{path}` ({})", level.replace('_', " "))
                } else {
                    (*m).to_owned()
                };
                let _ = write!(
                    out,
                    "| {label}, faces of {} | {:.1} |",
                    r.face_res, r.frame_ms.median
                );
                for p in &passes {
                    match r.pass_ms.get(*p) {
                        Some(ms) => {
                            let _ = write!(out, " {ms:.1} |");
                        }
                        None => out.push_str(" – |"),
                    }
                }
                let _ = writeln!(
                    out,
                    " {} | {} |",
                    thousands(r.counters.quads_splatted),
                    thousands(r.counters.texels_shaded)
                );
            }
        }
    }
    let (w, h) = size(report);
    let _ = writeln!(
        out,
        "\nMedian milliseconds per frame and per pass, {w}×{h} pixels."
    );
    Ok(out)
}

/// `125593.4` → `125,593`.
fn thousands(x: f64) -> String {
    let digits = format!("{:.0}", x.max(0.0));
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i) % 3 == 0 {
            out.push(',');
        }
        out.push(c);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::RunRecord;

    fn run(level: &str, path: &str, method: &str, shimmer: f64) -> RunRecord {
        let mut r = RunRecord {
            level: format!("assets/levels/{level}.ron"),
            path: format!("assets/paths/{path}.ron"),
            method: method.into(),
            face_res: 128,
            size: [320, 180],
            frames: 10,
            coverage_error: 0.01,
            ..Default::default()
        };
        r.shimmer.mean = shimmer;
        r.frame_ms.median = 40.0;
        r.pass_ms.insert("capture".into(), 5.0);
        r.counters.quads_splatted = 125_593.4;
        r
    }

    fn report() -> Report {
        Report {
            adapter: "llvmpipe (Vulkan)".into(),
            command: "target/debug/texel-eval suite --methods naive,splat --out x".into(),
            runs: vec![
                run("stone_circle", "yaw", "naive", 0.03),
                run("stone_circle", "yaw", "splat", 0.0002),
                run("sprites", "yaw", "naive", 0.02),
                run("sprites", "yaw", "splat", 0.004),
            ],
            ..Default::default()
        }
    }

    #[test]
    fn a_shimmer_table_has_the_asked_rows_the_ratio_and_its_source() {
        let block = Block::parse("table=shimmer report=r.json rows=sprites:yaw").unwrap();
        let t = render(&block, &report()).unwrap();
        assert!(
            t.contains("| `yaw` (sprites) | 0.0200 | 0.0040 | 5.0× |"),
            "{t}"
        );
        assert!(!t.contains("(stone circle)"), "{t}");
        assert!(
            t.contains("*coverage error, mean of 2 paths* | 0.0100 | 0.0100 |"),
            "{t}"
        );
        assert!(
            t.contains("`texel-eval suite --methods naive,splat --out x`"),
            "{t}"
        );
        assert!(t.contains("llvmpipe (Vulkan)"), "{t}");
    }

    #[test]
    fn a_colour_table_shows_each_paths_colour_error() {
        let mut r = report();
        r.runs[2].colour_error = Some(crate::colour::ColourError {
            mean: 0.02,
            p95: 0.1,
        });
        r.runs[3].colour_error = Some(crate::colour::ColourError {
            mean: 0.01,
            p95: 0.05,
        });
        let block = Block::parse("table=colour report=r.json").unwrap();
        let t = render(&block, &r).unwrap();
        assert!(
            t.contains("| `yaw` (sprites) | 0.0200 | 0.0100 | 2.0× |"),
            "{t}"
        );
        assert!(t.contains("| `yaw` (stone circle) | – | – | – |"), "{t}");
        assert!(t.contains("Mean colour error"), "{t}");
    }

    #[test]
    fn a_speed_table_lists_each_run_with_its_passes() {
        let block =
            Block::parse("table=speed report=r.json rows=stone_circle:yaw passes=capture,shade")
                .unwrap();
        let t = render(&block, &report()).unwrap();
        assert!(
            t.contains("| naive, faces of 128 | 40.0 | 5.0 | – | 125,593 | 0 |"),
            "{t}"
        );
    }

    #[test]
    fn blocks_name_what_is_wrong() {
        assert!(
            Block::parse("table=hue report=r")
                .unwrap_err()
                .contains("unknown table")
        );
        assert!(Block::parse("table=speed").unwrap_err().contains("report"));
        assert!(
            Block::parse("table=speed report=r rows=yaw")
                .unwrap_err()
                .contains("level:path")
        );
        let block = Block::parse("table=shimmer report=r rows=colonnade:yaw").unwrap();
        assert!(
            render(&block, &report())
                .unwrap_err()
                .contains("no path `yaw` on level `colonnade`")
        );
        let block = Block::parse("table=shimmer report=r methods=march").unwrap();
        assert!(
            render(&block, &report())
                .unwrap_err()
                .contains("no method `march`")
        );
    }

    #[test]
    fn refresh_rewrites_blocks_from_their_report_and_keeps_the_rest() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(
            dir.path().join("r.json"),
            serde_json::to_string(&report()).unwrap(),
        )
        .unwrap();
        let file = dir.path().join("doc.md");
        let text = "# Doc\n<!-- texel-eval table=shimmer report=r.json -->\nold\n<!-- /texel-eval -->\nafter\n";
        let new = refresh(text, &file).unwrap();
        assert!(new.starts_with("# Doc\n<!-- texel-eval table=shimmer report=r.json -->\n| path"));
        assert!(new.ends_with("<!-- /texel-eval -->\nafter\n"), "{new}");
        assert!(!new.contains("old"));
        assert_eq!(
            refresh(&new, &file).unwrap(),
            new,
            "a second pass changes nothing"
        );
        let unclosed = "<!-- texel-eval table=shimmer report=r.json -->\nold\n";
        let e = refresh(unclosed, &file).unwrap_err().to_string();
        assert!(e.contains("doc.md:1:") && e.contains("no closing"), "{e}");
        let missing =
            "x\n<!-- texel-eval table=shimmer report=gone.json -->\n<!-- /texel-eval -->\n";
        let e = refresh(missing, &file).unwrap_err().to_string();
        assert!(e.contains("doc.md:2:") && e.contains("gone.json"), "{e}");
    }

    #[test]
    fn an_include_block_holds_the_benchs_file_as_it_is() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("bench.md"), "| a |\n|---|\n| 1 |").unwrap();
        let file = dir.path().join("doc.md");
        let text = "<!-- texel-eval include=bench.md -->\nold\n<!-- /texel-eval -->\n";
        assert_eq!(
            refresh(text, &file).unwrap(),
            "<!-- texel-eval include=bench.md -->\n| a |\n|---|\n| 1 |\n<!-- /texel-eval -->\n"
        );
        let gone = "<!-- texel-eval include=gone.md -->\n<!-- /texel-eval -->\n";
        let e = refresh(gone, &file).unwrap_err().to_string();
        assert!(e.contains("doc.md:1:") && e.contains("gone.md"), "{e}");
        std::fs::write(dir.path().join("nested.md"), "<!-- /texel-eval -->\n").unwrap();
        let nested = "<!-- texel-eval include=nested.md -->\n<!-- /texel-eval -->\n";
        assert!(
            refresh(nested, &file)
                .unwrap_err()
                .to_string()
                .contains("marker")
        );
    }
}
