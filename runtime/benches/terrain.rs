//! Terrain costs (issue 14), reported, never asserted:
//!
//! - `walk_1280x720`: the mean frame of the 1280×720 walk on `stone_circle` (its `walk_cells`
//!   path, and `jog_cells` at terrain_walk's pace) and on `terrain_hills` with its heights
//!   baked at 257×257 (`terrain_walk`). Each iteration settles the probes at the path's
//!   first frame (untimed) and plays the whole path forward once, and counts as its mean
//!   frame, as `texel-run render` plays it: every frame of the path weighs the same in
//!   every sample. The target is that the terrain adds at most 20%. terrain_walk
//!   crosses a probe cell every five frames, walk_cells every ten, so most of what separates
//!   those two is crossfades (both probes' quads drawn): `jog_cells` is the comparison at
//!   the same pace.
//! - `dab`: one brush dab (`texel-run play`'s: raise or lower, radius 3, a tenth of a second,
//!   8 units ahead of the camera) through `Session::update_level_region` with the box the
//!   dab may change, and the next frame drawn, with the camera at rest and while walking,
//!   beside the same frames without a dab; the faces a dab marks and the stable faces
//!   captured again are printed once.
//!
//! `cargo bench -p texel_runtime --bench terrain` measures (on whatever Vulkan driver the
//! machine has; the walks take about 15 minutes) and writes both tables to
//! `docs/results/benches/terrain.md` (a filtered run, `-- dab` say, writes only what it
//! measured); `cargo test --benches` runs each once as a smoke test, a walk as two frames of
//! its path after the probes settle.

#[path = "common/results.rs"]
mod results;

use std::fmt::Write as _;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::Mutex;
use std::time::{Duration, Instant};

use criterion::{Criterion, SamplingMode, criterion_group, criterion_main};
use glam::{UVec2, Vec2, Vec3};
use texel_probes::probe_set::Slot;
use texel_render::context::{GpuContext, test_context};
use texel_render::input::{Camera, Schedule};
use texel_runtime::load::{LoadedLevel, load_level};
use texel_runtime::path::CameraPath;
use texel_runtime::play_sculpt::{DABS_PER_SECOND, brush};
use texel_runtime::session::{FrameRequest, Session};
use texel_scene::Transform;
use texel_scene::sculpt::{self, Dab, Placement};
use texel_scene::terrain::{HeightSource, Heightfield, Terrain};

const DT: f32 = 1.0 / 30.0;
/// Samples a case: each is one call of the routine (`SamplingMode::Flat`).
const SAMPLES: usize = 10;
/// The tables measured so far (walks, dabs), written out after each group.
static TABLES: Mutex<[String; 2]> = Mutex::new([String::new(), String::new()]);

/// Keeps `table` as the `index`th table and writes all that were measured.
fn publish(index: usize, table: String, adapter: &str) {
    eprintln!("\n{table}");
    if !measuring() {
        return;
    }
    let mut tables = TABLES.lock().unwrap_or_else(|e| e.into_inner());
    tables[index] = table;
    let all: Vec<&str> = (tables.iter())
        .filter(|t| !t.is_empty())
        .map(String::as_str)
        .collect();
    results::write("terrain", adapter, &all.join("\n"));
}
/// Frames drawn at one camera for the probes there to settle (captured, no crossfade left).
const SETTLE_FRAMES: u32 = 8;

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn level(name: &str) -> LoadedLevel {
    load_level(&repo().join("assets/levels").join(name)).expect("bundled level loads")
}

fn path(name: &str) -> CameraPath {
    CameraPath::load(&repo().join("assets/paths").join(name)).expect("bundled path loads")
}

/// The level's terrain entity and component.
fn terrain_of(level: &LoadedLevel) -> (hecs::Entity, Terrain) {
    let world = level.scene.world();
    level
        .scene
        .entities()
        .find_map(|e| world.get::<&Terrain>(e).ok().map(|t| (e, (*t).clone())))
        .expect("a terrain")
}

/// `terrain_hills` with its noise baked at `resolution` samples per edge.
fn terrain_hills(resolution: u32) -> LoadedLevel {
    let mut level = level("terrain_hills.ron");
    let (entity, mut terrain) = terrain_of(&level);
    if let HeightSource::Noise { resolution: r, .. } = &mut terrain.heightmap {
        *r = resolution;
    }
    let field = Heightfield::from_noise(&terrain.heightmap, terrain.size, terrain.max_height)
        .expect("noise bakes");
    level
        .scene
        .world_mut()
        .insert_one(entity, terrain.clone())
        .expect("terrain entity");
    level.assets.insert_heightfield(&terrain, Arc::new(field));
    level
}

fn request(camera: Camera, size: UVec2) -> FrameRequest {
    FrameRequest {
        camera,
        dt: DT,
        schedule: Schedule::Ours,
        size,
    }
}

