//! Cull: compacts the texels worth drawing into a splat list with indirect draw arguments
//! (`shaders/cull.wgsl`).

use crate::context::GpuContext;
use crate::passes::LazyCompute;
use bytemuck::{Pod, Zeroable};

use super::{
    ARRAY, FLOAT, UINT, bind_group, compute_pipeline, entry, storage, texture, uniform,
    uniform_buffer,
};
use crate::probe_store::ProbeStore;
use crate::shader;
use texel_probes::cube::Face;
use texel_probes::probe_set::Slot;

/// Bytes per splat record (four corners with packed extras).
pub const SPLAT_BYTES: u64 = 64;
/// Most splats one frame may hold (128 MiB of records, the binding limit lavapipe has).
pub const MAX_SPLATS: u64 = (128 << 20) / SPLAT_BYTES;

/// `wgpu`'s indexed indirect arguments (the first five words, which the splat pass's
/// indirect draw reads), then what the cull pass looked at.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct DrawArgs {
    /// Indices per instance (6: two triangles over 4 corners).
    pub index_count: u32,
    /// Splats written by the cull pass.
    pub instance_count: u32,
    /// 0.
    pub first_index: u32,
    /// 0.
    pub base_vertex: i32,
    /// 0.
    pub first_instance: u32,
    /// Texels and run heads the cull pass looked at: every texel of the scanned faces, and
    /// the entries of the listed faces' draw lists (`listed_args` adds them on the GPU).
    pub entries: u32,
}

/// What the cull pass produces: the splat records and the indirect arguments that draw them.
#[derive(Clone, Copy)]
pub struct SplatList<'a> {
    /// The splat records.
    pub splats: &'a wgpu::Buffer,
    /// Indirect draw arguments (`DrawArgs`): the count of `splats` written.
    pub args: &'a wgpu::Buffer,
}

/// The cull pass and the splat list it fills.
pub struct CullPass {
    pipeline: LazyCompute,
    listed_pipeline: LazyCompute,
    listed_args_pipeline: LazyCompute,
    kept_pipeline: LazyCompute,
    kept_args_pipeline: LazyCompute,
    outlined_pipeline: LazyCompute,
    outlined_args_pipeline: LazyCompute,
    /// `listed`'s workgroup counts, sized on the GPU from the draw lists.
    dispatch: wgpu::Buffer,
    dispatch_bind: wgpu::BindGroup,
    /// `kept_quads`'s and `outlined`'s, from the entries `main` and `listed` kept.
    kept_dispatch: wgpu::Buffer,
    kept_dispatch_bind: wgpu::BindGroup,
    outlined_dispatch: wgpu::Buffer,
    outlined_dispatch_bind: wgpu::BindGroup,
    /// Where each listed face's entries start in `listed`'s index space.
    starts: wgpu::Buffer,
    /// The texels and runs `main` and `listed` keep (`Kept` in `cull.wgsl`): two counts,
    /// then an entry per splat the list holds, the plain ones for `kept_quads` from the
    /// front, the outlined ones for `outlined` from the back.
    kept: wgpu::Buffer,
    starts_layout: wgpu::BindGroupLayout,
    /// `starts` and `kept`.
    starts_bind: wgpu::BindGroup,
    layout: wgpu::BindGroupLayout,
    textures_layout: wgpu::BindGroupLayout,
    splats: wgpu::Buffer,
    args: wgpu::Buffer,
    capacity: u64,
    work: wgpu::Buffer,
}

/// `CullWork` in `cull.wgsl`: the drawn (slot, face) pairs, the `count` scanned first, then
/// the `listed` ones.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct CullWork {
    count: u32,
    listed: u32,
    _pad: [u32; 2],
    faces: [[u32; 4]; 18],
}

/// Size of `CullWork` (WGSL `CullWork`).
pub const CULL_WORK_SIZE: usize = size_of::<CullWork>();

/// How the cull pass visits one drawn face.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Visit {
    /// Every texel (the paper schedule; ours with runs off).
    Scan,
    /// The face's draw list (our schedule: run heads, lit eye texels).
    List,
}

