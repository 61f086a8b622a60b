//! What opening the GPU costs: the device, then the renderer (its shader modules parsed and
//! validated; each pipeline compiles on first use), twice in one process. Run on each
//! driver:
//!
//! ```sh
//! cargo run -p texel_render --example startup_cost
//! VK_ICD_FILENAMES=/usr/lib/chromium/vk_swiftshader_icd.json \
//!     cargo run -p texel_render --example startup_cost
//! ```
//!
//! What the first frames then compile, and how long each pipeline takes, is printed by any
//! run with `TEXEL_PIPELINE_TIMES=1` (for example `texel-run render`).

use std::time::Instant;

use texel_render::context::GpuContext;
use texel_render::frame::Renderer;

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
    for round in ["first", "second"] {
        let t = Instant::now();
        if let Err(e) = Renderer::headless(&ctx) {
            eprintln!("error: {e}");
            std::process::exit(1);
        }
        let ms = t.elapsed().as_secs_f64() * 1e3;
        println!("renderer built ({round:>6}): {ms:8.1} ms");
    }
}