/// A session on `level`, its probes settled at `camera`.
fn settled(ctx: &GpuContext, level: &LoadedLevel, camera: Camera, size: UVec2) -> Session {
    let mut session = Session::headless(ctx, level, size, camera.fov_y).expect("session");
    for _ in 0..SETTLE_FRAMES {
        session
            .draw_offscreen(ctx, &request(camera, size))
            .expect("frame");
    }
    session
}

/// One dab of `texel-run play`'s raise (or lower) brush ([`texel_runtime::play_sculpt::brush`]:
/// radius 3, a tenth of a second) at `at` (world X, Z); returns the box it may change
/// ([`Placement::region_bounds`]).
fn dab(level: &mut LoadedLevel, at: Vec2, raise: bool) -> (Vec3, Vec3) {
    let (entity, terrain) = terrain_of(level);
    let origin =
        (level.scene.world().get::<&Transform>(entity)).map_or(Vec3::ZERO, |t| t.translation);
    let mut field = (**level.assets.heightfield(&terrain).expect("heights")).clone();
    let place = Placement::new(&terrain, origin, &field);
    let d = Dab {
        centre: Vec3::new(at.x, 0.0, at.y),
        dt: 1.0 / DABS_PER_SECOND,
        invert: false,
        target: 0.0,
    };
    let region = sculpt::dab(&mut field, &place, &brush(raise), &d).expect("a dab on the terrain");
    level.assets.insert_heightfield(&terrain, Arc::new(field));
    place.region_bounds(region)
}

/// A point on the ground 8 units ahead of `camera`.
fn ahead(camera: &Camera) -> Vec2 {
    let f = Vec2::new(camera.forward.x, camera.forward.z).normalize_or_zero();
    Vec2::new(camera.position.x, camera.position.z) + 8.0 * f
}

/// Whether criterion measures (`cargo bench` passes `--bench`) rather than running each
/// routine once as a smoke test (`cargo test --benches`).
fn measuring() -> bool {
    std::env::args().any(|a| a == "--bench")
}

/// The frame size: 1280×720 when measuring; as a smoke test 160×90, which draws the same
/// passes (a 1280×720 smoke test took minutes on lavapipe and told nothing more).
fn frame_size() -> UVec2 {
    if measuring() {
        UVec2::new(1280, 720)
    } else {
        UVec2::new(160, 90)
    }
}

fn walk(c: &mut Criterion) {
    // Without an adapter this fails, unless TEXEL_ALLOW_NO_GPU opts out.
    let Some(ctx) = test_context() else {
        return;
    };
    let size = frame_size();
    let mut group = c.benchmark_group("walk_1280x720");
    // An iteration is a whole walk along the path (about half a minute), a sample one
    // iteration. Before, an iteration was one frame of the path played forth and back: a
    // sample of 13 frames held a stretch of it, ten of them about one pass forth and back,
    // so how much of its costlier stretches they held moved the mean (the terrain's samples
    // ran from 419 to 738 ms a frame, the estimate ±10 % between runs). Played back, the
    // walk is another motion, dearer: passes back took 1.46× the passes forth on the
    // terrain, 1.23× on `jog_cells` (2026-12-06). Before that (the path in a loop, linear
    // sampling) one sample held the jump from its end to its start.
    group
        .sample_size(SAMPLES)
        .sampling_mode(SamplingMode::Flat)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(60));
    let measuring = measuring();
    let mut rows = Vec::new();
    for (name, level, path) in [
        (
            "stone_circle",
            level("stone_circle.ron"),
            path("walk_cells.ron"),
        ),
        // The same pace as terrain_walk (a cell every five frames, against walk_cells' ten):
        // a crossfade runs on most frames of both, so what differs is the terrain's cost.
        (
            "stone_circle_jog",
            level("stone_circle.ron"),
            path("jog_cells.ron"),
        ),
        (
            "terrain_hills_257",
            terrain_hills(257),
            path("terrain_walk.ron"),
        ),
    ] {
        let fov = path.fov_y(60f32.to_radians());
        let mut session = settled(&ctx, &level, path.camera(0, fov), size);
        // A walk: frames 1, 2, … after the probes settled at frame 0 (as `settled` does).
        let frames = if measuring { path.frames } else { 3 };
        let start = path.camera(0, fov);
        let mut samples = results::Samples::default();
        let (mut quads, mut texels) = (0, 0);
        group.bench_function(name, |b| {
            b.iter_custom(|iters| {
                let mut mean_frames = Duration::ZERO;
                for _ in 0..iters {
                    for _ in 0..SETTLE_FRAMES {
                        let frame = session.draw_offscreen(&ctx, &request(start, size));
                        frame.expect("frame");
                    }
                    (quads, texels) = (0, 0);
                    let t = Instant::now();
                    for i in 1..frames {
                        let camera = path.camera(i, fov);
                        let (frame, _) = session
                            .draw_offscreen(&ctx, &request(camera, size))
                            .expect("frame");
                        quads += frame.stats.counters.quads_splatted;
                        texels += frame.stats.counters.texels_shaded;
                    }
                    mean_frames += t.elapsed() / (frames - 1).max(1);
                }
                samples.push(mean_frames, iters);
                mean_frames
            })
        });
        let per_frame = |n: u64| n / u64::from(frames - 1).max(1);
        let walk = format!("{name}, `{}`", path_name(name));
        rows.push((
            walk,
            samples.median_ms(SAMPLES),
            per_frame(quads),
            per_frame(texels),
        ));
    }
    group.finish();
    let mut table = String::from(
        "| walk (level, path) | mean frame of a walk | quads drawn a frame | texels lit a frame |\n\
         |---|---:|---:|---:|\n",
    );
    for (walk, ms, quads, texels) in &rows {
        let _ = writeln!(table, "| {walk} | {ms:.1} ms | {quads} | {texels} |");
    }
    if let [_, (_, jog_ms, jog_quads, _), (_, hills_ms, hills_quads, _)] = rows.as_slice() {
        let _ = writeln!(
            table,
            "| terrain_walk ÷ jog_cells | {:.2}× | {:.2}× | |",
            hills_ms / jog_ms,
            *hills_quads as f64 / (*jog_quads).max(1) as f64
        );
    }
    publish(0, table, &ctx.describe());
}

