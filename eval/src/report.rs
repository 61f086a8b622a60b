//! The report a run or a suite writes (`DIR/report.json`) and its Markdown table.
//!
//! # Schema of `report.json`
//!
//! ```text
//! {
//!   "adapter":    string,          // GPU adapter and backend the frames were timed on
//!   "command":    string,          // the command line that produced the report
//!   "duration_s": number,          // wall time of the whole run or suite
//!   "stamp": {"date", "commit", "machine": string},  // when, which commit, which CPU
//!   "runs": [ {                    // one record per level × path × method × face_res
//!     "level":      string,        // level file
//!     "path":       string,        // camera-path file
//!     "method":     string,        // raster | naive | snap | cubemap | splat-paper | splat | march
//!     "face_res":   integer,       // texels per cube-face edge (splat, cubemap); for raster,
//!                                  // naive and snap the art-pixel size of the same texel size
//!     "size":       [w, h],        // output pixels
//!     "frames":     integer,       // frames rendered
//!     "reference":  string,        // "gpu" (plain raster G-buffer) or "cpu" (ray cast)
//!     "frame_ms":   {"median": number, "p90": number},  // CPU wall time per frame, ms
//!     "pass_ms":    {pass: number},                      // median ms per pass
//!     "counters":   {"faces_captured", "texels_shaded", "quads_splatted",
//!                    "screen_visible_texels": number},   // mean per frame
//!     "shimmer":    {"mean", "p95", "max": number},      // per-frame flicker fraction, 0..1
//!     "shimmer_per_frame": [number],                     // frames 1.. (0 has no predecessor)
//!     "shimmer_all": {"mean", "p95", "max"}|null,       // the same with the truth's own changes
//!     "coverage_error": number,    // mean fraction of pixels whose id differs from reference
//!     "colour_error": {"mean", "p95": number}|absent, // OKLab ΔE against the raster's frames,
//!                                  // both reduced to art pixels (absent without raster)
//!     "hole_rate":  number,        // mean fraction of pixels with geometry shown as sky
//!     "eye_fraction": number|null, // mean fraction of pixels from the eye probe (splat only)
//!     "eye_flicker_share": number|null, // share of flickering pixels from the eye probe
//!     "steps_per_pixel": number|null,   // march steps per pixel (march only)
//!     "fallback_fraction": number|null, // marched pixels their first probe could not resolve
//!     "sprite_shimmer": number|null,    // mean flicker of sprites' pixels (levels with sprites)
//!     "moving_shimmer": number|null,    // mean flicker of moving objects' pixels, followed
//!                                       // with their objects (levels with animators)
//!     "still_shimmer": number|null,     // the same over the still world's pixels
//!     "crossings": {"crossing", "quiet": number, "crossing_frames", "quiet_frames":
//!                   integer}|absent     // shimmer on splat's crossing and quiet frames
//!   } ]
//! }
//! ```

use std::collections::BTreeMap;
use std::fmt::Write as _;

use serde::{Deserialize, Serialize};

use crate::metrics::Summary;

/// Median and 90th percentile of frame times, ms.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Timing {
    /// Median.
    pub median: f64,
    /// 90th percentile.
    pub p90: f64,
}

/// Mean work counters per frame.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct CounterMeans {
    /// Cube faces rasterized.
    pub faces_captured: f64,
    /// Texels lit.
    pub texels_shaded: f64,
    /// Quads splatted.
    pub quads_splatted: f64,
    /// Distinct probe texels on screen.
    pub screen_visible_texels: f64,
}

