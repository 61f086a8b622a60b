//! Terrain splats: what each one-texel terrain quad of the cull pass's list shows, pixel by
//! pixel (`shaders/terrain_splat.wgsl`), written between cull and splat. The records are
//! kept per texel in a cache behind the list's (stamped with what each was made from, sealed
//! with its contents and the shadows' epoch where it lies), and again by block
//! ([`BLOCK_SLOTS`]: a record is made from its block and pixels, whichever probe's texel
//! shows it, so a crossing's new probe finds most records the old one made). Both are
//! cleared when what no stamp holds changes: the scene, or the shade pass's globals (lights,
//! ambient, bands), or the number of animated shadow casters. A caster that moves marks
//! where its shadow may have come or gone with a new epoch ([`ShadowTiles`]): only the
//! records and pixels there are made again. A first dispatch takes each quad's record from
//! the cache or queues the quad as a miss; a second (`shadows`) finds each miss's block and
//! takes its record from the blocks' slots where it is there, else lists it for the fourth
//! and, where one of its four terrain pixels' lights is not in the table, for the third;
//! the third (`cast_rays`) casts the shadow rays from those pixels' centres; the fourth
//! (`make`) makes the records not found. Each runs only the misses listed for it ([`Stage`]):
//! an invocation paid for its shader's rare code whether it ran it or not.

use crate::context::GpuContext;
use crate::gpu_scene::{CasterNow, GpuScene};
use crate::passes::LazyCompute;
use crate::passes::cull::{MAX_SPLATS, SPLAT_BYTES, SplatList};
use crate::passes::shade::ShadeGlobals;
use crate::shader;
use crate::shadow_region::{ShadowTiles, TILE_ENTRIES};

use super::{ARRAY, FLOAT, compute_pipeline, entry, storage, texture, uniform};

/// Bytes of one record (`TerrainSplat` in `shaders/lib/view.wgsl`): four packed colours, the
/// pixels' grid, the terrain's plane.
pub const RECORD_BYTES: u64 = 48;
/// Invocations per workgroup of `main`.
const GROUP: u64 = 64;
const _: () = assert!(MAX_SPLATS.div_ceil(GROUP) <= 65535);

/// What the terrain splat pass reads.
#[derive(Clone, Copy)]
pub struct TerrainSplatInputs<'a> {
    /// The frame's view.
    pub view: &'a wgpu::Buffer,
    /// The scene (objects, terrains, textures, point lights).
    pub scene: &'a GpuScene,
    /// The shade pass's globals, which light the terrain's pixels.
    pub shade_globals: &'a wgpu::Buffer,
    /// Their contents as far as a record depends on them (`ShadePass::globals_key`).
    pub globals_key: &'a ShadeGlobals,
    /// The cull pass's list.
    pub list: SplatList<'a>,
    /// Texels per face edge of the largest slot (the texel keys' stride).
    pub max_n: u32,
    /// Whether the frame has haze (`Look::haze` above 0): only then does `haze` run.
    pub haze: bool,
}