/// The path each walk of [`walk`] plays.
fn path_name(walk: &str) -> &'static str {
    match walk {
        "stone_circle" => "walk_cells",
        "stone_circle_jog" => "jog_cells",
        _ => "terrain_walk",
    }
}

fn dabs(c: &mut Criterion) {
    // Without an adapter this fails, unless TEXEL_ALLOW_NO_GPU opts out.
    let Some(ctx) = test_context() else {
        return;
    };
    let size = frame_size();
    let path = path("terrain_walk.ron");
    let fov = path.fov_y(60f32.to_radians());
    let mut group = c.benchmark_group("dab");
    group
        .sample_size(SAMPLES)
        .measurement_time(Duration::from_secs(20));
    let mut table = String::from(
        "| camera | frame | dab and frame | faces a dab marks | stable faces captured over the \
         next 8 frames |\n|---|---:|---:|---:|---:|\n",
    );
    for moving in [false, true] {
        let mut level = terrain_hills(257);
        let mut session = settled(&ctx, &level, path.camera(0, fov), size);
        let mut frame = 0u32;
        let path = &path;
        let mut next_camera = move || {
            let camera = path.camera(if moving { frame % path.frames } else { 0 }, fov);
            frame += 1;
            camera
        };
        let label = if moving { "moving" } else { "at_rest" };
        let (mut frames, mut dabs) = (results::Samples::default(), results::Samples::default());
        group.bench_function(format!("frame_{label}"), |b| {
            b.iter_custom(|iters| {
                let t = Instant::now();
                for _ in 0..iters {
                    session
                        .draw_offscreen(&ctx, &request(next_camera(), size))
                        .expect("frame");
                }
                frames.push(t.elapsed(), iters);
                t.elapsed()
            })
        });
        let mut raise = true;
        let mut reported = None;
        group.bench_function(format!("dab_and_frame_{label}"), |b| {
            b.iter_custom(|iters| {
                let mut total = Duration::ZERO;
                for _ in 0..iters {
                    let camera = next_camera();
                    let (min, max) = dab(&mut level, ahead(&camera), raise);
                    raise = !raise;
                    let t = Instant::now();
                    let marked = session
                        .update_level_region(&ctx, &level, min, max)
                        .expect("update");
                    let (drawn, _) = session
                        .draw_offscreen(&ctx, &request(camera, size))
                        .expect("frame");
                    total += t.elapsed();
                    if reported.is_none() {
                        let mut stable = count_stable(&drawn.input);
                        for _ in 0..7 {
                            let (drawn, _) = session
                                .draw_offscreen(&ctx, &request(camera, size))
                                .expect("frame");
                            stable += count_stable(&drawn.input);
                        }
                        reported = Some((marked, stable));
                    }
                }
                dabs.push(total, iters);
                total
            })
        });
        let (marked, stable) = reported.unwrap_or_default();
        let _ = writeln!(
            table,
            "| {} | {:.1} ms | {:.1} ms | {marked} | {stable} |",
            label.replace('_', " "),
            frames.median_ms(SAMPLES),
            dabs.median_ms(SAMPLES)
        );
    }
    group.finish();
    publish(1, table, &ctx.describe());
}

fn count_stable(input: &texel_render::input::FrameInput) -> usize {
    input
        .captures
        .iter()
        .filter(|w| w.slot != Slot::Eye)
        .count()
}

criterion_group!(benches, walk, dabs);
criterion_main!(benches);
