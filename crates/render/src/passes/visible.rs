//! Visible: counts the distinct probe texels the final frame shows (`shaders/visible.wgsl`).

use super::{UINT, bind_group, compute_pipeline, entry, storage, texture};
use crate::context::GpuContext;
use crate::passes::LazyCompute;
use crate::shader;

/// The visible-texel counting pass and its bitset.
pub struct VisiblePass {
    pipeline: LazyCompute,
    layout: wgpu::BindGroupLayout,
    /// One bit per texel key.
    pub bits: wgpu::Buffer,
    words: u64,
}

impl VisiblePass {
    /// Builds the pipeline.
    pub fn new(device: &wgpu::Device) -> Result<Self, shader::ShaderError> {
        let module = shader::module(device, "visible.wgsl")?;
        let c = wgpu::ShaderStages::COMPUTE;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("visible::layout"),
            entries: &[
                entry(0, c, texture(UINT, wgpu::TextureViewDimension::D2)),
                entry(1, c, storage(false)),
            ],
        });
        let pipeline = compute_pipeline(device, "visible", &module, "main", &[&layout]);
        Ok(VisiblePass {
            pipeline,
            layout,
            bits: bits_buffer(device, 1),
            words: 1,
        })
    }

    /// Bytes of the bitset.
    pub fn bytes(&self) -> u64 {
        self.words * 4
    }

    /// Sizes the bitset for texel keys over faces of `max_n`.
    pub fn ensure_capacity(&mut self, device: &wgpu::Device, max_n: u32) {
        let words = (18 * u64::from(max_n) * u64::from(max_n)).div_ceil(32);
        if words != self.words {
            self.bits = bits_buffer(device, words);
            self.words = words;
        }
    }

    /// Clears the bitset and marks the keys of `keys`.
    pub fn record(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        keys: &wgpu::TextureView,
        size: (u32, u32),
    ) {
        encoder.clear_buffer(&self.bits, 0, None);
        let bind = bind_group(
            &ctx.device,
            "visible::bind",
            &self.layout,
            &[
                wgpu::BindingResource::TextureView(keys),
                self.bits.as_entire_binding(),
            ],
        );
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("visible::pass"),
            timestamp_writes: None,
        });
        pass.set_pipeline(self.pipeline.get());
        pass.set_bind_group(0, &bind, &[]);
        pass.dispatch_workgroups(size.0.div_ceil(8), size.1.div_ceil(8), 1);
    }
}

fn bits_buffer(device: &wgpu::Device, words: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("visible::bits"),
        size: words * 4,
        usage: wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_SRC
            | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}
