//! The baselines' G-buffer pass (`shaders/gbuffer.wgsl`): rasterizes the scene from a camera
//! into screen-sized targets (world position and view-axis depth, normal, object index with
//! packed albedo). The low-resolution methods shade it per pixel; at full resolution it is the
//! evaluator's reference G-buffer.

use crate::passes::bind_group;
use crate::passes::{RenderSpec, render_pipeline, uniform_buffer};
use bytemuck::{Pod, Zeroable};
use glam::{Mat4, UVec2, Vec3};

use crate::gpu_scene::GpuScene;
use crate::passes::{entry, storage, uniform};
use crate::shader;

/// World position (xyz) and view-axis depth (w; `SKY_DEPTH` = sky).
pub const WORLD_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
/// World normal.
pub const NORMAL_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Object index + 1 (x; 0 = sky), albedo × vertex colour and object flags as RGBA8 (y).
/// Packed in one target: four targets would exceed the 32 bytes per sample of the default
/// limits.
pub const ID_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg32Uint;
/// Shaded colour, linear.
pub const LIT_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Depth test.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

pub use texel_geom::limits::SKY_DEPTH;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct CameraUniform {
    view_proj: [[f32; 4]; 4],
    axis: [f32; 4],
}

/// One texture and its view.
pub struct Target {
    /// The texture.
    pub texture: wgpu::Texture,
    /// Its view.
    pub view: wgpu::TextureView,
}

impl Target {
    /// A `size` texture of `format`: a render attachment that shaders read and copies read
    /// back.
    pub(crate) fn new(
        device: &wgpu::Device,
        label: &str,
        size: UVec2,
        format: wgpu::TextureFormat,
    ) -> Self {
        use wgpu::TextureUsages as U;
        let usage = U::RENDER_ATTACHMENT | U::TEXTURE_BINDING | U::COPY_SRC;
        Self::with_usage(device, label, size, format, usage)
    }

    fn with_usage(
        device: &wgpu::Device,
        label: &str,
        size: UVec2,
        format: wgpu::TextureFormat,
        usage: wgpu::TextureUsages,
    ) -> Self {
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width: size.x,
                height: size.y,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage,
            view_formats: &[],
        });
        let view = texture.create_view(&Default::default());
        Target { texture, view }
    }
}

/// The screen-sized targets of one resolution: the G-buffer and the shaded image.
pub struct ScreenTargets {
    /// Width and height.
    pub size: UVec2,
    /// World position and depth.
    pub world: Target,
    /// Normal.
    pub normal: Target,
    /// Object index + 1 and packed albedo.
    pub ids: Target,
    /// Depth test.
    pub depth: Target,
    /// Shaded colour.
    pub lit: Target,
}

impl ScreenTargets {
    /// Allocates every target at `size`.
    pub fn new(device: &wgpu::Device, size: UVec2) -> Self {
        use wgpu::TextureUsages as U;
        let t = |label, format| Target::new(device, label, size, format);
        let lit_usage = U::STORAGE_BINDING | U::TEXTURE_BINDING | U::COPY_SRC;
        ScreenTargets {
            size,
            world: t("baselines::gbuffer::world", WORLD_FORMAT),
            normal: t("baselines::gbuffer::normal", NORMAL_FORMAT),
            ids: t("baselines::gbuffer::ids", ID_FORMAT),
            depth: t("baselines::gbuffer::depth", DEPTH_FORMAT),
            lit: Target::with_usage(
                device,
                "baselines::gbuffer::lit",
                size,
                LIT_FORMAT,
                lit_usage,
            ),
        }
    }
}

/// The G-buffer pass.
pub struct GBufferPass {
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
    camera: wgpu::Buffer,
}

impl GBufferPass {
    /// Builds the pipeline.
    pub fn new(device: &wgpu::Device) -> Result<Self, shader::ShaderError> {
        let module = shader::module(device, "gbuffer.wgsl")?;
        let vf = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("baselines::gbuffer::layout"),
            entries: &[entry(0, vf, uniform(false)), entry(1, vf, storage(true))],
        });
        // Both sides, as the capture pass: planes are one-sided surfaces.
        let vertex_buffers = [Some(GpuScene::vertex_layout())];
        let pipeline = render_pipeline(
            device,
            RenderSpec {
                owner: "baselines::gbuffer",
                module: &module,
                vertex: "vs",
                layouts: &[&layout],
                vertex_buffers: &vertex_buffers,
                fragment: "fs",
                targets: &[WORLD_FORMAT, NORMAL_FORMAT, ID_FORMAT],
                depth: Some((DEPTH_FORMAT, true, wgpu::CompareFunction::Less)),
            },
        );
        let camera = uniform_buffer(
            device,
            "baselines::gbuffer::camera",
            size_of::<CameraUniform>() as u64,
        );
        Ok(GBufferPass {
            pipeline,
            layout,
            camera,
        })
    }

    /// Records the rasterization of `scene` through `view_proj` into `targets`; depth is
    /// measured along the unit `axis` from `eye`.
    #[allow(clippy::too_many_arguments)]
    pub fn record(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        targets: &ScreenTargets,
        scene: &GpuScene,
        view_proj: Mat4,
        eye: Vec3,
        axis: Vec3,
    ) {
        let cam = CameraUniform {
            view_proj: view_proj.to_cols_array_2d(),
            axis: axis.extend(axis.dot(eye)).to_array(),
        };
        queue.write_buffer(&self.camera, 0, bytemuck::bytes_of(&cam));
        let bind = bind_group(
            device,
            "baselines::gbuffer::bind",
            &self.layout,
            &[
                self.camera.as_entire_binding(),
                scene.objects.as_entire_binding(),
            ],
        );
        let attach = |view, clear| {
            Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(clear),
                    store: wgpu::StoreOp::Store,
                },
            })
        };
        let sky = wgpu::Color {
            a: f64::from(SKY_DEPTH),
            ..wgpu::Color::TRANSPARENT
        };
        let clear = wgpu::Color::TRANSPARENT;
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("baselines::gbuffer::pass"),
            color_attachments: &[
                attach(&targets.world.view, sky),
                attach(&targets.normal.view, clear),
                attach(&targets.ids.view, clear),
            ],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &targets.depth.view,
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
        if scene.vertex_count == 0 {
            return;
        }
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &bind, &[]);
        pass.set_vertex_buffer(0, scene.vertices.slice(..));
        pass.draw(0..scene.vertex_count, 0..1);
    }
}
