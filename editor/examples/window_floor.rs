//! The floor of the editor's UI frame on this machine: an eframe window of the editor's size
//! and renderer with panels of text (and with `--fill`, a changing picture over the central
//! panel), repainting as fast as it can and rendering nothing else. It prints the frames a second it reached over `SECONDS`, then
//! closes. Under Xvfb on a CPU Vulkan (lavapipe) this is what the window alone costs: the
//! editor's UI frames a second cannot exceed it, whatever the viewport does.
//!
//! ```sh
//! cargo run -p texel_editor --example window_floor -- [--fill] [--immediate]
//! ```

use std::time::{Duration, Instant};

/// How long it measures.
const SECONDS: f64 = 6.0;

struct Floor {
    start: Option<Instant>,
    frames: u32,
    /// Paint a changing picture over the whole central panel (`--fill`).
    fill: bool,
}

impl eframe::App for Floor {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        let ctx = ui.ctx().clone();
        let start = *self.start.get_or_insert_with(Instant::now);
        self.frames += 1;
        egui::Panel::left("outliner").show(ui, |ui| {
            for i in 0..40 {
                ui.label(format!("Entity {i}"));
            }
        });
        egui::Panel::right("inspector").show(ui, |ui| {
            for i in 0..30 {
                ui.horizontal(|ui| {
                    ui.label(format!("field {i}"));
                    let _ = ui.button("value");
                });
            }
        });
        egui::CentralPanel::default().show(ui, |ui| {
            let rect = ui.available_rect_before_wrap();
            let shade = (self.frames % 200) as u8;
            if self.fill {
                ui.painter()
                    .rect_filled(rect, 0.0, egui::Color32::from_rgb(shade, 90, 140));
            }
        });
        let elapsed = start.elapsed().as_secs_f64();
        if elapsed >= SECONDS {
            println!(
                "{} frames in {elapsed:.1} s: {:.1} frames a second, {:.1} ms a frame",
                self.frames,
                f64::from(self.frames) / elapsed,
                elapsed * 1e3 / f64::from(self.frames)
            );
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
        }
        ctx.request_repaint_after(Duration::ZERO);
    }
}

fn main() -> eframe::Result<()> {
    let mut wgpu_options = egui_wgpu::WgpuConfiguration::default();
    if std::env::args().any(|a| a == "--immediate") {
        wgpu_options.surface.present_mode = wgpu::PresentMode::AutoNoVsync;
    }
    let options = eframe::NativeOptions {
        renderer: eframe::Renderer::Wgpu,
        wgpu_options,
        viewport: egui::ViewportBuilder::default()
            .with_inner_size([1280.0, 800.0])
            .with_title("window floor"),
        ..Default::default()
    };
    eframe::run_native(
        "window floor",
        options,
        Box::new(|_| {
            Ok(Box::new(Floor {
                start: None,
                frames: 0,
                fill: std::env::args().any(|a| a == "--fill"),
            }))
        }),
    )
}
