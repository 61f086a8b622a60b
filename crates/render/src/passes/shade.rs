//! Shade: lights the captured faces, once per texel (`shaders/shade.wgsl`).

use crate::context::GpuContext;
use crate::passes::LazyCompute;
use bytemuck::{Pod, Zeroable};
use glam::Vec3;

use super::{
    ARRAY, FLOAT, UINT, UNIFORM_STRIDE, bind_group, compute_pipeline, entry, storage,
    storage_texture, texture, uniform, uniform_buffer,
};
use crate::gpu_scene::{GpuScene, MAX_SUNS};
use crate::input::{LightFilter, Look};
use crate::passes::capture::MAX_CAPTURES;
use crate::probe_store::{LIT_FORMAT, ProbeStore};
use crate::shader;
use texel_probes::cube::FaceMask;
use texel_probes::probe_set::Slot;
use texel_probes::visibility::TexelRect;

/// Most shade jobs in a frame: every capture plus edge re-shades of up to four neighbours.
pub const MAX_JOBS: usize = MAX_CAPTURES * 3;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct ShadeFace {
    origin: [f32; 3],
    face: u32,
    n: u32,
    view_cull: u32,
    valid_mask: u32,
    job: u32,
    slot: u32,
    _pad: u32,
    rect_min: [u32; 2],
    keep_min: [u32; 2],
    keep_max: [u32; 2],
    /// 0: every texel of the dispatch is lit; else 1 + the filter's boxes.
    boxes: u32,
    /// Bit i: box i holds texels lit again (a light's reach), not casters.
    lit_mask: u32,
    _pad2: [u32; 2],
    /// Box i's min at 2i, its max at 2i + 1.
    box_corners: [[f32; 4]; 2 * LightFilter::MAX_BOXES],
}

impl ShadeFace {
    /// A record carrying `filter` (every texel when `None`), zero elsewhere.
    fn filtered(filter: Option<JobFilter>) -> Self {
        let f = filter.unwrap_or(JobFilter {
            keep: TexelRect {
                x0: 0,
                y0: 0,
                x1: 0,
                y1: 0,
            },
            boxes: 0,
            lit_mask: 0,
            corners: [[0.0; 4]; 2 * LightFilter::MAX_BOXES],
        });
        ShadeFace {
            keep_min: [f.keep.x0, f.keep.y0],
            keep_max: [f.keep.x1, f.keep.y1],
            boxes: if filter.is_some() { f.boxes + 1 } else { 0 },
            lit_mask: f.lit_mask,
            box_corners: f.corners,
            ..Zeroable::zeroed()
        }
    }
}

/// Size of `ShadeFace` (WGSL `ShadeFace`).
pub const SHADE_FACE_SIZE: usize = size_of::<ShadeFace>();

/// One face to light: whole (after a capture) or only its edges (after a neighbour's).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShadeJob {
    /// Slot of the probe.
    pub slot: Slot,
    /// The face.
    pub face: texel_probes::cube::Face,
    /// Probe origin.
    pub origin: glam::Vec3,
    /// Faces of the probe holding data for `origin`.
    pub valid: texel_probes::cube::FaceMask,
    /// Only the four edges.
    pub border: bool,
    /// Only texels the view can see (eye faces in our schedule).
    pub view_cull: bool,
    /// Only these texels (None: the whole face; ignored for borders).
    pub rect: Option<TexelRect>,
    /// Of those, only the texels an edit may have changed (`None`: all).
    pub filter: Option<JobFilter>,
}

/// The texels of a job an edit may have changed ([`crate::input::PartialFace`]): those of
/// `keep`, and the others whose light the boxes of a [`LightFilter`] say may have changed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JobFilter {
    keep: TexelRect,
    boxes: u32,
    lit_mask: u32,
    corners: [[f32; 4]; 2 * LightFilter::MAX_BOXES],
}

impl JobFilter {
    /// Every texel of `keep`, and those `filter` picks.
    pub fn new(keep: TexelRect, filter: &LightFilter) -> Self {
        let mut out = JobFilter {
            keep,
            boxes: 0,
            lit_mask: 0,
            corners: [[0.0; 4]; 2 * LightFilter::MAX_BOXES],
        };
        let boxes = (filter.casters.iter().map(|b| (b, false)))
            .chain(filter.lit.iter().map(|b| (b, true)))
            .take(LightFilter::MAX_BOXES);
        for (i, ((lo, hi), lit)) in boxes.enumerate() {
            out.corners[2 * i] = lo.extend(0.0).to_array();
            out.corners[2 * i + 1] = hi.extend(0.0).to_array();
            out.lit_mask |= u32::from(lit) << i;
            out.boxes += 1;
        }
        out
    }
}

