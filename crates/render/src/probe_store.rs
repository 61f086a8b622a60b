//! Where probes live on the GPU: one set of six-layer texture arrays per slot (eye, and the
//! two stable slots that take turns as grid and previous), each at its own face resolution.
//!
//! | texture | format | contents |
//! |---|---|---|
//! | `geo` | `rgba32float` | world normal (xyz), Chebyshev depth from the origin (w; `SKY_DEPTH` = sky) |
//! | `ids` | `r32uint` | entity id (0 = sky) |
//! | `albedo` | `rgba8unorm` | albedo × vertex colour × texture (rgb), object flags (a) |
//! | `shading` | `r32uint` | `pack4x8snorm` of the normal-mapped normal (w = 1), 0 without a normal map |
//! | `depth` | `depth32float` | capture depth test |
//! | `lit` | `rgba32float` | shaded, posterized, outlined colour (rgb); neighbour bits and silhouette edges (a: an integer below 2^24) |
//! | `runs` | `r32uint` | stable slots: texels in the run this texel heads (`RUN_COLUMN` set for a column run; 0 = inside a run) |
//!
//! Beside the textures, each slot has a draw list (`shaders/lib/lists.wgsl`): the texels the
//! cull pass visits per face.

use texel_probes::cube::FaceMask;
use texel_probes::probe_set::Slot;

use crate::context::GpuContext;

/// Formats of the slot textures.
pub const GEO_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
/// Entity ids.
pub const ID_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;
/// Albedo.
pub const ALBEDO_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
/// Normal-mapped normals.
pub const SHADING_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;
/// Capture depth, and the depth of every scene raster (`passes::raster`).
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// Lit colour.
pub const LIT_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
/// Runs of alike texels.
pub const RUNS_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;

/// One texture array and a view per layer.
pub struct LayeredTexture {
    /// The six-layer texture.
    pub texture: wgpu::Texture,
    /// All six layers, for shaders.
    pub array_view: wgpu::TextureView,
    /// One view per layer (face), for render attachments.
    pub layer_views: Vec<wgpu::TextureView>,
}

impl LayeredTexture {
    /// A six-layer texture of `n × n` texels of `format`, labelled `label`.
    pub(crate) fn new(
        ctx: &GpuContext,
        label: &str,
        n: u32,
        format: wgpu::TextureFormat,
        usage: wgpu::TextureUsages,
    ) -> Self {
        let texture = ctx.device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width: n,
                height: n,
                depth_or_array_layers: 6,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage,
            view_formats: &[],
        });
        let array_view = texture.create_view(&wgpu::TextureViewDescriptor {
            label: Some(label),
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });
        let layer_views = (0..6)
            .map(|layer| {
                texture.create_view(&wgpu::TextureViewDescriptor {
                    label: Some(label),
                    dimension: Some(wgpu::TextureViewDimension::D2),
                    base_array_layer: layer,
                    array_layer_count: Some(1),
                    ..Default::default()
                })
            })
            .collect();
        LayeredTexture {
            texture,
            array_view,
            layer_views,
        }
    }
}

/// The textures of one slot.
pub struct SlotTextures {
    /// Texels per face edge.
    pub n: u32,
    /// Normal and depth.
    pub geo: LayeredTexture,
    /// Entity ids.
    pub ids: LayeredTexture,
    /// Albedo and flags.
    pub albedo: LayeredTexture,
    /// Normal-mapped normals (lighting only; the geometric normal in `geo` sizes and culls
    /// quads and finds creases).
    pub shading: LayeredTexture,
    /// Capture depth buffer.
    pub depth: LayeredTexture,
    /// Lit colour.
    pub lit: LayeredTexture,
    /// Runs of alike texels along rows or columns (`shaders/runs.wgsl`).
    pub runs: LayeredTexture,
    /// Draw list: per-face counts, then per-face entries (`shaders/lib/lists.wgsl`).
    pub list: wgpu::Buffer,
}

