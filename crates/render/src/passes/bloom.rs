//! Bloom (`shaders/bloom.wgsl`): light spilling from bright pixels, on a frame whose pixels
//! are the art pixels (texel splatting's internal frame before the palette and the upscale;
//! the naive and snap baselines' shaded screen before theirs), so it holds as still as they
//! do. Two fullscreen draws at the frame's size: the light above the threshold blurred
//! along x into a float texture, then along y and added to the frame into a texture of the
//! frame's format that the next pass reads.

use bytemuck::{Pod, Zeroable};

use super::{
    FLOAT, RenderSpec, bind_group, entry, render_pipeline, texture, uniform, uniform_buffer,
};
use crate::baselines::gbuffer::Target;
use crate::context::GpuContext;
use crate::passes::LazyRender;
use crate::shader;

/// A bloom as the renderer takes it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BloomInput {
    /// Relative luminance (linear, 0–1) above which a pixel spills light.
    pub threshold: f32,
    /// How much of the spilled light is added (0–4).
    pub strength: f32,
    /// How far it spills, in art pixels (1–16).
    pub radius: u32,
}

/// The largest radius the pass takes (a larger one is clamped).
pub const MAX_BLOOM_RADIUS: u32 = 16;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct BloomUniform {
    threshold: f32,
    strength: f32,
    radius: u32,
    encoded: u32,
    size: [u32; 2],
    _pad2: [u32; 2],
}

/// The format of the horizontal sums.
const SUMS_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// The bloom pass and its two textures (made at the first frame of a size).
pub struct BloomPass {
    horizontal: LazyRender,
    vertical: LazyRender,
    layout: wgpu::BindGroupLayout,
    uniform: wgpu::Buffer,
    bloom: Option<BloomInput>,
    /// Size, the horizontal sums, the frame with its bloom.
    targets: Option<((u32, u32), wgpu::TextureView, wgpu::TextureView)>,
    format: wgpu::TextureFormat,
    encoded: bool,
}

impl BloomPass {
    /// Builds the pipelines for frames of `format`, holding sRGB-encoded colours if
    /// `encoded` (texel splatting's internal frame), else linear ones (the baselines').
    pub fn new(
        device: &wgpu::Device,
        format: wgpu::TextureFormat,
        encoded: bool,
    ) -> Result<Self, shader::ShaderError> {
        let module = shader::module(device, "bloom.wgsl")?;
        let f = wgpu::ShaderStages::FRAGMENT;
        let d2 = wgpu::TextureViewDimension::D2;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("bloom::layout"),
            entries: &[
                entry(0, f, texture(FLOAT, d2)),
                entry(1, f, uniform(false)),
                entry(2, f, texture(FLOAT, d2)),
            ],
        });
        let layouts = [&layout];
        let (sums, frames) = ([SUMS_FORMAT], [format]);
        let spec = |fragment, targets| RenderSpec {
            owner: "bloom",
            module: &module,
            vertex: "vs",
            layouts: &layouts,
            vertex_buffers: &[],
            fragment,
            targets,
            depth: None,
        };
        let horizontal = render_pipeline(device, spec("fs_h", &sums));
        let vertical = render_pipeline(device, spec("fs_v", &frames));
        let uniform = uniform_buffer(device, "bloom::uniform", size_of::<BloomUniform>() as u64);
        Ok(BloomPass {
            horizontal,
            vertical,
            layout,
            uniform,
            bloom: None,
            targets: None,
            format,
            encoded,
        })
    }

    /// The bloom of the frames from the next one on (`None`: none; a strength of 0 is none).
    pub fn set(&mut self, bloom: Option<BloomInput>) {
        self.bloom = bloom.filter(|b| b.strength > 0.0 && b.strength.is_finite());
        if self.bloom.is_none() {
            self.targets = None;
        }
    }

    /// Whether frames get a bloom.
    pub fn on(&self) -> bool {
        self.bloom.is_some()
    }

    /// The frame with its bloom, as the last [`BloomPass::record`] drew it.
    pub fn output(&self) -> Option<&wgpu::TextureView> {
        self.targets.as_ref().map(|t| &t.2)
    }

    /// Records the bloom of `frame` (`size` pixels, `scale` of them to an art pixel);
    /// returns the frame with it, or `None` when there is no bloom.
    pub fn record(
        &mut self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        frame: &wgpu::TextureView,
        size: (u32, u32),
        scale: f32,
    ) -> Option<&wgpu::TextureView> {
        let b = self.bloom?;
        let (device, queue) = (&ctx.device, &ctx.queue);
        let u = BloomUniform {
            threshold: if b.threshold.is_finite() {
                b.threshold.clamp(0.0, 1.0)
            } else {
                1.0
            },
            strength: b.strength.clamp(0.0, 4.0),
            radius: ((b.radius.clamp(1, MAX_BLOOM_RADIUS) as f32 * scale.clamp(1.0, 8.0)).round()
                as u32),
            encoded: u32::from(self.encoded),
            size: [size.0, size.1],
            _pad2: [0; 2],
        };
        queue.write_buffer(&self.uniform, 0, bytemuck::bytes_of(&u));
        if self.targets.as_ref().is_none_or(|t| t.0 != size) {
            let make = |label, format| Target::new(device, label, size.into(), format).view;
            let sums = make("bloom::sums", SUMS_FORMAT);
            let out = make("bloom::frame", self.format);
            self.targets = Some((size, sums, out));
        }
        let (_, sums, out) = self.targets.as_ref()?;
        let bind = |src, frame| {
            bind_group(
                device,
                "bloom::bind",
                &self.layout,
                &[
                    wgpu::BindingResource::TextureView(src),
                    self.uniform.as_entire_binding(),
                    wgpu::BindingResource::TextureView(frame),
                ],
            )
        };
        super::present::draw(encoder, self.horizontal.get(), &bind(frame, frame), sums);
        super::present::draw(encoder, self.vertical.get(), &bind(sums, frame), out);
        Some(out)
    }
}
