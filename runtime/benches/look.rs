//! The cost of each look (issue 61), reported, never asserted: one frame of the 1280×720
//! walk along `walk_cells` on `palette_night` (the stone circle in a palette) with nothing,
//! the palette, the palette dithered, a bloom, and a strong highlight on every material.
//! Printed once per case with the quads drawn a frame (dithering parts runs).
//!
//! `cargo bench -p texel_runtime --bench look` measures (on whatever Vulkan driver the machine
//! has) and writes the table to `docs/results/benches/look.md`; `cargo test --benches` runs
//! one small case of each once as a smoke test.

#[path = "common/frames.rs"]
mod frames;
#[path = "common/results.rs"]
mod results;

use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use glam::UVec2;
use texel_render::context::test_context;
use texel_render::input::Schedule;
use texel_runtime::load::{LoadedLevel, load_level};
use texel_runtime::path::CameraPath;
use texel_runtime::session::{FrameRequest, Session};
use texel_scene::{Bloom, Specular};

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The looks measured, by name.
const LOOKS: [&str; 5] = [
    "plain",
    "palette",
    "palette, dither 0.4",
    "bloom",
    "highlight",
];

/// `palette_night` dressed as `look` (its palette files are loaded with it either way).
fn level(look: &str) -> LoadedLevel {
    let mut level =
        load_level(&repo().join("assets/levels/palette_night.ron")).expect("bundled level");
    let s = &mut level.scene;
    match look {
        "palette" => s.palette.as_mut().expect("a palette").dither = 0.0,
        "palette, dither 0.4" => {}
        _ => s.palette = None,
    }
    if look == "bloom" {
        s.settings.bloom = Some(Bloom::default());
    }
    if look == "highlight" {
        let entities: Vec<_> = s.entities().collect();
        for e in entities {
            let mut row = s.row(e).expect("a row");
            if let Some(m) = &mut row.material {
                m.specular = Some(Specular {
                    strength: 1.5,
                    shininess: 16.0,
                });
                s.set_row(e, row).expect("set");
            }
        }
    }
    level
}

fn looks(c: &mut Criterion) {
    // Without an adapter this fails, unless TEXEL_ALLOW_NO_GPU opts out.
    let Some(ctx) = test_context() else {
        return;
    };
    let measuring = frames::measuring();
    let size = frames::frame_size(UVec2::new(96, 54));
    let path = CameraPath::load(&repo().join("assets/paths/walk_cells.ron")).expect("bundled path");
    let fov = path.fov_y(60f32.to_radians());
    let mut group = c.benchmark_group("look_walk_1280x720");
    const SAMPLES: usize = 10;
    group
        .sample_size(SAMPLES)
        .measurement_time(Duration::from_secs(15));
    let mut table = String::from("| look | frame | quads drawn |\n|---|---:|---:|\n");
    for look in LOOKS {
        let level = level(look);
        let mut session = Session::headless(&ctx, &level, size, fov).expect("session");
        let request = |i: u32| FrameRequest {
            camera: path.camera(i % path.frames, fov),
            dt: path.dt,
            schedule: Schedule::Ours,
            size,
        };
        let frames = if measuring { path.frames } else { 2 };
        let mut quads = 0u64;
        for i in 0..frames {
            let (frame, _) = session.draw_offscreen(&ctx, &request(i)).expect("frame");
            quads += frame.stats.counters.quads_splatted;
        }
        let quads = quads / u64::from(frames.max(1));
        eprintln!("{look}: {quads} quads per frame");
        let ms = frames::median_frame_ms(&mut group, look, SAMPLES, |i| {
            session.draw_offscreen(&ctx, &request(i)).expect("frame");
        });
        let _ = writeln!(table, "| {look} | {ms:.0} ms | {quads} |");
    }
    group.finish();
    eprintln!("\n{table}");
    if measuring {
        results::write("look", &ctx.describe(), &table);
    }
}

criterion_group!(benches, looks);
criterion_main!(benches);
