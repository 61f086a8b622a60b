//! `texel-run render`: renders a level offscreen along a camera path (or from one camera)
//! and writes one PNG per frame plus `stats.json` (per-frame pass times and counters).

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, anyhow};
use glam::UVec2;
use serde::Serialize;
use texel_render::context::GpuContext;
use texel_render::input::Schedule;
use texel_render::stats::FrameStats;

use crate::load::load_level;
use crate::path::CameraPath;
use crate::session::{FrameRequest, Session, set_face_resolution};

/// Options of a headless run.
#[derive(Debug, Clone)]
pub struct RenderOptions {
    /// Output size.
    pub size: UVec2,
    /// Vertical field of view, radians.
    pub fov_y: f32,
    /// Cube-face resolution overriding the level's (None: the level's).
    pub face_res: Option<u32>,
    /// Scheduling method.
    pub schedule: Schedule,
    /// Where to write PNGs and `stats.json`.
    pub out: PathBuf,
    /// Write a PNG for every frame (else only the last).
    pub all_frames: bool,
    /// Frames to render from the player start when no path is given (None: 1).
    pub frames: Option<u32>,
}

/// One frame of `stats.json`.
#[derive(Debug, Serialize)]
pub struct FrameRecord {
    /// Frame number.
    pub frame: u32,
    /// Camera position.
    pub camera: [f32; 3],
    /// Origin of the camera cell's grid probe ([`texel_render::input::FrameInput::cell_probe`]).
    pub grid_origin: [f32; 3],
    /// Whether a previous probe was drawn (a crossfade ran, or the next cell's probe filled
    /// ahead of a crossing).
    pub crossfading: bool,
    /// Whether the next cell's probe filled behind the cell's before the crossing
    /// ([`texel_render::input::FrameInput::filling_ahead`]).
    pub filling_ahead: bool,
    /// Crossfade progress.
    pub fade_t: f32,
    /// Cost and work.
    #[serde(flatten)]
    pub stats: FrameStats,
}

/// The whole `stats.json`.
#[derive(Debug, Serialize)]
pub struct RunRecord {
    /// Level file.
    pub level: String,
    /// GPU adapter.
    pub adapter: String,
    /// Output size.
    pub size: [u32; 2],
    /// Schedule name.
    pub schedule: &'static str,
    /// Face resolution of the level's default grid.
    pub face_resolution: Option<u32>,
    /// Median frame time over the frames, ms.
    pub median_frame_ms: f64,
    /// The most the process had resident by the end, bytes (Linux; none elsewhere).
    pub peak_resident_bytes: Option<u64>,
    /// Per frame.
    pub frames: Vec<FrameRecord>,
}

/// The schedule's name in files and on the command line.
pub fn schedule_name(s: Schedule) -> &'static str {
    match s {
        Schedule::Ours => "ours",
        Schedule::Paper => "paper",
    }
}

/// Renders `level` along `path`; returns the record also written to `out/stats.json`.
pub fn render(level: &Path, path: Option<&CameraPath>, opts: &RenderOptions) -> Result<RunRecord> {
    let mut loaded = load_level(level)?;
    if let Some(n) = opts.face_res {
        set_face_resolution(&mut loaded, n).map_err(|e| anyhow!("--face-res: {e}"))?;
    }
    std::fs::create_dir_all(&opts.out)
        .with_context(|| format!("creating {}", opts.out.display()))?;
    let ctx = GpuContext::headless()?;
    // Before any target of this size exists: the device may allow less than the renderer.
    texel_render::validate::device_output(&ctx.device.limits(), opts.size)
        .map_err(|e| anyhow!("--size: {e}"))?;
    let mut session = Session::headless(&ctx, &loaded, opts.size, opts.fov_y)?;
    let default_path;
    let path = match path {
        Some(p) => p,
        None => {
            let c = session.start_camera();
            let (yaw, pitch) = yaw_pitch(c.forward);
            default_path = CameraPath::still(
                crate::path::Keyframe {
                    position: c.position.into(),
                    yaw,
                    pitch,
                },
                opts.frames.unwrap_or(1),
            );
            &default_path
        }
    };
    let request = |i: u32| FrameRequest {
        camera: path.camera(i, opts.fov_y),
        dt: path.dt,
        schedule: opts.schedule,
        size: opts.size,
    };
    // Warm up (shader compilation on first use), so frame 0 is honest.
    session.warm_up(&ctx, &request(0))?;

    let mut frames = Vec::new();
    for i in 0..path.frames {
        let (frame, pixels) = session.draw_offscreen(&ctx, &request(i))?;
        if opts.all_frames || i + 1 == path.frames {
            let file = opts.out.join(format!("frame_{i:04}.png"));
            image::save_buffer(
                &file,
                &pixels,
                opts.size.x,
                opts.size.y,
                image::ColorType::Rgba8,
            )
            .with_context(|| format!("writing {}", file.display()))?;
        }
        let (stats, input) = (frame.stats, frame.input);
        eprint!(
            "\rframe {}/{} ({:.0} ms)   ",
            i + 1,
            path.frames,
            stats.frame_ms
        );
        frames.push(FrameRecord {
            frame: i,
            camera: input.camera.position.to_array(),
            grid_origin: input.cell_probe().origin.to_array(),
            crossfading: input.previous.is_some(),
            filling_ahead: input.filling_ahead,
            fade_t: input.fade_t,
            stats,
        });
    }
    eprintln!();
    let mut ms: Vec<f64> = frames.iter().map(|f| f.stats.frame_ms).collect();
    ms.sort_by(f64::total_cmp);
    let record = RunRecord {
        level: level.display().to_string(),
        adapter: ctx.describe(),
        size: opts.size.to_array(),
        schedule: schedule_name(opts.schedule),
        face_resolution: opts.face_res,
        median_frame_ms: ms.get(ms.len() / 2).copied().unwrap_or(0.0),
        peak_resident_bytes: crate::soak::peak_rss_bytes(),
        frames,
    };
    let json = serde_json::to_string_pretty(&record)?;
    let stats_path = opts.out.join("stats.json");
    std::fs::write(&stats_path, json)
        .with_context(|| format!("writing {}", stats_path.display()))?;
    Ok(record)
}

/// Yaw and pitch in degrees of a view direction (inverse of `Camera::from_yaw_pitch`).
pub fn yaw_pitch(forward: glam::Vec3) -> (f32, f32) {
    let f = forward.normalize();
    let pitch = f.y.clamp(-1.0, 1.0).asin().to_degrees();
    let yaw = (-f.x).atan2(-f.z).to_degrees();
    (yaw, pitch)
}