/// The terrain splat pass.
pub struct TerrainSplatPass {
    /// `main`: each quad's record from the cache, or its index queued as a miss.
    pipeline: LazyCompute,
    size_pipeline: LazyCompute,
    /// `haze`: the haze over every record, dispatched as `main` is, on a frame with haze.
    haze_pipeline: LazyCompute,
    /// `shadows`: each queued miss's block, its record where the block's slot holds it,
    /// else which lights reach its pixels as far as the table knows.
    shadows: Stage,
    /// `cast_rays`: the shadow rays of the pixels `shadows` did not find in the table.
    cast_rays: Stage,
    /// `make`: the records of the misses `shadows` did not find.
    make: Stage,
    /// `cast_rays`' group 0 (the view, the terrains, the lights and the queue) and group 2
    /// (the BVH); its group 1 is empty.
    cast_layout: wgpu::BindGroupLayout,
    bvh_layout: wgpu::BindGroupLayout,
    empty_bind: wgpu::BindGroup,
    /// The casters' poses the cache's shadows were cast with (`GpuScene::casters`).
    casters: Option<Vec<CasterNow>>,
    /// Where shadows last changed (`shadow_tiles` in the shader), and its uniform buffer.
    tiles: ShadowTiles,
    tiles_buffer: wgpu::Buffer,
    /// The sizing dispatches' group 0: only the queue.
    misses_layout: wgpu::BindGroupLayout,
    misses: Misses,
    layout: wgpu::BindGroupLayout,
    /// `size`'s group 0: only the splats and their count.
    size_layout: wgpu::BindGroupLayout,
    dispatch: wgpu::Buffer,
    dispatch_bind: wgpu::BindGroup,
    /// One record per splat of the list, then the cache (see [`Layout`]).
    records: wgpu::Buffer,
    /// How `records` is laid out.
    layout_now: Layout,
    /// The cache must be cleared before the next pass (a new scene or new globals).
    stale: bool,
    /// The shade pass's globals the cache was made with (`ShadePass::globals_key`).
    globals_key: Option<ShadeGlobals>,
    /// The cache's slots at most ([`CACHE_SLOTS_MAX`] unless a test asks for fewer).
    slots_max: u64,
}

/// How the records buffer is laid out: `splats` records (the list's capacity), then the
/// cache: one slot per record key (a texel key, `texel_key` in `lib/common.wgsl`: 3 slots ×
/// 6 faces × `max_n`², times 3 band shifts: an outline's strips are a band darker or lighter
/// than its body) where the binding holds them and they fit in [`CACHE_SLOTS_MAX`], else as
/// many slots as do, each key at a hash of it (`cache_slot` in `terrain_splat.wgsl`), where a
/// record whose checksum fails is made again.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Layout {
    splats: u64,
    cache: u64,
    /// [`BLOCK_SLOTS`] where there is a cache, else 0.
    blocks: u64,
}

/// Slots of the records kept by block, after those kept by texel (`block_slot` in the
/// shader; 12 MiB): a record is made from its block and pixels, whichever probe's texel shows
/// it, so a crossing's new probe finds most of its records where the old one made them.
pub const BLOCK_SLOTS: u64 = 1 << 18;

/// The cache's slots at most: 2²¹ records, 96 MiB (faces of 128 need 884,736 slots; faces of
/// 256 would need 3.5 M, and of 496, a 1280×720 view's at pixel size 2.5, 13.3 M: they share
/// these slots by hash).
pub const CACHE_SLOTS_MAX: u64 = 1 << 21;

/// Fewer slots than this: no cache (a hashed cache that small would mostly collide).
const CACHE_SLOTS_MIN: u64 = 1 << 12;

impl Layout {
    /// For a list of `splats` records and faces of at most `max_n` texels, within a binding
    /// of at most `limit` bytes and at most `slots_max` cache slots.
    fn new(splats: u64, max_n: u32, limit: u64, slots_max: u64) -> Self {
        let keys = RECORD_KEYS_PER_TEXEL_SQUARED * u64::from(max_n) * u64::from(max_n);
        let room = (limit / RECORD_BYTES).saturating_sub(splats + BLOCK_SLOTS);
        let cache = keys.min(room).min(slots_max);
        if keys > 0 && cache >= CACHE_SLOTS_MIN.min(keys) {
            Layout {
                splats,
                cache,
                blocks: BLOCK_SLOTS,
            }
        } else {
            Layout {
                splats,
                cache: 0,
                blocks: 0,
            }
        }
    }

    fn bytes(self) -> u64 {
        (self.splats + self.cache + self.blocks).max(1) * RECORD_BYTES
    }
}

/// Record keys per texel of a face edge, squared: 3 band shifts × 3 probe slots × 6 faces.
const RECORD_KEYS_PER_TEXEL_SQUARED: u64 = 3 * 3 * 6;

