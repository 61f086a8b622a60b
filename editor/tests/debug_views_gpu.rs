//! Debug views on a headless device (lavapipe in CI): the probe origins of the last frame,
//! the eye-sourced pixel tint and the grid probe's lit faces read back. (How long the first
//! frame after an edit stalls is measured by `benches/edit_stall.rs`.)

use glam::UVec2;
use texel_editor::viewport::debug::{DebugState, DebugView};
use texel_render::context::test_context;
use texel_render::input::Schedule;

use crate::support;

use support::{camera, gpu_view, stone_circle};

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
