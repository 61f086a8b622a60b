//! The play window's overlay: frame rate, per-pass times, counters, modes, the controls and
//! the faces the last terrain dab marked, drawn with egui over the frame, and the crosshair.

use glam::UVec2;
use texel_render::context::GpuContext;
use texel_render::input::Schedule;
use texel_render::stats::FrameStats;
use winit::event::WindowEvent;
use winit::window::Window;

use crate::first_person::WalkCamera;
use crate::headless::schedule_name;

/// Seconds over which the overlay averages frames per second.
pub const FPS_WINDOW: f32 = 0.5;
/// The controls, as the overlay lists them.
pub const KEY_HELP: [&str; 3] = [
    "click: mouse look · WASD: move · Shift: run · Space/E: jump (walk), up (fly) · Ctrl/Q: down",
    "F: walk/fly (through walls) · Tab: schedule · F3: overlay · Esc: release mouse, again to quit",
    "R/G (hold): raise/lower the ground under the crosshair",
];

/// Frames per second averaged over [`FPS_WINDOW`] seconds.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct FpsMeter {
    frames: u32,
    elapsed: f32,
    fps: f32,
}

impl FpsMeter {
    pub(super) fn tick(&mut self, dt: f32) -> f32 {
        self.frames += 1;
        self.elapsed += dt;
        if self.elapsed >= FPS_WINDOW {
            self.fps = self.frames as f32 / self.elapsed;
            *self = FpsMeter {
                fps: self.fps,
                ..FpsMeter::default()
            };
        }
        self.fps
    }
}

/// The overlay's lines: rate, per-pass times, counters, modes and the controls.
pub(super) fn overlay_lines(
    stats: &FrameStats,
    fps: f32,
    schedule: Schedule,
    camera: &WalkCamera,
) -> Vec<String> {
    let clock = if stats.gpu_timestamps { "GPU" } else { "CPU" };
    let eye = camera.eye();
    let mut lines = vec![
        format!(
            "{fps:5.1} fps   frame {:.2} ms   schedule: {}   {}",
            stats.frame_ms,
            schedule_name(schedule),
            if camera.fly { "fly" } else { "walk" }
        ),
        format!(
            "eye ({:.2}, {:.2}, {:.2})   yaw {:.1}°   pitch {:.1}°",
            eye.x, eye.y, eye.z, camera.yaw_deg, camera.pitch_deg
        ),
    ];
    lines.extend(
        stats
            .passes
            .iter()
            .map(|p| format!("  {:<10} {:8.3} ms ({clock})", p.pass, p.ms)),
    );
    let c = &stats.counters;
    lines.push(format!(
        "faces captured {}   texels shaded {}",
        c.faces_captured, c.texels_shaded
    ));
    lines.push(format!(
        "quads splatted {}   visible texels {}",
        c.quads_splatted, c.screen_visible_texels
    ));
    lines.extend(KEY_HELP.map(str::to_owned));
    lines
}

/// The overlay's line on sculpting: how many probe faces the last dab marked for capture.
pub(super) fn dab_line(marked: Option<u32>) -> Option<String> {
    marked.map(|n| format!("last dab marked {n} probe faces"))
}

/// A small cross at the centre of the window, where the view's centre ray (which the
/// sculpting keys dab at) meets the scene.
fn draw_crosshair(ctx: &egui::Context) {
    let c = ctx.content_rect().center();
    let painter = ctx.layer_painter(egui::LayerId::new(
        egui::Order::Foreground,
        egui::Id::unique("play::crosshair"),
    ));
    for (width, colour) in [
        (3.0, egui::Color32::from_black_alpha(160)),
        (1.0, egui::Color32::WHITE),
    ] {
        let stroke = egui::Stroke::new(width, colour);
        painter.line_segment([c - egui::vec2(6.0, 0.0), c + egui::vec2(6.0, 0.0)], stroke);
        painter.line_segment([c - egui::vec2(0.0, 6.0), c + egui::vec2(0.0, 6.0)], stroke);
    }
}

fn draw_overlay(ctx: &egui::Context, lines: &[String]) {
    egui::Area::new(egui::Id::unique("play::overlay"))
        .anchor(egui::Align2::LEFT_TOP, egui::vec2(8.0, 8.0))
        .interactable(false)
        .show(ctx, |ui| {
            egui::Frame::new()
                .fill(egui::Color32::from_black_alpha(170))
                .inner_margin(8.0)
                .corner_radius(4.0)
                .show(ui, |ui| {
                    for line in lines {
                        let text = egui::RichText::new(line)
                            .monospace()
                            .color(egui::Color32::WHITE);
                        ui.add(egui::Label::new(text).extend());
                    }
                });
        });
}

/// The egui overlay of the play window: its input state and its renderer.
pub(super) struct Overlay {
    state: egui_winit::State,
    renderer: egui_wgpu::Renderer,
}

impl Overlay {
    /// An overlay for `window`, drawn into views of `format` (sRGB: egui writes linear
    /// colour and lets the view encode it).
    pub(super) fn new(ctx: &GpuContext, window: &Window, format: wgpu::TextureFormat) -> Self {
        let max_texture = ctx.device.limits().max_texture_dimension_2d as usize;
        let state = egui_winit::State::new(
            egui::Context::default(),
            egui::ViewportId::ROOT,
            window,
            Some(window.scale_factor() as f32),
            window.theme(),
            Some(max_texture),
        );
        let renderer =
            egui_wgpu::Renderer::new(&ctx.device, format, egui_wgpu::RendererOptions::default());
        Overlay { state, renderer }
    }

    /// Passes a window event to egui (it takes no input; it needs sizes, scale and time).
    pub(super) fn on_window_event(&mut self, window: &Window, event: &WindowEvent) {
        let _ = self.state.on_window_event(window, event);
    }

    /// Runs egui for the overlay (or for nothing but the crosshair, so its textures stay in
    /// step) and paints it over `target`.
    pub(super) fn paint(
        &mut self,
        ctx: &GpuContext,
        window: &Window,
        lines: Option<&[String]>,
        target: &wgpu::TextureView,
        size: UVec2,
    ) {
        let o = self;
        let raw = o.state.take_egui_input(window);
        let egui_ctx = o.state.egui_ctx().clone();
        let mut out = egui_ctx.run_pass(raw, |ctx| {
            if let Some(lines) = lines {
                draw_overlay(ctx, lines);
            }
            draw_crosshair(ctx);
        });
        let (device, queue) = (&ctx.device, &ctx.queue);
        for (id, deltas) in &out.textures_delta.set {
            for delta in deltas {
                o.renderer.update_texture(device, queue, *id, delta);
            }
        }
        let jobs = egui_ctx.tessellate(std::mem::take(&mut out.shapes), out.pixels_per_point);
        let screen = egui_wgpu::ScreenDescriptor {
            size_in_pixels: size.to_array(),
            pixels_per_point: out.pixels_per_point,
        };
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("play::overlay"),
        });
        let mut commands = o
            .renderer
            .update_buffers(device, queue, &mut encoder, &jobs, &screen);
        {
            let pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("play::overlay"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: target,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Load,
                        store: wgpu::StoreOp::Store,
                    },
                })],
                ..Default::default()
            });
            o.renderer
                .render(&mut pass.forget_lifetime(), &jobs, &screen);
        }
        commands.push(encoder.finish());
        queue.submit(commands);
        for id in &out.textures_delta.free {
            o.renderer.free_texture(id);
        }
        out.textures_delta.clear();
    }
}