/// One run: a method along a path on a level at one face resolution.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct RunRecord {
    /// Level file.
    pub level: String,
    /// Camera-path file.
    pub path: String,
    /// Method name.
    pub method: String,
    /// Face resolution.
    pub face_res: u32,
    /// Output size.
    pub size: [u32; 2],
    /// Frames rendered.
    pub frames: u32,
    /// `gpu` or `cpu`: where the reference G-buffer came from.
    pub reference: String,
    /// Frame wall time.
    pub frame_ms: Timing,
    /// Median milliseconds per pass.
    pub pass_ms: BTreeMap<String, f64>,
    /// Mean work counters.
    pub counters: CounterMeans,
    /// Per-frame flicker fraction.
    pub shimmer: Summary,
    /// Flicker fraction of frames 1...
    pub shimmer_per_frame: Vec<f64>,
    /// The per-frame flicker of every tested pixel, the truth's own changes included (the
    /// shimmer before intended change was left out); `None` in reports older than it.
    #[serde(default)]
    pub shimmer_all: Option<Summary>,
    /// Mean coverage error.
    pub coverage_error: f64,
    /// Mean colour error against the raster's frames, at the art-pixel scale
    /// ([`crate::colour`]); none when the raster did not run first.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub colour_error: Option<crate::colour::ColourError>,
    /// Mean hole rate.
    pub hole_rate: f64,
    /// Mean eye fraction (splat methods).
    pub eye_fraction: Option<f64>,
    /// Share of flicker from the eye probe (splat methods).
    pub eye_flicker_share: Option<f64>,
    /// Steps per marched pixel, over every probe it asked (march only).
    #[serde(default)]
    pub steps_per_pixel: Option<f64>,
    /// Fraction of marched pixels whose first probe could not say what the ray hits, so
    /// another probe, the eye probe or the sky answered (march only).
    #[serde(default)]
    pub fallback_fraction: Option<f64>,
    /// Mean flicker fraction of moving objects' pixels (levels with animators).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub moving_shimmer: Option<f64>,
    /// Mean flicker fraction of the still world's pixels on the same frames.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub still_shimmer: Option<f64>,
    /// Mean flicker fraction of sprites' pixels (levels with sprites).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sprite_shimmer: Option<f64>,
    /// Mean shimmer on splat's crossing frames and on its quiet frames (a run whose plan
    /// had splat at its face resolution; [`crate::crossings`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub crossings: Option<crate::crossings::CrossingSplit>,
}

impl RunRecord {
    /// The path's file stem (`yaw` for `assets/paths/yaw.ron`).
    pub fn path_name(&self) -> &str {
        file_stem(&self.path)
    }

    /// The level's file stem.
    pub fn level_name(&self) -> &str {
        file_stem(&self.level)
    }
}

/// A summary row: its name, the value of a run, and the decimals to print.
type SummaryRow = (&'static str, fn(&RunRecord) -> f64, usize);

fn file_stem(s: &str) -> &str {
    let base = s.rsplit(['/', '\\']).next().unwrap_or(s);
    base.strip_suffix(".ron").unwrap_or(base)
}

/// The whole `report.json`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Report {
    /// GPU adapter description.
    pub adapter: String,
    /// The command that produced it.
    pub command: String,
    /// Wall time of the whole run, seconds.
    pub duration_s: f64,
    /// When, from which commit and on what machine it ran (empty in reports written before
    /// the stamp existed).
    #[serde(default)]
    pub stamp: crate::stamp::Stamp,
    /// One record per run.
    pub runs: Vec<RunRecord>,
    /// The suite's surveyed walks (`texel-eval suite --survey`), apart from the bundled
    /// paths' runs: the chart leaves them out and table.md lists the worst.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub survey: Vec<RunRecord>,
}

/// Most runs a report may hold.
pub const MAX_RUNS: usize = 10_000;
/// Largest time (ms per frame or per pass) a report may hold: about 2.8 hours.
pub const MAX_MS: f64 = 1.0e7;
/// Largest mean counter a report may hold.
pub const MAX_COUNTER: f64 = 1.0e12;

impl Report {
    /// Reads and checks a `report.json` written by `texel-eval run` or `suite`: a regular file
    /// within `TEXEL_MAX_REPORT_BYTES` (see `texel_scene::read`), valid JSON of this schema,
    /// and every number within [`Report::check`]'s ranges. Errors start with the file's path.
    pub fn load(path: &std::path::Path) -> anyhow::Result<Report> {
        use texel_scene::read::{FileKind, read_bounded_string};
        let text = read_bounded_string(path, FileKind::Report)?;
        let report: Report = serde_json::from_str(&text)
            .map_err(|e| anyhow::anyhow!("{}: not a report: {e}", path.display()))?;
        report
            .check()
            .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
        Ok(report)
    }

