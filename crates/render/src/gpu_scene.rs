//! The scene on the GPU: one vertex buffer of world-space triangles (meshes are static, so
//! they are transformed once at upload), one record per object (material and entity id),
//! the textures (`textures`: one atlas, a record per image, a record per distinct surface),
//! the lights, and the shadow BVH over every shadow-casting triangle.

use bytemuck::{Pod, Zeroable};
use glam::{Mat3, Vec3};
use wgpu::util::DeviceExt;

use crate::bvh::{BvhNode, GpuBvh, build_bvh};
use crate::context::GpuContext;
use crate::input::SceneInput;
use crate::textures::{AtlasError, GpuTextures, TextureSet};

/// Largest number of directional lights the shade pass reads.
pub const MAX_SUNS: usize = 4;

/// One capture vertex (68 bytes).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct Vertex {
    /// World position.
    pub position: [f32; 3],
    /// Index into the object buffer.
    pub object: u32,
    /// World normal.
    pub normal: [f32; 3],
    /// Vertex colour, RGBA8 (linear), multiplied into the albedo.
    pub colour: u32,
    /// Texture coordinates (before the surface's UV scale).
    pub uv: [f32; 2],
    /// Index of the surface's textures (`textures::GpuSurface`; 0 = none).
    pub surface: u32,
    /// World-space gradient of the triangle's U (the same on its three vertices): with
    /// [`Vertex::grad_v`], the UV footprint of any probe texel or pixel follows from its
    /// world footprint, without screen derivatives (which some rasterizers get wrong in
    /// quads that straddle a triangle edge), and it is the normal map's tangent frame.
    pub grad_u: [f32; 3],
    /// World-space gradient of the triangle's V.
    pub grad_v: [f32; 3],
}

/// World bounds of an object-space box under `m`.
fn transform_bounds(m: glam::Mat4, min: Vec3, max: Vec3) -> (Vec3, Vec3) {
    let mut lo = Vec3::splat(f32::INFINITY);
    let mut hi = Vec3::splat(f32::NEG_INFINITY);
    for i in 0..8 {
        let c = Vec3::new(
            if i & 1 == 0 { min.x } else { max.x },
            if i & 2 == 0 { min.y } else { max.y },
            if i & 4 == 0 { min.z } else { max.z },
        );
        let p = m.transform_point3(c);
        lo = lo.min(p);
        hi = hi.max(p);
    }
    (lo, hi)
}

/// The uniform block of the terrains `cast` (indices into `scene.terrains`, all walkable)
/// and the texture holding their heights and quadtrees.
fn upload_fields(
    ctx: &GpuContext,
    scene: &SceneInput,
    cast: &[usize],
) -> (wgpu::Buffer, wgpu::TextureView) {
    use crate::bvh::field::{self, HeightField};
    let fields: Vec<(usize, HeightField)> = (cast.iter())
        .filter_map(|&i| {
            let t = &scene.terrains[i];
            HeightField::new(t.corner, t.size, t.samples, &t.heights).map(|f| (i, f))
        })
        .collect();
    let (block, data) = field::pack(&fields.iter().map(|(i, f)| (*i, f)).collect::<Vec<_>>());
    let view = field::upload_data(&ctx.device, &ctx.queue, &data);
    let buffer = ctx
        .device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("scene::bvh_fields"),
            contents: bytemuck::bytes_of(&block),
            usage: wgpu::BufferUsages::UNIFORM,
        });
    (buffer, view)
}

/// The largest axis scale of `m`.
fn max_scale(m: glam::Mat4) -> f32 {
    let (scale, _, _) = m.to_scale_rotation_translation();
    scale.abs().max_element()
}

/// The terrains' records and their heights and gradients in one float array (each list at
/// least one element long, as bindings need).
fn terrain_records(scene: &SceneInput, textures: &mut TextureSet) -> (Vec<GpuTerrain>, Vec<f32>) {
    let mut records = Vec::with_capacity(scene.terrains.len().max(1));
    let mut data: Vec<f32> = Vec::new();
    for t in &scene.terrains {
        let heights_at = data.len() as u32;
        data.extend_from_slice(&t.heights);
        let gradient_at = data.len() as u32;
        for (at, c) in &t.gradient {
            data.extend_from_slice(&[*at, c.x, c.y, c.z]);
        }
        let (displacement, strength, tile_size) = match &t.displacement {
            Some((tex, strength, tile)) => (textures.data_texture(tex), *strength, *tile),
            None => (crate::textures::NO_TEXTURE, 0.0, 1.0),
        };
        let paint = t
            .paint
            .as_ref()
            .map_or(crate::textures::NO_TEXTURE, |p| textures.paint_texture(p));
        records.push(GpuTerrain {
            corner: t.corner.to_array(),
            max_height: t.max_height,
            size: t.size.to_array(),
            samples: t.samples.to_array(),
            heights_at,
            gradient_at,
            gradient_len: t.gradient.len() as u32,
            displacement,
            strength,
            tile_size,
            pixel_density: t.pixel_density,
            band_distance: t.band_distance,
            band_transition: t.band_transition,
            paint,
            _pad: [0; 2],
        });
    }
    if records.is_empty() {
        records.push(GpuTerrain::zeroed());
    }
    if data.is_empty() {
        data.push(0.0);
    }
    (records, data)
}

/// The world-space gradients of U and V over the triangle `p` with UVs `uv` (zero for a
/// degenerate triangle or UV map).
pub fn uv_gradients(p: [Vec3; 3], uv: [glam::Vec2; 3]) -> (Vec3, Vec3) {
    let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
    let n = e1.cross(e2);
    let area2 = n.length_squared();
    if !(area2.is_finite() && area2 > 1e-20) {
        return (Vec3::ZERO, Vec3::ZERO);
    }
    // Gradients of the barycentric coordinates along e1 and e2.
    let ga = e2.cross(n) / area2;
    let gb = n.cross(e1) / area2;
    let (d1, d2) = (uv[1] - uv[0], uv[2] - uv[0]);
    let gu = ga * d1.x + gb * d2.x;
    let gv = ga * d1.y + gb * d2.y;
    if gu.is_finite() && gv.is_finite() {
        (gu, gv)
    } else {
        (Vec3::ZERO, Vec3::ZERO)
    }
}

/// One object's material and id (32 bytes; `shaders/lib/scene.wgsl` `Object`).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct GpuObject {
    /// Linear albedo.
    pub albedo: [f32; 3],
    /// Bit 0: outlined; bit 1: emissive (drawn unlit); bit 2: a terrain, whose index is in
    /// bits 8..32 (only the low 8 bits reach the albedo target's alpha).
    pub flags: u32,
    /// Linear emissive colour.
    pub emissive: [f32; 3],
    /// Entity id (non-zero).
    pub id: u32,
}

