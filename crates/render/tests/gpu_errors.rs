//! GPU errors become messages: a validation error no scope caught, or a lost device, is
//! reported by `GpuContext::check` (and fails the next frame) instead of wgpu's default
//! handler, which panics.

use crate::common;

use glam::{UVec2, Vec3};
use texel_render::context::{GpuContext, GpuError, test_context};
use texel_render::frame::{RenderError, Renderer};
use texel_render::input::{Camera, Schedule};

/// A device of the test's own: these tests break theirs (an error, a lost device), and
/// `test_context`'s is shared by the binary's other tests when they run in one process.
fn own_context() -> Option<GpuContext> {
    test_context()?;
    Some(GpuContext::headless().expect("a second device on the adapter"))
}

#[test]
fn an_uncaptured_validation_error_fails_the_next_frame_with_its_message() {
    let Some(ctx) = own_context() else { return };
    let mut r = Renderer::headless(&ctx).expect("renderer");
    r.set_scene(&ctx, &common::boxes_scene()).expect("scene");
    let size = UVec2::new(64, 36);
    let cam = Camera::looking(Vec3::new(0.3, 1.6, 3.0), Vec3::new(0.0, -0.25, -1.0));
    let input = common::frame(cam, Vec3::new(0.0, 2.0, 3.0), 32, size, Schedule::Ours);
    r.render_offscreen(&ctx, &input).expect("a clean frame");
    assert!(ctx.check().is_ok());

    // A buffer both mappable for reading and a vertex buffer is invalid without a feature.
    let _bad = ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("gpu_errors::invalid"),
        size: 16,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::VERTEX,
        mapped_at_creation: false,
    });
    match r.render_offscreen(&ctx, &input) {
        Err(RenderError::Gpu(GpuError::Uncaptured(message))) => {
            assert!(message.contains("gpu_errors::invalid"), "{message}");
        }
        other => panic!(
            "expected the uncaptured error, got {:?}",
            other.map(|f| f.0)
        ),
    }
    // Reported once: the frame after is clean again.
    r.render_offscreen(&ctx, &input).expect("the next frame");
}

#[test]
fn a_lost_device_is_an_error_not_a_panic() {
    let Some(ctx) = own_context() else { return };
    let mut r = Renderer::headless(&ctx).expect("renderer");
    r.set_scene(&ctx, &common::boxes_scene()).expect("scene");
    ctx.device.destroy();
    let _ = ctx.device.poll(wgpu::PollType::Poll);
    assert!(
        matches!(ctx.check(), Err(GpuError::Lost(_))),
        "{:?}",
        ctx.check()
    );
}
