//! Sprites, in two steps. `shade` (`shaders/sprite_shade.wgsl`, compute): every texel of every
//! sprite in view lit once, for the grid probe's copy and during a crossfade the previous
//! probe's, into [`crate::gpu_sprites::GpuSprites::lit`]. `draw` (`shaders/sprites.wgsl`): one
//! instance per sprite expanded to a quad in the vertex stage, drawn into the frame after the
//! splats and the moving objects, each pixel taking its texel's colour. Turned toward the
//! grid probe's origin (the two copies splitting the pixels with the splats' Bayer pattern),
//! or toward the camera in [`SpriteFacing::Camera`]. Nothing to do, and nothing bound,
//! without sprites.

use crate::passes::LazyCompute;
use crate::passes::LazyRender;
use bytemuck::{Pod, Zeroable};

use super::shade::{Sun, gpu_suns};
use super::splat::{KEY_FORMAT, SPLAT_DEPTH_FORMAT};
use super::{
    ARRAY, FLOAT, RenderSpec, bind_group, compute_pipeline, entry, storage, texture, uniform,
};
use crate::context::GpuContext;
use crate::gpu_scene::{GpuScene, MAX_SUNS};
use crate::input::{Look, SpriteFacing};
use crate::probe_store::ProbeStore;
use crate::shader;
use texel_probes::probe_set::Slot;

/// `SpriteGlobals` in `shaders/lib/sprite_view.wgsl`.
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
    epoch: u32,
    _pad: u32,
}

/// The sprite passes.
pub struct SpritePass {
    shade: LazyCompute,
    shade_layout: wgpu::BindGroupLayout,
    probes_layout: wgpu::BindGroupLayout,
    bvh_layout: wgpu::BindGroupLayout,
    draw: LazyRender,
    draw_layout: wgpu::BindGroupLayout,
    globals: wgpu::Buffer,
    /// What sprites turn toward.
    pub facing: SpriteFacing,
    /// `SpriteGlobals::epoch`.
    epoch: std::cell::Cell<u32>,
}

/// What one frame's shading and drawing bind.
pub struct SpriteBinds {
    shade: wgpu::BindGroup,
    probes: wgpu::BindGroup,
    bvh: wgpu::BindGroup,
    draw: wgpu::BindGroup,
    count: u32,
    copies: u32,
}