impl ShadeJob {
    /// Columns × rows the job dispatches over on a face of `n` texels.
    fn extent(&self, n: u32) -> (u32, u32) {
        self.rect.map_or((n, n), |r| (r.x1 - r.x0, r.y1 - r.y0))
    }
}

/// What the shade pass reads besides its jobs.
#[derive(Clone, Copy)]
pub struct ShadeInputs<'a> {
    /// The probe textures (captured faces in, lit colours out).
    pub store: &'a ProbeStore,
    /// Lights, objects and the shadow BVH.
    pub scene: &'a GpuScene,
    /// Sky, ambient light and bands.
    pub look: &'a Look,
    /// The frame's view (frustum, stable probes), read by view-culled jobs only; `None`
    /// when no job is view-culled (the cubemap baseline).
    pub view: Option<&'a wgpu::Buffer>,
    /// Whether silhouettes' edges are searched (`shaders/shade.wgsl`, the edge search): our
    /// schedule's splats'; the paper's schedule and the cubemap baseline end every silhouette
    /// half a texel out, as the reference does, and texel marching has no quads to end. A
    /// face lit without them and drawn later by our splats keeps its quads half a texel out
    /// until it is lit again.
    pub edges: bool,
}

/// `Sun` in `shaders/lib/lighting.wgsl`: direction toward the light, colour × intensity.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub(crate) struct Sun {
    to_light: [f32; 4],
    colour: [f32; 4],
}

/// The scene's suns as `lib/lighting.wgsl` reads them, and how many there are.
pub(crate) fn gpu_suns(scene: &GpuScene) -> ([Sun; MAX_SUNS], u32) {
    let mut suns = [Sun::zeroed(); MAX_SUNS];
    for (s, (to_light, colour)) in suns.iter_mut().zip(&scene.suns) {
        s.to_light = to_light.extend(0.0).to_array();
        s.colour = colour.extend(0.0).to_array();
    }
    (suns, scene.suns.len().min(MAX_SUNS) as u32)
}

/// `ShadeGlobals` in `shaders/lib/shade_globals.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct ShadeGlobals {
    suns: [Sun; MAX_SUNS],
    ambient: [f32; 4],
    sky: [f32; 4],
    sun_count: u32,
    point_count: u32,
    bands: u32,
    /// 1: search silhouettes' edges ([`ShadeInputs::edges`]).
    edges: u32,
    queue_base: [u32; 4],
    /// 1: lit texels carry their surface's dither rank ([`ShadePass::dither`]).
    dither: u32,
    /// 1: edge rays walk the still instances from their texel's subtree
    /// ([`ShadePass::edge_roots`]).
    edge_roots: u32,
    _pad: [u32; 2],
}

/// The shade pass.
pub struct ShadePass {
    pipeline: LazyCompute,
    light_pipeline: LazyCompute,
    border_pipeline: LazyCompute,
    layout: wgpu::BindGroupLayout,
    bvh_layout: wgpu::BindGroupLayout,
    stable_layout: wgpu::BindGroupLayout,
    no_view: wgpu::Buffer,
    faces: wgpu::Buffer,
    globals: wgpu::Buffer,
    /// `work` in `shade.wgsl`: first the texels lit this frame (one `u32`, counted on the
    /// GPU), then each slot's queue length, then the queue of texels waiting for `light`.
    work: wgpu::Buffer,
    /// Per slot: `light`'s indirect dispatch arguments (bound for `main` only: a buffer may
    /// not be storage and indirect arguments in one dispatch).
    job_args: wgpu::Buffer,
    args_layout: wgpu::BindGroupLayout,
    /// The globals last written, less what changes with the jobs (see
    /// [`ShadePass::globals_key`]).
    globals_key: ShadeGlobals,
    /// Whether frames are mapped to a dithered palette: lit texels then carry their
    /// surface's dither rank (`lib/common.wgsl` `surface_dither_rank`). Only texels lit from
    /// then on change.
    pub dither: bool,
    /// Whether a texel's edge rays walk the still instances' top level from a subtree that
    /// holds all they may meet (`lib/edge_rays.wgsl` `edge_statics`; on by default, off
    /// under `TEXEL_NO_EDGE_ROOTS`), or from its root (the same frames, to compare against).
    pub edge_roots: bool,
}