/// Bytes of one queued miss (`Miss` in the shader).
pub const MISS_BYTES: u64 = 48;
// A miss for every splat of the largest list fits in one binding of wgpu's default limit.
const _: () =
    assert!(MISSES_HEADER_BYTES + CELL_LIGHTS_BYTES + MISS_BYTES * MAX_SPLATS <= 128 << 20);

/// Bytes of the queue's head that [`TerrainSplatPass::counts`] holds.
pub const TERRAIN_COUNTS_BYTES: u64 = 16;

/// What one terrain splats pass did.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct TerrainCounts {
    /// Records made (quads whose record was not in the cache).
    pub records_made: u32,
    /// Terrain pixels whose shadow rays were cast.
    pub pixels_cast: u32,
    /// Quads whose record was not kept for their texel but was found on their block, made
    /// by another probe's or texel's quad (not counted in `records_made`).
    pub records_shared: u32,
}

impl TerrainCounts {
    /// From the first [`TERRAIN_COUNTS_BYTES`] bytes of [`TerrainSplatPass::counts`].
    pub fn from_bytes(bytes: &[u8]) -> Self {
        let word =
            |i: usize| u32::from_le_bytes([bytes[i], bytes[i + 1], bytes[i + 2], bytes[i + 3]]);
        TerrainCounts {
            records_made: word(4).saturating_sub(word(12)),
            pixels_cast: word(8),
            records_shared: word(12),
        }
    }
}

/// Slots of the terrain pixels' lights (`Misses::lights` in the shader; 4 MiB): a 1280×720
/// view at pixel size 2.5 holds about 150,000 art pixels, and a terrain pixel is at least a
/// probe texel, so a view shows fewer terrain pixels than that; the slots stay mostly empty
/// (four times as many changed nothing measurable).
const CELL_LIGHT_SLOTS: u64 = 1 << 20;
/// Bytes of the pixels' lights table in the queue's buffer.
pub const CELL_LIGHTS_BYTES: u64 = 4 * CELL_LIGHT_SLOTS;
/// Bytes of the queue's head (`Misses` in the shader, up to `lights`).
pub const MISSES_HEADER_BYTES: u64 = 32;

/// The queue of misses (`Misses` in the shader: the list's count, the misses' count, the
/// pixels whose rays were cast, the misses found on their block, padding, the counts of the
/// lists `make` and `cast_rays` take, padding, the pixels' lights, then one
/// `Miss` per quad of the list at most) and the sizing dispatches' bind group over it. A new one starts zeroed: no pixel's lights known.
struct Misses {
    buffer: wgpu::Buffer,
    bind: wgpu::BindGroup,
}

impl Misses {
    fn new(device: &wgpu::Device, layout: &wgpu::BindGroupLayout, splats: u64) -> Self {
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("terrain_splat::misses"),
            size: MISSES_HEADER_BYTES + CELL_LIGHTS_BYTES + MISS_BYTES * splats.max(1),
            usage: wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::COPY_SRC
                | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("terrain_splat::misses_bind"),
            layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 12,
                resource: buffer.as_entire_binding(),
            }],
        });
        Misses { buffer, bind }
    }
}