impl SpritePass {
    /// Builds the pipelines for a `colour` target (with the frame's key target and splat
    /// depth).
    pub fn new(
        device: &wgpu::Device,
        colour: wgpu::TextureFormat,
    ) -> Result<Self, shader::ShaderError> {
        let c = wgpu::ShaderStages::COMPUTE;
        let vf = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let frag = wgpu::ShaderStages::FRAGMENT;
        let shade_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sprites::shade_layout"),
            entries: &[
                entry(0, c, uniform(false)),
                entry(1, c, storage(true)),
                entry(2, c, texture(FLOAT, ARRAY)),
                entry(3, c, uniform(false)),
                entry(4, c, storage(true)),
                entry(5, c, storage(false)),
                entry(6, c, storage(false)),
            ],
        });
        // The slots' geometry and lit textures only (lib/slots.wgsl bindings 0–2 and 6–8):
        // refraction looks the background up there; the draw lists are not needed.
        let probes_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sprites::probes_layout"),
            entries: &[0, 1, 2, 6, 7, 8].map(|b| entry(b, c, texture(FLOAT, ARRAY))),
        });
        let bvh_layout = crate::passes::bvh_layout(device, "sprites::bvh_layout", c);
        let module = shader::module(device, "sprite_shade.wgsl")?;
        let shade = compute_pipeline(
            device,
            "sprites::shade",
            &module,
            "main",
            &[&shade_layout, &probes_layout, &bvh_layout],
        );
        let draw_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sprites::draw_layout"),
            entries: &[
                entry(0, vf, uniform(false)),
                entry(1, vf, storage(true)),
                entry(2, frag, texture(FLOAT, ARRAY)),
                entry(3, vf, uniform(false)),
                entry(4, frag, storage(true)),
            ],
        });
        let module = shader::module(device, "sprites.wgsl")?;
        let draw = super::strip_pipeline(
            device,
            RenderSpec {
                owner: "sprites",
                module: &module,
                vertex: "vs",
                layouts: &[&draw_layout],
                vertex_buffers: &[],
                fragment: "fs",
                targets: &[colour, KEY_FORMAT],
                depth: Some((SPLAT_DEPTH_FORMAT, true, wgpu::CompareFunction::Greater)),
            },
        );
        let globals = super::uniform_buffer(
            device,
            "sprites::globals",
            size_of::<SpriteGlobals>() as u64,
        );
        Ok(SpritePass {
            shade,
            shade_layout,
            probes_layout,
            bvh_layout,
            draw,
            draw_layout,
            globals,
            facing: SpriteFacing::Probe,
            epoch: std::cell::Cell::new(0),
        })
    }

    /// Writes the lights of `scene` and `look` and binds what the passes read, with the view
    /// globals `view`; `None` when the scene has no sprites. `fading`: a crossfade runs.
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
            epoch: self.epoch.get(),
            _pad: 0,
        };
        // Moving shadows and a camera-facing quad change what the texels show every frame.
        if !scene.animated.is_empty() || self.facing == SpriteFacing::Camera {
            self.epoch.set(self.epoch.get().wrapping_add(1));
        }
        ctx.queue
            .write_buffer(&self.globals, 0, bytemuck::bytes_of(&globals));
        let device = &ctx.device;
        let shade = bind_group(
            device,
            "sprites::shade",
            &self.shade_layout,
            &[
                view.as_entire_binding(),
                sprites.records.as_entire_binding(),
                wgpu::BindingResource::TextureView(&sprites.frames_view),
                self.globals.as_entire_binding(),
                scene.points.as_entire_binding(),
                sprites.lit.as_entire_binding(),
                sprites.lit_keys.as_entire_binding(),
            ],
        );
        let probe_entries: Vec<wgpu::BindGroupEntry<'_>> = [0u32, 1, 2, 6, 7, 8]
            .into_iter()
            .map(|binding| {
                let t = store.slot(Slot::ALL[(binding % 3) as usize]);
                let view = if binding < 3 {
                    &t.geo.array_view
                } else {
                    &t.lit.array_view
                };
                wgpu::BindGroupEntry {
                    binding,
                    resource: wgpu::BindingResource::TextureView(view),
                }
            })
            .collect();
        let probes = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("sprites::probes"),
            layout: &self.probes_layout,
            entries: &probe_entries,
        });
        let bvh = bind_group(
            device,
            "sprites::bvh",
            &self.bvh_layout,
            &scene.bvh_resources(),
        );
        let draw = bind_group(
            device,
            "sprites::draw",
            &self.draw_layout,
            &[
                view.as_entire_binding(),
                sprites.records.as_entire_binding(),
                wgpu::BindingResource::TextureView(&sprites.frames_view),
                self.globals.as_entire_binding(),
                sprites.lit.as_entire_binding(),
            ],
        );
        // The previous probe's copies only while a crossfade runs toward the probes.
        let copies = if fading && self.facing == SpriteFacing::Probe {
            2
        } else {
            1
        };
        Some(SpriteBinds {
            shade,
            probes,
            bvh,
            draw,
            count,
            copies,
        })
    }

    /// Lights the texels of the sprites in view (one workgroup per sprite and copy).
    pub fn shade(&self, encoder: &mut wgpu::CommandEncoder, binds: &SpriteBinds) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("sprites::shade"),
            timestamp_writes: None,
        });
        pass.set_pipeline(self.shade.get());
        pass.set_bind_group(0, &binds.shade, &[]);
        pass.set_bind_group(1, &binds.probes, &[]);
        pass.set_bind_group(2, &binds.bvh, &[]);
        // At most 65535 workgroups per dimension: sprites beyond are spread over z.
        let x = binds.count.min(65_535);
        pass.dispatch_workgroups(x, binds.copies, binds.count.div_ceil(65_535).max(1));
    }

    /// Draws the sprites into `pass` (the frame's colour, key and depth targets).
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>, binds: &SpriteBinds) {
        pass.set_pipeline(self.draw.get());
        pass.set_bind_group(0, &binds.draw, &[]);
        pass.draw(0..4, 0..binds.count * binds.copies);
    }
}
