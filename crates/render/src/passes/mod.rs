//! The render passes, one module and one WGSL file each. Each pass owns its pipeline and
//! layouts, built once (pipelines compiled on first use: [`LazyCompute`], [`LazyRender`]);
//! `frame.rs` is the only place that orders them.

use std::sync::OnceLock;

use crate::pipeline_cache;

pub mod background;
pub mod bloom;
pub mod capture;
pub mod cull;
pub mod lines;
pub mod march;
pub mod moving;
pub mod occlusion;
pub mod present;
pub mod raster;
pub mod runs;
pub mod shade;
pub mod splat;
pub mod sprites;
pub mod terrain_splat;
pub mod visible;

/// Stride of per-face uniform records addressed with dynamic offsets.
pub const UNIFORM_STRIDE: u64 = 256;

/// A bind group layout entry visible to `stages`.
pub(crate) fn entry(
    binding: u32,
    stages: wgpu::ShaderStages,
    ty: wgpu::BindingType,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: stages,
        ty,
        count: None,
    }
}

/// A uniform buffer binding (optionally with a dynamic offset).
pub(crate) fn uniform(dynamic: bool) -> wgpu::BindingType {
    wgpu::BindingType::Buffer {
        ty: wgpu::BufferBindingType::Uniform,
        has_dynamic_offset: dynamic,
        min_binding_size: None,
    }
}

/// A storage buffer binding.
pub(crate) fn storage(read_only: bool) -> wgpu::BindingType {
    wgpu::BindingType::Buffer {
        ty: wgpu::BufferBindingType::Storage { read_only },
        has_dynamic_offset: false,
        min_binding_size: None,
    }
}

/// A `texture_2d_array` (or `texture_2d`) binding of `sample` type, read with textureLoad.
pub(crate) fn texture(
    sample: wgpu::TextureSampleType,
    dim: wgpu::TextureViewDimension,
) -> wgpu::BindingType {
    wgpu::BindingType::Texture {
        sample_type: sample,
        view_dimension: dim,
        multisampled: false,
    }
}

/// A uniform buffer of `size` bytes the CPU writes (`queue.write_buffer`).
pub(crate) fn uniform_buffer(device: &wgpu::Device, label: &str, size: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// A storage texture binding of `format` with `access`.
pub(crate) fn storage_texture(
    access: wgpu::StorageTextureAccess,
    format: wgpu::TextureFormat,
    dim: wgpu::TextureViewDimension,
) -> wgpu::BindingType {
    wgpu::BindingType::StorageTexture {
        access,
        format,
        view_dimension: dim,
    }
}

/// Unfilterable float sample type (textureLoad only).
pub(crate) const FLOAT: wgpu::TextureSampleType =
    wgpu::TextureSampleType::Float { filterable: false };
/// Unsigned integer sample type.
pub(crate) const UINT: wgpu::TextureSampleType = wgpu::TextureSampleType::Uint;
/// 2D array views.
pub(crate) const ARRAY: wgpu::TextureViewDimension = wgpu::TextureViewDimension::D2Array;

/// What distinguishes one render pipeline from another here; the rest (triangle lists, no
/// blending, one sample, no multiview) is the same for every pass.
pub(crate) struct RenderSpec<'a> {
    /// Owner, for labels (`"splat"` → `"splat::pipeline"`).
    pub owner: &'a str,
    /// The shader module.
    pub module: &'a wgpu::ShaderModule,
    /// Vertex entry point.
    pub vertex: &'a str,
    /// Bind group layouts, group 0 first.
    pub layouts: &'a [&'a wgpu::BindGroupLayout],
    /// Vertex buffers (none for vertex pulling and fullscreen triangles).
    pub vertex_buffers: &'a [Option<wgpu::VertexBufferLayout<'a>>],
    /// Fragment entry point.
    pub fragment: &'a str,
    /// Colour target formats, location 0 first.
    pub targets: &'a [wgpu::TextureFormat],
    /// Depth format, whether to write depth, and the compare function.
    pub depth: Option<(wgpu::TextureFormat, bool, wgpu::CompareFunction)>,
}

/// A pipeline layout over `layouts`, labelled after `owner`.
pub(crate) fn pipeline_layout(
    device: &wgpu::Device,
    owner: &str,
    layouts: &[&wgpu::BindGroupLayout],
) -> wgpu::PipelineLayout {
    let layouts: Vec<Option<&wgpu::BindGroupLayout>> = layouts.iter().map(|l| Some(*l)).collect();
    device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(&format!("{owner}::pipeline_layout")),
        bind_group_layouts: &layouts,
        immediate_size: 0,
    })
}

/// The render pipeline of `spec`, compiled when first used ([`LazyRender::get`]).
pub(crate) fn render_pipeline(device: &wgpu::Device, spec: RenderSpec<'_>) -> LazyRender {
    let writes = vec![(None, wgpu::ColorWrites::ALL); spec.targets.len()];
    pipeline_of(device, spec, &writes, wgpu::PrimitiveTopology::TriangleList)
}

