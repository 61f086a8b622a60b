//! Draw ranges: the vertex buffer cut into runs of one object with their world bounds, so a
//! raster draws only what its frustum meets, and terrain chunks at the level of detail each
//! view picks ([`chunk_lod`]); neighbouring runs merge into one draw.

use glam::Vec3;

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
    /// The instance record it is drawn with (`GpuScene::instances`): 0, the identity, for
    /// vertices written in world space; another for a shared mesh's object-space vertices.
    pub instance: u32,
}

/// A draw: `(first vertex, vertex count, instance record)`.
pub type Run = (u32, u32, u32);

impl DrawRange {
    /// Whether any part of the box may be inside the clip volume of `view_proj` (depth 0..1):
    /// false only when all eight corners are beyond one clip plane.
    pub fn may_be_visible(&self, view_proj: &glam::Mat4) -> bool {
        box_may_be_visible(self.min, self.max, view_proj)
    }
}

/// Whether any part of the box `min..max` may be inside the clip volume of `view_proj`
/// ([`DrawRange::may_be_visible`]). A box wholly beyond one clip plane holds only boxes that
/// are too (the plane is a half-space in world space): `RangeIndex` skips them.
pub(super) fn box_may_be_visible(min: Vec3, max: Vec3, view_proj: &glam::Mat4) -> bool {
    let corners: [glam::Vec4; 8] = std::array::from_fn(|i| {
        let p = Vec3::new(
            if i & 1 == 0 { min.x } else { max.x },
            if i & 2 == 0 { min.y } else { max.y },
            if i & 4 == 0 { min.z } else { max.z },
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

/// Every range at level 0 (terrains at full detail), neighbours merged.
pub fn full_detail_runs(ranges: &[DrawRange]) -> Vec<Run> {
    merge_runs(ranges.iter().filter(|r| r.lod == 0))
}

/// Vertex runs `(first, count, instance)` of `ranges` (in buffer order), contiguous ones of
/// one instance record merged into one draw.
pub(super) fn merge_runs<'a>(ranges: impl Iterator<Item = &'a DrawRange>) -> Vec<Run> {
    let mut runs: Vec<Run> = Vec::new();
    for r in ranges {
        match runs.last_mut() {
            Some(last) if last.0 + last.1 == r.first && last.2 == r.instance => last.1 += r.count,
            _ => runs.push((r.first, r.count, r.instance)),
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
pub(super) fn chunk_lod_within(r: &DrawRange, origin: Vec3, n: u32, texels: f32) -> u32 {
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
pub fn visible_runs(ranges: &[DrawRange], view_proj: &glam::Mat4, lod: LodFrom) -> Vec<Run> {
    merge_runs(
        ranges_drawn_by(
            ranges,
            None,
            view_proj,
            lod,
            CaptureCull::Footprint,
            &|_: &DrawRange| true,
        )
        .into_iter(),
    )
}

/// [`visible_runs`] split by [`DrawRange::terrain`]: the plain terrain's runs, then the rest
/// (each in the order `visible_runs` draws them), under `cull`; and how many ranges they
/// hold.
pub fn visible_runs_by_kind(
    ranges: &[DrawRange],
    view_proj: &glam::Mat4,
    lod: LodFrom,
    cull: CaptureCull,
) -> ([Vec<Run>; 2], usize) {
    visible_runs_where(ranges, None, view_proj, lod, cull, &|_: &DrawRange| true)
}

/// [`visible_runs_by_kind`] of the ranges `keep` keeps (an eye's far face: those wholly
/// beyond the eye's distance, `crate::far_field`); with `index` (the scene's
/// [`RangeIndex`](super::RangeIndex) over `ranges`), only the ranges it leaves are tested.
pub fn visible_runs_where(
    ranges: &[DrawRange],
    index: Option<&super::RangeIndex>,
    view_proj: &glam::Mat4,
    lod: LodFrom,
    cull: CaptureCull,
    keep: &dyn Fn(&DrawRange) -> bool,
) -> ([Vec<Run>; 2], usize) {
    let visible = ranges_drawn_by(ranges, index, view_proj, lod, cull, keep);
    let count = visible.len();
    let (terrain, rest): (Vec<&DrawRange>, Vec<&DrawRange>) =
        visible.into_iter().partition(|r| r.terrain);
    ([terrain, rest].map(|r| merge_runs(r.into_iter())), count)
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

/// The ranges a face draws under `cull` of those `keep` keeps (asked last, of the ranges
/// the rest keeps), in the order it draws them;
/// with `index` (over `ranges`), only those it leaves are tested, the same ones drawn.
pub(super) fn ranges_drawn_by<'a>(
    ranges: &'a [DrawRange],
    index: Option<&super::RangeIndex>,
    view_proj: &glam::Mat4,
    lod: LodFrom,
    cull: CaptureCull,
    keep: &dyn Fn(&DrawRange) -> bool,
) -> Vec<&'a DrawRange> {
    let wanted = |r: &DrawRange| match lod {
        LodFrom::Full => r.lod == 0,
        LodFrom::Probe(origin, n) => r.lod == chunk_lod(r, origin, n),
        LodFrom::Eye(origin, n) => r.lod == chunk_lod_within(r, origin, n, EYE_LOD_SAMPLE_TEXELS),
        LodFrom::Texel(size) => r.lod == lod_for_texel(r, size),
    };
    let drawn = |r: &&DrawRange| {
        wanted(r)
            && (cull != CaptureCull::Footprint || spans_a_texel(r, lod))
            && (cull == CaptureCull::Nothing || r.may_be_visible(view_proj))
            && keep(r)
    };
    let mut visible: Vec<&DrawRange> = match index {
        Some(index) => (index.candidates(view_proj, lod, cull).into_iter())
            .map(|i| &ranges[i as usize])
            .filter(drawn)
            .collect(),
        None => ranges.iter().filter(drawn).collect(),
    };
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
