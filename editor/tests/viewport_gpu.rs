//! The viewport's GPU path on a headless device (lavapipe in CI): the level renders into a
//! texture egui can show, picking returns the entity under a pixel, and an edit re-uploads
//! the scene; the orthographic view renders from orthographic probes; the viewport's own
//! picture (a paint callback) shows a frame's bytes, held or re-projected. Prints the frame
//! times measured.

use glam::{UVec2, Vec3};
use texel_editor::viewport::picture::Picture;
use texel_editor::viewport::reproject;
use texel_render::context::test_context;
use texel_render::input::Schedule;
use texel_render::target::{FRAME_FORMAT, OffscreenTarget};
use texel_scene::Transform;

use crate::support;

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
        "viewport 160x120 frame ms: {times:?}, start {:.2} ms",
        gpu.report.start_ms
    );
    // The renderer's start (its shaders compiled) is not a scene upload: before any edit
    // a stroke's refreshes are paced as for a quick upload.
    assert!(gpu.report.start_ms > 0.0, "the start is timed");
    assert_eq!(gpu.report.upload_ms, None, "no edit, no upload");
    let stats = gpu.report.stats.clone().expect("stats");
    assert!(stats.counters.quads_splatted > 0);
    assert!(gpu.texture().is_some());
    let picked = gpu.pick(size / 2).expect("pick");
    // Entity 2 in level order (after the ground) is "Trilithon 1 upright L": id 2.
    assert_eq!(picked, Some(2));

    // Move that stone away: after an edit (new revision) the centre shows something else.
    let e = level.scene.entities().nth(1).expect("entity");
    let before = level.scene.row(e).expect("row");
    let mut row = before.clone();
    row.transform = Some(Transform::from_translation(Vec3::new(50.0, 1.6, 50.0)));
    level.scene.set_row(e, row).expect("set");
    for _ in 0..3 {
        gpu.render(&level, 1, camera.camera(), size, Schedule::Ours, 0.016)
            .expect("render");
    }
    assert_ne!(gpu.pick(size / 2).expect("pick"), Some(2));
    assert!(gpu.report.upload_ms.is_some(), "the edit's upload is timed");

    // Back where it stood, as a gizmo drag step is taken in: that entity alone, in place.
    let mut row = level.scene.row(e).expect("row");
    row.transform = before.transform;
    level.scene.set_row(e, row).expect("set");
    gpu.use_entities(Some(vec![1]));
    for _ in 0..6 {
        gpu.render(&level, 2, camera.camera(), size, Schedule::Ours, 0.016)
            .expect("render");
    }
    assert!(
        matches!(
            gpu.report.last_edit,
            Some(texel_runtime::session::EditUpdate::InPlace { faces_marked }) if faces_marked > 0
        ),
        "{:?}",
        gpu.report.last_edit
    );
    assert_eq!(
        gpu.pick(size / 2).expect("pick"),
        Some(2),
        "the stone is back"
    );
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
    assert_eq!(gpu.report.upload_ms, None, "no edit, no upload");
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

/// What egui draws of the viewport's texture, 1:1 into a plain RGBA8 target as eframe's
/// window: RGBA8 rows.
fn egui_draws(
    ctx: &texel_render::context::GpuContext,
    egui: &egui::mutex::RwLock<egui_wgpu::Renderer>,
    id: egui::TextureId,
    size: UVec2,
) -> Vec<u8> {
    let rect = rect_of(size);
    let mut mesh = egui::Mesh::with_texture(id);
    let uv = egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0));
    mesh.add_rect_with_uv(rect, uv, egui::Color32::WHITE);
    egui_paints(ctx, egui, egui::epaint::Primitive::Mesh(mesh), size)
}

fn rect_of(size: UVec2) -> egui::Rect {
    egui::Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(size.x as f32, size.y as f32))
}