/// The render pipeline of `spec` drawing 4-vertex triangle strips (one quad per instance).
pub(crate) fn strip_pipeline(device: &wgpu::Device, spec: RenderSpec<'_>) -> LazyRender {
    let writes = vec![(None, wgpu::ColorWrites::ALL); spec.targets.len()];
    pipeline_of(
        device,
        spec,
        &writes,
        wgpu::PrimitiveTopology::TriangleStrip,
    )
}

/// The render pipeline of `spec` drawing line lists, with each colour target's blend and
/// write mask (`writes[i]` for `spec.targets[i]`).
pub(crate) fn line_pipeline(
    device: &wgpu::Device,
    spec: RenderSpec<'_>,
    writes: &[(Option<wgpu::BlendState>, wgpu::ColorWrites)],
) -> LazyRender {
    pipeline_of(device, spec, writes, wgpu::PrimitiveTopology::LineList)
}

fn pipeline_of(
    device: &wgpu::Device,
    spec: RenderSpec<'_>,
    writes: &[(Option<wgpu::BlendState>, wgpu::ColorWrites)],
    topology: wgpu::PrimitiveTopology,
) -> LazyRender {
    let targets = (spec.targets.iter().zip(writes))
        .map(|(&format, &(blend, write_mask))| {
            Some(wgpu::ColorTargetState {
                format,
                blend,
                write_mask,
            })
        })
        .collect();
    let vertex_buffers = (spec.vertex_buffers.iter())
        .map(|buffer| {
            buffer.as_ref().map(|b| VertexBuffer {
                stride: b.array_stride,
                step_mode: b.step_mode,
                attributes: b.attributes.to_vec(),
            })
        })
        .collect();
    LazyRender {
        device: device.clone(),
        cache: pipeline_cache::current(),
        layout: pipeline_layout(device, spec.owner, spec.layouts),
        module: spec.module.clone(),
        label: format!("{}::pipeline", spec.owner),
        vertex: spec.vertex.to_owned(),
        fragment: spec.fragment.to_owned(),
        vertex_buffers,
        targets,
        depth: spec
            .depth
            .map(|(format, write, compare)| wgpu::DepthStencilState {
                format,
                depth_write_enabled: Some(write),
                depth_compare: Some(compare),
                stencil: Default::default(),
                bias: Default::default(),
            }),
        topology,
        pipeline: OnceLock::new(),
    }
}

/// A vertex buffer's layout, owned.
struct VertexBuffer {
    stride: wgpu::BufferAddress,
    step_mode: wgpu::VertexStepMode,
    attributes: Vec<wgpu::VertexAttribute>,
}

/// A render pipeline compiled on its first use, as [`LazyCompute`] is: the moving parts',
/// sprites' and baselines' pipelines cost nothing where nothing draws them.
pub(crate) struct LazyRender {
    device: wgpu::Device,
    /// The cache of the context the pass was built for ([`pipeline_cache::building`]).
    cache: Option<pipeline_cache::PipelineCache>,
    layout: wgpu::PipelineLayout,
    module: wgpu::ShaderModule,
    label: String,
    vertex: String,
    fragment: String,
    vertex_buffers: Vec<Option<VertexBuffer>>,
    targets: Vec<Option<wgpu::ColorTargetState>>,
    depth: Option<wgpu::DepthStencilState>,
    topology: wgpu::PrimitiveTopology,
    pipeline: OnceLock<wgpu::RenderPipeline>,
}

impl LazyRender {
    /// The pipeline, compiled now if this is its first use.
    /// Another renderer's on the same device when it compiled the same one
    /// ([`crate::pipeline_cache`]).
    pub(crate) fn get(&self) -> &wgpu::RenderPipeline {
        self.pipeline.get_or_init(|| {
            let compile = || timed_compile(&self.label, &self.vertex, || self.compile());
            match &self.cache {
                Some(cache) => cache.render(&self.module, self.key(), compile),
                None => compile(),
            }
        })
    }

    /// What tells this pipeline from another on the same module: everything but the layout.
    fn key(&self) -> String {
        let buffers: Vec<_> = (self.vertex_buffers.iter())
            .map(|b| b.as_ref().map(|b| (b.stride, b.step_mode, &b.attributes)))
            .collect();
        format!(
            "{}|{}|{}|{:?}|{:?}|{:?}|{buffers:?}",
            self.label, self.vertex, self.fragment, self.targets, self.depth, self.topology
        )
    }

    fn compile(&self) -> wgpu::RenderPipeline {
        let buffers: Vec<Option<wgpu::VertexBufferLayout<'_>>> = (self.vertex_buffers.iter())
            .map(|buffer| {
                buffer.as_ref().map(|b| wgpu::VertexBufferLayout {
                    array_stride: b.stride,
                    step_mode: b.step_mode,
                    attributes: &b.attributes,
                })
            })
            .collect();
        (self.device).create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(&self.label),
            layout: Some(&self.layout),
            vertex: wgpu::VertexState {
                module: &self.module,
                entry_point: Some(&self.vertex),
                compilation_options: Default::default(),
                buffers: &buffers,
            },
            fragment: Some(wgpu::FragmentState {
                module: &self.module,
                entry_point: Some(&self.fragment),
                compilation_options: Default::default(),
                targets: &self.targets,
            }),
            primitive: wgpu::PrimitiveState {
                topology: self.topology,
                ..Default::default()
            },
            depth_stencil: self.depth.clone(),
            multisample: Default::default(),
            multiview_mask: None,
            cache: None,
        })
    }
}

