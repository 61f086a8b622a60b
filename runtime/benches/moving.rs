//! The cost of moving objects (issue 15), reported, never asserted: one frame of the 1280×720
//! walk on `stone_circle` (its `walk_cells` path, played in a loop) with 1, 10 and 100 boxes
//! turning inside the circle, beside the same level with those boxes frozen (ordinary still
//! geometry, captured into the probes). Printed once per case: the texels lit per frame (the
//! stable faces lit again where the boxes' shadows came or went show up here) and the quads.
//!
//! `cargo bench -p texel_runtime --bench moving` measures (on whatever Vulkan driver the
//! machine has) and writes the table to `docs/results/benches/moving.md`; `cargo test
//! --benches` runs one small case once as a smoke test.

#[path = "common/frames.rs"]
mod frames;
#[path = "common/results.rs"]
mod results;

use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use glam::{UVec2, Vec3};
use texel_render::context::test_context;
use texel_render::input::Schedule;
use texel_runtime::load::{LoadedLevel, load_level};
use texel_runtime::path::CameraPath;
use texel_runtime::session::{FrameRequest, Session};
use texel_scene::animator::{Animator, Motion};
use texel_scene::{EntityRow, Geometry, Material, Name, Transform};

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// `stone_circle` with `n` boxes of 0.4 on a spiral inside the circle, each turning about Y
/// (or standing still when `frozen`).
fn level_with_boxes(n: usize, frozen: bool) -> LoadedLevel {
    let mut level =
        load_level(&repo().join("assets/levels/stone_circle.ron")).expect("bundled level loads");
    for i in 0..n {
        let a = i as f32 * 2.399;
        let r = 1.0 + 4.0 * ((i as f32 + 0.5) / n as f32).sqrt();
        let row = EntityRow {
            name: Some(Name(format!("Box {i}"))),
            transform: Some(Transform {
                translation: Vec3::new(r * a.cos(), 0.6 + 0.3 * (i % 3) as f32, r * a.sin()),
                ..Transform::default()
            }),
            geometry: Some(Geometry::Box {
                size: Vec3::splat(0.4),
            }),
            material: Some(Material::default()),
            animator: (!frozen).then_some(Animator {
                motion: Motion::Rotate {
                    axis: Vec3::Y,
                    speed: 30.0 + (i % 7) as f32 * 10.0,
                },
                phase: 0.0,
            }),
            ..EntityRow::default()
        };
        level.scene.spawn(row);
    }
    level
}

fn walk(c: &mut Criterion) {
    // Without an adapter this fails, unless TEXEL_ALLOW_NO_GPU opts out.
    let Some(ctx) = test_context() else {
        return;
    };
    // `cargo test --benches` runs each case once to see it works: there the frames are
    // small, a few, and only one box.
    let measuring = frames::measuring();
    let size = frames::frame_size(UVec2::new(160, 90));
    let counts: &[usize] = if measuring { &[1, 10, 100] } else { &[1] };
    let path = CameraPath::load(&repo().join("assets/paths/walk_cells.ron")).expect("bundled path");
    let fov = path.fov_y(60f32.to_radians());
    let mut group = c.benchmark_group("moving_walk_1280x720");
    const SAMPLES: usize = 10;
    group
        .sample_size(SAMPLES)
        .measurement_time(Duration::from_secs(15));
    let mut table = String::from(
        "| boxes | moving | frozen | texels lit, moving | texels lit, frozen |\n\
         |---:|---:|---:|---:|---:|\n",
    );
    for &n in counts {
        let mut row = [(0.0, 0u64); 2];
        for frozen in [false, true] {
            let level = level_with_boxes(n, frozen);
            let mut session = Session::headless(&ctx, &level, size, fov).expect("session");
            let request = |i: u32| FrameRequest {
                camera: path.camera(i % path.frames, fov),
                dt: path.dt,
                schedule: Schedule::Ours,
                size,
            };
            // One pass along the path: probes settled, and the work per frame counted.
            let (mut texels, mut quads) = (0u64, 0u64);
            let frames = if measuring { path.frames } else { 4 };
            for i in 0..frames {
                let (frame, _) = session.draw_offscreen(&ctx, &request(i)).expect("frame");
                texels += frame.stats.counters.texels_shaded;
                quads += frame.stats.counters.quads_splatted;
            }
            let label = format!("{n}_{}", if frozen { "frozen" } else { "moving" });
            let frames = u64::from(frames.max(1));
            eprintln!(
                "{label}: {} texels lit, {} quads per frame",
                texels / frames,
                quads / frames
            );
            let ms = frames::median_frame_ms(&mut group, &label, SAMPLES, |i| {
                session.draw_offscreen(&ctx, &request(i)).expect("frame");
            });
            row[usize::from(frozen)] = (ms, texels / frames);
        }
        let [(moving, lit_moving), (frozen, lit_frozen)] = row;
        let _ = writeln!(
            table,
            "| {n} | {moving:.0} ms | {frozen:.0} ms | {lit_moving} | {lit_frozen} |"
        );
    }
    group.finish();
    eprintln!("\n{table}");
    if measuring {
        results::write("moving", &ctx.describe(), &table);
    }
}

criterion_group!(benches, walk);
criterion_main!(benches);
