//! March (`shaders/march.wgsl`): texel marching, the paper's alternative display. A
//! fullscreen pass that, per pixel, marches the view ray through the stable probes' cube
//! faces and shows the first texel the ray reaches, falling back to the other stable probe,
//! the eye probe and the sky. It replaces cull + splat + background and reuses everything
//! before them (capture, shade), so the two displays differ only in how texels reach pixels.

use super::cull::{probe_textures_bind_group, probe_textures_layout};
use super::{RenderSpec, bind_group, entry, render_pipeline, storage, uniform};
use crate::context::GpuContext;
use crate::passes::LazyRender;
use crate::passes::splat::{KEY_FORMAT, SPLAT_DEPTH_FORMAT};
use crate::probe_store::ProbeStore;
use crate::shader;

/// Bytes of the counters the shader adds to: steps taken, pixels that fell back.
pub const COUNTERS_BYTES: u64 = 8;

/// What the march counted over one frame.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct MarchCounts {
    /// Steps taken over every pixel and every probe marched.
    pub steps: u64,
    /// Pixels the first probe they asked could not resolve.
    pub fallbacks: u64,
}

impl MarchCounts {
    /// The counts in the bytes read back from the counters buffer.
    pub fn from_bytes(bytes: &[u8]) -> Self {
        let word = |i: usize| {
            bytes.get(4 * i..4 * i + 4).map_or(0, |b| {
                u64::from(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            })
        };
        MarchCounts {
            steps: word(0),
            fallbacks: word(1),
        }
    }
}

/// The march pass.
pub struct MarchPass {
    pipeline: LazyRender,
    layout: wgpu::BindGroupLayout,
    slots_layout: wgpu::BindGroupLayout,
    /// Steps and fallbacks of the last frame, cleared before each.
    pub counters: wgpu::Buffer,
}

impl MarchPass {
    /// Builds the pipeline for a `colour` target.
    pub fn new(
        device: &wgpu::Device,
        colour: wgpu::TextureFormat,
    ) -> Result<Self, shader::ShaderError> {
        let module = shader::module(device, "march.wgsl")?;
        let f = wgpu::ShaderStages::FRAGMENT;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("march::layout"),
            entries: &[
                entry(0, wgpu::ShaderStages::VERTEX_FRAGMENT, uniform(false)),
                entry(1, f, storage(false)),
            ],
        });
        // The slots' textures as the cull pass binds them (`lib/slots.wgsl`).
        let slots_layout = probe_textures_layout(device, f);
        let pipeline = render_pipeline(
            device,
            RenderSpec {
                owner: "march",
                module: &module,
                vertex: "vs",
                layouts: &[&layout, &slots_layout],
                vertex_buffers: &[],
                fragment: "fs",
                targets: &[colour, KEY_FORMAT],
                // Every pixel writes the depth of what it shows, so lines test against it.
                depth: Some((SPLAT_DEPTH_FORMAT, true, wgpu::CompareFunction::Always)),
            },
        );
        let counters = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("march::counters"),
            size: COUNTERS_BYTES,
            usage: wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::COPY_SRC
                | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Ok(MarchPass {
            pipeline,
            layout,
            slots_layout,
            counters,
        })
    }

    /// The bind groups: the view globals and the counters (group 0), every slot's textures
    /// (group 1).
    pub fn bind_groups(
        &self,
        ctx: &GpuContext,
        view: &wgpu::Buffer,
        store: &ProbeStore,
    ) -> [wgpu::BindGroup; 2] {
        let own = [view.as_entire_binding(), self.counters.as_entire_binding()];
        [
            bind_group(&ctx.device, "march::bind", &self.layout, &own),
            probe_textures_bind_group(&ctx.device, &self.slots_layout, store),
        ]
    }

    /// Clears the counters (before the render pass that draws).
    pub fn clear(&self, encoder: &mut wgpu::CommandEncoder) {
        encoder.clear_buffer(&self.counters, 0, None);
    }

    /// Draws the fullscreen triangle.
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>, binds: &[wgpu::BindGroup; 2]) {
        pass.set_pipeline(self.pipeline.get());
        pass.set_bind_group(0, &binds[0], &[]);
        pass.set_bind_group(1, &binds[1], &[]);
        pass.draw(0..3, 0..1);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_read_from_little_endian_words() {
        let bytes = [7, 1, 0, 0, 3, 0, 0, 0];
        assert_eq!(
            MarchCounts::from_bytes(&bytes),
            MarchCounts {
                steps: 263,
                fallbacks: 3
            }
        );
        assert_eq!(MarchCounts::from_bytes(&[]), MarchCounts::default());
    }
}