/// Runs `compile`; with `TEXEL_PIPELINE_TIMES` set, prints what it compiled and how long
/// that took (where a first frame's time goes on a driver that compiles slowly).
fn timed_compile<T>(label: &str, entry: &str, compile: impl FnOnce() -> T) -> T {
    if std::env::var_os("TEXEL_PIPELINE_TIMES").is_none() {
        return compile();
    }
    let start = std::time::Instant::now();
    let pipeline = compile();
    let ms = start.elapsed().as_secs_f64() * 1e3;
    eprintln!("pipeline {label} ({entry}) compiled in {ms:.1} ms");
    pipeline
}

/// The compute pipeline of `entry` in `module`, compiled when first used
/// ([`LazyCompute::get`]).
pub(crate) fn compute_pipeline(
    device: &wgpu::Device,
    owner: &str,
    module: &wgpu::ShaderModule,
    entry: &str,
    layouts: &[&wgpu::BindGroupLayout],
) -> LazyCompute {
    LazyCompute {
        device: device.clone(),
        cache: pipeline_cache::current(),
        layout: pipeline_layout(device, owner, layouts),
        module: module.clone(),
        label: format!("{owner}::pipeline"),
        entry: entry.to_owned(),
        pipeline: OnceLock::new(),
    }
}

/// A compute pipeline compiled on its first use, so that a renderer pays only for the
/// pipelines its scenes and schedules dispatch: the terrain's when there is a terrain, the
/// paper schedule's when it runs. Compiling all of them took 1.9 s on lavapipe and 10-12 s
/// on SwiftShader (`cargo run -p texel_render --example startup_cost`); the shader modules
/// are still parsed and validated up front, so a WGSL error shows when the renderer starts.
pub(crate) struct LazyCompute {
    device: wgpu::Device,
    /// The cache of the context the pass was built for ([`pipeline_cache::building`]).
    cache: Option<pipeline_cache::PipelineCache>,
    layout: wgpu::PipelineLayout,
    module: wgpu::ShaderModule,
    label: String,
    entry: String,
    pipeline: OnceLock<wgpu::ComputePipeline>,
}

impl LazyCompute {
    /// The pipeline, compiled now if this is its first use.
    /// Another renderer's on the same device when it compiled the same one
    /// ([`crate::pipeline_cache`]).
    pub(crate) fn get(&self) -> &wgpu::ComputePipeline {
        self.pipeline.get_or_init(|| {
            let compile = || {
                timed_compile(&self.label, &self.entry, || {
                    (self.device).create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                        label: Some(&self.label),
                        layout: Some(&self.layout),
                        module: &self.module,
                        entry_point: Some(&self.entry),
                        compilation_options: Default::default(),
                        cache: None,
                    })
                })
            };
            match &self.cache {
                Some(cache) => {
                    let key = format!("{}|{}", self.label, self.entry);
                    cache.compute(&self.module, key, compile)
                }
                None => compile(),
            }
        })
    }
}

/// A bind group binding `resources[i]` at binding `i`.
/// An indirect dispatch's arguments (x, y, z workgroups) that a compute stage writes: the
/// buffer and its bind group in `layout`, which holds it at binding 0.
pub(crate) fn dispatch_args(
    device: &wgpu::Device,
    label: &str,
    layout: &wgpu::BindGroupLayout,
) -> (wgpu::Buffer, wgpu::BindGroup) {
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: 12,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::INDIRECT,
        mapped_at_creation: false,
    });
    let bind = bind_group(device, label, layout, &[buffer.as_entire_binding()]);
    (buffer, bind)
}

pub(crate) fn bind_group(
    device: &wgpu::Device,
    label: &str,
    layout: &wgpu::BindGroupLayout,
    resources: &[wgpu::BindingResource<'_>],
) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry<'_>> = resources
        .iter()
        .enumerate()
        .map(|(i, r)| wgpu::BindGroupEntry {
            binding: i as u32,
            resource: r.clone(),
        })
        .collect();
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout,
        entries: &entries,
    })
}

/// The layout of the shadow BVH group every ray-tracing pass binds (`lib/bvh.wgsl`: nodes,
/// triangles, animated instances, the terrains' field records and data;
/// [`crate::gpu_scene::GpuScene::bvh_resources`]), visible to `stages`.
pub(crate) fn bvh_layout(
    device: &wgpu::Device,
    label: &str,
    stages: wgpu::ShaderStages,
) -> wgpu::BindGroupLayout {
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some(label),
        entries: &[
            entry(0, stages, storage(true)),
            entry(1, stages, storage(true)),
            entry(2, stages, storage(true)),
            entry(3, stages, uniform(false)),
            entry(4, stages, texture(FLOAT, ARRAY)),
        ],
    })
}