impl CullPass {
    /// Builds the pipeline.
    pub fn new(device: &wgpu::Device) -> Result<Self, shader::ShaderError> {
        let module = shader::module(device, "cull.wgsl")?;
        let c = wgpu::ShaderStages::COMPUTE;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("cull::layout"),
            entries: &[
                entry(0, c, uniform(false)),
                entry(1, c, storage(false)),
                entry(2, c, storage(false)),
                entry(3, c, uniform(false)),
            ],
        });
        let one_buffer = |label| {
            device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(label),
                entries: &[entry(0, c, storage(false))],
            })
        };
        let starts_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("cull::starts_layout"),
            entries: &[entry(0, c, storage(false)), entry(1, c, storage(false))],
        });
        let dispatch_layout = one_buffer("cull::dispatch_layout");
        let textures_layout = probe_textures_layout(device, c);
        // The scanning and entry dispatches, and the one-invocation dispatches that size the
        // next (`sizes`: they also bind the dispatch buffer they write).
        let pipeline_for = |name: &str, sizes: bool| {
            let groups = [&layout, &textures_layout, &starts_layout, &dispatch_layout];
            let groups = if sizes { &groups[..] } else { &groups[..3] };
            compute_pipeline(device, &format!("cull::{name}"), &module, name, groups)
        };
        let pipeline = pipeline_for("main", false);
        let listed_pipeline = pipeline_for("listed", false);
        let listed_args_pipeline = pipeline_for("listed_args", true);
        let kept_pipeline = pipeline_for("kept_quads", false);
        let kept_args_pipeline = pipeline_for("kept_args", true);
        let outlined_pipeline = pipeline_for("outlined", false);
        let outlined_args_pipeline = pipeline_for("outlined_args", true);
        let (dispatch, dispatch_bind) =
            super::dispatch_args(device, "cull::dispatch", &dispatch_layout);
        let (kept_dispatch, kept_dispatch_bind) =
            super::dispatch_args(device, "cull::kept_dispatch", &dispatch_layout);
        let (outlined_dispatch, outlined_dispatch_bind) =
            super::dispatch_args(device, "cull::outlined_dispatch", &dispatch_layout);
        let starts = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("cull::starts"),
            size: 4 * 19,
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        });
        let kept = kept_buffer(device, 1024);
        let starts_bind = starts_bind_group(device, &starts_layout, &starts, &kept);
        let args = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("cull::args"),
            size: size_of::<DrawArgs>() as u64,
            usage: wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::INDIRECT
                | wgpu::BufferUsages::COPY_DST
                | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let work = uniform_buffer(device, "cull::work", size_of::<CullWork>() as u64);
        Ok(CullPass {
            work,
            pipeline,
            listed_pipeline,
            listed_args_pipeline,
            kept_pipeline,
            kept_args_pipeline,
            outlined_pipeline,
            outlined_args_pipeline,
            dispatch,
            dispatch_bind,
            kept_dispatch,
            kept_dispatch_bind,
            outlined_dispatch,
            outlined_dispatch_bind,
            starts,
            kept,
            starts_layout,
            starts_bind,
            layout,
            textures_layout,
            splats: splat_buffer(device, 1024),
            args,
            capacity: 1024,
        })
    }

    /// Grows the splat list to hold every texel of three slots of `max_n` (up to
    /// [`MAX_SPLATS`]).
    pub fn ensure_capacity(&mut self, device: &wgpu::Device, max_n: u32) {
        let want = (18 * u64::from(max_n) * u64::from(max_n)).min(MAX_SPLATS);
        if want > self.capacity {
            self.splats = splat_buffer(device, want);
            self.kept = kept_buffer(device, want);
            self.starts_bind =
                starts_bind_group(device, &self.starts_layout, &self.starts, &self.kept);
            self.capacity = want;
        }
    }

    /// The splat list the last [`CullPass::record`] filled.
    pub fn list(&self) -> SplatList<'_> {
        SplatList {
            splats: &self.splats,
            args: &self.args,
        }
    }

    /// Records the cull dispatches over the drawn faces, `(slot, face)` pairs, each visited
    /// as `visit` says; returns the splat list they fill.
    pub fn record(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        view: &wgpu::Buffer,
        store: &ProbeStore,
        max_n: u32,
        drawn: &[(Slot, Face, Visit)],
    ) -> SplatList<'_> {
        let (device, queue) = (&ctx.device, &ctx.queue);
        let drawn = &drawn[..drawn.len().min(18)];
        let mut work = CullWork::zeroed();
        let scanned = drawn.iter().filter(|d| d.2 == Visit::Scan);
        let listed = drawn.iter().filter(|d| d.2 == Visit::List);
        work.count = scanned.clone().count() as u32;
        work.listed = drawn.len() as u32 - work.count;
        for (i, (slot, face, _)) in scanned.chain(listed).enumerate() {
            work.faces[i] = [slot.index() as u32, face.index() as u32, 0, 0];
        }
        queue.write_buffer(&self.work, 0, bytemuck::bytes_of(&work));
        let scanned_texels: u32 = (drawn.iter())
            .filter(|d| d.2 == Visit::Scan)
            .map(|d| store.slot(d.0).n.pow(2))
            .sum();
        let reset = DrawArgs {
            index_count: 6,
            instance_count: 0,
            first_index: 0,
            base_vertex: 0,
            first_instance: 0,
            entries: scanned_texels,
        };
        queue.write_buffer(&self.args, 0, bytemuck::bytes_of(&reset));
        queue.write_buffer(&self.kept, 0, &[0; 8]);
        let bind = bind_group(
            device,
            "cull::bind",
            &self.layout,
            &[
                view.as_entire_binding(),
                self.splats.as_entire_binding(),
                self.args.as_entire_binding(),
                self.work.as_entire_binding(),
            ],
        );
        let textures = probe_textures_bind_group(device, &self.textures_layout, store);
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("cull::pass"),
            timestamp_writes: None,
        });
        pass.set_bind_group(0, &bind, &[]);
        pass.set_bind_group(1, &textures, &[]);
        pass.set_bind_group(2, &self.starts_bind, &[]);
        if work.count > 0 {
            pass.set_pipeline(self.pipeline.get());
            let groups = max_n.div_ceil(8);
            pass.dispatch_workgroups(groups, groups, work.count);
        }
        if work.listed > 0 {
            pass.set_pipeline(self.listed_args_pipeline.get());
            pass.set_bind_group(3, &self.dispatch_bind, &[]);
            pass.dispatch_workgroups(1, 1, 1);
            pass.set_pipeline(self.listed_pipeline.get());
            pass.dispatch_workgroups_indirect(&self.dispatch, 0);
        }
        if !drawn.is_empty() {
            // The texels and runs the scan and the lists kept: plain, then outlined.
            pass.set_pipeline(self.kept_args_pipeline.get());
            pass.set_bind_group(3, &self.kept_dispatch_bind, &[]);
            pass.dispatch_workgroups(1, 1, 1);
            pass.set_pipeline(self.kept_pipeline.get());
            pass.dispatch_workgroups_indirect(&self.kept_dispatch, 0);
            pass.set_pipeline(self.outlined_args_pipeline.get());
            pass.set_bind_group(3, &self.outlined_dispatch_bind, &[]);
            pass.dispatch_workgroups(1, 1, 1);
            pass.set_pipeline(self.outlined_pipeline.get());
            pass.dispatch_workgroups_indirect(&self.outlined_dispatch, 0);
        }
        drop(pass);
        self.list()
    }
}

