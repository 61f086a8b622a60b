//! Background: the eye probe (or the sky) behind every pixel (`shaders/background.wgsl`),
//! after a compute step that works out once per eye texel what its outline strips need
//! (`strip_ends`: where they start, and the colour's OKLab lightness a band darker and
//! lighter), which the fullscreen draw reads per pixel.

use super::{
    ARRAY, FLOAT, LazyCompute, RenderSpec, UINT, bind_group, compute_pipeline, entry,
    render_pipeline, storage_texture, texture, uniform,
};
use crate::context::GpuContext;
use crate::passes::LazyRender;
use crate::passes::splat::{KEY_FORMAT, SPLAT_DEPTH_FORMAT};
use crate::probe_store::{LayeredTexture, SlotTextures};
use crate::shader;

/// Each eye texel's strip starts (left, right, up, down: `background.wgsl` `strip_starts`)
/// and its colour in OKLab, posterized two ways (`strip_lab`): f32, so the pixels come out
/// as when the fill worked them out itself.
const STRIPS_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

/// The background pass.
pub struct BackgroundPass {
    pipeline: LazyRender,
    layout: wgpu::BindGroupLayout,
    ends_pipeline: LazyCompute,
    ends_layout: wgpu::BindGroupLayout,
    /// The eye's strip starts and OKLab colours, for faces of its size (made on first use).
    strips: Option<(u32, [LayeredTexture; 2])>,
}

/// The bind groups of a frame's background ([`BackgroundPass::bind_group`]).
pub struct BackgroundBinds {
    draw: wgpu::BindGroup,
    ends: wgpu::BindGroup,
    /// Texels per eye face edge.
    n: u32,
}

impl BackgroundPass {
    /// Builds the pipeline for a `colour` target.
    pub fn new(
        device: &wgpu::Device,
        colour: wgpu::TextureFormat,
    ) -> Result<Self, shader::ShaderError> {
        let module = shader::module(device, "background.wgsl")?;
        let f = wgpu::ShaderStages::FRAGMENT;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("background::layout"),
            entries: &[
                entry(0, wgpu::ShaderStages::VERTEX_FRAGMENT, uniform(false)),
                entry(1, f, texture(UINT, ARRAY)),
                entry(2, f, texture(FLOAT, ARRAY)),
                entry(3, f, texture(FLOAT, ARRAY)),
                entry(4, f, texture(FLOAT, ARRAY)),
                entry(5, f, texture(FLOAT, ARRAY)),
            ],
        });
        let c = wgpu::ShaderStages::COMPUTE;
        let write = wgpu::StorageTextureAccess::WriteOnly;
        let ends_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("background::ends_layout"),
            entries: &[
                entry(0, c, uniform(false)),
                entry(2, c, texture(FLOAT, ARRAY)),
                entry(3, c, texture(FLOAT, ARRAY)),
                entry(6, c, storage_texture(write, STRIPS_FORMAT, ARRAY)),
                entry(7, c, storage_texture(write, STRIPS_FORMAT, ARRAY)),
            ],
        });
        let ends_pipeline = compute_pipeline(
            device,
            "background::ends",
            &module,
            "strip_ends",
            &[&ends_layout],
        );
        let pipeline = render_pipeline(
            device,
            RenderSpec {
                owner: "background",
                module: &module,
                vertex: "vs",
                layouts: &[&layout],
                vertex_buffers: &[],
                fragment: "fs",
                targets: &[colour, KEY_FORMAT],
                // At the eye's surface, pushed back: where no splat wrote depth, or where the
                // splat lies behind what the eye sees (see background.wgsl).
                depth: Some((
                    SPLAT_DEPTH_FORMAT,
                    false,
                    wgpu::CompareFunction::GreaterEqual,
                )),
            },
        );
        Ok(BackgroundPass {
            pipeline,
            layout,
            ends_pipeline,
            ends_layout,
            strips: None,
        })
    }

    /// The bind groups over the view globals and the eye slot (faces of `eye.n` texels),
    /// and the strips' textures made for that size.
    pub fn bind_group(
        &mut self,
        ctx: &GpuContext,
        view: &wgpu::Buffer,
        eye: &SlotTextures,
    ) -> BackgroundBinds {
        if self.strips.as_ref().is_none_or(|(n, _)| *n != eye.n) {
            use wgpu::TextureUsages as U;
            let usage = U::STORAGE_BINDING | U::TEXTURE_BINDING;
            let made = ["background::starts", "background::lab"]
                .map(|label| LayeredTexture::new(ctx, label, eye.n, STRIPS_FORMAT, usage));
            self.strips = Some((eye.n, made));
        }
        let [starts, lab] = &self.strips.as_ref().expect("made above").1;
        let (starts, lab) = (&starts.array_view, &lab.array_view);
        let view_of = wgpu::BindingResource::TextureView;
        let draw = bind_group(
            &ctx.device,
            "background::bind",
            &self.layout,
            &[
                view.as_entire_binding(),
                view_of(&eye.ids.array_view),
                view_of(&eye.lit.array_view),
                view_of(&eye.geo.array_view),
                view_of(starts),
                view_of(lab),
            ],
        );
        let entries = [
            (0, view.as_entire_binding()),
            (2, view_of(&eye.lit.array_view)),
            (3, view_of(&eye.geo.array_view)),
            (6, view_of(starts)),
            (7, view_of(lab)),
        ];
        let entries: Vec<wgpu::BindGroupEntry<'_>> = (entries.into_iter())
            .map(|(binding, resource)| wgpu::BindGroupEntry { binding, resource })
            .collect();
        let ends = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("background::ends_bind"),
            layout: &self.ends_layout,
            entries: &entries,
        });
        BackgroundBinds {
            draw,
            ends,
            n: eye.n,
        }
    }

    /// Works out the strips of every texel of the `faces` faces the eye draws (before
    /// [`BackgroundPass::draw`], outside its render pass).
    pub fn strip_ends(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        binds: &BackgroundBinds,
        faces: u32,
    ) {
        if faces == 0 {
            return;
        }
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("background::ends"),
            timestamp_writes: None,
        });
        pass.set_pipeline(self.ends_pipeline.get());
        pass.set_bind_group(0, &binds.ends, &[]);
        let groups = binds.n.div_ceil(8);
        pass.dispatch_workgroups(groups, groups, faces);
    }

    /// Draws the fullscreen triangle.
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>, binds: &BackgroundBinds) {
        pass.set_pipeline(self.pipeline.get());
        pass.set_bind_group(0, &binds.draw, &[]);
        pass.draw(0..3, 0..1);
    }

    /// GPU bytes of the strips' textures.
    pub fn bytes(&self) -> u64 {
        (self.strips.iter().flat_map(|(_, t)| t))
            .map(|t| crate::memory::texture_bytes(&t.texture))
            .sum()
    }
}