    /// Checks every number against what a run can produce: fractions (shimmer, coverage
    /// error, hole rate, eye shares) finite within 0..=1, times within 0..=[`MAX_MS`],
    /// counters within 0..=[`MAX_COUNTER`], sizes within the renderer's limit, frames within
    /// a camera path's, at most [`MAX_RUNS`] runs. The error names the run and the field.
    pub fn check(&self) -> Result<(), String> {
        fn within(v: f64, max: f64, what: &str) -> Result<(), String> {
            if v.is_finite() && (0.0..=max).contains(&v) {
                Ok(())
            } else {
                Err(format!("{what} must be a number in 0..={max}, got {v}"))
            }
        }
        within(self.duration_s, 1.0e9, "duration_s")?;
        if self.runs.len() + self.survey.len() > MAX_RUNS {
            return Err(format!(
                "{} runs, at most {MAX_RUNS} are charted",
                self.runs.len() + self.survey.len()
            ));
        }
        let max_side = texel_render::validate::MAX_OUTPUT_SIDE;
        let max_frames = texel_runtime::path::MAX_FRAMES;
        for (i, r) in self.runs.iter().chain(&self.survey).enumerate() {
            let at = |field: &str| format!("run {i} ({} {}): {field}", r.method, r.path);
            if r.size.iter().any(|&s| s == 0 || s > max_side) {
                return Err(format!("{}: each side must be 1..={max_side}", at("size")));
            }
            if r.frames > max_frames {
                return Err(format!("{} must be at most {max_frames}", at("frames")));
            }
            if r.face_res > *texel_scene::limits::FACE_RESOLUTIONS.end() {
                return Err(format!("{} is too large", at("face_res")));
            }
            if r.shimmer_per_frame.len() > max_frames as usize {
                return Err(format!("{} has too many frames", at("shimmer_per_frame")));
            }
            let fractions = [
                ("shimmer.mean", r.shimmer.mean),
                ("shimmer.p95", r.shimmer.p95),
                ("shimmer.max", r.shimmer.max),
                ("coverage_error", r.coverage_error),
                ("hole_rate", r.hole_rate),
                ("eye_fraction", r.eye_fraction.unwrap_or(0.0)),
                ("eye_flicker_share", r.eye_flicker_share.unwrap_or(0.0)),
                ("fallback_fraction", r.fallback_fraction.unwrap_or(0.0)),
                ("moving_shimmer", r.moving_shimmer.unwrap_or(0.0)),
                ("still_shimmer", r.still_shimmer.unwrap_or(0.0)),
                ("sprite_shimmer", r.sprite_shimmer.unwrap_or(0.0)),
            ]
            .into_iter()
            .chain(
                r.shimmer_per_frame
                    .iter()
                    .map(|&v| ("shimmer_per_frame", v)),
            );
            for (field, v) in fractions {
                within(v, 1.0, &at(field))?;
            }
            // OKLab distances stay below about 1.1 (black to white is 1).
            if let Some(c) = r.colour_error {
                within(c.mean, 2.0, &at("colour_error.mean"))?;
                within(c.p95, 2.0, &at("colour_error.p95"))?;
            }
            let times = [
                ("frame_ms.median", r.frame_ms.median),
                ("frame_ms.p90", r.frame_ms.p90),
            ];
            for (field, v) in times {
                within(v, MAX_MS, &at(field))?;
            }
            for (pass, &v) in &r.pass_ms {
                within(v, MAX_MS, &at(&format!("pass_ms.{pass}")))?;
            }
            let c = &r.counters;
            for (field, v) in [
                ("counters.faces_captured", c.faces_captured),
                ("counters.texels_shaded", c.texels_shaded),
                ("counters.quads_splatted", c.quads_splatted),
                ("counters.screen_visible_texels", c.screen_visible_texels),
                ("steps_per_pixel", r.steps_per_pixel.unwrap_or(0.0)),
            ] {
                within(v, MAX_COUNTER, &at(field))?;
            }
        }
        Ok(())
    }

    /// A compact Markdown table: one row per path, one column per method, holding the mean
    /// shimmer at the highest face resolution (raster at its only one), then rows of the
    /// mean over paths of the coverage error and of the median frame time.
    pub fn summary_table(&self) -> String {
        let top = self.runs.iter().map(|r| r.face_res).max().unwrap_or(0);
        let mut methods: Vec<&str> = Vec::new();
        // One row per level and path (the same path may fly through two levels).
        let mut paths: Vec<(&str, &str)> = Vec::new();
        for r in &self.runs {
            if !methods.contains(&r.method.as_str()) {
                methods.push(&r.method);
            }
            let key = (r.level_name(), r.path_name());
            if !paths.contains(&key) {
                paths.push(key);
            }
        }
        let pick = |path: Option<(&str, &str)>, method: &str| -> Vec<&RunRecord> {
            self.runs
                .iter()
                .filter(|r| {
                    r.method == method
                        && (r.face_res == top || method == "raster")
                        && path.is_none_or(|(l, p)| r.level_name() == l && r.path_name() == p)
                })
                .collect()
        };
        let mut out = format!("| shimmer (face res {top}) |");
        for m in &methods {
            let _ = write!(out, " {m} |");
        }
        out.push_str("\n|---|");
        out.push_str(&"---:|".repeat(methods.len()));
        out.push('\n');
        let cell = |v: &[f64], digits: usize| match v.len() {
            0 => "–".to_owned(),
            n => format!("{:.digits$}", v.iter().sum::<f64>() / n as f64),
        };
        for &(level, path) in &paths {
            // A path's first level names it alone; another level's row says which.
            if paths.iter().find(|(_, p)| *p == path).map(|(l, _)| *l) == Some(level) {
                let _ = write!(out, "| {path} |");
            } else {
                let _ = write!(out, "| {path} ({level}) |");
            }
            for m in &methods {
                let v: Vec<f64> = (pick(Some((level, path)), m).iter())
                    .map(|r| r.shimmer.mean)
                    .collect();
                let _ = write!(out, " {} |", cell(&v, 4));
            }
            out.push('\n');
        }
        let rows: [SummaryRow; 3] = [
            ("coverage error (mean)", |r| r.coverage_error, 4),
            (
                "colour error, mean ΔE (mean)",
                |r| r.colour_error.map_or(f64::NAN, |c| c.mean),
                4,
            ),
            ("median frame ms (mean)", |r| r.frame_ms.median, 1),
        ];
        for (name, f, digits) in rows {
            let _ = write!(out, "| *{name}* |");
            for m in &methods {
                let v: Vec<f64> = (pick(None, m).iter().map(|r| f(r)))
                    .filter(|v| !v.is_nan())
                    .collect();
                let _ = write!(out, " {} |", cell(&v, digits));
            }
            out.push('\n');
        }
        out
    }

