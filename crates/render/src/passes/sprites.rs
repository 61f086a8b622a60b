//! Sprites: one instance per sprite expanded to a quad in the vertex stage
//! (`shaders/sprites.wgsl`), drawn into the frame after the splats and the moving objects.
//! Turned toward the grid probe's origin (and, during a crossfade, a second copy toward the
//! previous probe's, the two splitting the pixels with the splats' Bayer pattern), or toward
//! the camera in [`SpriteFacing::Camera`]. Nothing to do, and nothing bound, without sprites.

use bytemuck::{Pod, Zeroable};

use super::cull::{probe_textures_bind_group, probe_textures_layout};
use super::shade::{Sun, gpu_suns};
use super::splat::{KEY_FORMAT, SPLAT_DEPTH_FORMAT};
use super::{ARRAY, FLOAT, RenderSpec, bind_group, entry, storage, texture, uniform};
use crate::context::GpuContext;
use crate::gpu_scene::{GpuScene, MAX_SUNS};
use crate::input::{Look, SpriteFacing};
use crate::probe_store::ProbeStore;
use crate::shader;

/// `SpriteGlobals` in `shaders/sprites.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct SpriteGlobals {
    suns: [Sun; MAX_SUNS],
    ambient: [f32; 4],
    sun_count: u32,
    point_count: u32,
    bands: u32,
    facing: u32,
    key_base: u32,
    count: u32,
    _pad: [u32; 2],
}

/// The sprite pass.
pub struct SpritePass {
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
    slots_layout: wgpu::BindGroupLayout,
    bvh_layout: wgpu::BindGroupLayout,
    globals: wgpu::Buffer,
    /// What sprites turn toward.
    pub facing: SpriteFacing,
}

/// What one frame's draw binds.
pub struct SpriteBinds {
    scene: wgpu::BindGroup,
    slots: wgpu::BindGroup,
    bvh: wgpu::BindGroup,
    instances: u32,
}

impl SpritePass {
    /// Builds the pipeline for a `colour` target (with the frame's key target and splat
    /// depth).
    pub fn new(
        device: &wgpu::Device,
        colour: wgpu::TextureFormat,
    ) -> Result<Self, shader::ShaderError> {
        let module = shader::module(device, "sprites.wgsl")?;
        let vf = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let frag = wgpu::ShaderStages::FRAGMENT;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sprites::layout"),
            entries: &[
                entry(0, vf, uniform(false)),
                entry(1, vf, storage(true)),
                entry(2, frag, texture(FLOAT, ARRAY)),
                entry(3, vf, uniform(false)),
                entry(4, frag, storage(true)),
            ],
        });
        let slots_layout = probe_textures_layout(device, frag);
        let bvh_layout = crate::passes::bvh_layout(device, "sprites::bvh_layout", frag);
        let layouts = [&layout, &slots_layout, &bvh_layout];
        let spec = RenderSpec {
            owner: "sprites",
            module: &module,
            vertex: "vs",
            layouts: &layouts,
            vertex_buffers: &[],
            fragment: "fs",
            targets: &[colour, KEY_FORMAT],
            depth: Some((SPLAT_DEPTH_FORMAT, true, wgpu::CompareFunction::Greater)),
        };
        let pipeline = super::strip_pipeline(device, spec);
        let globals = super::uniform_buffer(
            device,
            "sprites::globals",
            size_of::<SpriteGlobals>() as u64,
        );
        Ok(SpritePass {
            pipeline,
            layout,
            slots_layout,
            bvh_layout,
            globals,
            facing: SpriteFacing::Probe,
        })
    }

    /// Writes the lights of `scene` and `look` and binds what the draw reads, with the view
    /// globals `view`; `None` when the scene has no sprites.
    pub fn prepare(
        &self,
        ctx: &GpuContext,
        view: &wgpu::Buffer,
        scene: &GpuScene,
        store: &ProbeStore,
        look: &Look,
        fading: bool,
    ) -> Option<SpriteBinds> {
        let sprites = scene.sprites.as_ref()?;
        let (suns, sun_count) = gpu_suns(scene);
        let count = sprites.len();
        let globals = SpriteGlobals {
            suns,
            ambient: look.ambient.extend(0.0).to_array(),
            sun_count,
            point_count: scene.point_count,
            bands: look.bands,
            facing: u32::from(self.facing == SpriteFacing::Camera),
            key_base: scene.sprite_key_base(),
            count,
            _pad: [0; 2],
        };
        ctx.queue
            .write_buffer(&self.globals, 0, bytemuck::bytes_of(&globals));
        let device = &ctx.device;
        let scene_bind = bind_group(
            device,
            "sprites::scene",
            &self.layout,
            &[
                view.as_entire_binding(),
                sprites.records.as_entire_binding(),
                wgpu::BindingResource::TextureView(&sprites.frames_view),
                self.globals.as_entire_binding(),
                scene.points.as_entire_binding(),
            ],
        );
        let slots = probe_textures_bind_group(device, &self.slots_layout, store);
        let bvh = bind_group(
            device,
            "sprites::bvh",
            &self.bvh_layout,
            &scene.bvh_resources(),
        );
        // The previous probe's copies only while a crossfade runs toward the probes.
        let copies = if fading && self.facing == SpriteFacing::Probe {
            2
        } else {
            1
        };
        Some(SpriteBinds {
            scene: scene_bind,
            slots,
            bvh,
            instances: count * copies,
        })
    }

    /// Draws the sprites into `pass` (the frame's colour, key and depth targets).
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>, binds: &SpriteBinds) {
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &binds.scene, &[]);
        pass.set_bind_group(1, &binds.slots, &[]);
        pass.set_bind_group(2, &binds.bvh, &[]);
        pass.draw(0..4, 0..binds.instances);
    }
}
