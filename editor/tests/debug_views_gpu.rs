//! Debug views and edit responsiveness on a headless device (lavapipe in CI): the probe
//! origins of the last frame, the eye-sourced pixel tint and the grid probe's lit faces read
//! back; and how long the first frame after an edit stalls at the still and the moving
//! resolution (printed).

use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

use egui::mutex::RwLock;
use glam::{UVec2, Vec3};
use texel_editor::camera::EditorCamera;
use texel_editor::viewport::debug::{DebugState, DebugView};
use texel_editor::viewport::gpu::{FORMAT, GpuView};
use texel_editor::viewport::{SCALE_MOVING, SCALE_STILL};
use texel_render::context::{GpuContext, test_context};
use texel_render::input::Schedule;
use texel_runtime::load::{LoadedLevel, load_level};
use texel_scene::Transform;

fn gpu_view(ctx: &GpuContext) -> GpuView {
    let egui_renderer = egui_wgpu::Renderer::new(&ctx.device, FORMAT, Default::default());
    let rs = egui_wgpu::RenderState {
        adapter: ctx.adapter.clone(),
        available_adapters: vec![ctx.adapter.clone()],
        instance: ctx.instance.clone(),
        device: ctx.device.clone(),
        queue: ctx.queue.clone(),
        target_format: FORMAT,
        renderer: Arc::new(RwLock::new(egui_renderer)),
    };
    GpuView::new(&rs).expect("renderer on the shared device")
}

fn stone_circle() -> LoadedLevel {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/levels/stone_circle.ron");
    load_level(&path).expect("stone_circle")
}

fn camera() -> EditorCamera {
    let mut camera = EditorCamera::default();
    camera.focus(Vec3::new(1.206, 1.6, 5.946), 6.0);
    camera
}

#[test]
fn debug_views_read_back_probe_data() {
    let Some(ctx) = test_context() else {
        return;
    };
    let mut gpu = gpu_view(&ctx);
    let level = stone_circle();
    let cam = camera();
    let size = UVec2::new(160, 120);
    for _ in 0..6 {
        gpu.render(&level, 0, cam.camera(), size, Schedule::Ours, 0.016)
            .expect("render");
    }

    // Probe origins: the eye probe sits at the eye, the grid probe on the lattice.
    let probes = gpu.probes.expect("probes of the last frame");
    assert!((probes.eye.origin - cam.eye).length() < 1e-4);
    let cell = level.scene.settings.cell_size;
    let lattice = probes.grid.origin / cell;
    assert!((lattice - lattice.round()).length() < 1e-3, "{lattice}");

    // Eye-sourced pixels: one flag per pixel, and the tint is built from them.
    let ids = gpu.frame_ids().expect("frame ids");
    assert_eq!(ids.size, size);
    assert_eq!(ids.from_eye.len(), (size.x * size.y) as usize);
    assert!(ids.entity.iter().any(|&e| e != 0));
    let eye = ids.from_eye.iter().filter(|&&e| e).count();
    eprintln!("eye-sourced pixels: {eye} of {}", ids.from_eye.len());

    // The grid probe's lit faces: six n×n sRGB images, not one flat colour.
    let (n, faces) = gpu.probe_faces(&probes.grid).expect("faces");
    assert_eq!(n, probes.grid.face_resolution);
    assert_eq!(faces.len(), 6);
    assert!(faces.iter().all(|f| f.len() == (n * n * 4) as usize));
    let varied = faces.iter().any(|f| f.chunks(4).any(|p| p != &f[..4]));
    assert!(varied, "the faces hold a picture");

    let ui = egui::Context::default();
    let mut debug = DebugState::default();
    debug.update(&ui, &gpu, true, true);
    assert_eq!(debug.readbacks, 0, "nothing read while the views are off");
    debug.flags.toggle(DebugView::EyePixels);
    debug.flags.toggle(DebugView::CubeFaces);
    debug.update(&ui, &gpu, false, false);
    assert!(debug.has_eye_tint());
    assert_eq!(debug.face_count(), 6);
    assert_eq!(debug.readbacks, 2);
    // Nothing rendered and the probe unchanged: no more reads.
    debug.update(&ui, &gpu, false, false);
    assert_eq!(debug.readbacks, 2);
    debug.flags = Default::default();
    debug.update(&ui, &gpu, true, true);
    assert!(!debug.has_eye_tint());
    assert_eq!(debug.face_count(), 0);
}

/// The first render after an edit (scene upload, new frame driver and probes, first frame)
/// at the viewport's still and moving resolutions, for a 1280×800 window.
#[test]
fn edit_stall_at_still_and_moving_resolution() {
    let Some(ctx) = test_context() else {
        return;
    };
    let mut gpu = gpu_view(&ctx);
    let mut level = stone_circle();
    let cam = camera();
    // The central panel of a 1280×800 window is about 730×750 points.
    let panel = glam::Vec2::new(730.0, 750.0);
    let still = (panel * SCALE_STILL).as_uvec2();
    let moving = (panel * SCALE_MOVING).as_uvec2();
    let mut revision = 0;
    let mut stall = |level: &mut LoadedLevel, size: UVec2, gpu: &mut GpuView| {
        // Move a stone (as a gizmo step does), then render the first frame after it.
        revision += 1;
        let e = level.scene.entities().nth(1).expect("entity");
        let mut row = level.scene.row(e).expect("row");
        let mut t = row.transform.unwrap_or_default();
        t.translation.x += 0.1;
        row.transform = Some(Transform { ..t });
        level.scene.set_row(e, row).expect("set");
        let t0 = Instant::now();
        gpu.render(level, revision, cam.camera(), size, Schedule::Ours, 0.016)
            .expect("render");
        ctx.wait_idle().expect("idle");
        let total = t0.elapsed().as_secs_f64() * 1e3;
        assert_eq!(gpu.report.size, size);
        (total, gpu.report.upload_ms, gpu.report.frame_ms)
    };
    // Warm up pipelines and allocations.
    stall(&mut level, still, &mut gpu);
    let s = stall(&mut level, still, &mut gpu);
    let m = stall(&mut level, moving, &mut gpu);
    // Refining after a cheap first frame: the same revision at the still size.
    let t0 = Instant::now();
    gpu.render(&level, revision, cam.camera(), still, Schedule::Ours, 0.016)
        .expect("render");
    ctx.wait_idle().expect("idle");
    let refine = t0.elapsed().as_secs_f64() * 1e3;
    let mut settled = Vec::new();
    for _ in 0..3 {
        let t0 = Instant::now();
        gpu.render(&level, revision, cam.camera(), still, Schedule::Ours, 0.016)
            .expect("render");
        ctx.wait_idle().expect("idle");
        settled.push(t0.elapsed().as_secs_f64() * 1e3);
    }
    eprintln!(
        "edit stall, still {still}: {:.1} ms (upload {:.1}, frame {:.1}); \
         moving {moving}: {:.1} ms (upload {:.1}, frame {:.1}); refine at still {:.1} ms; \
         later still frames {settled:.1?} ms",
        s.0, s.1, s.2, m.0, m.1, m.2, refine
    );
    assert!(s.0 > 0.0 && m.0 > 0.0 && refine > 0.0);
}
