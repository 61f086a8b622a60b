//! The scene raster that capture and the reference G-buffer share (`lib/raster.wgsl` on the
//! WGSL side): one pipeline shape over the scene's vertex buffer, and one recorded pass that
//! clears the targets and draws every scene triangle.

use crate::passes::LazyRender;
use texel_probes::visibility::TexelRect;

use super::{RenderSpec, render_pipeline};
use crate::gpu_scene::GpuScene;

/// Depth format of every scene raster: the probes' capture depth
/// ([`crate::probe_store::DEPTH_FORMAT`]).
pub use crate::probe_store::DEPTH_FORMAT;

/// A scene-raster pipeline (entry points `vs`, `fs`) writing `targets`. Both sides of each
/// triangle are drawn (default primitive state): a cube face's projection flips Y (and so the
/// winding), and planes are one-sided surfaces that must still occlude from below.
pub(crate) fn pipeline(
    device: &wgpu::Device,
    owner: &str,
    module: &wgpu::ShaderModule,
    layout: &wgpu::BindGroupLayout,
    targets: &[wgpu::TextureFormat],
) -> LazyRender {
    let spec = RasterSpec {
        owner,
        module,
        layout,
        targets,
    };
    let vertices = [GpuScene::vertex_layout(), GpuScene::instance_layout()];
    pipeline_with(device, &spec, ("vs", "fs"), &vertices)
}

/// What every pipeline of one scene raster shares.
pub(crate) struct RasterSpec<'a> {
    pub(crate) owner: &'a str,
    pub(crate) module: &'a wgpu::ShaderModule,
    pub(crate) layout: &'a wgpu::BindGroupLayout,
    pub(crate) targets: &'a [wgpu::TextureFormat],
}

/// A scene-raster pipeline over the entry points `(vertex, fragment)` and the vertex
/// buffers' attributes `vertices` lists (the scene's vertices, then perhaps its instance
/// records: see [`pipeline`]).
pub(crate) fn pipeline_with(
    device: &wgpu::Device,
    spec: &RasterSpec<'_>,
    (vertex, fragment): (&str, &str),
    vertices: &[wgpu::VertexBufferLayout<'_>],
) -> LazyRender {
    let vertex_buffers: Vec<_> = vertices.iter().cloned().map(Some).collect();
    render_pipeline(
        device,
        RenderSpec {
            owner: spec.owner,
            module: spec.module,
            vertex,
            layouts: &[spec.layout],
            vertex_buffers: &vertex_buffers,
            fragment,
            targets: spec.targets,
            depth: Some((DEPTH_FORMAT, true, wgpu::CompareFunction::Less)),
        },
    )
}

/// Layout entries of what every scene raster binds after its own uniform (binding 0):
/// [`GpuScene::raster_resources`], bindings 1..=6.
pub(crate) fn scene_layout_entries() -> [wgpu::BindGroupLayoutEntry; 6] {
    use super::{ARRAY, FLOAT, entry, storage, texture};
    let vf = wgpu::ShaderStages::VERTEX_FRAGMENT;
    [
        entry(1, vf, storage(true)),
        entry(2, vf, texture(FLOAT, ARRAY)),
        entry(3, vf, storage(true)),
        entry(4, vf, storage(true)),
        entry(5, vf, storage(true)),
        entry(6, vf, storage(true)),
    ]
}

/// Where one scene raster draws: colour targets with their clear values, and a depth view.
pub(crate) struct RasterTargets<'a> {
    /// Colour targets, location 0 first, each cleared to its colour.
    pub(crate) colour: &'a [(&'a wgpu::TextureView, wgpu::Color)],
    /// Depth, cleared to 1 (unless `load`) and discarded afterwards unless `keep_depth`.
    pub(crate) depth: &'a wgpu::TextureView,
    /// Keep the depth for a later pass (the G-buffer's sprites); captures discard it.
    pub(crate) keep_depth: bool,
    /// Load the targets (colours and depth) instead of clearing them (an eye face drawn
    /// over its far face: `crate::far_field`).
    pub(crate) load: bool,
}

/// How one scene raster draws: the pipeline, its group-0 bind group with dynamic offsets,
/// and an optional scissor (an empty one draws nothing).
pub(crate) struct RasterDraw<'a> {
    pub(crate) pipeline: &'a wgpu::RenderPipeline,
    pub(crate) bind: &'a wgpu::BindGroup,
    pub(crate) offsets: &'a [u32],
    pub(crate) scissor: Option<TexelRect>,
    /// Draw only these vertex runs `(first, count, instance)` (the ranges the view may
    /// see); `None` draws every range at full detail.
    pub(crate) runs: Option<&'a [crate::gpu_scene::Run]>,
    /// Runs drawn first, with their own pipeline (a capture's plain terrain chunks, whose
    /// vertex stage passes only the point and the object: lavapipe's cost per triangle
    /// grows with the varyings it sets up).
    pub(crate) first: Option<(&'a wgpu::RenderPipeline, &'a [crate::gpu_scene::Run])>,
}

/// Records one render pass that clears `targets` and draws every triangle of `scene`.
pub(crate) fn record(
    encoder: &mut wgpu::CommandEncoder,
    label: &str,
    targets: &RasterTargets<'_>,
    scene: &GpuScene,
    draw: &RasterDraw<'_>,
) {
    let colour: Vec<Option<wgpu::RenderPassColorAttachment<'_>>> = targets
        .colour
        .iter()
        .map(|&(view, clear)| {
            Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: if targets.load {
                        wgpu::LoadOp::Load
                    } else {
                        wgpu::LoadOp::Clear(clear)
                    },
                    store: wgpu::StoreOp::Store,
                },
            })
        })
        .collect();
    let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &colour,
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: targets.depth,
            depth_ops: Some(wgpu::Operations {
                load: if targets.load {
                    wgpu::LoadOp::Load
                } else {
                    wgpu::LoadOp::Clear(1.0)
                },
                store: if targets.keep_depth {
                    wgpu::StoreOp::Store
                } else {
                    wgpu::StoreOp::Discard
                },
            }),
            stencil_ops: None,
        }),
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    });
    if scene.vertex_count == 0 || draw.scissor.is_some_and(|r| r.area() == 0) {
        return;
    }
    if let Some(r) = draw.scissor {
        pass.set_scissor_rect(r.x0, r.y0, r.x1 - r.x0, r.y1 - r.y0);
    }
    pass.set_bind_group(0, draw.bind, draw.offsets);
    pass.set_vertex_buffer(0, scene.vertices.slice(..));
    pass.set_vertex_buffer(1, scene.instances.slice(..));
    if let Some((pipeline, runs)) = draw.first.filter(|(_, runs)| !runs.is_empty()) {
        pass.set_pipeline(pipeline);
        for &(first, count, instance) in runs {
            pass.draw(first..first + count, instance..instance + 1);
        }
    }
    pass.set_pipeline(draw.pipeline);
    match draw.runs {
        Some(runs) => {
            for &(first, count, instance) in runs {
                pass.draw(first..first + count, instance..instance + 1);
            }
        }
        None => {
            for (first, count, instance) in crate::gpu_scene::full_detail_runs(&scene.ranges) {
                pass.draw(first..first + count, instance..instance + 1);
            }
        }
    }
}

/// The clear value of a target storing depth in alpha: [`texel_geom::limits::SKY_DEPTH`].
pub(crate) const SKY_CLEAR: wgpu::Color = wgpu::Color {
    r: 0.0,
    g: 0.0,
    b: 0.0,
    a: texel_geom::limits::SKY_DEPTH as f64,
};
