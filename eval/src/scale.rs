//! Frame cost against level size (`texel-eval scale`): generated towns of N entities
//! (`texel_runtime::generate`, the generator of `texel-run gen`) walked down their street,
//! each in a process of its own so that its peak memory is its own and a level the GPU
//! refuses is a row with its error, not the end of the run. A bundled level walked along its
//! own path is measured in the same run as the reference the scale targets are stated
//! against (issue 58: a 10,000-entity level's median frame ≤ 1.5× stone_circle's).
//!
//! One measurement ([`measure`]): load the level (timed), open a session on it (timed with
//! the load: the level's preparation, scene upload and probe plan), warm up, draw the walk's
//! frames, and keep each pass's median, the counters of the last frame and the process's
//! peak resident memory. The rows go to `scale.json`, `scale.md` and a chart
//! (`scale.png`, `scale.svg`: each pass's median and the frame against N, log–log).

use std::collections::BTreeMap;
use std::path::Path;
use std::time::Instant;

use anyhow::{Context, Result, anyhow};
use glam::UVec2;
use serde::{Deserialize, Serialize};
use texel_render::context::GpuContext;
use texel_render::input::Schedule;
use texel_runtime::load::load_level;
use texel_runtime::path::CameraPath;
use texel_runtime::session::{FrameRequest, Session, set_face_resolution};

/// The passes charted, in the chart's order, besides the whole frame.
pub const CHARTED_PASSES: [&str; 4] = ["capture", "shade", "cull", "splat"];

/// One level measured: a generated town of `entities`, or the reference level.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ScaleRow {
    /// "town" for a generated town, else the reference level's file name.
    pub label: String,
    /// Entities in the level.
    pub entities: usize,
    /// Point lights in the level.
    pub point_lights: usize,
    /// Loading the file and opening a session on it (preparation, upload, plan), ms.
    pub load_ms: f64,
    /// Of `load_ms`, reading the file and its assets, ms.
    pub read_ms: f64,
    /// Median frame time over the walk, ms (`None`: refused, see `error`).
    pub frame_ms: Option<f64>,
    /// Median time of each pass over the walk, ms.
    pub passes: BTreeMap<String, f64>,
    /// Objects drawn into a captured face (the eye's far faces among them), on average over
    /// the walk.
    pub objects_per_face: f64,
    /// Objects the eye's faces drew a frame (their far faces aside), on average over the
    /// walk.
    #[serde(default)]
    pub eye_objects_per_frame: f64,
    /// Probe texels lit a frame, median over the walk.
    pub texels_shaded: u64,
    /// GPU bytes of the scene, the shadow trees, textures and probes (last frame).
    pub gpu_bytes: u64,
    /// The process's peak resident memory, bytes (Linux; 0 elsewhere).
    pub peak_resident_bytes: u64,
    /// Why the level was not drawn.
    pub error: Option<String>,
    /// The GPU adapter that drew it.
    pub adapter: String,
}

/// What one measurement draws.
#[derive(Debug, Clone, Copy)]
pub struct Walk {
    /// Output size.
    pub size: UVec2,
    /// Cube-face resolution of the level's grid.
    pub face_res: u32,
    /// Vertical field of view, radians.
    pub fov_y: f32,
}