/// Bytes of one slot's record in `job_args`: x, y, z workgroups and padding.
const JOB_ARGS_BYTES: u64 = 16;
/// Where the queue starts in `work` (`WORK_QUEUE` in `shade.wgsl`), in `u32`s.
const WORK_QUEUE: u64 = 64;
const _: () = assert!((MAX_JOBS as u64) < WORK_QUEUE);
// A queued texel packs its job in 6 bits (`shade.wgsl`), and `all_faces` holds 54 records.
const _: () = assert!(MAX_JOBS == 54);

impl ShadePass {
    /// Builds the pipeline.
    pub fn new(device: &wgpu::Device) -> Result<Self, shader::ShaderError> {
        let module = shader::module(device, "shade.wgsl")?;
        let c = wgpu::ShaderStages::COMPUTE;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("shade::layout"),
            entries: &[
                entry(0, c, uniform(true)),
                entry(1, c, uniform(false)),
                entry(2, c, texture(FLOAT, ARRAY)),
                entry(3, c, texture(UINT, ARRAY)),
                entry(4, c, texture(FLOAT, ARRAY)),
                entry(
                    5,
                    c,
                    storage_texture(wgpu::StorageTextureAccess::WriteOnly, LIT_FORMAT, ARRAY),
                ),
                entry(6, c, storage(true)),
                entry(7, c, storage(true)),
                entry(8, c, storage(false)),
                entry(9, c, storage(false)),
                entry(10, c, uniform(false)),
                entry(11, c, texture(UINT, ARRAY)),
            ],
        });
        let bvh_layout = crate::passes::bvh_layout(device, "shade::bvh_layout", c);
        let mut stable_entries: Vec<_> = (0..6)
            .map(|b| {
                let sample = if b % 3 == 1 { UINT } else { FLOAT };
                entry(b, c, texture(sample, ARRAY))
            })
            .collect();
        stable_entries.push(entry(6, c, uniform(false)));
        let stable_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("shade::stable_layout"),
            entries: &stable_entries,
        });
        let args_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("shade::args_layout"),
            entries: &[entry(0, c, storage(false))],
        });
        let layouts = [&layout, &bvh_layout, &stable_layout, &args_layout];
        let pipeline = compute_pipeline(device, "shade", &module, "main", &layouts);
        let light_pipeline =
            compute_pipeline(device, "shade::light", &module, "light", &layouts[..3]);
        let border_pipeline =
            compute_pipeline(device, "shade::border", &module, "border", &layouts);
        let buffer = |label, size| uniform_buffer(device, label, size);
        let no_view = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("shade::no_view"),
            size: size_of::<crate::view::ViewGlobals>() as u64,
            usage: wgpu::BufferUsages::UNIFORM,
            mapped_at_creation: false,
        });
        let storage_buffer = |label, size, extra| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::STORAGE | extra,
                mapped_at_creation: false,
            })
        };
        Ok(ShadePass {
            light_pipeline,
            work: work_buffer(device, 0),
            job_args: storage_buffer(
                "shade::job_args",
                JOB_ARGS_BYTES * Slot::ALL.len() as u64,
                wgpu::BufferUsages::INDIRECT | wgpu::BufferUsages::COPY_DST,
            ),
            args_layout,
            no_view,
            stable_layout,
            pipeline,
            border_pipeline,
            layout,
            bvh_layout,
            faces: buffer("shade::faces", UNIFORM_STRIDE * MAX_JOBS as u64),
            globals: buffer("shade::globals", size_of::<ShadeGlobals>() as u64),
            globals_key: ShadeGlobals::zeroed(),
            dither: false,
            edge_roots: std::env::var_os("TEXEL_NO_EDGE_ROOTS").is_none(),
        })
    }

    /// Records the shade jobs (view-culled jobs read the frame's view: its frustum and the
    /// stable probes) and returns, per slot ([`Slot::index`]), the stable faces they light
    /// (whole or at their edges).
    pub fn record(
        &mut self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        jobs: &[ShadeJob],
        inputs: &ShadeInputs<'_>,
    ) -> [FaceMask; 3] {
        let mut stable = [FaceMask::EMPTY; 3];
        for j in jobs.iter().filter(|j| j.slot != Slot::Eye) {
            stable[j.slot.index()].insert(j.face);
        }
        self.dispatch(ctx, encoder, jobs, inputs);
        stable
    }

    /// Its first `u32` counts the texels the last [`ShadePass::record`] lit, on the GPU.
    pub fn texels_lit(&self) -> &wgpu::Buffer {
        &self.work
    }

    /// The frame's globals (`shaders/lib/shade_globals.wgsl`), written by
    /// [`ShadePass::record`]: the terrain splats pass lights terrain pixels with them.
    pub fn globals(&self) -> &wgpu::Buffer {
        &self.globals
    }

    /// The globals [`ShadePass::record`] last wrote, less the jobs' queue and the edge
    /// search (equal bytes: the same lights, ambient, sky and bands).
    pub fn globals_key(&self) -> &ShadeGlobals {
        &self.globals_key
    }

    fn dispatch(
        &mut self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        jobs: &[ShadeJob],
        inputs: &ShadeInputs<'_>,
    ) {
        let ShadeInputs {
            store,
            scene,
            look,
            view,
            edges,
        } = *inputs;
        let (device, queue) = (&ctx.device, &ctx.queue);
        // Without a frame's view (the cubemap baseline), nothing is view-culled and the view
        // is never read; a zeroed one fills the binding.
        let view = view.unwrap_or(&self.no_view);
        let jobs = &jobs[..jobs.len().min(MAX_JOBS)];
        // The light queue: each slot's part holds at most the texels its jobs dispatch over.
        let area = |j: &ShadeJob| {
            let n = store.slot(j.slot).n;
            let (w, h) = j.extent(n);
            if j.border {
                4 * u64::from(n)
            } else {
                u64::from(w) * u64::from(h)
            }
        };
        let mut queue_base = [0u32; 4];
        let mut total = 0u64;
        for slot in Slot::ALL {
            queue_base[slot.index()] = total as u32;
            total += jobs
                .iter()
                .filter(|j| j.slot == slot)
                .map(area)
                .sum::<u64>();
        }
        if self.work.size() < 4 * (WORK_QUEUE + total) {
            self.work = work_buffer(device, total);
        }
        encoder.clear_buffer(&self.work, 0, Some(4 * WORK_QUEUE));
        // Written every frame, jobs or not: the terrain splats pass lights with them too.
        let mut g = globals(scene, look);
        g.dither = u32::from(self.dither);
        self.globals_key = g;
        g.queue_base = queue_base;
        g.edges = u32::from(edges);
        g.edge_roots = u32::from(self.edge_roots);
        queue.write_buffer(&self.globals, 0, bytemuck::bytes_of(&g));
        if jobs.is_empty() {
            return;
        }
        let args: Vec<[u32; 4]> = Slot::ALL.iter().map(|_| [0, 1, 1, 0]).collect();
        queue.write_buffer(&self.job_args, 0, bytemuck::cast_slice(&args));
        for j in jobs.iter().filter(|j| j.view_cull && !j.border) {
            store.clear_lists(queue, j.slot, FaceMask::single(j.face));
        }
        let job_args = bind_group(
            device,
            "shade::job_args",
            &self.args_layout,
            &[self.job_args.as_entire_binding()],
        );
        let mut bytes = vec![0u8; UNIFORM_STRIDE as usize * jobs.len()];
        for (i, j) in jobs.iter().enumerate() {
            let f = ShadeFace {
                origin: j.origin.to_array(),
                face: j.face.index() as u32,
                n: store.slot(j.slot).n,
                view_cull: u32::from(j.view_cull),
                valid_mask: u32::from(j.valid.bits()),
                job: i as u32,
                slot: j.slot.index() as u32,
                _pad: 0,
                rect_min: j.rect.map_or([0, 0], |r| [r.x0, r.y0]),
                ..ShadeFace::filtered(j.filter)
            };
            let at = i * UNIFORM_STRIDE as usize;
            bytes[at..at + size_of::<ShadeFace>()].copy_from_slice(bytemuck::bytes_of(&f));
        }
        queue.write_buffer(&self.faces, 0, &bytes);
        let bvh = bind_group(
            device,
            "shade::bvh",
            &self.bvh_layout,
            &scene.bvh_resources(),
        );
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("shade::pass"),
            timestamp_writes: None,
        });
        pass.set_bind_group(1, &bvh, &[]);
        // Eye jobs read both stable slots; stable jobs must not see the slot they write, so
        // they get the eye slot's textures (which they do not read).
        let for_eye = self.stable_bind_group(device, store, [Slot::StableA, Slot::StableB], view);
        let for_stable = self.stable_bind_group(device, store, [Slot::Eye, Slot::Eye], view);
        // Stable slots first: eye texels may copy their colours in the same pass. Per slot:
        // sort every job's texels into the queue, and the edges of faces next to new ones
        // (border jobs), then light the queue in one dispatch.
        for slot in [Slot::StableA, Slot::StableB, Slot::Eye] {
            let mine: Vec<(usize, &ShadeJob)> = jobs
                .iter()
                .enumerate()
                .filter(|(_, j)| j.slot == slot)
                .collect();
            let Some(&(first, _)) = mine.first() else {
                continue;
            };
            pass.set_bind_group(
                2,
                if slot == Slot::Eye {
                    &for_eye
                } else {
                    &for_stable
                },
                &[],
            );
            let n = store.slot(slot).n;
            let bind = self.slot_bind_group(device, store, slot, scene);
            let offset = |i: usize| (i as u64 * UNIFORM_STRIDE) as u32;
            for &(i, j) in mine.iter().filter(|(_, j)| !j.border) {
                let (w, h) = j.extent(n);
                if w == 0 || h == 0 {
                    continue;
                }
                pass.set_bind_group(0, &bind, &[offset(i)]);
                pass.set_pipeline(self.pipeline.get());
                pass.set_bind_group(3, &job_args, &[]);
                pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
            }
            for &(i, _) in mine.iter().filter(|(_, j)| j.border) {
                pass.set_bind_group(0, &bind, &[offset(i)]);
                pass.set_pipeline(self.border_pipeline.get());
                pass.set_bind_group(3, &job_args, &[]);
                pass.dispatch_workgroups((4 * n).div_ceil(64), 1, 1);
            }
            if mine.iter().any(|(_, j)| area(j) > 0) {
                pass.set_bind_group(0, &bind, &[offset(first)]);
                pass.set_pipeline(self.light_pipeline.get());
                let args = slot.index() as u64 * JOB_ARGS_BYTES;
                pass.dispatch_workgroups_indirect(&self.job_args, args);
            }
        }
    }

    fn stable_bind_group(
        &self,
        device: &wgpu::Device,
        store: &ProbeStore,
        slots: [Slot; 2],
        view: &wgpu::Buffer,
    ) -> wgpu::BindGroup {
        let mut resources = Vec::new();
        for slot in slots {
            let t = store.slot(slot);
            for v in [&t.geo.array_view, &t.ids.array_view, &t.lit.array_view] {
                resources.push(wgpu::BindingResource::TextureView(v));
            }
        }
        resources.push(view.as_entire_binding());
        bind_group(device, "shade::stable", &self.stable_layout, &resources)
    }

    fn slot_bind_group(
        &self,
        device: &wgpu::Device,
        store: &ProbeStore,
        slot: Slot,
        scene: &GpuScene,
    ) -> wgpu::BindGroup {
        let slot = store.slot(slot);
        let tex = wgpu::BindingResource::TextureView;
        let face = wgpu::BindingResource::Buffer(wgpu::BufferBinding {
            buffer: &self.faces,
            offset: 0,
            size: wgpu::BufferSize::new(size_of::<ShadeFace>() as u64),
        });
        bind_group(
            device,
            "shade::slot",
            &self.layout,
            &[
                face,
                self.globals.as_entire_binding(),
                tex(&slot.geo.array_view),
                tex(&slot.ids.array_view),
                tex(&slot.albedo.array_view),
                tex(&slot.lit.array_view),
                scene.objects.as_entire_binding(),
                scene.points.as_entire_binding(),
                self.work.as_entire_binding(),
                slot.list.as_entire_binding(),
                wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                    buffer: &self.faces,
                    offset: 0,
                    size: wgpu::BufferSize::new(UNIFORM_STRIDE * MAX_JOBS as u64),
                }),
                tex(&slot.shading.array_view),
            ],
        )
    }
}

fn globals(scene: &GpuScene, look: &Look) -> ShadeGlobals {
    let (suns, sun_count) = gpu_suns(scene);
    let v4 = |v: Vec3| v.extend(1.0).to_array();
    ShadeGlobals {
        suns,
        ambient: v4(look.ambient),
        sky: v4(look.sky),
        sun_count,
        point_count: scene.point_count,
        bands: look.bands.max(2),
        edges: 0,
        queue_base: [0; 4],
        dither: 0,
        edge_roots: 0,
        _pad: [0; 2],
    }
}

/// The `work` buffer, with room for a queue of `queue` texels.
fn work_buffer(device: &wgpu::Device, queue: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("shade::work"),
        size: 4 * (WORK_QUEUE + queue),
        usage: wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_SRC
            | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}