/// What egui paints of `primitive` over the whole of a plain RGBA8 target of `size`, as
/// eframe's window: RGBA8 rows.
fn egui_paints(
    ctx: &texel_render::context::GpuContext,
    egui: &egui::mutex::RwLock<egui_wgpu::Renderer>,
    primitive: egui::epaint::Primitive,
    size: UVec2,
) -> Vec<u8> {
    let target = OffscreenTarget::with_format(ctx, size.x, size.y, FRAME_FORMAT);
    let rect = rect_of(size);
    let jobs = [egui::ClippedPrimitive {
        clip_rect: rect,
        primitive,
    }];
    let screen = egui_wgpu::ScreenDescriptor {
        size_in_pixels: [size.x, size.y],
        pixels_per_point: 1.0,
    };
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    let mut renderer = egui.write();
    let extra = renderer.update_buffers(&ctx.device, &ctx.queue, &mut encoder, &jobs, &screen);
    {
        let pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("test::egui"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &target.view,
                resolve_target: None,
                depth_slice: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        renderer.render(&mut pass.forget_lifetime(), &jobs, &screen);
    }
    ctx.queue
        .submit(extra.into_iter().chain([encoder.finish()]));
    target.read_rgba(ctx).expect("read back")
}

#[test]
fn the_viewport_shows_the_colours_the_game_shows() {
    // egui takes a texture's values as gamma-encoded; the renderer writes sRGB-encoded
    // colours. Sampled through an sRGB view they were decoded once more, and the editor showed
    // the level darker than `texel-run` (the sky 195 → 139).
    let Some(ctx) = test_context() else {
        return;
    };
    let (mut gpu, egui) = support::gpu_view_and_egui(&ctx);
    let level = support::stone_circle();
    let camera = support::camera().camera();
    let size = UVec2::new(160, 120);
    let mut session = texel_runtime::session::Session::headless(&ctx, &level, size, camera.fov_y)
        .expect("session");
    let mut game = Vec::new();
    for _ in 0..4 {
        gpu.render(&level, 0, camera, size, Schedule::Ours, 0.016)
            .expect("render");
        let request = texel_runtime::session::FrameRequest {
            camera,
            dt: 0.016,
            schedule: Schedule::Ours,
            size,
        };
        game = session.draw_offscreen(&ctx, &request).expect("frame").1;
    }
    let id = gpu.texture().expect("a texture");
    let shown = egui_draws(&ctx, &egui, id, size);
    assert_eq!(shown.len(), game.len());
    let off = shown
        .chunks_exact(4)
        .zip(game.chunks_exact(4))
        .filter(|(a, b)| (0..3).any(|c| a[c].abs_diff(b[c]) > 2))
        .count();
    let total = (size.x * size.y) as usize;
    assert!(
        off * 100 < total,
        "{off} of {total} pixels egui shows differ from the game's frame (first: {:?} against {:?})",
        &shown[..4],
        &game[..4]
    );
}

#[test]
fn the_viewports_own_picture_shows_the_frames_bytes() {
    // Under eframe the viewport's picture is drawn by a paint callback of its own
    // (`viewport::picture`: opaque, no blending), held or re-projected.
    let Some(ctx) = test_context() else {
        return;
    };
    let (mut gpu, egui) = support::gpu_view_and_egui(&ctx);
    let level = support::stone_circle();
    let camera = support::camera().camera();
    let size = UVec2::new(160, 120);
    let mut frame = (size, Vec::new());
    for _ in 0..4 {
        frame =
            (gpu.render_pixels(&level, 0, camera, size, Schedule::Ours, 0.016)).expect("render");
    }
    let (size, game) = frame;
    let image = egui::ColorImage::from_rgba_unmultiplied([size.x as usize, size.y as usize], &game);
    let rect = rect_of(size);
    let paint = |triangles| {
        let picture = Picture {
            frame: (1, std::sync::Arc::new(image.clone())),
            triangles,
            rect,
            target: FRAME_FORMAT,
        };
        let callback = egui_wgpu::Callback::new_paint_callback(rect, picture);
        egui_paints(
            &ctx,
            &egui,
            egui::epaint::Primitive::Callback(callback),
            size,
        )
    };
    // Held: the frame's own bytes, pixel for pixel.
    let shown = paint(reproject::triangles(rect, &camera, &camera, 6.0));
    assert_eq!(shown.len(), game.len());
    let off = (shown.chunks_exact(4).zip(game.chunks_exact(4)))
        .filter(|(a, b)| (0..3).any(|c| a[c] != b[c]))
        .count();
    assert_eq!(off, 0, "{off} pixels differ from the frame's");
    // Turned a little to the right: the picture moves left over the background, its right
    // edge uncovered.
    let mut turned = camera;
    turned.forward = (camera.forward + camera.forward.cross(Vec3::Y) * 0.05).normalize();
    let moved = paint(reproject::triangles(rect, &camera, &turned, 6.0));
    let row = (size.y / 2 * size.x) as usize * 4;
    let last = row + (size.x as usize - 1) * 4;
    assert_eq!(
        &moved[last..last + 3],
        &[24, 26, 30],
        "the background at the uncovered edge"
    );
    assert_ne!(moved, shown, "the picture moved");
}