impl SlotTextures {
    /// Allocates a slot of `n × n` faces.
    pub fn new(ctx: &GpuContext, slot: Slot, n: u32) -> Self {
        use wgpu::TextureUsages as U;
        // Copied aside and back around a face captured in part (`passes::capture`).
        let gbuf = U::RENDER_ATTACHMENT | U::TEXTURE_BINDING | U::COPY_SRC | U::COPY_DST;
        let name = |what: &str| format!("probes::{slot:?}::{what}");
        SlotTextures {
            n,
            geo: LayeredTexture::new(ctx, &name("geo"), n, GEO_FORMAT, gbuf),
            ids: LayeredTexture::new(ctx, &name("ids"), n, ID_FORMAT, gbuf),
            // Also written by the capture's terrain colouring.
            albedo: LayeredTexture::new(
                ctx,
                &name("albedo"),
                n,
                ALBEDO_FORMAT,
                gbuf | U::STORAGE_BINDING,
            ),
            shading: LayeredTexture::new(ctx, &name("shading"), n, SHADING_FORMAT, gbuf),
            // The eye's is copied from its far faces' (`far_field`).
            depth: LayeredTexture::new(
                ctx,
                &name("depth"),
                n,
                DEPTH_FORMAT,
                U::RENDER_ATTACHMENT | U::COPY_DST,
            ),
            lit: LayeredTexture::new(
                ctx,
                &name("lit"),
                n,
                LIT_FORMAT,
                U::STORAGE_BINDING | U::TEXTURE_BINDING | U::COPY_SRC,
            ),
            runs: LayeredTexture::new(
                ctx,
                &name("runs"),
                n,
                RUNS_FORMAT,
                U::STORAGE_BINDING | U::TEXTURE_BINDING,
            ),
            list: ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(&name("list")),
                size: 4 * (LIST_HEADER + 6 * u64::from(n) * u64::from(n)),
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
        }
    }
}

/// Counts at the head of a draw list (`LIST_HEADER` in `lib/lists.wgsl`).
const LIST_HEADER: u64 = 8;

/// The three slots. A slot is reallocated when asked for another face resolution.
pub struct ProbeStore {
    slots: [SlotTextures; 3],
    /// Bumped whenever any slot is reallocated (bind groups must be rebuilt).
    pub generation: u64,
}

impl ProbeStore {
    /// Three slots of `n × n` faces.
    pub fn new(ctx: &GpuContext, n: u32) -> Self {
        let store = ProbeStore {
            slots: Slot::ALL.map(|s| SlotTextures::new(ctx, s, n)),
            generation: 0,
        };
        for slot in Slot::ALL {
            store.clear_lists(&ctx.queue, slot, FaceMask::ALL);
        }
        store
    }

    /// GPU bytes of every slot's faces and draw lists.
    pub fn bytes(&self) -> u64 {
        use crate::memory::texture_bytes;
        (self.slots.iter())
            .map(|s| {
                [
                    &s.geo, &s.ids, &s.albedo, &s.shading, &s.depth, &s.lit, &s.runs,
                ]
                .iter()
                .map(|t| texture_bytes(&t.texture))
                .sum::<u64>()
                    + s.list.size()
            })
            .sum()
    }

    /// The textures of `slot`.
    pub fn slot(&self, slot: Slot) -> &SlotTextures {
        &self.slots[slot.index()]
    }

    /// Makes sure `slot` holds faces of `n` texels; returns whether it was reallocated.
    pub fn ensure(&mut self, ctx: &GpuContext, slot: Slot, n: u32) -> bool {
        if self.slots[slot.index()].n == n {
            return false;
        }
        self.slots[slot.index()] = SlotTextures::new(ctx, slot, n);
        self.clear_lists(&ctx.queue, slot, FaceMask::ALL);
        self.generation += 1;
        true
    }

    /// Empties the draw lists of `faces` of `slot` (before the commands that refill them:
    /// queue writes land before the next submission's commands).
    pub fn clear_lists(&self, queue: &wgpu::Queue, slot: Slot, faces: FaceMask) {
        let list = &self.slots[slot.index()].list;
        for face in faces.iter() {
            let f = face.index() as u64;
            queue.write_buffer(list, 4 * f, &[0; 4]);
        }
    }
}