fn record_buffer(device: &wgpu::Device, layout: Layout) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("terrain_splat::records"),
        size: layout.bytes(),
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
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
                entry(11, c, storage(false)),
                entry(12, c, storage(false)),
                entry(14, c, uniform(false)),
            ],
        });
        let size_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("terrain_splat::size_layout"),
            entries: &[
                entry(9, c, storage(true)),
                entry(10, c, storage(true)),
                entry(12, c, storage(false)),
            ],
        });
        let dispatch_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("terrain_splat::dispatch_layout"),
            entries: &[entry(0, c, storage(false))],
        });
        let pipeline = compute_pipeline(device, "terrain_splat", &module, "main", &[&layout]);
        let haze_pipeline =
            compute_pipeline(device, "terrain_splat::haze", &module, "haze", &[&layout]);
        // Within a stage's 8 storage buffers: the terrains, their data, the point lights and
        // the queue (with the pixels' lights) here, the BVH's three in group 2.
        let cast_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("terrain_splat::cast_layout"),
            entries: &[
                entry(0, c, uniform(false)),
                entry(5, c, storage(true)),
                entry(6, c, storage(true)),
                entry(7, c, uniform(false)),
                entry(8, c, storage(true)),
                entry(12, c, storage(false)),
                entry(14, c, uniform(false)),
            ],
        });
        let empty_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("terrain_splat::empty_layout"),
            entries: &[],
        });
        let empty_bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("terrain_splat::empty_bind"),
            layout: &empty_layout,
            entries: &[],
        });
        let bvh_layout = super::bvh_layout(device, "terrain_splat::bvh_layout", c);
        let misses_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("terrain_splat::misses_layout"),
            entries: &[entry(12, c, storage(false))],
        });
        let stage = |name: &str, size: &str, layouts: &[&wgpu::BindGroupLayout]| {
            let label = format!("terrain_splat::{name}");
            let (dispatch, dispatch_bind) =
                super::dispatch_args(device, &format!("{label}_dispatch"), &dispatch_layout);
            Stage {
                run: compute_pipeline(device, &label, &module, name, layouts),
                size: compute_pipeline(
                    device,
                    &format!("terrain_splat::{size}"),
                    &module,
                    size,
                    &[&misses_layout, &dispatch_layout],
                ),
                dispatch,
                dispatch_bind,
            }
        };
        let shadows = stage("shadows", "size_misses", &[&layout]);
        let cast_rays = stage(
            "cast_rays",
            "size_casts",
            &[&cast_layout, &empty_layout, &bvh_layout],
        );
        let make = stage("make", "size_makes", &[&layout]);
        let size_pipeline = compute_pipeline(
            device,
            "terrain_splat::size",
            &module,
            "size",
            &[&size_layout, &dispatch_layout],
        );
        let (dispatch, dispatch_bind) =
            super::dispatch_args(device, "terrain_splat::dispatch", &dispatch_layout);
        let misses = Misses::new(device, &misses_layout, 1);
        Ok(TerrainSplatPass {
            pipeline,
            size_pipeline,
            haze_pipeline,
            shadows,
            cast_rays,
            make,
            cast_layout,
            bvh_layout,
            empty_bind,
            casters: None,
            tiles: ShadowTiles::default(),
            tiles_buffer: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("terrain_splat::shadow_tiles"),
                size: 4 * TILE_ENTRIES as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            misses_layout,
            misses,
            layout,
            size_layout,
            dispatch,
            dispatch_bind,
            records: record_buffer(device, Layout::new(1, 0, 0, CACHE_SLOTS_MAX)),
            layout_now: Layout::new(1, 0, 0, CACHE_SLOTS_MAX),
            stale: false,
            globals_key: None,
            slots_max: CACHE_SLOTS_MAX,
        })
    }

    /// One record per splat `list` can hold (written for its terrain quads only), at its
    /// index; the cache after them.
    pub fn records(&self) -> &wgpu::Buffer {
        &self.records
    }

    /// The last pass's counts ([`TerrainCounts::from_bytes`] reads them): the first
    /// [`TERRAIN_COUNTS_BYTES`] bytes of this buffer.
    pub fn counts(&self) -> &wgpu::Buffer {
        &self.misses.buffer
    }

    /// Caps the cache at `slots` slots (at most [`CACHE_SLOTS_MAX`]), so that a test can make
    /// the keys of small faces share slots by hash, as those of large faces do; the next
    /// pass lays the records out again, with an empty cache.
    pub fn set_cache_slots_max(&mut self, slots: u64) {
        self.slots_max = slots.min(CACHE_SLOTS_MAX);
    }

    /// Slots of the cache as laid out by the last pass (0: no cache).
    pub fn cache_slots(&self) -> u64 {
        self.layout_now.cache
    }

    /// Forgets every cached record (a new scene: other heights, colours, objects).
    pub fn forget(&mut self) {
        self.stale = true;
        self.casters = None;
    }

    /// Records the pass over `inputs.list`; lays the records out for the list's capacity
    /// first, and clears the cache when the globals' key differs from the last one's.
    pub fn record(
        &mut self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        inputs: &TerrainSplatInputs<'_>,
    ) {
        let TerrainSplatInputs {
            view,
            scene,
            shade_globals,
            globals_key,
            list,
            max_n,
            haze,
        } = *inputs;
        let splats = list.splats.size() / SPLAT_BYTES;
        let limits = ctx.device.limits();
        let limit = (limits.max_storage_buffer_binding_size).min(limits.max_buffer_size);
        let layout = Layout::new(splats, max_n, limit, self.slots_max);
        // A new buffer starts zeroed: an empty cache.
        let records_new = layout != self.layout_now;
        if records_new {
            self.records = record_buffer(&ctx.device, layout);
            self.misses = Misses::new(&ctx.device, &self.misses_layout, layout.splats);
            self.layout_now = layout;
        }
        let key = bytemuck::bytes_of(globals_key);
        if self.globals_key.as_ref().map(bytemuck::bytes_of) != Some(key) {
            self.globals_key = Some(*globals_key);
            self.stale = true;
        }
        // A caster that moved may shadow other pixels: those where its shadow may have come
        // or gone are marked with a new epoch, which their records' and pixels' stamps hold.
        let casters = scene.casters();
        match &self.casters {
            Some(before) if before.len() == casters.len() => {
                let mut moved = false;
                for (a, b) in before.iter().zip(&casters) {
                    if a.key != b.key {
                        let lights = &scene.shadow_lights;
                        let shadows = lights.footprints(a.min.min(b.min), a.max.max(b.max));
                        self.tiles.mark(&shadows);
                        moved = true;
                    }
                }
                if moved {
                    let entries = bytemuck::cast_slice(self.tiles.entries());
                    ctx.queue.write_buffer(&self.tiles_buffer, 0, entries);
                }
            }
            Some(_) => self.stale = true,
            None => {}
        }
        self.casters = Some(casters);
        if self.stale && layout.cache > 0 && !records_new {
            encoder.clear_buffer(&self.records, layout.splats * RECORD_BYTES, None);
        }
        if self.stale && !records_new {
            let lights = Some(CELL_LIGHTS_BYTES);
            encoder.clear_buffer(&self.misses.buffer, MISSES_HEADER_BYTES, lights);
        }
        self.stale = false;
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
            (12, self.misses.buffer.as_entire_binding()),
            (14, self.tiles_buffer.as_entire_binding()),
        ];
        let entries =
            resources.map(|(binding, resource)| wgpu::BindGroupEntry { binding, resource });
        // `main` and `make` read the list's count from the queue that `size` wrote it to, not
        // from `args` (binding 10), which only `size` binds.
        let pick = |keep: fn(u32) -> bool| -> Vec<wgpu::BindGroupEntry<'_>> {
            entries
                .iter()
                .filter(|e| keep(e.binding))
                .cloned()
                .collect()
        };
        let bind = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("terrain_splat::bind"),
            layout: &self.layout,
            entries: &pick(|b| b != 10),
        });
        let size_bind = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("terrain_splat::size_bind"),
            layout: &self.size_layout,
            entries: &pick(|b| matches!(b, 9 | 10 | 12)),
        });
        let cast_bind = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("terrain_splat::cast_bind"),
            layout: &self.cast_layout,
            entries: &pick(|b| matches!(b, 0 | 5 | 6 | 7 | 8 | 12 | 14)),
        });
        let bvh_bind = super::bind_group(
            &ctx.device,
            "terrain_splat::bvh",
            &self.bvh_layout,
            &scene.bvh_resources(),
        );
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("terrain_splat"),
            timestamp_writes: None,
        });
        pass.set_pipeline(self.size_pipeline.get());
        pass.set_bind_group(0, &size_bind, &[]);
        pass.set_bind_group(1, &self.dispatch_bind, &[]);
        pass.dispatch_workgroups(1, 1, 1);
        pass.set_pipeline(self.pipeline.get());
        pass.set_bind_group(0, &bind, &[]);
        pass.dispatch_workgroups_indirect(&self.dispatch, 0);
        let cast_groups = [&cast_bind, &self.empty_bind, &bvh_bind];
        for (stage, groups) in [
            (&self.shadows, &[&bind][..]),
            (&self.cast_rays, &cast_groups[..]),
            (&self.make, &[&bind][..]),
        ] {
            pass.set_pipeline(stage.size.get());
            pass.set_bind_group(0, &self.misses.bind, &[]);
            pass.set_bind_group(1, &stage.dispatch_bind, &[]);
            pass.dispatch_workgroups(1, 1, 1);
            pass.set_pipeline(stage.run.get());
            for (i, group) in groups.iter().enumerate() {
                pass.set_bind_group(i as u32, *group, &[]);
            }
            pass.dispatch_workgroups_indirect(&stage.dispatch, 0);
        }
        if haze {
            pass.set_pipeline(self.haze_pipeline.get());
            pass.set_bind_group(0, &bind, &[]);
            pass.dispatch_workgroups_indirect(&self.dispatch, 0);
        }
    }
}

