//! The baselines' G-buffer pass (`shaders/gbuffer.wgsl`): rasterizes the scene from a camera
//! into screen-sized targets (world position and view-axis depth, normal, object index with
//! packed albedo). The low-resolution methods shade it per pixel; at full resolution it is the
//! evaluator's reference G-buffer.

use crate::context::GpuContext;
use crate::passes::LazyRender;
use crate::passes::bind_group;
use crate::passes::raster::{self, RasterDraw, RasterTargets};
use crate::passes::uniform_buffer;
use bytemuck::{Pod, Zeroable};
use glam::{Mat4, UVec2, Vec3};

use crate::gpu_scene::GpuScene;
use crate::passes::{entry, uniform};
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
pub use crate::passes::raster::DEPTH_FORMAT;

pub use texel_geom::limits::SKY_DEPTH;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct CameraUniform {
    view_proj: [[f32; 4]; 4],
    axis: [f32; 4],
    inv_view_proj: [[f32; 4]; 4],
    size: [f32; 4],
    eye: [f32; 4],
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

/// What the G-buffer sees: `view_proj` for the raster; depth is measured along the unit
/// `axis` from `eye`.
#[derive(Debug, Clone, Copy)]
pub struct RasterCamera {
    /// World → clip.
    pub view_proj: Mat4,
    /// The eye.
    pub eye: Vec3,
    /// Unit view axis.
    pub axis: Vec3,
    /// Whether the camera is orthographic (terrain pixels then take no distance bands, as
    /// under an orthographic probe).
    pub ortho: bool,
    /// The point sprites turn toward, and the face resolution their matched size and
    /// snapping follow (the reference: the frame's grid probe; a baseline: its camera).
    pub sprite_eye: (Vec3, u32),
}

/// `SpriteCamera` in `shaders/gbuffer_sprites.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct SpriteCamera {
    view_proj: [[f32; 4]; 4],
    axis: [f32; 4],
    eye: [f32; 4],
    key_base: u32,
    _pad: [u32; 3],
}

/// The sprites' part of the G-buffer.
struct SpriteRaster {
    pipeline: LazyRender,
    layout: wgpu::BindGroupLayout,
    camera: wgpu::Buffer,
}

/// The G-buffer pass.
pub struct GBufferPass {
    pipeline: LazyRender,
    layout: wgpu::BindGroupLayout,
    camera: wgpu::Buffer,
    sprites: SpriteRaster,
}