/// A point light (32 bytes; WGSL `PointLight`).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct GpuPointLight {
    /// World position.
    pub position: [f32; 3],
    /// Fade-out radius.
    pub radius: f32,
    /// Colour × intensity.
    pub colour: [f32; 4],
}

/// Object flag: outlines are drawn on it.
pub const FLAG_OUTLINED: u32 = 1;
/// Object flag: drawn unlit with its emissive colour.
pub const FLAG_EMISSIVE: u32 = 2;
/// Object flag: coloured as the terrain whose index is `flags >> 8`.
pub const FLAG_TERRAIN: u32 = 4;
/// Object flag: animated (drawn by the moving pass, never captured); its motion record's
/// index is in bits 8..32.
pub const FLAG_ANIMATED: u32 = 8;
/// Object flag: its triangles are in the static BVH (it casts shadows and is not animated),
/// so rays can find its silhouette's edges (`shaders/shade.wgsl`, the edge search).
pub const FLAG_IN_BVH: u32 = 16;

/// One animated object's pose this frame (272 bytes; WGSL `Motion` in `shaders/moving.wgsl`,
/// also read by `gbuffer.wgsl`).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct GpuMotion {
    /// Base-pose world → world now.
    pub to_now: [[f32; 4]; 4],
    /// Its normal matrix (upper 3×3).
    pub normal_now: [[f32; 4]; 4],
    /// Base-pose world → the object's rigid frame.
    pub frame: [[f32; 4]; 4],
    /// The rigid frame → base-pose world.
    pub frame_inv: [[f32; 4]; 4],
    /// Bounds centre in base-pose world (xyz).
    pub centre: [f32; 4],
}

/// An animated object's shadow-casting tree where the object is now (112 bytes; WGSL
/// `BvhInstance` in `shaders/lib/bvh.wgsl`): shadow rays in world space are carried into the
/// base pose and traverse the tree built there, so a moving object's shadow moves without a
/// rebuild.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct GpuBvhInstance {
    /// World now → base-pose world.
    pub from_now: [[f32; 4]; 4],
    /// World bounds now (xyz).
    pub min: [f32; 4],
    /// World bounds now (xyz).
    pub max: [f32; 4],
    /// Root node of its tree in the scene's BVH buffers; `u32::MAX`: casts no shadow.
    pub root: u32,
    /// Padding.
    pub _pad: [u32; 3],
}

impl GpuBvhInstance {
    /// The record of no tree (every ray misses it).
    pub const NONE: GpuBvhInstance = GpuBvhInstance {
        from_now: [[0.0; 4]; 4],
        min: [0.0; 4],
        max: [0.0; 4],
        root: u32::MAX,
        _pad: [0; 3],
    };
}

/// An animated object as uploaded: where its vertices are and how its poses map onto them.
#[derive(Debug, Clone, PartialEq)]
pub struct AnimatedObject {
    /// Index into the scene's objects.
    pub object: usize,
    /// Its base transform (object → world), the pose its vertices were uploaded at.
    pub base: glam::Mat4,
    /// Base-pose world → its rigid frame (the base transform's rotation and translation,
    /// inverted; scale is left in the world units the cells are measured in).
    pub frame: glam::Mat4,
    /// Bounds centre, base-pose world.
    pub centre: Vec3,
    /// Bounds, base-pose world.
    pub min: Vec3,
    /// Bounds, base-pose world.
    pub max: Vec3,
    /// Root of its shadow tree in the scene's BVH buffers (`u32::MAX`: casts no shadow).
    pub bvh_root: u32,
    /// Vertex runs `(first, count)`.
    pub runs: Vec<(u32, u32)>,
}

impl AnimatedObject {
    /// Its shadow tree's record for `transform` (object → world now).
    pub fn instance(&self, transform: glam::Mat4) -> GpuBvhInstance {
        if self.bvh_root == u32::MAX {
            return GpuBvhInstance::NONE;
        }
        let to_now = transform * self.base.inverse();
        let (min, max) = transform_bounds(to_now, self.min, self.max);
        GpuBvhInstance {
            from_now: to_now.inverse().to_cols_array_2d(),
            min: min.extend(0.0).to_array(),
            max: max.extend(0.0).to_array(),
            root: self.bvh_root,
            _pad: [0; 3],
        }
    }

    /// Its motion record for `transform` (object → world now).
    pub fn motion(&self, transform: glam::Mat4) -> GpuMotion {
        let to_now = transform * self.base.inverse();
        let normal = glam::Mat4::from_mat3(Mat3::from_mat4(to_now).inverse().transpose());
        GpuMotion {
            to_now: to_now.to_cols_array_2d(),
            normal_now: normal.to_cols_array_2d(),
            frame: self.frame.to_cols_array_2d(),
            frame_inv: self.frame.inverse().to_cols_array_2d(),
            centre: self.centre.extend(1.0).to_array(),
        }
    }
}

/// One terrain's colouring (80 bytes; WGSL `Terrain` in `lib/terrain.wgsl`); its heights and
/// gradient live in the shared `terrain_data` buffer.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct GpuTerrain {
    /// World position of sample (0, 0) at height 0.
    pub corner: [f32; 3],
    /// Height of normalised elevation 1.
    pub max_height: f32,
    /// World extent X, Z.
    pub size: [f32; 2],
    /// Samples along X, Z.
    pub samples: [u32; 2],
    /// First height in `terrain_data`.
    pub heights_at: u32,
    /// First gradient stop in `terrain_data` (4 floats each: at, r, g, b).
    pub gradient_at: u32,
    /// Number of stops.
    pub gradient_len: u32,
    /// Displacement texture record, or `textures::NO_TEXTURE`.
    pub displacement: u32,
    /// Displacement strength.
    pub strength: f32,
    /// Displacement tile size, world units.
    pub tile_size: f32,
    /// Pixels per world unit in band 0.
    pub pixel_density: f32,
    /// Distance of band 0.
    pub band_distance: f32,
    /// Transition share of a band.
    pub band_transition: f32,
    /// Paint layer texture record, or `textures::NO_TEXTURE`.
    pub paint: u32,
    /// Padding.
    pub _pad: [u32; 2],
}

/// Most triangles in one [`DrawRange`]: a terrain chunk of 32×32 quads.
pub const RANGE_TRIANGLES: u32 = 2048;

