//! Runs: after shading, groups each stable face's texels into row (then column) runs that
//! one splat quad can draw (`shaders/runs.wgsl`), and lists the run heads for the cull pass,
//! which then emits one quad per run instead of one per texel. Runs are cached with the
//! shading: only faces lit this frame are redone.

use crate::context::GpuContext;
use crate::passes::LazyCompute;
use bytemuck::{Pod, Zeroable};

use super::{
    ARRAY, FLOAT, UINT, UNIFORM_STRIDE, bind_group, compute_pipeline, entry, storage,
    storage_texture, texture, uniform_buffer,
};
use crate::probe_store::{ProbeStore, RUNS_FORMAT};
use crate::shader;
use texel_probes::cube::FaceMask;
use texel_probes::probe_set::Slot;

/// Texels per row segment one thread scans (`SEGMENT` in `runs.wgsl`): the longest run.
pub const SEGMENT: u32 = 16;

/// `RunsFaces` in `runs.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct RunsFaces {
    n: u32,
    face_mask: u32,
    slot: u32,
    _pad: u32,
}

/// Size of `RunsFaces` (WGSL `RunsFaces`).
pub const RUNS_FACES_SIZE: usize = size_of::<RunsFaces>();

/// The runs pass.
pub struct RunsPass {
    rows: LazyCompute,
    columns: LazyCompute,
    layout: wgpu::BindGroupLayout,
    faces: wgpu::Buffer,
}

impl RunsPass {
    /// Builds the pipeline.
    pub fn new(device: &wgpu::Device) -> Result<Self, shader::ShaderError> {
        let module = shader::module(device, "runs.wgsl")?;
        let c = wgpu::ShaderStages::COMPUTE;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("runs::layout"),
            entries: &[
                entry(0, c, super::uniform(true)),
                entry(1, c, texture(FLOAT, ARRAY)),
                entry(2, c, texture(UINT, ARRAY)),
                entry(3, c, texture(FLOAT, ARRAY)),
                entry(
                    4,
                    c,
                    storage_texture(wgpu::StorageTextureAccess::ReadWrite, RUNS_FORMAT, ARRAY),
                ),
                entry(5, c, storage(false)),
            ],
        });
        let rows = compute_pipeline(device, "runs::rows", &module, "rows", &[&layout]);
        let columns = compute_pipeline(device, "runs::columns", &module, "columns", &[&layout]);
        let faces = uniform_buffer(
            device,
            "runs::faces",
            UNIFORM_STRIDE * Slot::ALL.len() as u64,
        );
        Ok(RunsPass {
            rows,
            columns,
            layout,
            faces,
        })
    }

    /// Recomputes the runs of `faces` in each slot (indexed by [`Slot::index`]).
    pub fn record(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        store: &ProbeStore,
        faces: [FaceMask; 3],
    ) {
        let (device, queue) = (&ctx.device, &ctx.queue);
        if faces.iter().all(|m| m.is_empty()) {
            return;
        }
        let mut bytes = vec![0u8; UNIFORM_STRIDE as usize * Slot::ALL.len()];
        for slot in Slot::ALL {
            let r = RunsFaces {
                n: store.slot(slot).n,
                face_mask: u32::from(faces[slot.index()].bits()),
                slot: slot.index() as u32,
                _pad: 0,
            };
            let at = slot.index() * UNIFORM_STRIDE as usize;
            bytes[at..at + RUNS_FACES_SIZE].copy_from_slice(bytemuck::bytes_of(&r));
        }
        queue.write_buffer(&self.faces, 0, &bytes);
        for slot in Slot::ALL {
            store.clear_lists(queue, slot, faces[slot.index()]);
        }
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("runs::pass"),
            timestamp_writes: None,
        });
        for slot in Slot::ALL {
            if faces[slot.index()].is_empty() {
                continue;
            }
            let t = store.slot(slot);
            let uniform = wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                buffer: &self.faces,
                offset: 0,
                size: wgpu::BufferSize::new(RUNS_FACES_SIZE as u64),
            });
            let tex = wgpu::BindingResource::TextureView;
            let bind = bind_group(
                device,
                "runs::bind",
                &self.layout,
                &[
                    uniform,
                    tex(&t.geo.array_view),
                    tex(&t.ids.array_view),
                    tex(&t.lit.array_view),
                    tex(&t.runs.array_view),
                    t.list.as_entire_binding(),
                ],
            );
            let offset = (slot.index() as u64 * UNIFORM_STRIDE) as u32;
            pass.set_bind_group(0, &bind, &[offset]);
            let groups = (t.n.div_ceil(SEGMENT) * t.n).div_ceil(64);
            for pipeline in [&self.rows, &self.columns] {
                pass.set_pipeline(pipeline.get());
                pass.dispatch_workgroups(groups, 1, 6);
            }
        }
    }
}
