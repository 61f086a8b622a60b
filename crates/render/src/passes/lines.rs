//! Lines: world-space segments (the editor's ground grid) drawn into the frame after the
//! background, depth-tested against the splats without writing depth, alpha-blended, texel
//! keys untouched (`shaders/lines.wgsl`). The list is set by the renderer (`Renderer::set_lines`
//! calls [`LinesPass::set`]); an empty list (the default) draws nothing and costs nothing.

use super::{RenderSpec, bind_group, entry, line_pipeline, uniform};
use crate::context::GpuContext;
use crate::passes::LazyRender;
use crate::passes::splat::{KEY_FORMAT, SPLAT_DEPTH_FORMAT};
use crate::shader;

/// One end of a line segment: consecutive pairs of a list are the segments.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct LineVertex {
    /// World position.
    pub position: [f32; 3],
    /// sRGB-encoded colour with straight (not premultiplied) alpha, as egui's `Color32`
    /// unmultiplied bytes.
    pub colour: [u8; 4],
}

/// The lines pass: its pipeline and the current list.
pub struct LinesPass {
    pipeline: LazyRender,
    layout: wgpu::BindGroupLayout,
    vertices: Option<wgpu::Buffer>,
    count: u32,
}

impl LinesPass {
    /// Builds the pipeline for a `colour` target (with the frame's key target and splat depth).
    pub fn new(
        device: &wgpu::Device,
        colour: wgpu::TextureFormat,
    ) -> Result<Self, shader::ShaderError> {
        let module = shader::module(device, "lines.wgsl")?;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("lines::layout"),
            entries: &[entry(0, wgpu::ShaderStages::VERTEX, uniform(false))],
        });
        let attributes = wgpu::vertex_attr_array![0 => Float32x3, 1 => Unorm8x4];
        let vertex_buffer = wgpu::VertexBufferLayout {
            array_stride: size_of::<LineVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &attributes,
        };
        let pipeline = line_pipeline(
            device,
            RenderSpec {
                owner: "lines",
                module: &module,
                vertex: "vs",
                layouts: &[&layout],
                vertex_buffers: &[Some(vertex_buffer)],
                fragment: "fs",
                targets: &[colour, KEY_FORMAT],
                // Hidden behind splats, drawn over the background; depth is left as it was.
                depth: Some((SPLAT_DEPTH_FORMAT, false, wgpu::CompareFunction::Greater)),
            },
            &[
                (
                    Some(wgpu::BlendState::ALPHA_BLENDING),
                    wgpu::ColorWrites::ALL,
                ),
                (None, wgpu::ColorWrites::empty()),
            ],
        );
        Ok(LinesPass {
            pipeline,
            layout,
            vertices: None,
            count: 0,
        })
    }

    /// Replaces the list (an odd last vertex is ignored). The buffer grows to fit and is kept.
    pub fn set(&mut self, ctx: &GpuContext, lines: &[LineVertex]) {
        let lines = &lines[..lines.len() & !1];
        let bytes: &[u8] = bytemuck::cast_slice(lines);
        let fits = self
            .vertices
            .as_ref()
            .is_some_and(|b| b.size() >= bytes.len() as u64);
        if !fits && !bytes.is_empty() {
            self.vertices = Some(ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("lines::vertices"),
                size: (bytes.len() as u64).next_power_of_two(),
                usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }));
        }
        if let Some(buffer) = &self.vertices
            && !bytes.is_empty()
        {
            ctx.queue.write_buffer(buffer, 0, bytes);
        }
        self.count = lines.len() as u32;
    }

    /// Draws the list into `pass` (the frame's colour, key and depth targets) with the view
    /// globals `view`; nothing when the list is empty.
    pub fn draw(&self, ctx: &GpuContext, pass: &mut wgpu::RenderPass<'_>, view: &wgpu::Buffer) {
        let device = &ctx.device;
        let Some(vertices) = self.vertices.as_ref().filter(|_| self.count > 0) else {
            return;
        };
        let bind = bind_group(
            device,
            "lines::bind",
            &self.layout,
            &[view.as_entire_binding()],
        );
        pass.set_pipeline(self.pipeline.get());
        pass.set_bind_group(0, &bind, &[]);
        pass.set_vertex_buffer(0, vertices.slice(..));
        pass.draw(0..self.count, 0..1);
    }
}