/// Measures `level` along `path` (see the module's doc). A level that loads but cannot be
/// drawn (too large for the device) is a row with its error; one that does not load is an
/// error.
pub fn measure(level: &Path, path: &CameraPath, walk: Walk, label: &str) -> Result<ScaleRow> {
    // The device first: opening it is not the level's load.
    let ctx = GpuContext::headless()?;
    let start = Instant::now();
    let mut loaded = load_level(level).with_context(|| format!("loading {}", level.display()))?;
    let read_ms = start.elapsed().as_secs_f64() * 1e3;
    set_face_resolution(&mut loaded, walk.face_res).map_err(|e| anyhow!("--face-res: {e}"))?;
    let entities = loaded.scene.entities().count();
    let point_lights = (loaded.scene.world())
        .query::<&texel_scene::PointLight>()
        .iter()
        .count();
    let mut row = ScaleRow {
        label: label.to_owned(),
        entities,
        point_lights,
        load_ms: 0.0,
        read_ms,
        frame_ms: None,
        passes: BTreeMap::new(),
        objects_per_face: 0.0,
        eye_objects_per_frame: 0.0,
        texels_shaded: 0,
        gpu_bytes: 0,
        peak_resident_bytes: 0,
        error: None,
        adapter: String::new(),
    };
    row.adapter = ctx.describe();
    let session = Session::headless(&ctx, &loaded, walk.size, walk.fov_y);
    row.load_ms = start.elapsed().as_secs_f64() * 1e3;
    let mut session = match session {
        Ok(s) => s,
        Err(e) => {
            row.error = Some(format!("{e:#}"));
            row.peak_resident_bytes = texel_runtime::soak::peak_rss_bytes().unwrap_or(0);
            return Ok(row);
        }
    };
    let request = |i: u32| FrameRequest {
        camera: path.camera(i, walk.fov_y),
        dt: path.dt,
        schedule: Schedule::Ours,
        size: walk.size,
    };
    session.warm_up(&ctx, &request(0))?;
    let mut frames = Vec::new();
    let mut per_pass: BTreeMap<String, Vec<f64>> = BTreeMap::new();
    let (mut faces, mut objects, mut shaded) = (0u64, 0u64, Vec::new());
    let mut eye_objects = 0u64;
    for i in 0..path.frames {
        let (frame, _) = session.draw_offscreen(&ctx, &request(i))?;
        let s = frame.stats;
        frames.push(s.frame_ms);
        for p in &s.passes {
            per_pass.entry(p.pass.to_owned()).or_default().push(p.ms);
        }
        faces += u64::from(s.counters.faces_captured) + u64::from(s.counters.far_faces_captured);
        objects += s.counters.objects_captured;
        eye_objects += s.counters.eye_objects_captured;
        shaded.push(s.counters.texels_shaded as f64);
        let c = &s.counters;
        row.gpu_bytes = c.gpu_scene_bytes + c.gpu_bvh_bytes + c.gpu_probe_bytes + c.texture_bytes;
    }
    row.frame_ms = Some(median(&mut frames));
    row.passes = (per_pass.into_iter())
        .map(|(k, mut v)| (k, median(&mut v)))
        .collect();
    row.objects_per_face = objects as f64 / faces.max(1) as f64;
    row.eye_objects_per_frame = eye_objects as f64 / f64::from(path.frames.max(1));
    row.texels_shaded = median(&mut shaded) as u64;
    row.peak_resident_bytes = texel_runtime::soak::peak_rss_bytes().unwrap_or(0);
    Ok(row)
}

/// The middle value (the upper middle for an even count; 0 for none).
fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(0.0)
}

/// The walk a benchmark takes through a generated level of `count` entities at `density`:
/// north down the street from 2 m inside its south end, at eye height, `frames` frames at
/// 30 a second and `speed` metres a second.
pub fn street_walk(count: usize, density: f32, frames: u32, speed: f32) -> String {
    let z = texel_runtime::generate::side(count, density) / 2.0 - 2.0;
    let length = speed * frames as f32 / 30.0;
    format!(
        "(frames: {frames}, dt: {:.7}, keyframes: [(position: (0.0, 1.6, {z:.2})), \
         (position: (0.0, 1.6, {:.2}))])",
        1.0 / 30.0,
        z - length
    )
}

/// All the rows of a run, and how they were drawn.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct ScaleReport {
    /// The command that measured it (without the program's path).
    pub command: String,
    /// When, which commit, which machine.
    pub stamp: String,
    /// The GPU adapter.
    pub adapter: String,
    /// Output size.
    pub size: [u32; 2],
    /// Cube-face resolution.
    pub face_res: u32,
    /// Frames of each walk.
    pub frames: u32,
    /// The towns' walking speed, m/s.
    pub speed: f32,
    /// The reference level's row, if one was measured.
    pub reference: Option<ScaleRow>,
    /// The towns, by size.
    pub towns: Vec<ScaleRow>,
}

