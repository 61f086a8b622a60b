//! Screen shade (`shaders/screen_shade.wgsl`): lights a screen G-buffer once per pixel with
//! the texel shade pass's lighting, posterization and outline rule, so the baselines differ
//! from texel splatting only in where colours are computed, never in how (haze included).

use crate::context::GpuContext;
use crate::passes::LazyCompute;
use crate::passes::{bind_group, compute_pipeline, storage_texture, uniform_buffer};
use bytemuck::{Pod, Zeroable};
use glam::Vec3;

use super::gbuffer::{LIT_FORMAT, ScreenTargets};
use crate::gpu_scene::{GpuScene, MAX_SUNS};
use crate::input::Look;
use crate::passes::shade::{Sun, gpu_suns};
use crate::passes::{FLOAT, UINT, entry, storage, texture, uniform};
use crate::shader;

/// `ScreenGlobals` in `shaders/screen_shade.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct ScreenGlobals {
    suns: [Sun; MAX_SUNS],
    ambient: [f32; 4],
    sky: [f32; 4],
    eye: [f32; 4],
    axis: [f32; 4],
    sun_count: u32,
    point_count: u32,
    bands: u32,
    outlines: u32,
    size: [u32; 2],
    haze: f32,
    _pad: u32,
}

/// Where the shaded image is seen from (outlines compare how much neighbours face the eye).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Eye {
    /// Camera position.
    pub position: Vec3,
    /// Unit view axis.
    pub axis: Vec3,
    /// Whether the camera is orthographic (every ray is `axis`).
    pub ortho: bool,
    /// Whether outlines are drawn (the low-resolution methods; not the plain raster).
    pub outlines: bool,
}

/// The screen shade pass.
pub struct ScreenShadePass {
    pipeline: LazyCompute,
    layout: wgpu::BindGroupLayout,
    bvh_layout: wgpu::BindGroupLayout,
    globals: wgpu::Buffer,
}

impl ScreenShadePass {
    /// Builds the pipeline.
    pub fn new(device: &wgpu::Device) -> Result<Self, shader::ShaderError> {
        let module = shader::module(device, "screen_shade.wgsl")?;
        let c = wgpu::ShaderStages::COMPUTE;
        let d2 = wgpu::TextureViewDimension::D2;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("baselines::shade::layout"),
            entries: &[
                entry(0, c, uniform(false)),
                entry(1, c, texture(FLOAT, d2)),
                entry(2, c, texture(FLOAT, d2)),
                entry(3, c, texture(UINT, d2)),
                entry(
                    4,
                    c,
                    storage_texture(wgpu::StorageTextureAccess::WriteOnly, LIT_FORMAT, d2),
                ),
                entry(5, c, storage(true)),
                entry(6, c, storage(true)),
            ],
        });
        let bvh_layout = crate::passes::bvh_layout(device, "baselines::shade::bvh_layout", c);
        let layouts = [&layout, &bvh_layout];
        let pipeline = compute_pipeline(device, "baselines::shade", &module, "main", &layouts);
        let globals = uniform_buffer(
            device,
            "baselines::shade::globals",
            size_of::<ScreenGlobals>() as u64,
        );
        Ok(ScreenShadePass {
            pipeline,
            layout,
            bvh_layout,
            globals,
        })
    }

    /// Records the shading of every pixel of `targets` into `targets.lit`, with screen-space
    /// outlines when `outlines`. Returns the number of pixels shaded.
    pub fn record(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        targets: &ScreenTargets,
        scene: &GpuScene,
        look: &Look,
        eye: Eye,
    ) -> u64 {
        let (device, queue) = (&ctx.device, &ctx.queue);
        let (suns, sun_count) = gpu_suns(scene);
        let g = ScreenGlobals {
            suns,
            ambient: look.ambient.extend(1.0).to_array(),
            sky: look.sky.extend(1.0).to_array(),
            eye: eye
                .position
                .extend(f32::from(u8::from(eye.ortho)))
                .to_array(),
            axis: eye.axis.extend(0.0).to_array(),
            sun_count,
            point_count: scene.point_count,
            // The same floor as the shade pass.
            bands: look.bands.max(2),
            outlines: u32::from(eye.outlines),
            size: targets.size.to_array(),
            haze: look.haze.max(0.0),
            _pad: 0,
        };
        queue.write_buffer(&self.globals, 0, bytemuck::bytes_of(&g));
        let tex = wgpu::BindingResource::TextureView;
        let bind = bind_group(
            device,
            "baselines::shade::bind",
            &self.layout,
            &[
                self.globals.as_entire_binding(),
                tex(&targets.world.view),
                tex(&targets.normal.view),
                tex(&targets.ids.view),
                tex(&targets.lit.view),
                scene.objects.as_entire_binding(),
                scene.points.as_entire_binding(),
            ],
        );
        let bvh = bind_group(
            device,
            "baselines::shade::bvh",
            &self.bvh_layout,
            &scene.bvh_resources(),
        );
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("baselines::shade::pass"),
            timestamp_writes: None,
        });
        pass.set_pipeline(self.pipeline.get());
        pass.set_bind_group(0, &bind, &[]);
        pass.set_bind_group(1, &bvh, &[]);
        pass.dispatch_workgroups(targets.size.x.div_ceil(8), targets.size.y.div_ceil(8), 1);
        u64::from(targets.size.x) * u64::from(targets.size.y)
    }
}
