//! Per-stage timing of one frame, for the texel passes and the baselines alike (so their
//! times compare like with like): GPU timestamps between stages in one submission when the
//! adapter has them, else one submission per stage timed on the CPU. Stages are named where
//! they run.

use std::time::Instant;

use crate::context::{GpuContext, GpuError};
use crate::stats::PassTime;
use crate::target::read_buffer;

/// Most timed stages of one frame.
pub(crate) const MAX_STAGES: u32 = 12;

/// The timestamp query set a renderer keeps for [`Stages`], when the adapter has timestamps.
pub(crate) fn query_set(ctx: &GpuContext, label: &str) -> Option<wgpu::QuerySet> {
    ctx.timestamps.then(|| {
        ctx.device.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some(label),
            ty: wgpu::QueryType::Timestamp,
            count: MAX_STAGES + 1,
        })
    })
}

/// What a timed frame returns: per-stage times, whether they are GPU timestamps, and the
/// bytes of the buffers [`Stages::finish`] was asked to copy back.
pub(crate) struct Timed {
    pub(crate) passes: Vec<PassTime>,
    pub(crate) gpu_timestamps: bool,
    pub(crate) readback: Vec<u8>,
}

/// Records a frame's stages into one encoder (or one per stage without timestamps).
pub(crate) struct Stages<'a> {
    ctx: &'a GpuContext,
    queries: Option<&'a wgpu::QuerySet>,
    encoder: wgpu::CommandEncoder,
    names: Vec<&'static str>,
    cpu_ms: Vec<f64>,
}

impl<'a> Stages<'a> {
    pub(crate) fn new(ctx: &'a GpuContext, queries: Option<&'a wgpu::QuerySet>) -> Self {
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        if let Some(q) = queries {
            encoder.write_timestamp(q, 0);
        }
        Stages {
            ctx,
            queries,
            encoder,
            names: Vec::new(),
            cpu_ms: Vec::new(),
        }
    }

    /// Records the stage `name` with `f` and returns what `f` returns.
    pub(crate) fn run<R>(
        &mut self,
        name: &'static str,
        f: impl FnOnce(&mut wgpu::CommandEncoder) -> R,
    ) -> R {
        self.names.push(name);
        match self.queries {
            Some(q) => {
                let out = f(&mut self.encoder);
                let index = (self.names.len() as u32).min(MAX_STAGES);
                self.encoder.write_timestamp(q, index);
                out
            }
            None => {
                let t = Instant::now();
                let out = f(&mut self.encoder);
                let done = std::mem::replace(
                    &mut self.encoder,
                    self.ctx.device.create_command_encoder(&Default::default()),
                );
                self.ctx.queue.submit([done.finish()]);
                let _ = self.ctx.wait_idle();
                self.cpu_ms.push(t.elapsed().as_secs_f64() * 1e3);
                out
            }
        }
    }

    /// Submits, copies each `(buffer, bytes)` back (concatenated, in order), waits, and
    /// returns the per-stage times with those bytes.
    pub(crate) fn finish(mut self, copies: &[(&wgpu::Buffer, u64)]) -> Result<Timed, GpuError> {
        let count = (self.names.len() as u32).min(MAX_STAGES) + 1;
        let stamps_bytes = 8 * u64::from(count);
        let copied: u64 = copies.iter().map(|(_, n)| n).sum();
        let stamps_at = copied.next_multiple_of(256);
        let size = stamps_at
            + if self.queries.is_some() {
                stamps_bytes
            } else {
                0
            };
        let readback = (size > 0).then(|| {
            self.ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("stages::readback"),
                size,
                usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
                mapped_at_creation: false,
            })
        });
        let mut resolve = None;
        if let Some(readback) = &readback {
            let mut at = 0;
            for (buffer, bytes) in copies {
                self.encoder
                    .copy_buffer_to_buffer(buffer, 0, readback, at, *bytes);
                at += bytes;
            }
            if let Some(q) = self.queries {
                let buf = self.ctx.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("stages::timestamps"),
                    size: stamps_bytes,
                    usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                    mapped_at_creation: false,
                });
                self.encoder.resolve_query_set(q, 0..count, &buf, 0);
                self.encoder
                    .copy_buffer_to_buffer(&buf, 0, readback, stamps_at, stamps_bytes);
                resolve = Some(buf);
            }
        }
        self.ctx.queue.submit([self.encoder.finish()]);
        let bytes = match &readback {
            Some(r) => read_buffer(self.ctx, r)?,
            None => {
                self.ctx.wait_idle()?;
                Vec::new()
            }
        };
        drop(resolve);
        let times: Vec<f64> = match self.queries {
            Some(_) => {
                let stamps: &[u64] = bytemuck::cast_slice(&bytes[stamps_at as usize..]);
                let period = f64::from(self.ctx.queue.get_timestamp_period());
                stamps
                    .windows(2)
                    .map(|w| w[1].saturating_sub(w[0]) as f64 * period / 1e6)
                    .collect()
            }
            None => self.cpu_ms,
        };
        let passes = self
            .names
            .iter()
            .zip(times)
            .map(|(&pass, ms)| PassTime { pass, ms })
            .collect();
        let copied = bytes.get(..copied as usize).unwrap_or_default().to_vec();
        Ok(Timed {
            passes,
            gpu_timestamps: self.queries.is_some(),
            readback: copied,
        })
    }
}