/// A run of vertices in the vertex buffer and their world bounds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DrawRange {
    /// First vertex.
    pub first: u32,
    /// Vertices (three per triangle).
    pub count: u32,
    /// Bounds.
    pub min: Vec3,
    /// Bounds.
    pub max: Vec3,
    /// Level of detail (0 for everything but terrain chunks).
    pub lod: u32,
    /// The chunk's coarsest level (0: no levels).
    pub max_lod: u32,
    /// World distance between samples at level 0.
    pub spacing: f32,
    /// An untextured terrain's triangles: a capture draws them with its terrain pipeline
    /// (`shaders/capture.wgsl` `vs_terrain`), which reads the surface from the heightmap.
    pub terrain: bool,
}

impl DrawRange {
    /// Whether any part of the box may be inside the clip volume of `view_proj` (depth 0..1):
    /// false only when all eight corners are beyond one clip plane.
    pub fn may_be_visible(&self, view_proj: &glam::Mat4) -> bool {
        let corners: [glam::Vec4; 8] = std::array::from_fn(|i| {
            let p = Vec3::new(
                if i & 1 == 0 { self.min.x } else { self.max.x },
                if i & 2 == 0 { self.min.y } else { self.max.y },
                if i & 4 == 0 { self.min.z } else { self.max.z },
            );
            *view_proj * p.extend(1.0)
        });
        let outside = |f: &dyn Fn(&glam::Vec4) -> bool| corners.iter().all(f);
        !(outside(&|c| c.x < -c.w)
            || outside(&|c| c.x > c.w)
            || outside(&|c| c.y < -c.w)
            || outside(&|c| c.y > c.w)
            || outside(&|c| c.z < 0.0)
            || outside(&|c| c.z > c.w))
    }
}

/// Every range at level 0 (terrains at full detail), neighbours merged.
pub fn full_detail_runs(ranges: &[DrawRange]) -> Vec<(u32, u32)> {
    merge_runs(ranges.iter().filter(|r| r.lod == 0))
}

/// Vertex runs `(first, count)` of `ranges` (in buffer order), contiguous ones merged into
/// one draw.
fn merge_runs<'a>(ranges: impl Iterator<Item = &'a DrawRange>) -> Vec<(u32, u32)> {
    let mut runs: Vec<(u32, u32)> = Vec::new();
    for r in ranges {
        match runs.last_mut() {
            Some(last) if last.0 + last.1 == r.first => last.1 += r.count,
            _ => runs.push((r.first, r.count)),
        }
    }
    runs
}

/// Probe texels a terrain sample may span at a chunk's nearest point: the capture stores the
/// full-detail surface's point and normal on each texel's ray whatever level drew it
/// (shaders/lib/terrain.wgsl `terrain_level0_hit`), so a coarser level changes only which
/// texels it covers at ridges (a coarse ridge lies below the true one), never their colour or
/// their shadows. Measured on `terrain_hills` `terrain_walk` (captures' time per frame, hole
/// rate): at 320×180, faces of 128, 75 ms at 1 texel, 64 at 2, 51 at 4, 40 at 8 with shimmer
/// 0.0141–0.0144; at 160×90, faces of 48, 38, 28 and 20 ms with holes 0.0013, 0.0014, 0.0020:
/// beyond 2 the ridges' holes grow.
pub const LOD_SAMPLE_TEXELS: f32 = 2.0;

/// Probe texels a terrain sample may span in the eye probe's captures. The eye shows only
/// where no stable probe's quad landed (on `terrain_walk` 1.4 % of the pixels, on
/// `terrain_descent` 0.6 %) and is captured again every frame, so its ridges may come from
/// a coarser mesh. Measured on those two paths (faces of 128, 320×180): shimmer, coverage
/// error and holes as at [`LOD_SAMPLE_TEXELS`] (0.0123 / 0.0082, 0.0090 / 0.0094, holes
/// 0.00036 / 0.00030 against 0.0122 / 0.0082, 0.0092 / 0.0096, 0.00028 / 0.00030).
pub const EYE_LOD_SAMPLE_TEXELS: f32 = 8.0;

/// The level a chunk is drawn at from `origin` on faces of `n` texels: the coarsest whose
/// sample spacing is at most `LOD_SAMPLE_TEXELS` probe texels at the chunk's nearest point
/// (a texel there is `2d / n`).
pub fn chunk_lod(r: &DrawRange, origin: Vec3, n: u32) -> u32 {
    chunk_lod_within(r, origin, n, LOD_SAMPLE_TEXELS)
}

/// [`chunk_lod`] with samples at most `texels` probe texels apart.
fn chunk_lod_within(r: &DrawRange, origin: Vec3, n: u32, texels: f32) -> u32 {
    if r.max_lod == 0 || r.spacing <= 0.0 {
        return 0;
    }
    let d = (origin.clamp(r.min, r.max) - origin).length();
    lod_for_span(r, texels * 2.0 * d / n as f32)
}

/// The coarsest level of `r` whose samples are at most `LOD_SAMPLE_TEXELS` texels of world
/// size `texel` apart.
fn lod_for_texel(r: &DrawRange, texel: f32) -> u32 {
    lod_for_span(r, LOD_SAMPLE_TEXELS * texel)
}

/// The coarsest level of `r` whose samples are at most `span` world units apart.
fn lod_for_span(r: &DrawRange, span: f32) -> u32 {
    if r.max_lod == 0 || r.spacing <= 0.0 || !span.is_finite() {
        return 0;
    }
    let ratio = span / r.spacing;
    if ratio < 2.0 {
        return 0;
    }
    (ratio.log2().floor() as u32).min(r.max_lod)
}

/// Probe texels an object's bounds must span, where the face sees them, for a capture to
/// draw it: an object smaller than that at its distance covers at most a few texels'
/// centres, so it is left out and a far field of small things costs nothing (its shadows
/// stay: rays trace the whole scene).
pub const DRAW_MIN_TEXELS: f32 = 1.0;

/// Whether a face capturing for `lod` draws `r`: terrain chunks always (their levels thin
/// them instead), other ranges when the diagonal of their bounds is at least
/// [`DRAW_MIN_TEXELS`] texels at their nearest point. A cube-face texel there measures
/// `2d / n × cos²φ` (d the distance, φ the angle from the face's axis: a texel toward a
/// face's edge subtends less, down to a third at its corners), an orthographic face's
/// texel its world size; a full-detail raster (a reference G-buffer) draws everything.
pub fn spans_a_texel(r: &DrawRange, lod: LodFrom) -> bool {
    if r.terrain {
        return true;
    }
    let diagonal = (r.max - r.min).length();
    match lod {
        LodFrom::Full => true,
        LodFrom::Texel(size) => diagonal >= DRAW_MIN_TEXELS * size,
        LodFrom::Probe(origin, n) | LodFrom::Eye(origin, n) => {
            let nearest = origin.clamp(r.min, r.max) - origin;
            let d = nearest.length();
            let toward = ((r.min + r.max) * 0.5 - origin).normalize_or_zero();
            let cos = toward.abs().max_element().max(1.0 / 3f32.sqrt());
            let texel = 2.0 * d / n as f32 * cos * cos;
            diagonal >= DRAW_MIN_TEXELS * texel
        }
    }
}

