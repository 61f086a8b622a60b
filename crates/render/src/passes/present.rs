//! Present: nearest upscale of the internal frame to the output (`shaders/present.wgsl`),
//! mapping each pixel to the palette when there is one (`crate::palette`).

use crate::context::GpuContext;
use crate::passes::LazyRender;
use bytemuck::{Pod, Zeroable};

use super::{
    FLOAT, RenderSpec, UINT, bind_group, entry, render_pipeline, texture, uniform, uniform_buffer,
};
use crate::baselines::gbuffer::Target;
use crate::palette::{PALETTE_UNIFORM_SIZE, PaletteInput, uniform_bytes};
use crate::shader;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct Sizes {
    output: [u32; 2],
    internal: [u32; 2],
    scale: [f32; 2],
    _pad: [u32; 2],
}

/// Internal pixels per output pixel, along x and y.
fn scale(internal: (u32, u32), output: (u32, u32)) -> [f32; 2] {
    [
        internal.0 as f32 / output.0.max(1) as f32,
        internal.1 as f32 / output.1.max(1) as f32,
    ]
}

/// The internal pixel the present pass copies to output pixel `(x, y)`: the one under the
/// output pixel's centre. The shader does the same single-precision multiply, so this
/// mirrors it exactly.
pub fn source_pixel(x: u32, y: u32, internal: (u32, u32), output: (u32, u32)) -> (u32, u32) {
    let [sx, sy] = scale(internal, output);
    let at = |p: u32, s: f32, max: u32| (((p as f32 + 0.5) * s) as u32).min(max.max(1) - 1);
    (at(x, sx, internal.0), at(y, sy, internal.1))
}

/// Size of `Sizes` (WGSL `Sizes`).
pub const SIZES_SIZE: usize = size_of::<Sizes>();

/// The present pass.
pub struct PresentPass {
    pipeline: LazyRender,
    /// The palette's mapping at the internal size (`fs_map`), into `mapped`.
    map_pipeline: LazyRender,
    layout: wgpu::BindGroupLayout,
    sizes: wgpu::Buffer,
    palette_buffer: wgpu::Buffer,
    palette: Option<PaletteInput>,
    /// The `max_n` the palette's uniform was last written for (`None`: not written since
    /// the palette was set): the colours' OKLab is computed and uploaded only on a change.
    palette_written: Option<u32>,
    /// The frame in its palette colours, at the internal size (made with the first mapped
    /// frame of a size).
    mapped: Option<((u32, u32), wgpu::TextureView)>,
    internal_format: wgpu::TextureFormat,
}

