//! Upscale (`shaders/upscale.wgsl`): draws a shaded screen image at the output size with
//! nearest sampling and a sub-texel offset, writing colour and entity id. Raster uses it at
//! scale 1, Naive at the art-pixel scale, Snap with its margin and restored remainder.

use crate::context::GpuContext;
use crate::passes::LazyRender;
use crate::passes::bind_group;
use bytemuck::{Pod, Zeroable};
use glam::Vec2;

use super::gbuffer::ScreenTargets;
use super::{Output, fullscreen_pipeline};
use crate::gpu_scene::GpuScene;
use crate::palette::PaletteInput;
use crate::passes::{FLOAT, UINT, entry, storage, texture, uniform, uniform_buffer};
use crate::shader;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct UpscaleUniform {
    scale: [f32; 2],
    offset: [f32; 2],
    src_size: [u32; 2],
    _pad: [u32; 2],
}

/// How output pixels map to source texels: `floor(pixel_centre · scale + offset)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mapping {
    /// Source texels per output pixel, per axis.
    pub scale: Vec2,
    /// Source coordinate of the output's top-left corner, in texels.
    pub offset: Vec2,
}

/// The upscale pass.
pub struct UpscalePass {
    pipeline: LazyRender,
    layout: wgpu::BindGroupLayout,
    uniform: wgpu::Buffer,
    palette: wgpu::Buffer,
}

impl UpscalePass {
    /// Builds the pipeline.
    pub fn new(device: &wgpu::Device) -> Result<Self, shader::ShaderError> {
        let module = shader::module(device, "upscale.wgsl")?;
        let f = wgpu::ShaderStages::FRAGMENT;
        let d2 = wgpu::TextureViewDimension::D2;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("baselines::upscale::layout"),
            entries: &[
                entry(0, f, uniform(false)),
                entry(1, f, texture(FLOAT, d2)),
                entry(2, f, texture(UINT, d2)),
                entry(3, f, storage(true)),
                entry(4, f, uniform(false)),
            ],
        });
        let pipeline = fullscreen_pipeline(device, &module, &layout, "baselines::upscale");
        let uniform = uniform_buffer(
            device,
            "baselines::upscale::uniform",
            size_of::<UpscaleUniform>() as u64,
        );
        let palette = uniform_buffer(
            device,
            "baselines::upscale::palette",
            crate::palette::PALETTE_UNIFORM_SIZE,
        );
        Ok(UpscalePass {
            pipeline,
            layout,
            uniform,
            palette,
        })
    }

    /// The palette the output is mapped to from the next frame on (`None`: as shaded).
    pub fn set_palette(&self, queue: &wgpu::Queue, palette: Option<&PaletteInput>) {
        queue.write_buffer(&self.palette, 0, &crate::palette::uniform_bytes(palette, 0));
    }

    /// Records drawing `lit` (`src.lit`, or it with a bloom; and `src`'s ids) into `out`
    /// through `mapping`.
    #[allow(clippy::too_many_arguments)]
    pub fn record(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        src: &ScreenTargets,
        lit: &wgpu::TextureView,
        scene: &GpuScene,
        mapping: Mapping,
        out: &Output,
    ) {
        let (device, queue) = (&ctx.device, &ctx.queue);
        let u = UpscaleUniform {
            scale: mapping.scale.to_array(),
            offset: mapping.offset.to_array(),
            src_size: src.size.to_array(),
            _pad: [0; 2],
        };
        queue.write_buffer(&self.uniform, 0, bytemuck::bytes_of(&u));
        let bind = bind_group(
            device,
            "baselines::upscale::bind",
            &self.layout,
            &[
                self.uniform.as_entire_binding(),
                wgpu::BindingResource::TextureView(lit),
                wgpu::BindingResource::TextureView(&src.ids.view),
                scene.objects.as_entire_binding(),
                self.palette.as_entire_binding(),
            ],
        );
        let mut pass = out.begin(encoder, "baselines::upscale::pass");
        pass.set_pipeline(self.pipeline.get());
        pass.set_bind_group(0, &bind, &[]);
        pass.draw(0..3, 0..1);
    }
}
