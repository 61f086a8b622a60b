//! A swatch edit reaches the render worker as a palette change alone: its next frame is
//! drawn in the new colour, and the scene was not uploaded again (on a headless GPU,
//! lavapipe in CI). Night (N) maps the next frame to the alternate.

use egui_kittest::Harness;
use texel_editor::app::EditorApp;
use texel_editor::files::Recent;
use texel_editor::palette_edits::Slot;
use texel_editor::viewport::worker::{Frame, RenderWorker};
use texel_render::context::test_context;

use crate::support;

fn worker<'a>(h: &'a Harness<'_, EditorApp>) -> &'a RenderWorker {
    h.state().viewport.worker.as_ref().expect("a render worker")
}

/// Steps the UI until it shows a frame of the document's current revision (and of the
/// view asked last), and returns it.
fn frame_of_now(h: &mut Harness<'_, EditorApp>) -> std::sync::Arc<Frame> {
    for _ in 0..40 {
        h.step();
        worker(h).wait_drawn().expect("a frame");
        h.step();
        let revision = h.state().state.document.revision;
        let night = h.state().viewport.night;
        if let Some(f) = &h.state().viewport.shown
            && f.document.1 == revision
            && f.view.night == night
        {
            return f.clone();
        }
    }
    panic!("no frame of the current revision");
}

/// The share of the frame's pixels that are `rgb`.
fn share(frame: &Frame, rgb: [u8; 3]) -> f64 {
    let px = &frame.image.pixels;
    let n = px.iter().filter(|p| [p.r(), p.g(), p.b()] == rgb).count();
    n as f64 / px.len() as f64
}

#[test]
fn a_swatch_edit_recolours_the_next_frame_without_an_upload() {
    let Some(ctx) = test_context() else {
        return;
    };
    let dir = tempfile::tempdir().expect("tempdir");
    let path = support::bundled_copy(dir.path(), "stone_circle");
    let palettes = dir.path().join("palettes");
    std::fs::create_dir_all(&palettes).expect("palettes");
    // One colour each: every pixel of a mapped frame is that colour.
    std::fs::write(palettes.join("day.hex"), "c82828\n").expect("day");
    std::fs::write(palettes.join("night.hex"), "102040\n").expect("night");
    let mut h = Harness::builder()
        .with_size([900.0, 600.0])
        .with_step_dt(1.0 / 60.0)
        .build_ui_state(
            |ui, app: &mut EditorApp| app.ui(ui),
            EditorApp::with_recent(Some(&path), Recent::default()),
        );
    let egui = h.ctx.clone();
    let app = h.state_mut();
    app.viewport.attach(support::gpu_view(&ctx), egui);
    app.viewport.camera = support::camera();
    app.pick_palette(Slot::Main, &palettes.join("day.hex"));
    app.pick_palette(Slot::Alternate, &palettes.join("night.hex"));
    assert!(app.dialogs.error.is_none(), "{:?}", app.dialogs.error);

    let first = frame_of_now(&mut h);
    assert!(share(&first, [200, 40, 40]) > 0.99, "the day colour");
    let uploads = first.report.uploads;
    let updates = first.report.palette_updates;

    let rel = "../palettes/day.hex";
    (h.state_mut().state.set_swatch(rel, 0, [30, 220, 60], None)).expect("swatch");
    let edited = frame_of_now(&mut h);
    assert!(share(&edited, [30, 220, 60]) > 0.99, "the edited colour");
    assert_eq!(edited.report.uploads, uploads, "no scene upload");
    assert_eq!(
        edited.report.palette_updates,
        updates + 1,
        "taken in as a palette change"
    );

    h.state_mut().viewport.night = true;
    let night = frame_of_now(&mut h);
    assert!(share(&night, [16, 32, 64]) > 0.99, "the night colour");
    assert_eq!(night.report.uploads, uploads, "no scene upload");
}
