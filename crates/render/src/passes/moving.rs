//! Moving: draws the animated objects straight into the frame after the splats, their pixels
//! cut on a grid fixed to each object and lit at the cells' centres where the objects are now
//! (`shaders/moving.wgsl`). Nothing to do, and nothing bound, in a scene without them.

use crate::passes::LazyRender;
use bytemuck::{Pod, Zeroable};

use super::shade::{Sun, gpu_suns};
use super::splat::{KEY_FORMAT, SPLAT_DEPTH_FORMAT};
use super::{RenderSpec, bind_group, entry, raster, render_pipeline, storage, uniform};
use crate::context::GpuContext;
use crate::gpu_scene::{GpuScene, MAX_SUNS};
use crate::input::Look;
use crate::shader;

/// `LightGlobals` in `shaders/moving.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct LightGlobals {
    suns: [Sun; MAX_SUNS],
    ambient: [f32; 4],
    sun_count: u32,
    point_count: u32,
    bands: u32,
    _pad: u32,
}

/// The moving pass.
pub struct MovingPass {
    pipeline: LazyRender,
    scene_layout: wgpu::BindGroupLayout,
    light_layout: wgpu::BindGroupLayout,
    bvh_layout: wgpu::BindGroupLayout,
    globals: wgpu::Buffer,
}

/// What one frame's draw binds.
pub struct MovingBinds {
    scene: wgpu::BindGroup,
    light: wgpu::BindGroup,
    bvh: wgpu::BindGroup,
}

impl MovingPass {
    /// Builds the pipeline for a `colour` target (with the frame's key target and splat
    /// depth).
    pub fn new(
        device: &wgpu::Device,
        colour: wgpu::TextureFormat,
    ) -> Result<Self, shader::ShaderError> {
        let module = shader::module(device, "moving.wgsl")?;
        let vf = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let frag = wgpu::ShaderStages::FRAGMENT;
        let scene_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("moving::scene_layout"),
            // The scene raster's objects, atlas, texture records and surfaces; not the
            // terrains (animated objects never are), which keeps the fragment stage within
            // the default limit of 8 storage buffers.
            entries: &[
                [entry(0, vf, uniform(false))].as_slice(),
                &raster::scene_layout_entries()[..4],
            ]
            .concat(),
        });
        let light_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("moving::light_layout"),
            entries: &[
                entry(0, frag, uniform(false)),
                entry(1, frag, storage(true)),
                entry(2, vf, storage(true)),
            ],
        });
        let bvh_layout = crate::passes::bvh_layout(device, "moving::bvh_layout", frag);
        let vertex_buffers = [Some(GpuScene::vertex_layout())];
        let pipeline = render_pipeline(
            device,
            RenderSpec {
                owner: "moving",
                module: &module,
                vertex: "vs",
                layouts: &[&scene_layout, &light_layout, &bvh_layout],
                vertex_buffers: &vertex_buffers,
                fragment: "fs",
                targets: &[colour, KEY_FORMAT],
                depth: Some((SPLAT_DEPTH_FORMAT, true, wgpu::CompareFunction::Greater)),
            },
        );
        let globals =
            super::uniform_buffer(device, "moving::globals", size_of::<LightGlobals>() as u64);
        Ok(MovingPass {
            pipeline,
            scene_layout,
            light_layout,
            bvh_layout,
            globals,
        })
    }

    /// Writes the lights of `scene` and `look` and binds what the draw reads, with the view
    /// globals `view`; `None` when the scene has no animated objects.
    pub fn prepare(
        &self,
        ctx: &GpuContext,
        view: &wgpu::Buffer,
        scene: &GpuScene,
        look: &Look,
    ) -> Option<MovingBinds> {
        if scene.animated.is_empty() {
            return None;
        }
        let (suns, sun_count) = gpu_suns(scene);
        let globals = LightGlobals {
            suns,
            ambient: look.ambient.extend(0.0).to_array(),
            sun_count,
            point_count: scene.point_count,
            bands: look.bands,
            _pad: 0,
        };
        ctx.queue
            .write_buffer(&self.globals, 0, bytemuck::bytes_of(&globals));
        let device = &ctx.device;
        let scene_bind = bind_group(
            device,
            "moving::scene",
            &self.scene_layout,
            &std::iter::once(view.as_entire_binding())
                .chain(scene.raster_resources().into_iter().take(4))
                .collect::<Vec<_>>(),
        );
        let light = bind_group(
            device,
            "moving::light",
            &self.light_layout,
            &[
                self.globals.as_entire_binding(),
                scene.points.as_entire_binding(),
                scene.motions.as_entire_binding(),
            ],
        );
        let bvh = bind_group(
            device,
            "moving::bvh",
            &self.bvh_layout,
            &scene.bvh_resources(),
        );
        Some(MovingBinds {
            scene: scene_bind,
            light,
            bvh,
        })
    }

    /// Draws every animated object of `scene` into `pass` (the frame's colour, key and depth
    /// targets, after the splats).
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>, binds: &MovingBinds, scene: &GpuScene) {
        pass.set_pipeline(self.pipeline.get());
        pass.set_bind_group(0, &binds.scene, &[]);
        pass.set_bind_group(1, &binds.light, &[]);
        pass.set_bind_group(2, &binds.bvh, &[]);
        pass.set_vertex_buffer(0, scene.vertices.slice(..));
        for (first, count) in scene.animated_runs() {
            pass.draw(first..first + count, 0..1);
        }
    }
}
