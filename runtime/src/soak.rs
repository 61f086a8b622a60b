//! `texel-run soak`: renders many frames headless along a camera path, looping it, and
//! watches the process's resident memory, so a leak per frame (a texture, a buffer, a bind
//! group, a growing list) shows as growth over thousands of frames. Not a test of the default
//! suite: 10,000 frames take minutes on a CPU rasterizer.

use std::path::Path;

use anyhow::{Result, anyhow};
use glam::UVec2;
use serde::Serialize;
use texel_render::context::GpuContext;
use texel_render::input::Schedule;

use crate::load::load_level;
use crate::path::CameraPath;
use crate::session::{FrameRequest, Session, set_face_resolution};

/// Frames rendered before the baseline is taken: caches, pools and the driver's own
/// allocations settle in the first frames (every probe slot, every fade pipeline used).
pub const SETTLE_FRAMES: u32 = 200;

/// Options of a soak run.
#[derive(Debug, Clone)]
pub struct SoakOptions {
    /// Output size.
    pub size: UVec2,
    /// Vertical field of view, radians.
    pub fov_y: f32,
    /// Cube-face resolution overriding the level's.
    pub face_res: Option<u32>,
    /// Frames in all (the path loops).
    pub frames: u32,
    /// Frames between two memory samples.
    pub sample_every: u32,
}

/// Resident memory at one frame.
#[derive(Debug, Clone, Copy, Serialize, PartialEq)]
pub struct Sample {
    /// Frames rendered so far.
    pub frame: u32,
    /// Resident set size, MiB.
    pub rss_mib: f64,
}

/// What a soak run measured.
#[derive(Debug, Clone, Serialize)]
pub struct SoakReport {
    /// GPU adapter.
    pub adapter: String,
    /// Frames rendered.
    pub frames: u32,
    /// Resident memory once the level is loaded and the renderer warmed up.
    pub start: Sample,
    /// Resident memory after [`SETTLE_FRAMES`] frames (the baseline growth is measured from).
    pub settled: Sample,
    /// Every sample, the last at the end of the run.
    pub samples: Vec<Sample>,
    /// Largest sample.
    pub peak_mib: f64,
}

impl SoakReport {
    /// Growth from the settled baseline to the end, MiB.
    pub fn growth_mib(&self) -> f64 {
        self.samples.last().map_or(0.0, |s| s.rss_mib) - self.settled.rss_mib
    }
}

/// The resident set size of this process, in bytes (Linux `/proc/self/status`).
pub fn rss_bytes() -> Option<u64> {
    parse_vm_rss(&std::fs::read_to_string("/proc/self/status").ok()?)
}

/// The most this process has had resident, in bytes (`VmHWM`, Linux only).
pub fn peak_rss_bytes() -> Option<u64> {
    parse_status_kib(
        &std::fs::read_to_string("/proc/self/status").ok()?,
        "VmHWM:",
    )
}

/// `VmRSS` of a `/proc/PID/status` text, in bytes.
fn parse_vm_rss(status: &str) -> Option<u64> {
    parse_status_kib(status, "VmRSS:")
}

/// The `key` line (in kB) of a `/proc/PID/status` text, in bytes.
fn parse_status_kib(status: &str, key: &str) -> Option<u64> {
    let line = status.lines().find(|l| l.starts_with(key))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

fn sample(frame: u32) -> Result<Sample> {
    let bytes = rss_bytes().ok_or_else(|| anyhow!("cannot read resident memory (/proc/self)"))?;
    Ok(Sample {
        frame,
        rss_mib: bytes as f64 / (1024.0 * 1024.0),
    })
}

/// Renders `opts.frames` frames of `level` along `path` (looping it), calling `progress` with
/// each memory sample.
pub fn soak(
    level: &Path,
    path: &CameraPath,
    opts: &SoakOptions,
    progress: &mut dyn FnMut(&Sample),
) -> Result<SoakReport> {
    let mut loaded = load_level(level)?;
    if let Some(n) = opts.face_res {
        set_face_resolution(&mut loaded, n).map_err(|e| anyhow!("--face-res: {e}"))?;
    }
    let ctx = GpuContext::headless()?;
    texel_render::validate::device_output(&ctx.device.limits(), opts.size)
        .map_err(|e| anyhow!("--size: {e}"))?;
    let mut session = Session::headless(&ctx, &loaded, opts.size, opts.fov_y)?;
    let request = |i: u32| FrameRequest {
        camera: path.camera(i % path.frames.max(1), opts.fov_y),
        dt: path.dt,
        schedule: Schedule::Ours,
        size: opts.size,
    };
    session.warm_up(&ctx, &request(0))?;
    let start = sample(0)?;
    progress(&start);
    let mut settled = start;
    let mut samples = Vec::new();
    let every = opts.sample_every.max(1);
    for i in 0..opts.frames {
        session.draw_offscreen(&ctx, &request(i))?;
        let done = i + 1;
        if done == SETTLE_FRAMES.min(opts.frames) {
            settled = sample(done)?;
        }
        if done % every == 0 || done == opts.frames {
            let s = sample(done)?;
            progress(&s);
            samples.push(s);
        }
    }
    let peak_mib = samples
        .iter()
        .chain([&start, &settled])
        .map(|s| s.rss_mib)
        .fold(0.0, f64::max);
    Ok(SoakReport {
        adapter: ctx.describe(),
        frames: opts.frames,
        start,
        settled,
        samples,
        peak_mib,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_vm_rss_in_kib() {
        let status = "Name:\ttexel-run\nVmPeak:\t  900 kB\nVmRSS:\t  123456 kB\nThreads:\t4\n";
        assert_eq!(parse_vm_rss(status), Some(123_456 * 1024));
        assert_eq!(parse_vm_rss("Name: x\n"), None);
        assert!(
            rss_bytes().is_some_and(|b| b > 0),
            "this process has resident memory"
        );
    }

    #[test]
    fn growth_is_measured_from_the_settled_sample_to_the_last() {
        let s = |frame, rss_mib| Sample { frame, rss_mib };
        let r = SoakReport {
            adapter: String::new(),
            frames: 3000,
            start: s(0, 100.0),
            settled: s(200, 180.0),
            samples: vec![s(1000, 181.0), s(2000, 185.0), s(3000, 184.5)],
            peak_mib: 185.0,
        };
        assert!((r.growth_mib() - 4.5).abs() < 1e-9);
    }
}
