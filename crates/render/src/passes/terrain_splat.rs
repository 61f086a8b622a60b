//! Terrain splats: what each one-texel terrain quad of the cull pass's list shows, pixel by
//! pixel (`shaders/terrain_splat.wgsl`), written between cull and splat.

use crate::context::GpuContext;
use crate::gpu_scene::GpuScene;
use crate::passes::cull::{MAX_SPLATS, SPLAT_BYTES, SplatList};
use crate::shader;

use super::{ARRAY, FLOAT, bind_group, compute_pipeline, entry, storage, texture, uniform};

/// Bytes of one record (`TerrainSplat` in `shaders/lib/view.wgsl`): four packed colours, the
/// pixels' grid, the terrain's plane.
pub const RECORD_BYTES: u64 = 48;
/// Invocations per workgroup of `main`.
const GROUP: u64 = 64;
const _: () = assert!(MAX_SPLATS.div_ceil(GROUP) <= 65535);

/// The terrain splat pass.
pub struct TerrainSplatPass {
    pipeline: wgpu::ComputePipeline,
    size_pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    /// `size`'s group 0: only the splats and their count.
    size_layout: wgpu::BindGroupLayout,
    dispatch: wgpu::Buffer,
    dispatch_bind: wgpu::BindGroup,
    records: wgpu::Buffer,
}

fn record_buffer(device: &wgpu::Device, splats: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("terrain_splat::records"),
        size: splats.max(1) * RECORD_BYTES,
        usage: wgpu::BufferUsages::STORAGE,
        mapped_at_creation: false,
    })
}

impl TerrainSplatPass {
    /// Builds the pipelines.
    pub fn new(device: &wgpu::Device) -> Result<Self, shader::ShaderError> {
        let module = shader::module(device, "terrain_splat.wgsl")?;
        let c = wgpu::ShaderStages::COMPUTE;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("terrain_splat::layout"),
            entries: &[
                entry(0, c, uniform(false)),
                entry(1, c, storage(true)),
                entry(2, c, texture(FLOAT, ARRAY)),
                entry(3, c, storage(true)),
                entry(5, c, storage(true)),
                entry(6, c, storage(true)),
                entry(7, c, uniform(false)),
                entry(8, c, storage(true)),
                entry(9, c, storage(true)),
                entry(10, c, storage(true)),
                entry(11, c, storage(false)),
            ],
        });
        let size_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("terrain_splat::size_layout"),
            entries: &[entry(9, c, storage(true)), entry(10, c, storage(true))],
        });
        let dispatch_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("terrain_splat::dispatch_layout"),
            entries: &[entry(0, c, storage(false))],
        });
        let pipeline = compute_pipeline(device, "terrain_splat", &module, "main", &[&layout]);
        let size_pipeline = compute_pipeline(
            device,
            "terrain_splat::size",
            &module,
            "size",
            &[&size_layout, &dispatch_layout],
        );
        let dispatch = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("terrain_splat::dispatch"),
            size: 12,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::INDIRECT,
            mapped_at_creation: false,
        });
        let dispatch_bind = bind_group(
            device,
            "terrain_splat::dispatch_bind",
            &dispatch_layout,
            &[dispatch.as_entire_binding()],
        );
        Ok(TerrainSplatPass {
            pipeline,
            size_pipeline,
            layout,
            size_layout,
            dispatch,
            dispatch_bind,
            records: record_buffer(device, 1),
        })
    }

    /// One record per splat `list` can hold (written for its terrain quads only).
    pub fn records(&self) -> &wgpu::Buffer {
        &self.records
    }

    /// Records the pass over `list`, lit with the shade pass's `shade_globals`; grows the
    /// records to the list's capacity first.
    pub fn record(
        &mut self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        view: &wgpu::Buffer,
        scene: &GpuScene,
        shade_globals: &wgpu::Buffer,
        list: SplatList<'_>,
    ) {
        let splats = list.splats.size() / SPLAT_BYTES;
        if self.records.size() < splats * RECORD_BYTES {
            self.records = record_buffer(&ctx.device, splats);
        }
        let [objects, atlas, infos, _surfaces, terrains, terrain_data] = scene.raster_resources();
        // Bindings as `lib/texture.wgsl` and `lib/terrain.wgsl` number them, less the
        // surfaces (binding 4), which no terrain reads.
        let resources = [
            (0, view.as_entire_binding()),
            (1, objects),
            (2, atlas),
            (3, infos),
            (5, terrains),
            (6, terrain_data),
            (7, shade_globals.as_entire_binding()),
            (8, scene.points.as_entire_binding()),
            (9, list.splats.as_entire_binding()),
            (10, list.args.as_entire_binding()),
            (11, self.records.as_entire_binding()),
        ];
        let entries =
            resources.map(|(binding, resource)| wgpu::BindGroupEntry { binding, resource });
        let bind = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("terrain_splat::bind"),
            layout: &self.layout,
            entries: &entries,
        });
        let size_bind = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("terrain_splat::size_bind"),
            layout: &self.size_layout,
            entries: &entries[8..10],
        });
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("terrain_splat"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&self.size_pipeline);
        pass.set_bind_group(0, &size_bind, &[]);
        pass.set_bind_group(1, &self.dispatch_bind, &[]);
        pass.dispatch_workgroups(1, 1, 1);
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &bind, &[]);
        pass.dispatch_workgroups_indirect(&self.dispatch, 0);
    }
}