/// How a raster picks terrain levels: from a probe (`origin`, `n` texels per face edge), or
/// level 0 everywhere (a G-buffer).
#[derive(Debug, Clone, Copy)]
pub enum LodFrom {
    /// Levels for a stable probe at `origin` with faces of `n` texels.
    Probe(Vec3, u32),
    /// Levels for the eye probe at `origin` with faces of `n` texels
    /// ([`EYE_LOD_SAMPLE_TEXELS`]).
    Eye(Vec3, u32),
    /// Levels for texels of one world size everywhere (an orthographic face).
    Texel(f32),
    /// Full detail.
    Full,
}

/// The vertex runs of `ranges` that may be visible through `view_proj`, at the level `lod`
/// picks for each chunk, neighbours merged; for a probe, nearest ranges first (their boxes'
/// nearest points), so the depth test rejects what they hide before it is shaded: a capture
/// fragment is heavy (the full-detail terrain point, terrain pixel colour, textures).
/// Measured on `terrain_hills` `terrain_walk` at 1280×720, faces of 128 (lavapipe):
/// captures 50 → 33 ms a frame, the frame's median 94–97 → 73–76 ms.
pub fn visible_runs(ranges: &[DrawRange], view_proj: &glam::Mat4, lod: LodFrom) -> Vec<(u32, u32)> {
    merge_runs(visible_ranges(ranges, view_proj, lod).into_iter())
}

/// [`visible_runs`] split by [`DrawRange::terrain`]: the plain terrain's runs, then the rest
/// (each in the order `visible_runs` draws them), under `cull`; and how many ranges they
/// hold.
pub fn visible_runs_by_kind(
    ranges: &[DrawRange],
    view_proj: &glam::Mat4,
    lod: LodFrom,
    cull: CaptureCull,
) -> ([Vec<(u32, u32)>; 2], usize) {
    let visible = ranges_drawn(ranges, view_proj, lod, cull);
    let count = visible.len();
    let (terrain, rest): (Vec<&DrawRange>, Vec<&DrawRange>) =
        visible.into_iter().partition(|r| r.terrain);
    ([terrain, rest].map(|r| merge_runs(r.into_iter())), count)
}

/// The ranges [`visible_runs`] draws, in its order.
fn visible_ranges<'a>(
    ranges: &'a [DrawRange],
    view_proj: &glam::Mat4,
    lod: LodFrom,
) -> Vec<&'a DrawRange> {
    ranges_drawn(ranges, view_proj, lod, CaptureCull::Footprint)
}

/// What a capture leaves out of a face.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum CaptureCull {
    /// Nothing: every range at its level (to test the others against).
    Nothing,
    /// What lies wholly outside the face's frustum.
    Frustum,
    /// That, and what spans less than a texel there ([`spans_a_texel`]).
    #[default]
    Footprint,
}

/// The ranges a face draws under `cull`, in the order it draws them.
fn ranges_drawn<'a>(
    ranges: &'a [DrawRange],
    view_proj: &glam::Mat4,
    lod: LodFrom,
    cull: CaptureCull,
) -> Vec<&'a DrawRange> {
    let wanted = |r: &DrawRange| match lod {
        LodFrom::Full => r.lod == 0,
        LodFrom::Probe(origin, n) => r.lod == chunk_lod(r, origin, n),
        LodFrom::Eye(origin, n) => r.lod == chunk_lod_within(r, origin, n, EYE_LOD_SAMPLE_TEXELS),
        LodFrom::Texel(size) => r.lod == lod_for_texel(r, size),
    };
    let mut visible: Vec<&DrawRange> = ranges
        .iter()
        .filter(|r| {
            wanted(r)
                && (cull != CaptureCull::Footprint || spans_a_texel(r, lod))
                && (cull == CaptureCull::Nothing || r.may_be_visible(view_proj))
        })
        .collect();
    if let LodFrom::Probe(origin, _) | LodFrom::Eye(origin, _) = lod {
        let distance = |r: &DrawRange| (origin.clamp(r.min, r.max) - origin).length_squared();
        visible.sort_by(|a, b| {
            distance(a)
                .total_cmp(&distance(b))
                .then(a.first.cmp(&b.first))
        });
    }
    visible
}

