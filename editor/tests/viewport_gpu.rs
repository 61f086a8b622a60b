//! The viewport's GPU path on a headless device (lavapipe in CI): the level renders into a
//! texture egui can show, picking returns the entity under a pixel, and an edit re-uploads
//! the scene; the orthographic view renders from orthographic probes. Prints the frame times
//! measured.

use glam::{UVec2, Vec3};
use texel_render::context::test_context;
use texel_render::input::Schedule;
use texel_scene::Transform;

mod support;

#[test]
fn viewport_renders_and_picks_on_eframes_kind_of_device() {
    let Some(ctx) = test_context() else {
        return;
    };
    let mut gpu = support::gpu_view(&ctx);
    let mut level = support::stone_circle();
    // Look straight at the first upright of trilithon 1.
    let camera = support::camera();
    let size = UVec2::new(160, 120);
    let mut times = Vec::new();
    for _ in 0..4 {
        gpu.render(&level, 0, camera.camera(), size, Schedule::Ours, 0.016)
            .expect("render");
        times.push(gpu.report.frame_ms);
    }
    ctx.wait_idle().expect("idle");
    eprintln!(
        "viewport 160x120 frame ms: {times:?}, upload {:.2} ms",
        gpu.report.upload_ms
    );
    // The renderer's start (its shaders compiled) is not a scene upload: before any edit
    // a stroke's refreshes are paced as for a quick upload.
    assert!(gpu.report.start_ms > 0.0, "the start is timed");
    assert_eq!(gpu.report.upload_ms, 0.0, "no edit, no upload");
    let stats = gpu.report.stats.clone().expect("stats");
    assert!(stats.counters.quads_splatted > 0);
    assert!(gpu.texture().is_some());
    let picked = gpu.pick(size / 2).expect("pick");
    // Entity 2 in level order (after the ground) is "Trilithon 1 upright L": id 2.
    assert_eq!(picked, Some(2));

    // Move that stone away: after an edit (new revision) the centre shows something else.
    let e = level.scene.entities().nth(1).expect("entity");
    let mut row = level.scene.row(e).expect("row");
    row.transform = Some(Transform::from_translation(Vec3::new(50.0, 1.6, 50.0)));
    level.scene.set_row(e, row).expect("set");
    for _ in 0..3 {
        gpu.render(&level, 1, camera.camera(), size, Schedule::Ours, 0.016)
            .expect("render");
    }
    assert_ne!(gpu.pick(size / 2).expect("pick"), Some(2));
    assert!(gpu.report.upload_ms > 0.0, "the edit's upload is timed");
}

#[test]
fn orthographic_view_renders_from_orthographic_probes_and_picks() {
    let Some(ctx) = test_context() else {
        return;
    };
    let mut gpu = support::gpu_view(&ctx);
    let level = support::stone_circle();
    let mut camera = support::camera();
    camera.ortho = true;
    let size = UVec2::new(160, 120);
    for _ in 0..3 {
        gpu.render(&level, 0, camera.camera(), size, Schedule::Ours, 0.016)
            .expect("render");
    }
    ctx.wait_idle().expect("idle");
    // The frame driver saw the editor camera's orthographic height: its grid probe (and the
    // eye probe) are orthographic faces, not cubes.
    let probes = gpu.probes.expect("probes of the last frame");
    assert!(probes.grid.ortho.is_some(), "{:?}", probes.grid);
    assert!(probes.eye.ortho.is_some());
    // The renderer's start (its shaders compiled) is not a scene upload: before any edit
    // a stroke's refreshes are paced as for a quick upload.
    assert!(gpu.report.start_ms > 0.0, "the start is timed");
    assert_eq!(gpu.report.upload_ms, 0.0, "no edit, no upload");
    let stats = gpu.report.stats.clone().expect("stats");
    assert!(stats.counters.quads_splatted > 0);
    // The centre still shows the upright the view is focused on.
    assert_eq!(gpu.pick(size / 2).expect("pick"), Some(2));

    // Back to perspective: cube probes again.
    camera.ortho = false;
    gpu.render(&level, 0, camera.camera(), size, Schedule::Ours, 0.016)
        .expect("render");
    let probes = gpu.probes.expect("probes of the last frame");
    assert!(probes.grid.ortho.is_none());
}