    /// A Markdown table: one row per path and method, one column group per face
    /// resolution (shimmer mean, coverage error, median frame ms).
    pub fn markdown_table(&self) -> String {
        let mut res: Vec<u32> = self.runs.iter().map(|r| r.face_res).collect();
        res.sort_unstable();
        res.dedup();
        let mut out = String::from("| level | path | method |");
        for n in &res {
            let _ = write!(out, " shimmer @{n} | coverage err @{n} | ms @{n} |");
        }
        out.push_str("\n|---|---|---|");
        out.push_str(&"---:|---:|---:|".repeat(res.len()));
        out.push('\n');
        let mut rows: Vec<(&str, &str, &str)> = Vec::new();
        for r in &self.runs {
            let key = (r.level_name(), r.path_name(), r.method.as_str());
            if !rows.contains(&key) {
                rows.push(key);
            }
        }
        for (level, path, method) in rows {
            let _ = write!(out, "| {level} | {path} | {method} |");
            for n in &res {
                let r = self.runs.iter().find(|r| {
                    r.level_name() == level
                        && r.path_name() == path
                        && r.method == method
                        && r.face_res == *n
                });
                match r {
                    Some(r) => {
                        let _ = write!(
                            out,
                            " {:.4} | {:.4} | {:.1} |",
                            r.shimmer.mean, r.coverage_error, r.frame_ms.median
                        );
                    }
                    None => out.push_str(" – | – | – |"),
                }
            }
            out.push('\n');
        }
        // Sprite pixels apart, where a level has sprites.
        let sprites: Vec<&RunRecord> = (self.runs.iter())
            .filter(|r| r.sprite_shimmer.is_some())
            .collect();
        if !sprites.is_empty() {
            out.push_str("\n| level | path | method | face res | sprite-pixel shimmer |\n");
            out.push_str("|---|---|---|---:|---:|\n");
            for r in sprites {
                let _ = writeln!(
                    out,
                    "| {} | {} | {} | {} | {:.5} |",
                    r.level_name(),
                    r.path_name(),
                    r.method,
                    r.face_res,
                    r.sprite_shimmer.unwrap_or(0.0)
                );
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_table_has_a_row_per_path_and_method_and_a_column_group_per_resolution() {
        let run = |method: &str, face_res, shimmer| RunRecord {
            level: "assets/levels/stone_circle.ron".into(),
            path: "assets/paths/yaw.ron".into(),
            method: method.into(),
            face_res,
            shimmer: Summary {
                mean: shimmer,
                p95: shimmer,
                max: shimmer,
            },
            ..Default::default()
        };
        let report = Report {
            runs: vec![
                run("splat", 32, 0.0),
                run("splat", 64, 0.001),
                run("naive", 64, 0.2),
            ],
            ..Default::default()
        };
        let t = report.markdown_table();
        assert_eq!(t.lines().count(), 4, "{t}");
        assert!(
            t.contains("| stone_circle | yaw | naive | – | – | – | 0.2000 |"),
            "{t}"
        );
        let summary = report.summary_table();
        assert!(summary.contains("| yaw | 0.0010 | 0.2000 |"), "{summary}");
        assert!(
            summary.starts_with("| shimmer (face res 64) | splat | naive |"),
            "{summary}"
        );
        let json = serde_json::to_string(&report).expect("serialises");
        let back: Report = serde_json::from_str(&json).expect("parses");
        assert_eq!(back, report);
    }
}