/// Why a scene does not fit the device.
#[derive(Debug, thiserror::Error)]
pub enum UploadError {
    /// The textures.
    #[error(transparent)]
    Atlas(#[from] AtlasError),
    /// The sprites' sheets.
    #[error(transparent)]
    Sprites(#[from] crate::gpu_sprites::SpriteError),
}

/// The horizontal direction toward the first sun (sprites' shadow proxies face it), +Z
/// without a sun or under a sun straight overhead.
fn suns_toward(scene: &SceneInput) -> Vec3 {
    scene
        .suns
        .first()
        .map(|s| Vec3::new(-s.direction.x, 0.0, -s.direction.z))
        .and_then(|v| v.try_normalize())
        .unwrap_or(Vec3::Z)
}

/// The uploaded scene.
pub struct GpuScene {
    /// Capture vertices.
    pub vertices: wgpu::Buffer,
    /// Number of vertices (non-indexed triangle list).
    pub vertex_count: u32,
    /// Object records.
    pub objects: wgpu::Buffer,
    /// Point lights (at least one record; `point_count` says how many are real).
    pub points: wgpu::Buffer,
    /// Number of point lights.
    pub point_count: u32,
    /// Directional lights, `(direction toward the light, colour)`.
    pub suns: Vec<(Vec3, Vec3)>,
    /// Shadow BVH nodes.
    pub bvh_nodes: wgpu::Buffer,
    /// Shadow BVH triangles.
    pub bvh_triangles: wgpu::Buffer,
    /// Shadow-casting triangles in the BVH.
    pub shadow_triangles: usize,
    /// Entity id of each object, by object index.
    pub object_ids: Vec<u32>,
    /// The textures.
    pub textures: GpuTextures,
    /// Consecutive runs of at most [`RANGE_TRIANGLES`] triangles of one object with their
    /// world bounds: a raster draws only the ranges its frustum meets.
    pub ranges: Vec<DrawRange>,
    /// Animated objects' shadow trees where they are now: a header (its `root` the top-level
    /// tree's root, or none), then one record per caster in the top-level tree's order.
    pub bvh_instances: wgpu::Buffer,
    /// Where the top-level tree's nodes start in `bvh_nodes`.
    pub tlas_root: u32,
    /// Animated objects' motion records, one per [`GpuScene::animated`] (at least one).
    pub motions: wgpu::Buffer,
    /// The animated objects, in motion record order.
    pub animated: Vec<AnimatedObject>,
    /// Terrain records (at least one).
    pub terrains: wgpu::Buffer,
    /// Terrains in the scene (records in use).
    pub terrain_count: usize,
    /// The sprites, if the scene has any.
    pub sprites: Option<crate::gpu_sprites::GpuSprites>,
    /// Terrain heights and gradient stops (at least one word).
    pub terrain_data: wgpu::Buffer,
    /// The shadow-casting terrains walked as heightfields: their records
    /// ([`crate::bvh::field::GpuFields`]) and data (`r32float`, a flat list).
    pub bvh_fields: wgpu::Buffer,
    /// View of the fields' data texture.
    pub field_data: wgpu::TextureView,
    /// Terrains walked as heightfields by the shadow rays.
    pub shadow_fields: usize,
    /// Where each animated shadow caster stands ([`GpuScene::casters`]).
    casters: std::sync::Mutex<Vec<CasterNow>>,
    /// The scene's lights and lowest point, for where a moved caster's shadow may fall.
    pub shadow_lights: crate::shadow_region::ShadowLights,
}

/// Where an animated shadow caster stands ([`GpuScene::casters`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CasterNow {
    /// A hash of its instance record (its pose and bounds).
    pub key: u64,
    /// World bounds now.
    pub min: Vec3,
    /// World bounds now.
    pub max: Vec3,
}

fn pack_colour(c: [f32; 4]) -> u32 {
    let b = |v: f32| (v.clamp(0.0, 1.0) * 255.0).round() as u32;
    b(c[0]) | (b(c[1]) << 8) | (b(c[2]) << 16) | (b(c[3]) << 24)
}

impl GpuScene {
    /// Uploads `scene`: transforms every mesh to world space, packs the textures and builds
    /// the shadow BVH. Fails only when the textures do not fit the device's limits.
    pub fn upload(ctx: &GpuContext, scene: &SceneInput) -> Result<GpuScene, UploadError> {
        let mut vertices = Vec::new();
        let mut ranges: Vec<DrawRange> = Vec::new();
        let mut textures = TextureSet::default();
        let mut objects = Vec::with_capacity(scene.objects.len().max(1));
        let mut casters: Vec<[Vec3; 3]> = Vec::new();
        // Motion record index of each animated object (terrains never move).
        let mut animated_index: Vec<Option<u32>> = vec![None; scene.objects.len()];
        let mut animated: Vec<AnimatedObject> = Vec::new();
        let mut animated_casters: Vec<(usize, Vec<[Vec3; 3]>)> = Vec::new();
        // Terrains whose shadows and edge rays walk their heights rather than triangles.
        let walked = crate::bvh::field::walked_terrains(&scene.terrains);
        let mut cast_fields: Vec<usize> = Vec::new();
        for &i in &scene.animated {
            let terrain = scene.objects.get(i).and_then(|o| o.material.terrain);
            if i < scene.objects.len() && terrain.is_none() && animated_index[i].is_none() {
                animated_index[i] = Some(animated.len() as u32);
                let o = &scene.objects[i];
                let (_, rotation, translation) = o.transform.to_scale_rotation_translation();
                animated.push(AnimatedObject {
                    object: i,
                    base: o.transform,
                    frame: glam::Mat4::from_rotation_translation(rotation, translation).inverse(),
                    centre: translation,
                    min: translation,
                    max: translation,
                    bvh_root: u32::MAX,
                    runs: Vec::new(),
                });
            }
        }
        for (index, o) in scene.objects.iter().enumerate() {
            let normal_m = Mat3::from_mat4(o.transform).inverse().transpose();
            let flip = o.transform.determinant() < 0.0;
            let m = &o.material;
            let emissive = m.emissive.max_element() > 0.0;
            let terrain = m
                .terrain
                .filter(|&t| t < scene.terrains.len())
                .map_or(0, |t| FLAG_TERRAIN | ((t as u32) << 8));
            let moving = animated_index[index].filter(|_| terrain == 0);
            let field = m.terrain.filter(|&t| walked.get(t) == Some(&true));
            if let Some(t) = field.filter(|t| m.casts_shadows && !cast_fields.contains(t)) {
                cast_fields.push(t);
            }
            let animated_flag = moving.map_or(0, |i| FLAG_ANIMATED | (i << 8));
            let ranges_before = ranges.len();
            let mut own_casters: Vec<[Vec3; 3]> = Vec::new();
            objects.push(GpuObject {
                albedo: m.albedo.to_array(),
                flags: u32::from(m.outlined) * FLAG_OUTLINED
                    + u32::from(emissive) * FLAG_EMISSIVE
                    + terrain
                    + animated_flag
                    + u32::from(m.casts_shadows && moving.is_none()) * FLAG_IN_BVH,
                emissive: m.emissive.to_array(),
                id: o.id,
            });
            let own = textures.surface(&m.maps);
            let mut part_surfaces: Vec<u32> = Vec::with_capacity(o.mesh.parts.len());
            for part in &o.mesh.parts {
                // The material's textures win over the mesh's own.
                let maps = if m.maps.is_empty() {
                    &part.maps
                } else {
                    &m.maps
                };
                part_surfaces.push(textures.surface(maps));
            }
            // Its surface comes from the heightmap alone (no texture, no normal map).
            let plain_terrain = terrain != 0 && own == 0 && part_surfaces.iter().all(|&s| s == 0);
            let mut piece = 0usize;
            let mut piece_start = 0u32;
            for (t, tri) in o.mesh.indices.chunks_exact(3).enumerate() {
                let t = t as u32;
                // A new range at every piece (level of a chunk) and every RANGE_TRIANGLES.
                while piece < o.mesh.pieces.len()
                    && t >= o.mesh.pieces[piece].first_triangle + o.mesh.pieces[piece].triangles
                {
                    piece += 1;
                }
                let lod_piece = o.mesh.pieces.get(piece).filter(|p| t >= p.first_triangle);
                let starts_piece = lod_piece.is_some_and(|p| p.first_triangle == t);
                if starts_piece {
                    piece_start = t;
                }
                if starts_piece || (t - piece_start).is_multiple_of(RANGE_TRIANGLES) {
                    let (lod, max_lod, spacing, min, max) = match lod_piece {
                        Some(p) => {
                            let (lo, hi) = transform_bounds(o.transform, p.min, p.max);
                            (p.lod, p.max_lod, p.spacing * max_scale(o.transform), lo, hi)
                        }
                        None => (
                            0,
                            0,
                            0.0,
                            Vec3::splat(f32::INFINITY),
                            Vec3::splat(f32::NEG_INFINITY),
                        ),
                    };
                    ranges.push(DrawRange {
                        first: vertices.len() as u32,
                        count: 0,
                        min,
                        max,
                        lod,
                        max_lod,
                        spacing,
                        terrain: plain_terrain,
                    });
                }
                let level0 = lod_piece.is_none_or(|p| p.lod == 0);
                let surface = match o.mesh.parts.partition_point(|p| p.first_triangle <= t) {
                    0 => own,
                    after => part_surfaces[after - 1],
                };
                let order = if flip { [0, 2, 1] } else { [0, 1, 2] };
                let world: [Vec3; 3] = order.map(|c| {
                    o.transform
                        .transform_point3(o.mesh.positions[tri[c] as usize])
                });
                let (gu, gv) = uv_gradients(world, order.map(|c| o.mesh.uv(tri[c] as usize)));
                if let Some(r) = ranges.last_mut() {
                    r.count += 3;
                    if r.max_lod == 0 {
                        for p in world {
                            r.min = r.min.min(p);
                            r.max = r.max.max(p);
                        }
                    }
                }
                for (k, &c) in order.iter().enumerate() {
                    let i = tri[c] as usize;
                    let p = world[k];
                    let n = (normal_m * o.mesh.normals[i]).normalize_or_zero();
                    vertices.push(Vertex {
                        position: p.to_array(),
                        object: index as u32,
                        normal: n.to_array(),
                        colour: pack_colour(o.mesh.colors.get(i).copied().unwrap_or([1.0; 4])),
                        uv: o.mesh.uv(i).to_array(),
                        surface,
                        grad_u: gu.to_array(),
                        grad_v: gv.to_array(),
                    });
                }
                if m.casts_shadows && level0 && field.is_none() {
                    match moving {
                        None => casters.push(world),
                        Some(_) => own_casters.push(world),
                    }
                }
            }
            // An animated object's ranges are drawn by the moving pass (and the G-buffer),
            // never by a capture.
            if let Some(i) = moving {
                let own: Vec<DrawRange> = ranges.drain(ranges_before..).collect();
                let a = &mut animated[i as usize];
                let (lo, hi) = own.iter().fold(
                    (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
                    |(lo, hi), r| (lo.min(r.min), hi.max(r.max)),
                );
                if lo.cmple(hi).all() {
                    a.centre = 0.5 * (lo + hi);
                    (a.min, a.max) = (lo, hi);
                }
                a.runs = merge_runs(own.iter());
                if !own_casters.is_empty() {
                    animated_casters.push((i as usize, own_casters));
                }
            }
        }
        let motions: Vec<GpuMotion> = if animated.is_empty() {
            vec![GpuMotion::zeroed()]
        } else {
            animated.iter().map(|a| a.motion(a.base)).collect()
        };
        if objects.is_empty() {
            objects.push(GpuObject::zeroed());
        }
        let vertex_count = vertices.len() as u32;
        if vertices.is_empty() {
            vertices.push(Vertex::zeroed());
        }
        let mut points: Vec<GpuPointLight> = scene
            .points
            .iter()
            .map(|p| GpuPointLight {
                position: p.position.to_array(),
                radius: p.radius,
                colour: p.colour.extend(0.0).to_array(),
            })
            .collect();
        let point_count = points.len() as u32;
        if points.is_empty() {
            points.push(GpuPointLight::zeroed());
        }
        let suns = scene
            .suns
            .iter()
            .take(MAX_SUNS)
            .map(|s| (-s.direction.normalize_or_zero(), s.colour))
            .collect();
        let (gpu_terrains, terrain_data) = terrain_records(scene, &mut textures);
        let textures = textures.upload(ctx)?;
        // Shadow-casting sprites: frame 0's silhouette, standing toward the first sun.
        let toward_sun = suns_toward(scene);
        for sprite in scene.sprites.iter().filter(|s| s.casts_shadows) {
            casters.extend(crate::gpu_sprites::shadow_triangles(sprite, toward_sun));
        }
        let sprites = crate::gpu_sprites::GpuSprites::upload(ctx, &scene.sprites)?;
        let mut bvh: GpuBvh = build_bvh(&casters);
        // Each animated caster's own tree, in its base pose, after the static one.
        for (i, tris) in &animated_casters {
            animated[*i].bvh_root = bvh.append(&build_bvh(tris));
        }
        // Room after the trees for the per-frame top-level tree over the casters' bounds
        // (fewer than two nodes per caster), and the instance records behind a header.
        let tlas_root = bvh.nodes.len() as u32;
        let casters_n = animated_casters.len();
        bvh.nodes
            .extend(std::iter::repeat_n(BvhNode::zeroed(), 2 * casters_n));
        let instances = vec![GpuBvhInstance::NONE; 1 + casters_n];
        let (bvh_nodes, bvh_triangles) = bvh.upload(&ctx.device);
        let (bvh_fields, field_data) = upload_fields(ctx, scene, &cast_fields);
        let storage = |label, contents: &[u8], usage| {
            ctx.device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(label),
                    contents,
                    usage,
                })
        };
        let scene = GpuScene {
            vertices: storage(
                "scene::vertices",
                bytemuck::cast_slice(&vertices),
                wgpu::BufferUsages::VERTEX,
            ),
            vertex_count,
            objects: storage(
                "scene::objects",
                bytemuck::cast_slice(&objects),
                wgpu::BufferUsages::STORAGE,
            ),
            points: storage(
                "scene::points",
                bytemuck::cast_slice(&points),
                wgpu::BufferUsages::STORAGE,
            ),
            point_count,
            suns,
            bvh_nodes,
            bvh_triangles,
            shadow_triangles: casters.len(),
            // Sprites after the objects: a sprite pixel's key names `key_base + index`.
            object_ids: (scene.objects.iter().map(|o| o.id))
                .chain(scene.sprites.iter().map(|s| s.id))
                .collect(),
            sprites,
            textures,
            ranges,
            bvh_instances: storage(
                "scene::bvh_instances",
                bytemuck::cast_slice(&instances),
                wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            ),
            motions: storage(
                "scene::motions",
                bytemuck::cast_slice(&motions),
                wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            ),
            animated,
            tlas_root,
            casters: std::sync::Mutex::new(Vec::new()),
            shadow_lights: crate::shadow_region::ShadowLights::new(scene),
            terrain_count: scene.terrains.len(),
            terrains: storage(
                "scene::terrains",
                bytemuck::cast_slice(&gpu_terrains),
                wgpu::BufferUsages::STORAGE,
            ),
            terrain_data: storage(
                "scene::terrain_data",
                bytemuck::cast_slice(&terrain_data),
                wgpu::BufferUsages::STORAGE,
            ),
            bvh_fields,
            field_data,
            shadow_fields: cast_fields.len(),
        };
        // The casters at their base poses until a frame says otherwise.
        scene.set_poses(&ctx.queue, &[]);
        Ok(scene)
    }

