//! Splat: draws the culled texels as indexed, instanced world-space quads (`shaders/splat.wgsl`).

use wgpu::util::DeviceExt;

use super::{entry, storage, uniform};
use crate::shader;

/// Format of the per-pixel texel-key target (0 = no texel).
pub const KEY_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;
/// Format of the splat depth buffer.
pub const SPLAT_DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// The colour and key targets every on-screen pass writes.
pub fn targets(colour: wgpu::TextureFormat) -> [Option<wgpu::ColorTargetState>; 2] {
    let t = |format| {
        Some(wgpu::ColorTargetState {
            format,
            blend: None,
            write_mask: wgpu::ColorWrites::ALL,
        })
    };
    [t(colour), t(KEY_FORMAT)]
}

/// The splat pass.
pub struct SplatPass {
    pipeline: wgpu::RenderPipeline,
    dither_pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
    indices: wgpu::Buffer,
}

impl SplatPass {
    /// Builds the pipeline for a `colour` target.
    pub fn new(
        device: &wgpu::Device,
        colour: wgpu::TextureFormat,
    ) -> Result<Self, shader::ShaderError> {
        let module = shader::module(device, "splat.wgsl")?;
        let vf = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("splat::layout"),
            entries: &[entry(0, vf, uniform(false)), entry(1, vf, storage(true))],
        });
        let pl = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("splat::pipeline_layout"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline_for = |fragment: &str| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some("splat::pipeline"),
                layout: Some(&pl),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("vs"),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some(fragment),
                    compilation_options: Default::default(),
                    targets: &targets(colour),
                }),
                primitive: wgpu::PrimitiveState::default(),
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: SPLAT_DEPTH_FORMAT,
                    depth_write_enabled: Some(true),
                    depth_compare: Some(wgpu::CompareFunction::Less),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: Default::default(),
                multiview_mask: None,
                cache: None,
            })
        };
        let pipeline = pipeline_for("fs");
        let dither_pipeline = pipeline_for("fs_dither");
        let indices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("splat::indices"),
            contents: bytemuck::cast_slice(&[0u16, 1, 2, 0, 2, 3]),
            usage: wgpu::BufferUsages::INDEX,
        });
        Ok(SplatPass {
            pipeline,
            dither_pipeline,
            layout,
            indices,
        })
    }

    /// The bind group over the view globals and the splat list.
    pub fn bind_group(
        &self,
        device: &wgpu::Device,
        view: &wgpu::Buffer,
        splats: &wgpu::Buffer,
    ) -> wgpu::BindGroup {
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("splat::bind"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: view.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: splats.as_entire_binding(),
                },
            ],
        })
    }

    /// Draws the splats whose count the cull pass wrote into `args`; `dither` while a
    /// crossfade runs (grid and previous split the pixels with Bayer patterns).
    pub fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        bind: &wgpu::BindGroup,
        args: &wgpu::Buffer,
        dither: bool,
    ) {
        pass.set_pipeline(if dither {
            &self.dither_pipeline
        } else {
            &self.pipeline
        });
        pass.set_bind_group(0, bind, &[]);
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint16);
        pass.draw_indexed_indirect(args, 0);
    }
}