/// The entries `main` and `listed` keep for `kept_quads` and `outlined`: two counts, then
/// one 8-byte entry per splat the list holds (each draws at least one).
fn kept_buffer(device: &wgpu::Device, count: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("cull::kept"),
        size: 8 + 8 * count,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

fn starts_bind_group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    starts: &wgpu::Buffer,
    kept: &wgpu::Buffer,
) -> wgpu::BindGroup {
    bind_group(
        device,
        "cull::starts_bind",
        layout,
        &[starts.as_entire_binding(), kept.as_entire_binding()],
    )
}

fn splat_buffer(device: &wgpu::Device, count: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("cull::splats"),
        size: count * SPLAT_BYTES,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    })
}

/// Geo, ids, lit and runs of the three slots, bindings 0–11, and their draw lists, 12–14
/// (`cull.wgsl` group 1).
pub fn probe_textures_layout(
    device: &wgpu::Device,
    stages: wgpu::ShaderStages,
) -> wgpu::BindGroupLayout {
    let mut entries = Vec::new();
    for (kind, sample) in [(0, FLOAT), (1, UINT), (2, FLOAT), (3, UINT)] {
        for s in 0..3 {
            entries.push(entry(kind * 3 + s, stages, texture(sample, ARRAY)));
        }
    }
    for s in 0..3 {
        entries.push(entry(12 + s, stages, storage(true)));
    }
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("cull::probe_textures"),
        entries: &entries,
    })
}

/// The bind group of [`probe_textures_layout`].
pub fn probe_textures_bind_group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    store: &ProbeStore,
) -> wgpu::BindGroup {
    // Binding `kind · 3 + slot`: geo, ids, lit, runs, each for the three slots in order.
    let mut resources = Vec::new();
    for kind in 0..4 {
        for slot in Slot::ALL {
            let t = store.slot(slot);
            let view = match kind {
                0 => &t.geo.array_view,
                1 => &t.ids.array_view,
                2 => &t.lit.array_view,
                _ => &t.runs.array_view,
            };
            resources.push(wgpu::BindingResource::TextureView(view));
        }
    }
    for slot in Slot::ALL {
        resources.push(store.slot(slot).list.as_entire_binding());
    }
    bind_group(device, "cull::probe_textures", layout, &resources)
}
