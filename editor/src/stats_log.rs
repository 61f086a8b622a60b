//! `texel-editor --stats FILE`: the status bar's figures as JSON lines, one a second, so
//! benchmarks and tests read what a person sees. Each line:
//!
//! ```text
//! {"t_s": 3.0, "ui_frame_ms": 24.1, "ui_busy_ms": 3.2, "ui_fps": 41, "render_ms": 142.0,
//!  "edit_to_frame_ms": 310.0, "upload_ms": 280.0, "uploads": 2, "entities": 25,
//!  "playing": false}
//! ```
//!
//! `ui_frame_ms` is the wall time between the last two UI frames (the viewport renders on a
//! thread of its own, so no viewport frame is in it; while nothing moves egui repaints only
//! on input, and the gap is the wait for it), `ui_busy_ms` the UI thread's work on its last
//! frame (eframe's measure: the UI and its painting, not the wait for the display),
//! `ui_fps` the UI frames a second over the last second or more. `render_ms` is the render worker's last frame, `edit_to_frame_ms` the
//! wall time from the UI frame that saw the last edit to the one that showed it, `upload_ms`
//! the last scene upload (null before the first edit), `uploads` the scene uploads since the
//! renderer started.

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// How often a line is written.
pub const EVERY: Duration = Duration::from_secs(1);

/// One line's figures.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Figures {
    /// Wall time between the last two UI frames.
    pub ui_frame_ms: f64,
    /// The UI thread's work on its last frame (the UI and its painting).
    pub ui_busy_ms: f64,
    /// UI frames a second, over the last second or more.
    pub ui_fps: u32,
    /// The viewport's last render.
    pub render_ms: f64,
    /// The first frame after the last edit.
    pub edit_to_frame_ms: f64,
    /// The last scene upload.
    pub upload_ms: Option<f64>,
    /// Scene uploads since the renderer started.
    pub uploads: u64,
    /// Entities in the document.
    pub entities: usize,
    /// Whether Play runs.
    pub playing: bool,
}

/// The file the figures go to, and when the last line went.
#[derive(Debug)]
pub struct StatsLog {
    file: PathBuf,
    started: Instant,
    last: Option<Instant>,
}

impl StatsLog {
    /// Appends to `file` (created if missing; checked now, so a bad path fails at start).
    pub fn open(file: &Path) -> Result<StatsLog, String> {
        std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(file)
            .map_err(|e| format!("--stats {}: {e}", file.display()))?;
        Ok(StatsLog {
            file: file.to_owned(),
            started: Instant::now(),
            last: None,
        })
    }

    /// Appends a line of `figures` when a second has passed since the last one.
    pub fn tick(&mut self, figures: &Figures) -> Result<(), String> {
        if self.last.is_some_and(|t| t.elapsed() < EVERY) {
            return Ok(());
        }
        self.last = Some(Instant::now());
        let line = serde_json::json!({
            "t_s": (self.started.elapsed().as_secs_f64() * 10.0).round() / 10.0,
            "ui_frame_ms": figures.ui_frame_ms,
            "ui_busy_ms": figures.ui_busy_ms,
            "ui_fps": figures.ui_fps,
            "render_ms": figures.render_ms,
            "edit_to_frame_ms": figures.edit_to_frame_ms,
            "upload_ms": figures.upload_ms,
            "uploads": figures.uploads,
            "entities": figures.entities,
            "playing": figures.playing,
        });
        let mut f = std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(&self.file)
            .map_err(|e| format!("{}: {e}", self.file.display()))?;
        writeln!(f, "{line}").map_err(|e| format!("{}: {e}", self.file.display()))
    }
}