impl ScaleReport {
    /// The Markdown table of the rows, and each town's frame against the reference's.
    pub fn table(&self) -> String {
        let mut s = format!(
            "Generated towns walked down their street at {} m/s, {}×{}, faces of {}, {} frames, \
             {} ({}). Medians in ms; memory in MB; texels lit a frame.\n\n",
            self.speed,
            self.size[0],
            self.size[1],
            self.face_res,
            self.frames,
            self.adapter,
            self.stamp
        );
        s += "| level | entities | point lights | load (read) | frame | capture | shade | cull | splat \
              | objects a face | eye objects a frame | texels lit | GPU | peak resident | ÷ reference |\n";
        s += "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
        let reference = self.reference.as_ref().and_then(|r| r.frame_ms);
        for r in self.reference.iter().chain(&self.towns) {
            let pass = |p: &str| r.passes.get(p).map_or("—".into(), |ms| format!("{ms:.0}"));
            let ratio = match (r.frame_ms, reference) {
                (Some(f), Some(base)) if base > 0.0 => format!("{:.2}×", f / base),
                _ => "—".into(),
            };
            let frame = match (&r.frame_ms, &r.error) {
                (Some(ms), _) => format!("{ms:.0}"),
                (None, Some(e)) => format!("refused: {}", e.replace('|', "/")),
                (None, None) => "—".into(),
            };
            s += &format!(
                "| {} | {} | {} | {:.0} ({:.0}) | {frame} | {} | {} | {} | {} | {:.0} | {:.0} | {} | {:.1} | {:.0} | {ratio} |\n",
                r.label,
                r.entities,
                r.point_lights,
                r.load_ms,
                r.read_ms,
                pass("capture"),
                pass("shade"),
                pass("cull"),
                pass("splat"),
                r.objects_per_face,
                r.eye_objects_per_frame,
                r.texels_shaded,
                r.gpu_bytes as f64 / 1e6,
                r.peak_resident_bytes as f64 / 1e6,
            );
        }
        s += &format!("\n`{}`\n", self.command);
        s
    }
}

/// Writes `scale.json`, `scale.md`, `scale.png` and `scale.svg` into `dir`.
pub fn write(report: &ScaleReport, dir: &Path) -> Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let json = serde_json::to_string_pretty(report)?;
    write_atomic(&dir.join("scale.json"), json.as_bytes())?;
    write_atomic(&dir.join("scale.md"), report.table().as_bytes())?;
    crate::scale_chart::write_chart(report, dir)
}

/// Writes `bytes` to `path` through a temporary file beside it.
fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let tmp = path.with_extension("tmp");
    std::fs::write(&tmp, bytes).with_context(|| format!("writing {}", tmp.display()))?;
    std::fs::rename(&tmp, path).with_context(|| format!("writing {}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(label: &str, entities: usize, frame: Option<f64>) -> ScaleRow {
        ScaleRow {
            label: label.into(),
            entities,
            point_lights: 2,
            load_ms: 10.0,
            read_ms: 4.0,
            frame_ms: frame,
            passes: [("capture".to_owned(), 4.0), ("shade".to_owned(), 6.0)].into(),
            objects_per_face: 12.0,
            eye_objects_per_frame: 30.0,
            texels_shaded: 900,
            gpu_bytes: 2_000_000,
            peak_resident_bytes: 200_000_000,
            error: frame.is_none().then(|| "too large | for this GPU".into()),
            adapter: "test".into(),
        }
    }

    #[test]
    fn the_table_divides_each_frame_by_the_references_and_names_refusals() {
        let report = ScaleReport {
            command: "texel-eval scale --counts 100,1000".into(),
            stamp: "now".into(),
            adapter: "test".into(),
            size: [64, 36],
            face_res: 32,
            frames: 2,
            speed: 2.5,
            reference: Some(row("stone_circle", 25, Some(20.0))),
            towns: vec![row("town", 100, Some(30.0)), row("town", 1000, None)],
        };
        let t = report.table();
        assert!(t.contains(
            "| town | 100 | 2 | 10 (4) | 30 | 4 | 6 | — | — | 12 | 30 | 900 | 2.0 | 200 | 1.50× |"
        ));
        assert!(t.contains("refused: too large / for this GPU"), "{t}");
        assert_eq!(t.lines().filter(|l| l.starts_with("| ")).count(), 4);
        assert!(
            t.ends_with("\n`texel-eval scale --counts 100,1000`\n"),
            "{t}"
        );
    }

    #[test]
    fn the_street_walk_starts_inside_the_south_end() {
        let walk = street_walk(10_000, 4.0, 30, 15.0);
        let path = CameraPath::from_ron_str(&walk, "walk").expect("parses");
        assert_eq!(path.frames, 30);
        assert_eq!(path.keyframes[0].position, (0.0, 1.6, 248.0));
        assert_eq!(path.keyframes[1].position, (0.0, 1.6, 233.0));
    }
}
