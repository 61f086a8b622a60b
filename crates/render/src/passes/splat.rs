//! Splat: draws the culled texels as indexed, instanced world-space quads (`shaders/splat.wgsl`).

use crate::context::GpuContext;
use crate::passes::LazyRender;
use crate::passes::cull::SplatList;
use wgpu::util::DeviceExt;

use super::{RenderSpec, bind_group, entry, render_pipeline, storage, uniform};
use crate::shader;

/// Format of the per-pixel texel-key target (0 = no texel).
pub const KEY_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;
/// Format of the splat depth buffer. Its depth is reversed (1 at the near plane, 0 at the far
/// one: `ViewGlobals`' projection), so nearer fragments pass `Greater`.
pub const SPLAT_DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// How grid and previous share the pixels this frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Fade {
    /// No crossfade: no discard, so the depth test runs before the fragment shader.
    None = 0,
    /// Complementary Bayer patterns.
    Dither = 1,
    /// Bayer patterns, and the previous probe keeps the pixels whose grid face is not
    /// captured yet (the fragment stage then needs the world point).
    DitherPartial = 2,
}

/// The splat pass.
pub struct SplatPass {
    /// By (runs, [`Fade`]): quads that may span runs write each pixel's own texel key.
    pipelines: [[LazyRender; 3]; 2],
    layout: wgpu::BindGroupLayout,
    indices: wgpu::Buffer,
}

impl SplatPass {
    /// Builds the pipeline for a `colour` target.
    pub fn new(
        device: &wgpu::Device,
        colour: wgpu::TextureFormat,
    ) -> Result<Self, shader::ShaderError> {
        let module = shader::module(device, "splat.wgsl")?;
        let vf = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("splat::layout"),
            entries: &[
                entry(0, vf, uniform(false)),
                entry(1, vf, storage(true)),
                entry(2, wgpu::ShaderStages::VERTEX, storage(true)),
            ],
        });
        let pipeline_for = |vertex, fragment| {
            render_pipeline(
                device,
                RenderSpec {
                    owner: "splat",
                    module: &module,
                    vertex,
                    layouts: &[&layout],
                    vertex_buffers: &[],
                    fragment,
                    targets: &[colour, KEY_FORMAT],
                    depth: Some((SPLAT_DEPTH_FORMAT, true, wgpu::CompareFunction::Greater)),
                },
            )
        };
        let pipelines = [
            [
                pipeline_for("vs_texel", "fs_texel"),
                pipeline_for("vs_texel_fade", "fs_texel_dither"),
                pipeline_for("vs_texel_fade", "fs_texel_dither_partial"),
            ],
            [
                pipeline_for("vs", "fs"),
                pipeline_for("vs_fade", "fs_dither"),
                pipeline_for("vs_fade", "fs_dither_partial"),
            ],
        ];
        let indices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("splat::indices"),
            contents: bytemuck::cast_slice(&[0u16, 1, 2, 0, 2, 3]),
            usage: wgpu::BufferUsages::INDEX,
        });
        Ok(SplatPass {
            pipelines,
            layout,
            indices,
        })
    }

    /// The bind group: the view globals, the splat list and what its terrain quads show
    /// (`terrain`: [`crate::passes::terrain_splat::TerrainSplatPass::records`]).
    pub fn bind_group(
        &self,
        ctx: &GpuContext,
        view: &wgpu::Buffer,
        list: SplatList<'_>,
        terrain: &wgpu::Buffer,
    ) -> wgpu::BindGroup {
        let resources = [
            view.as_entire_binding(),
            list.splats.as_entire_binding(),
            terrain.as_entire_binding(),
        ];
        bind_group(&ctx.device, "splat::bind", &self.layout, &resources)
    }

    /// Draws the cull pass's `list` (`bind` from [`SplatPass::bind_group`] over it); `runs`
    /// when some quads may span several texels; `fade` how grid and previous share the
    /// pixels.
    pub fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        bind: &wgpu::BindGroup,
        list: SplatList<'_>,
        runs: bool,
        fade: Fade,
    ) {
        pass.set_pipeline(self.pipelines[usize::from(runs)][fade as usize].get());
        pass.set_bind_group(0, bind, &[]);
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint16);
        pass.draw_indexed_indirect(list.args, 0);
    }

    /// Binds every pipeline once for one quad past any list (the vertex stage puts it
    /// outside the clip volume: nothing is drawn), so that a driver that compiles shaders
    /// on their first draw (lavapipe builds its fragment variants then) does so now rather
    /// than on the first frame of the first crossfade. Measured on walk_cells at 1280×720,
    /// faces of 128: that frame's splat 12–17 ms, against 5–6 ms on the fade's next frame
    /// with the same quads.
    pub fn warm_up(&self, pass: &mut wgpu::RenderPass<'_>, bind: &wgpu::BindGroup) {
        pass.set_bind_group(0, bind, &[]);
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint16);
        for pipeline in self.pipelines.iter().flatten() {
            pass.set_pipeline(pipeline.get());
            pass.draw_indexed(0..6, 0, u32::MAX - 1..u32::MAX);
        }
    }
}
