//! Capture: rasterizes the scene into the cube faces the plan asks for (`shaders/capture.wgsl`).

use bytemuck::{Pod, Zeroable};
use texel_probes::cube::face_view_projection;

use super::{
    RenderSpec, UNIFORM_STRIDE, bind_group, entry, render_pipeline, storage, uniform,
    uniform_buffer,
};
use texel_probes::visibility::TexelRect;

use crate::gpu_scene::GpuScene;
use crate::input::CaptureInput;
use crate::probe_store::{ALBEDO_FORMAT, DEPTH_FORMAT, GEO_FORMAT, ID_FORMAT, ProbeStore};
use crate::shader;

/// Near and far planes of a capture, world units. Beyond `CAPTURE_FAR` is sky.
pub const CAPTURE_NEAR: f32 = 0.02;
/// See [`CAPTURE_NEAR`].
pub const CAPTURE_FAR: f32 = 500.0;
/// Most faces captured in one frame (three probes × six faces).
pub const MAX_CAPTURES: usize = 18;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct FaceParams {
    view_proj: [[f32; 4]; 4],
    origin: [f32; 4],
}

/// Size of `FaceParams` (WGSL `FaceParams`).
pub const FACE_PARAMS_SIZE: usize = size_of::<FaceParams>();

/// The capture pass.
pub struct CapturePass {
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
    faces: wgpu::Buffer,
}

impl CapturePass {
    /// Builds the pipeline.
    pub fn new(device: &wgpu::Device) -> Result<Self, shader::ShaderError> {
        let module = shader::module(device, "capture.wgsl")?;
        let vf = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("capture::layout"),
            entries: &[entry(0, vf, uniform(true)), entry(1, vf, storage(true))],
        });
        // Both sides are drawn (default primitive state): the face projection flips Y (and so
        // the winding), and planes are one-sided surfaces that must still occlude from below.
        let vertex_buffers = [Some(GpuScene::vertex_layout())];
        let pipeline = render_pipeline(
            device,
            RenderSpec {
                owner: "capture",
                module: &module,
                vertex: "vs",
                layouts: &[&layout],
                vertex_buffers: &vertex_buffers,
                fragment: "fs",
                targets: &[GEO_FORMAT, ID_FORMAT, ALBEDO_FORMAT],
                depth: Some((DEPTH_FORMAT, true, wgpu::CompareFunction::Less)),
            },
        );
        let faces = uniform_buffer(
            device,
            "capture::faces",
            UNIFORM_STRIDE * MAX_CAPTURES as u64,
        );
        Ok(CapturePass {
            pipeline,
            layout,
            faces,
        })
    }

    /// Records one render pass per capture (at most [`MAX_CAPTURES`]). `rects[i]`, when
    /// given, limits capture `i` to those texels (the rest of the face is cleared to sky).
    #[allow(clippy::too_many_arguments)]
    pub fn record(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        captures: &[CaptureInput],
        rects: &[Option<TexelRect>],
        store: &ProbeStore,
        scene: &GpuScene,
    ) {
        let captures = &captures[..captures.len().min(MAX_CAPTURES)];
        let mut bytes = vec![0u8; UNIFORM_STRIDE as usize * captures.len()];
        for (i, c) in captures.iter().enumerate() {
            let p = FaceParams {
                view_proj: face_view_projection(c.origin, c.face, CAPTURE_NEAR, CAPTURE_FAR)
                    .to_cols_array_2d(),
                origin: c.origin.extend(1.0).to_array(),
            };
            let at = i * UNIFORM_STRIDE as usize;
            bytes[at..at + size_of::<FaceParams>()].copy_from_slice(bytemuck::bytes_of(&p));
        }
        if bytes.is_empty() {
            return;
        }
        queue.write_buffer(&self.faces, 0, &bytes);
        let face = wgpu::BindingResource::Buffer(wgpu::BufferBinding {
            buffer: &self.faces,
            offset: 0,
            size: wgpu::BufferSize::new(size_of::<FaceParams>() as u64),
        });
        let resources = [face, scene.objects.as_entire_binding()];
        let bind = bind_group(device, "capture::bind", &self.layout, &resources);
        for (i, c) in captures.iter().enumerate() {
            let slot = store.slot(c.slot);
            let f = c.face.index();
            fn colour(
                view: &wgpu::TextureView,
                clear: wgpu::Color,
            ) -> Option<wgpu::RenderPassColorAttachment<'_>> {
                Some(wgpu::RenderPassColorAttachment {
                    view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(clear),
                        store: wgpu::StoreOp::Store,
                    },
                })
            }
            let sky = wgpu::Color {
                r: 0.0,
                g: 0.0,
                b: 0.0,
                a: f64::from(texel_geom::limits::SKY_DEPTH),
            };
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("capture::face"),
                color_attachments: &[
                    colour(&slot.geo.layer_views[f], sky),
                    colour(&slot.ids.layer_views[f], wgpu::Color::TRANSPARENT),
                    colour(&slot.albedo.layer_views[f], wgpu::Color::TRANSPARENT),
                ],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &slot.depth.layer_views[f],
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Discard,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            let rect = rects.get(i).copied().flatten();
            if scene.vertex_count == 0 || rect.is_some_and(|r| r.area() == 0) {
                continue;
            }
            if let Some(r) = rect {
                pass.set_scissor_rect(r.x0, r.y0, r.x1 - r.x0, r.y1 - r.y0);
            }
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &bind, &[(i as u64 * UNIFORM_STRIDE) as u32]);
            pass.set_vertex_buffer(0, scene.vertices.slice(..));
            pass.draw(0..scene.vertex_count, 0..1);
        }
    }
}