impl PresentPass {
    /// Builds the pipeline for a `colour` output: a plain copy of the internal frame's
    /// sRGB-encoded bytes, or a decode for an sRGB output (which encodes again on write).
    pub fn new(
        device: &wgpu::Device,
        colour: wgpu::TextureFormat,
    ) -> Result<Self, shader::ShaderError> {
        let module = shader::module(device, "present.wgsl")?;
        let f = wgpu::ShaderStages::FRAGMENT;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("present::layout"),
            entries: &[
                entry(0, f, texture(FLOAT, wgpu::TextureViewDimension::D2)),
                entry(1, f, uniform(false)),
                entry(2, f, texture(UINT, wgpu::TextureViewDimension::D2)),
                entry(3, f, uniform(false)),
            ],
        });
        let internal_format = colour.remove_srgb_suffix();
        let layouts = [&layout];
        let (outputs, internals) = ([colour], [internal_format]);
        let spec = |fragment, targets| RenderSpec {
            owner: "present",
            module: &module,
            vertex: "vs",
            layouts: &layouts,
            vertex_buffers: &[],
            fragment,
            targets,
            depth: None,
        };
        let fragment = if colour.is_srgb() { "fs_decode" } else { "fs" };
        let pipeline = render_pipeline(device, spec(fragment, &outputs));
        let map_pipeline = render_pipeline(device, spec("fs_map", &internals));
        let sizes = uniform_buffer(device, "present::sizes", size_of::<Sizes>() as u64);
        let palette_buffer = uniform_buffer(device, "present::palette", PALETTE_UNIFORM_SIZE);
        Ok(PresentPass {
            pipeline,
            map_pipeline,
            layout,
            sizes,
            palette_buffer,
            palette: None,
            palette_written: None,
            mapped: None,
            internal_format,
        })
    }

    /// The palette frames are mapped to from the next one on (`None`: colours as drawn).
    pub fn set_palette(&mut self, palette: Option<PaletteInput>) {
        self.palette = palette.filter(|p| !p.colours.is_empty());
        self.palette_written = None;
        if self.palette.is_none() {
            self.mapped = None;
        }
    }

    /// Whether frames are mapped to a palette (they then go through the internal target).
    pub fn has_palette(&self) -> bool {
        self.palette.is_some()
    }

    /// Records the upscale of `frame` (`internal` pixels, their texel keys in `keys`, dense
    /// over faces of `max_n`) into `target` (`output` pixels); with a palette, the frame is
    /// first mapped to it at the internal size.
    #[allow(clippy::too_many_arguments)]
    pub fn record(
        &mut self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        (frame, keys): (&wgpu::TextureView, &wgpu::TextureView),
        target: &wgpu::TextureView,
        internal: (u32, u32),
        output: (u32, u32),
        max_n: u32,
    ) {
        let (device, queue) = (&ctx.device, &ctx.queue);
        let sizes = Sizes {
            output: [output.0, output.1],
            internal: [internal.0, internal.1],
            scale: scale(internal, output),
            _pad: [0; 2],
        };
        queue.write_buffer(&self.sizes, 0, bytemuck::bytes_of(&sizes));
        let bind = |frame| {
            bind_group(
                device,
                "present::bind",
                &self.layout,
                &[
                    wgpu::BindingResource::TextureView(frame),
                    self.sizes.as_entire_binding(),
                    wgpu::BindingResource::TextureView(keys),
                    self.palette_buffer.as_entire_binding(),
                ],
            )
        };
        let Some(palette) = &self.palette else {
            draw(encoder, self.pipeline.get(), &bind(frame), target);
            return;
        };
        queue.write_buffer(
            &self.palette_buffer,
            0,
            &uniform_bytes(Some(palette), max_n),
        );
        if self
            .mapped
            .as_ref()
            .is_none_or(|(size, _)| *size != internal)
        {
            let mapped = Target::new(
                device,
                "present::mapped",
                internal.into(),
                self.internal_format,
            );
            self.mapped = Some((internal, mapped.view));
        }
        let Some((_, mapped)) = &self.mapped else {
            return;
        };
        draw(encoder, self.map_pipeline.get(), &bind(frame), mapped);
        draw(encoder, self.pipeline.get(), &bind(mapped), target);
    }
}

/// One fullscreen triangle of `pipeline` into `target`.
pub(crate) fn draw(
    encoder: &mut wgpu::CommandEncoder,
    pipeline: &wgpu::RenderPipeline,
    bind: &wgpu::BindGroup,
    target: &wgpu::TextureView,
) {
    let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("present::pass"),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view: target,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                store: wgpu::StoreOp::Store,
            },
        })],
        depth_stencil_attachment: None,
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    });
    pass.set_pipeline(pipeline);
    pass.set_bind_group(0, bind, &[]);
    pass.draw(0..3, 0..1);
}

#[cfg(test)]
mod tests {
    use super::source_pixel;

    #[test]
    fn source_pixels_cover_the_internal_frame_in_order() {
        for (internal, output) in [
            ((797, 448), (1280, 720)),
            ((64, 36), (64, 36)),
            ((3, 2), (7, 5)),
        ] {
            let xs: Vec<u32> = (0..output.0)
                .map(|x| source_pixel(x, 0, internal, output).0)
                .collect();
            assert!(xs.windows(2).all(|w| w[1] == w[0] || w[1] == w[0] + 1));
            assert_eq!((xs[0], *xs.last().unwrap()), (0, internal.0 - 1));
            let ys: Vec<u32> = (0..output.1)
                .map(|y| source_pixel(0, y, internal, output).1)
                .collect();
            assert!(ys.windows(2).all(|w| w[1] == w[0] || w[1] == w[0] + 1));
            assert_eq!((ys[0], *ys.last().unwrap()), (0, internal.1 - 1));
        }
        // Same size: identity.
        assert_eq!(source_pixel(17, 9, (64, 36), (64, 36)), (17, 9));
    }
}