impl GBufferPass {
    /// Builds the pipeline.
    pub fn new(device: &wgpu::Device) -> Result<Self, shader::ShaderError> {
        let module = shader::module(device, "gbuffer.wgsl")?;
        let vf = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("baselines::gbuffer::layout"),
            entries: &[
                [entry(0, vf, uniform(false))].as_slice(),
                &raster::scene_layout_entries(),
                &[entry(
                    7,
                    wgpu::ShaderStages::VERTEX,
                    crate::passes::storage(true),
                )],
            ]
            .concat(),
        });
        let targets = [WORLD_FORMAT, NORMAL_FORMAT, ID_FORMAT];
        let pipeline = raster::pipeline(device, "baselines::gbuffer", &module, &layout, &targets);
        let camera = uniform_buffer(
            device,
            "baselines::gbuffer::camera",
            size_of::<CameraUniform>() as u64,
        );
        let sprites = SpriteRaster::new(device, &targets)?;
        Ok(GBufferPass {
            pipeline,
            layout,
            camera,
            sprites,
        })
    }

    /// Records the rasterization of `scene` seen by `camera` into `targets`.
    pub fn record(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        targets: &ScreenTargets,
        scene: &GpuScene,
        camera: &RasterCamera,
    ) {
        let (device, queue) = (&ctx.device, &ctx.queue);
        let RasterCamera {
            view_proj,
            eye,
            axis,
            ortho,
            sprite_eye,
        } = *camera;
        let cam = CameraUniform {
            view_proj: view_proj.to_cols_array_2d(),
            axis: axis.extend(axis.dot(eye)).to_array(),
            inv_view_proj: view_proj.inverse().to_cols_array_2d(),
            size: [
                targets.size.x as f32,
                targets.size.y as f32,
                f32::from(u8::from(ortho)),
                0.0,
            ],
            eye: eye.extend(1.0).to_array(),
        };
        queue.write_buffer(&self.camera, 0, bytemuck::bytes_of(&cam));
        let bind = bind_group(
            device,
            "baselines::gbuffer::bind",
            &self.layout,
            &std::iter::once(self.camera.as_entire_binding())
                .chain(scene.raster_resources())
                .chain([scene.motions.as_entire_binding()])
                .collect::<Vec<_>>(),
        );
        let clear = wgpu::Color::TRANSPARENT;
        let colour = [
            (&targets.world.view, raster::SKY_CLEAR),
            (&targets.normal.view, clear),
            (&targets.ids.view, clear),
        ];
        let targets = RasterTargets {
            colour: &colour,
            depth: &targets.depth.view,
            // The sprites are drawn against it in a second pass.
            keep_depth: scene.sprites.is_some(),
            load: false,
        };
        // Terrains at full detail, no culling (a G-buffer is one view, drawn once).
        // Animated objects too, where their motion records put them.
        let mut runs = crate::gpu_scene::full_detail_runs(&scene.ranges);
        runs.extend(
            scene
                .animated_runs()
                .map(|(first, count)| (first, count, 0)),
        );
        let draw = RasterDraw {
            pipeline: self.pipeline.get(),
            bind: &bind,
            offsets: &[],
            scissor: None,
            runs: Some(&runs),
            first: None,
        };
        raster::record(encoder, "baselines::gbuffer::pass", &targets, scene, &draw);
        let Some(sprites) = &scene.sprites else {
            return;
        };
        let cam = SpriteCamera {
            view_proj: view_proj.to_cols_array_2d(),
            axis: axis.extend(axis.dot(eye)).to_array(),
            eye: sprite_eye.0.extend(sprite_eye.1 as f32).to_array(),
            key_base: scene.sprite_key_base(),
            _pad: [0; 3],
        };
        let r = &self.sprites;
        queue.write_buffer(&r.camera, 0, bytemuck::bytes_of(&cam));
        let bind = bind_group(
            device,
            "baselines::gbuffer::sprites",
            &r.layout,
            &[
                r.camera.as_entire_binding(),
                sprites.records.as_entire_binding(),
                wgpu::BindingResource::TextureView(&sprites.frames_view),
            ],
        );
        let load = |view| {
            Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                },
            })
        };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("baselines::gbuffer::sprites"),
            color_attachments: &colour.map(|(v, _)| load(v)),
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: targets.depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(r.pipeline.get());
        pass.set_bind_group(0, &bind, &[]);
        pass.draw(0..4, 0..sprites.len());
    }
}

impl SpriteRaster {
    fn new(
        device: &wgpu::Device,
        targets: &[wgpu::TextureFormat],
    ) -> Result<Self, shader::ShaderError> {
        let module = shader::module(device, "gbuffer_sprites.wgsl")?;
        let vf = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("baselines::gbuffer::sprites_layout"),
            entries: &[
                entry(0, vf, uniform(false)),
                entry(1, vf, crate::passes::storage(true)),
                entry(
                    2,
                    wgpu::ShaderStages::FRAGMENT,
                    crate::passes::texture(crate::passes::FLOAT, crate::passes::ARRAY),
                ),
            ],
        });
        let pipeline = crate::passes::strip_pipeline(
            device,
            crate::passes::RenderSpec {
                owner: "baselines::gbuffer::sprites",
                module: &module,
                vertex: "vs",
                layouts: &[&layout],
                vertex_buffers: &[],
                fragment: "fs",
                targets,
                depth: Some((DEPTH_FORMAT, true, wgpu::CompareFunction::Less)),
            },
        );
        let camera = uniform_buffer(
            device,
            "baselines::gbuffer::sprite_camera",
            size_of::<SpriteCamera>() as u64,
        );
        Ok(SpriteRaster {
            pipeline,
            layout,
            camera,
        })
    }
}