    /// What the shadow BVH group binds ([`crate::passes::bvh_layout`]).
    pub fn bvh_resources(&self) -> [wgpu::BindingResource<'_>; 5] {
        [
            self.bvh_nodes.as_entire_binding(),
            self.bvh_triangles.as_entire_binding(),
            self.bvh_instances.as_entire_binding(),
            self.bvh_fields.as_entire_binding(),
            wgpu::BindingResource::TextureView(&self.field_data),
        ]
    }

    /// Moves the animated objects to `poses` (the others to their base transforms).
    pub fn set_poses(&self, queue: &wgpu::Queue, poses: &[crate::input::Pose]) {
        if self.animated.is_empty() {
            return;
        }
        let transforms: Vec<glam::Mat4> = self
            .animated
            .iter()
            .map(|a| {
                let pose = poses.iter().rev().find(|p| p.object == a.object);
                pose.map(|p| p.transform)
                    .filter(|m| m.is_finite() && m.determinant().abs() > 1e-12)
                    .unwrap_or(a.base)
            })
            .collect();
        let records: Vec<GpuMotion> = (self.animated.iter().zip(&transforms))
            .map(|(a, &m)| a.motion(m))
            .collect();
        queue.write_buffer(&self.motions, 0, bytemuck::cast_slice(&records));
        // The casters where they are now, under a top-level tree over their bounds (so a
        // shadow ray tests the few whose boxes it meets, not every one), behind a header.
        let casting: Vec<GpuBvhInstance> = (self.animated.iter().zip(&transforms))
            .map(|(a, &m)| a.instance(m))
            .filter(|i| i.root != u32::MAX)
            .collect();
        let bounds: Vec<(Vec3, Vec3)> = (casting.iter())
            .map(|i| (Vec3::from_slice(&i.min[..3]), Vec3::from_slice(&i.max[..3])))
            .collect();
        let (nodes, order) = crate::bvh::build_tlas(&bounds, self.tlas_root, 1);
        let mut header = GpuBvhInstance::NONE;
        if !nodes.is_empty() {
            header.root = self.tlas_root;
            let offset = u64::from(self.tlas_root) * size_of::<BvhNode>() as u64;
            queue.write_buffer(&self.bvh_nodes, offset, bytemuck::cast_slice(&nodes));
        }
        let records: Vec<GpuBvhInstance> = std::iter::once(header)
            .chain(order.iter().map(|&k| casting[k as usize]))
            .collect();
        queue.write_buffer(&self.bvh_instances, 0, bytemuck::cast_slice(&records));
        let casters = casting
            .iter()
            .map(|i| {
                use std::hash::{Hash, Hasher};
                let mut h = std::collections::hash_map::DefaultHasher::new();
                bytemuck::bytes_of(i).hash(&mut h);
                CasterNow {
                    key: h.finish(),
                    min: Vec3::from_slice(&i.min[..3]),
                    max: Vec3::from_slice(&i.max[..3]),
                }
            })
            .collect();
        *self.casters.lock().unwrap_or_else(|e| e.into_inner()) = casters;
    }

