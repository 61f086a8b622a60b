//! Background: the eye probe (or the sky) behind every pixel (`shaders/background.wgsl`).

use super::{ARRAY, FLOAT, RenderSpec, UINT, bind_group, entry, render_pipeline, texture, uniform};
use crate::context::GpuContext;
use crate::passes::LazyRender;
use crate::passes::splat::{KEY_FORMAT, SPLAT_DEPTH_FORMAT};
use crate::probe_store::SlotTextures;
use crate::shader;

/// The background pass.
pub struct BackgroundPass {
    pipeline: LazyRender,
    layout: wgpu::BindGroupLayout,
}

impl BackgroundPass {
    /// Builds the pipeline for a `colour` target.
    pub fn new(
        device: &wgpu::Device,
        colour: wgpu::TextureFormat,
    ) -> Result<Self, shader::ShaderError> {
        let module = shader::module(device, "background.wgsl")?;
        let f = wgpu::ShaderStages::FRAGMENT;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("background::layout"),
            entries: &[
                entry(0, wgpu::ShaderStages::VERTEX_FRAGMENT, uniform(false)),
                entry(1, f, texture(UINT, ARRAY)),
                entry(2, f, texture(FLOAT, ARRAY)),
                entry(3, f, texture(FLOAT, ARRAY)),
            ],
        });
        let pipeline = render_pipeline(
            device,
            RenderSpec {
                owner: "background",
                module: &module,
                vertex: "vs",
                layouts: &[&layout],
                vertex_buffers: &[],
                fragment: "fs",
                targets: &[colour, KEY_FORMAT],
                // At the eye's surface, pushed back: where no splat wrote depth, or where the
                // splat lies behind what the eye sees (see background.wgsl).
                depth: Some((
                    SPLAT_DEPTH_FORMAT,
                    false,
                    wgpu::CompareFunction::GreaterEqual,
                )),
            },
        );
        Ok(BackgroundPass { pipeline, layout })
    }

    /// The bind group over the view globals and the eye slot.
    pub fn bind_group(
        &self,
        ctx: &GpuContext,
        view: &wgpu::Buffer,
        eye: &SlotTextures,
    ) -> wgpu::BindGroup {
        bind_group(
            &ctx.device,
            "background::bind",
            &self.layout,
            &[
                view.as_entire_binding(),
                wgpu::BindingResource::TextureView(&eye.ids.array_view),
                wgpu::BindingResource::TextureView(&eye.lit.array_view),
                wgpu::BindingResource::TextureView(&eye.geo.array_view),
            ],
        )
    }

    /// Draws the fullscreen triangle.
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>, bind: &wgpu::BindGroup) {
        pass.set_pipeline(self.pipeline.get());
        pass.set_bind_group(0, bind, &[]);
        pass.draw(0..3, 0..1);
    }
}
