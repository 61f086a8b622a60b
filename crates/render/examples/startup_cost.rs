//! What opening the GPU costs, step by step: the device, each pass's shader modules and
//! pipelines, then the whole renderer twice in one process (the second shows what the
//! driver caches within a process). Run on each driver:
//!
//! ```sh
//! cargo run -p texel_render --example startup_cost
//! VK_ICD_FILENAMES=/usr/lib/chromium/vk_swiftshader_icd.json \
//!     cargo run -p texel_render --example startup_cost
//! ```

use std::time::Instant;

use texel_render::context::GpuContext;
use texel_render::frame::Renderer;
use texel_render::passes::{
    background, capture, cull, lines, moving, present, runs, shade, splat, sprites, terrain_splat,
    visible,
};
use texel_render::target::FRAME_FORMAT;

/// Times `build`, printing `name` and its milliseconds; exits on an error.
fn timed<T, E: std::fmt::Display>(name: &str, build: impl FnOnce() -> Result<T, E>) -> f64 {
    let t = Instant::now();
    if let Err(e) = build() {
        eprintln!("error: {name}: {e}");
        std::process::exit(1);
    }
    let ms = t.elapsed().as_secs_f64() * 1e3;
    println!("  {name:<24} {ms:8.1} ms");
    ms
}

fn main() {
    let t = Instant::now();
    let ctx = match GpuContext::headless() {
        Ok(ctx) => ctx,
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(1);
        }
    };
    let device_ms = t.elapsed().as_secs_f64() * 1e3;
    println!("adapter: {}", ctx.describe());
    println!("device opened:            {device_ms:8.1} ms");
    let d = &ctx.device;
    let f = FRAME_FORMAT;
    println!("each pass (modules and pipelines):");
    let sum = timed("capture", || capture::CapturePass::new(d))
        + timed("shade", || shade::ShadePass::new(d))
        + timed("runs", || runs::RunsPass::new(d))
        + timed("cull", || cull::CullPass::new(d))
        + timed("splat", || splat::SplatPass::new(d, f))
        + timed("terrain_splat", || terrain_splat::TerrainSplatPass::new(d))
        + timed("background", || background::BackgroundPass::new(d, f))
        + timed("moving", || moving::MovingPass::new(d, f))
        + timed("sprites", || sprites::SpritePass::new(d, f))
        + timed("lines", || lines::LinesPass::new(d, f))
        + timed("visible", || visible::VisiblePass::new(d))
        + timed("present", || present::PresentPass::new(d, f));
    println!("  {:<24} {sum:8.1} ms", "all passes");
    for round in ["first", "second"] {
        let t = Instant::now();
        let renderer = Renderer::headless(&ctx);
        let ms = t.elapsed().as_secs_f64() * 1e3;
        if let Err(e) = renderer {
            eprintln!("error: {e}");
            std::process::exit(1);
        }
        println!("renderer built ({round:>6}): {ms:8.1} ms");
    }
}