    /// Where the animated shadow casters stand, in a fixed order (empty for a scene without
    /// them): what a shadow cast through the BVH depends on beyond the scene.
    pub fn casters(&self) -> Vec<CasterNow> {
        self.casters
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .clone()
    }

    /// Where sprites' indices start in the keys of their pixels (after the objects).
    pub fn sprite_key_base(&self) -> u32 {
        (self.object_ids.len() - self.sprites.as_ref().map_or(0, |s| s.cpu.len())) as u32
    }

    /// Every animated object's vertex runs.
    pub fn animated_runs(&self) -> impl Iterator<Item = (u32, u32)> + '_ {
        self.animated.iter().flat_map(|a| a.runs.iter().copied())
    }

    /// What every scene raster (capture, G-buffer) binds after its own uniform, bindings
    /// 1..=6 of `lib/raster.wgsl`'s includers: objects, the texture atlas, its records, the
    /// surfaces, the terrains and their data ([`crate::passes::raster::scene_layout_entries`]).
    pub fn raster_resources(&self) -> [wgpu::BindingResource<'_>; 6] {
        [
            self.objects.as_entire_binding(),
            wgpu::BindingResource::TextureView(&self.textures.view),
            self.textures.infos_buffer.as_entire_binding(),
            self.textures.surfaces.as_entire_binding(),
            self.terrains.as_entire_binding(),
            self.terrain_data.as_entire_binding(),
        ]
    }

    /// The vertex buffer's point and object index alone (locations 0 and 1), for a vertex
    /// stage that needs nothing else (`shaders/capture.wgsl` `vs_terrain`).
    pub fn point_vertex_layout() -> wgpu::VertexBufferLayout<'static> {
        const ATTRS: [wgpu::VertexAttribute; 2] =
            wgpu::vertex_attr_array![0 => Float32x3, 1 => Uint32];
        wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<Vertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &ATTRS,
        }
    }

    /// The vertex layout of [`Vertex`].
    pub fn vertex_layout() -> wgpu::VertexBufferLayout<'static> {
        const ATTRS: [wgpu::VertexAttribute; 8] = wgpu::vertex_attr_array![
            0 => Float32x3, 1 => Uint32, 2 => Float32x3, 3 => Uint32, 4 => Float32x2, 5 => Uint32,
            6 => Float32x3, 7 => Float32x3
        ];
        wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<Vertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &ATTRS,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec2;

    /// A view from the origin down −Z (far plane at 100) and a range of one triangle at
    /// `first` whose box is 2 units wide around `z` on the Z axis.
    fn down_z() -> (glam::Mat4, impl Fn(u32, f32) -> DrawRange) {
        let mut camera = crate::input::Camera::looking(Vec3::ZERO, -Vec3::Z);
        camera.far = 100.0;
        let r = |first, z: f32| DrawRange {
            first,
            count: 3,
            min: Vec3::new(-1.0, -1.0, z - 1.0),
            max: Vec3::new(1.0, 1.0, z + 1.0),
            lod: 0,
            max_lod: 0,
            spacing: 0.0,
            terrain: false,
        };
        (camera.projection(1.0) * camera.view(), r)
    }

    #[test]
    fn ranges_outside_a_frustum_are_skipped_and_neighbours_merge() {
        let (view_proj, r) = down_z();
        // In front, in front, behind, beyond the far plane, in front.
        let ranges = [r(0, -5.0), r(3, -9.0), r(6, 5.0), r(9, -200.0), r(12, -3.0)];
        assert_eq!(
            visible_runs(&ranges, &view_proj, LodFrom::Full),
            vec![(0, 6), (12, 3)]
        );
    }

    #[test]
    fn a_probe_draws_its_nearest_ranges_first() {
        let (view_proj, r) = down_z();
        // Buffer order far, nearest, next nearest, middle: drawn nearest first, the three
        // in buffer order merged.
        let ranges = [r(0, -30.0), r(3, -3.0), r(6, -3.5), r(9, -9.0)];
        assert_eq!(
            visible_runs(&ranges, &view_proj, LodFrom::Probe(Vec3::ZERO, 64)),
            vec![(3, 9), (0, 3)]
        );
        // Out of buffer order they are not merged.
        let ranges = [r(0, -30.0), r(3, -3.0), r(6, -9.0), r(9, -3.5)];
        assert_eq!(
            visible_runs(&ranges, &view_proj, LodFrom::Probe(Vec3::ZERO, 64)),
            vec![(3, 3), (9, 3), (6, 3), (0, 3)]
        );
    }

    #[test]
    fn a_probe_leaves_out_what_spans_less_than_a_texel_where_it_sees_it() {
        // A box of diagonal 2·√3 ≈ 3.46 straight ahead: one texel at distance d on faces of
        // 64 is d/32 there, so it is drawn up to d ≈ 111 and not beyond.
        let (_, r) = down_z();
        let probe = LodFrom::Probe(Vec3::ZERO, 64);
        assert!(spans_a_texel(&r(0, -100.0), probe));
        assert!(!spans_a_texel(&r(0, -125.0), probe));
        // Toward a face's corner a texel subtends a third: drawn three times as far.
        let corner = |d: f32| DrawRange {
            min: Vec3::splat(-d) - 1.0,
            max: Vec3::splat(-d) + 1.0,
            ..r(0, 0.0)
        };
        let d = |c: f32| (Vec3::splat(c - 1.0)).length();
        assert!(spans_a_texel(&corner(180.0), probe), "{}", d(180.0));
        assert!(!spans_a_texel(&corner(200.0), probe), "{}", d(200.0));
        // The eye likewise; a full-detail raster and terrain chunks draw everything; an
        // orthographic face compares with its texel's world size.
        assert!(!spans_a_texel(&r(0, -125.0), LodFrom::Eye(Vec3::ZERO, 64)));
        assert!(spans_a_texel(&r(0, -125.0), LodFrom::Full));
        let terrain = DrawRange {
            terrain: true,
            ..r(0, -1000.0)
        };
        assert!(spans_a_texel(&terrain, probe));
        assert!(spans_a_texel(&r(0, -1000.0), LodFrom::Texel(3.4)));
        assert!(!spans_a_texel(&r(0, -1.0), LodFrom::Texel(3.5)));
        // And the far box is not among a probe face's runs.
        let mut camera = crate::input::Camera::looking(Vec3::ZERO, -Vec3::Z);
        camera.far = 1000.0;
        let far = camera.projection(1.0) * camera.view();
        assert_eq!(
            visible_runs(&[r(0, -5.0), r(3, -125.0)], &far, probe),
            vec![(0, 3)]
        );
        assert_eq!(
            visible_runs(&[r(0, -5.0), r(3, -125.0)], &far, LodFrom::Full),
            vec![(0, 6)]
        );
    }

    #[test]
    fn a_capture_splits_plain_terrain_runs_from_the_rest() {
        let (view_proj, r) = down_z();
        let terrain = |first, z| DrawRange {
            terrain: true,
            ..r(first, z)
        };
        // Buffer order: terrain, terrain, object, terrain; nearest first within each kind,
        // and neighbours of different kinds never merged.
        let ranges = [
            terrain(0, -9.0),
            terrain(3, -3.0),
            r(6, -4.0),
            terrain(9, -5.0),
        ];
        let lod = LodFrom::Probe(Vec3::ZERO, 64);
        let ([plain, rest], count) =
            visible_runs_by_kind(&ranges, &view_proj, lod, CaptureCull::Footprint);
        assert_eq!(count, 4);
        assert_eq!(plain, vec![(3, 3), (9, 3), (0, 3)]);
        assert_eq!(rest, vec![(6, 3)]);
        // Drawn together, the middle three are one run.
        assert_eq!(visible_runs(&ranges, &view_proj, lod), vec![(3, 9), (0, 3)]);
    }

    #[test]
    fn the_eye_draws_terrain_chunks_coarser_than_a_stable_probe() {
        // A chunk 10 units away, samples 0.25 apart, levels 0..=4. On faces of 64 a texel
        // there is 2·10/64 = 0.3125: a stable probe keeps samples within 2 texels (0.625:
        // level 1, 0.5 apart), the eye within EYE_LOD_SAMPLE_TEXELS (level 3 at 8).
        let chunk = |lod| DrawRange {
            first: lod * 3,
            count: 3,
            min: Vec3::new(-1.0, -1.0, -11.0),
            max: Vec3::new(1.0, 1.0, -10.0),
            lod,
            max_lod: 4,
            spacing: 0.25,
            terrain: true,
        };
        assert_eq!(chunk_lod(&chunk(0), Vec3::ZERO, 64), 1);
        let eye = chunk_lod_within(&chunk(0), Vec3::ZERO, 64, EYE_LOD_SAMPLE_TEXELS);
        assert_eq!(eye, 3);
        let (view_proj, _) = down_z();
        let ranges: Vec<DrawRange> = (0..=4).map(chunk).collect();
        let drawn = |lod| visible_runs(&ranges, &view_proj, lod);
        assert_eq!(drawn(LodFrom::Probe(Vec3::ZERO, 64)), vec![(3, 3)]);
        assert_eq!(drawn(LodFrom::Eye(Vec3::ZERO, 64)), vec![(eye * 3, 3)]);
        assert_eq!(drawn(LodFrom::Full), vec![(0, 3)]);
    }

    #[test]
    fn uv_gradients_recover_a_linear_map() {
        // u = 2x + z, v = 3y on a tilted triangle.
        let p = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.5, 0.0),
            Vec3::new(0.0, 1.0, 1.0),
        ];
        let uv = p.map(|q| Vec2::new(2.0 * q.x + q.z, 3.0 * q.y));
        let (gu, gv) = uv_gradients(p, uv);
        for q in [p[1] - p[0], p[2] - p[0], (p[1] + p[2]) * 0.5 - p[0]] {
            let want = Vec2::new(2.0 * q.x + q.z, 3.0 * q.y);
            assert!((Vec2::new(gu.dot(q), gv.dot(q)) - want).length() < 1e-5);
        }
        assert_eq!(
            uv_gradients([Vec3::ZERO; 3], [Vec2::ZERO; 3]),
            (Vec3::ZERO, Vec3::ZERO)
        );
    }
}