/// One dispatch over a list of misses: `size` writes its workgroup counts from the list's
/// count into `dispatch` (bound in group 1 only then), `run` is dispatched by them.
struct Stage {
    size: LazyCompute,
    run: LazyCompute,
    dispatch: wgpu::Buffer,
    dispatch_bind: wgpu::BindGroup,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_cache_follows_the_list_where_the_binding_holds_it() {
        // Faces of 128: 3 × 3 × 6 × 128² keys after 1000 records, one slot each, then the
        // blocks' slots.
        let l = Layout::new(1000, 128, 128 << 20, CACHE_SLOTS_MAX);
        assert_eq!((l.splats, l.cache, l.blocks), (1000, 884_736, BLOCK_SLOTS));
        assert_eq!(l.bytes(), (1000 + 884_736 + BLOCK_SLOTS) * RECORD_BYTES);
        // Faces of 1024 would need 2.7 GB: the keys share the most slots allowed.
        let l = Layout::new(1000, 1024, 128 << 20, CACHE_SLOTS_MAX);
        assert_eq!((l.splats, l.cache), (1000, CACHE_SLOTS_MAX));
        assert!(l.bytes() <= 128 << 20);
        // A binding of 64 MiB holds fewer slots than that: as many as it holds.
        let l = Layout::new(1000, 1024, 64 << 20, CACHE_SLOTS_MAX);
        assert_eq!(l.cache, (64 << 20) / RECORD_BYTES - 1000 - BLOCK_SLOTS);
        assert!(l.bytes() <= 64 << 20);
        // Room for a few slots only: no cache, by texel or by block.
        let l = Layout::new(1000, 1024, 1100 * RECORD_BYTES, CACHE_SLOTS_MAX);
        assert_eq!((l.splats, l.cache, l.blocks), (1000, 0, 0));
        assert_eq!(l.bytes(), 1000 * RECORD_BYTES);
        assert_eq!(Layout::new(0, 0, 0, CACHE_SLOTS_MAX).bytes(), RECORD_BYTES);
        // A cap below the keys (a test's): the keys share that many slots.
        let l = Layout::new(1000, 64, 128 << 20, CACHE_SLOTS_MIN);
        assert_eq!(
            (l.splats, l.cache, l.blocks),
            (1000, CACHE_SLOTS_MIN, BLOCK_SLOTS)
        );
    }
}
