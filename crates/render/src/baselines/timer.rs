//! Per-stage timing of a baseline frame: GPU timestamps between stages in one submission
//! when the adapter has them, else one submission per stage timed on the CPU (as `frame.rs`
//! times the texel passes), so baseline and texel times compare like with like.

use std::time::Instant;

use crate::context::{GpuContext, GpuError};
use crate::stats::PassTime;
use crate::target::read_buffer;

/// Most timed stages of one baseline frame.
pub(crate) const MAX_STAGES: u32 = 4;

/// Times the stages of a frame: GPU timestamps between stages in one submission when the
/// adapter has them, else one submission per stage timed on the CPU (as `frame.rs` does).
pub(crate) struct Timer<'a> {
    ctx: &'a GpuContext,
    queries: Option<&'a wgpu::QuerySet>,
    encoder: wgpu::CommandEncoder,
    names: Vec<&'static str>,
    cpu_ms: Vec<f64>,
}

impl<'a> Timer<'a> {
    pub(crate) fn new(ctx: &'a GpuContext, queries: Option<&'a wgpu::QuerySet>) -> Self {
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        if let Some(q) = queries {
            encoder.write_timestamp(q, 0);
        }
        Timer {
            ctx,
            queries,
            encoder,
            names: Vec::new(),
            cpu_ms: Vec::new(),
        }
    }

    pub(crate) fn run(&mut self, name: &'static str, f: impl FnOnce(&mut wgpu::CommandEncoder)) {
        self.names.push(name);
        match self.queries {
            Some(q) => {
                f(&mut self.encoder);
                let index = (self.names.len() as u32).min(MAX_STAGES);
                self.encoder.write_timestamp(q, index);
            }
            None => {
                let t = Instant::now();
                f(&mut self.encoder);
                let done = std::mem::replace(
                    &mut self.encoder,
                    self.ctx.device.create_command_encoder(&Default::default()),
                );
                self.ctx.queue.submit([done.finish()]);
                let _ = self.ctx.wait_idle();
                self.cpu_ms.push(t.elapsed().as_secs_f64() * 1e3);
            }
        }
    }

    /// Submits and waits; returns the per-stage times and whether they are GPU timestamps.
    pub(crate) fn finish(mut self) -> Result<(Vec<PassTime>, bool), GpuError> {
        let Some(q) = self.queries else {
            self.ctx.queue.submit([self.encoder.finish()]);
            self.ctx.wait_idle()?;
            let passes = self.names.iter().zip(&self.cpu_ms);
            let passes = passes.map(|(&pass, &ms)| PassTime { pass, ms }).collect();
            return Ok((passes, false));
        };
        let count = self.names.len() as u32 + 1;
        let bytes = 8 * u64::from(count);
        let buffer = |label, usage| {
            self.ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes,
                usage,
                mapped_at_creation: false,
            })
        };
        use wgpu::BufferUsages as B;
        let resolve = buffer("baselines::timestamps", B::QUERY_RESOLVE | B::COPY_SRC);
        let readback = buffer("baselines::timestamps_readback", B::COPY_DST | B::MAP_READ);
        self.encoder.resolve_query_set(q, 0..count, &resolve, 0);
        self.encoder
            .copy_buffer_to_buffer(&resolve, 0, &readback, 0, bytes);
        self.ctx.queue.submit([self.encoder.finish()]);
        let raw = read_buffer(self.ctx, &readback)?;
        let stamps: &[u64] = bytemuck::cast_slice(&raw);
        let period = f64::from(self.ctx.queue.get_timestamp_period());
        let passes = self
            .names
            .iter()
            .zip(stamps.windows(2))
            .map(|(&pass, w)| PassTime {
                pass,
                ms: w[1].saturating_sub(w[0]) as f64 * period / 1e6,
            })
            .collect();
        Ok((passes, true))
    }
}
