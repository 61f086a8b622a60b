//! Occlusion of a stable face captured again in part ([`crate::input::PartialFace`]): what
//! the face already holds bounds what the objects an edit left alone can show, so those
//! lying wholly behind it are left out of the capture, and the face comes out the same.
//!
//! Before the face is drawn its rectangle's depths and ids are read back
//! ([`HeldFace::read`]). At a texel whose object the edits did not rewrite, that object is
//! still there (it did not move) and every other one left alone lost to it: the rasterizer
//! kept the fragment nearest along the face's axis (depth test `Less`). Drawn again, the
//! texel shows that object or something nearer, so a range whose nearest corner lies beyond
//! that object's depth at every texel its box may cover within the rectangle cannot show
//! there, and is skipped ([`HeldFace::hides`]). Texels open to anything: the sky's, the
//! edited objects' (their old surfaces bound nothing), a terrain's (its stored depth is the
//! full-detail surface's, not the drawn level's). The edited objects' own ranges are always
//! drawn.
//!
//! The depth a texel stores is not quite the depth the rasterizer tested: `capture.wgsl`
//! `centre_depth` stores where the texel's centre ray meets the triangle's plane, and takes
//! it only within a quarter of the interpolated depth of the fragment (the one the depth test
//! compared), so that depth is at most `4/3` of the stored one: the bound is the stored depth
//! times [`DEPTH_MARGIN`]. A fragment of a range lies between its triangle's vertices' depths,
//! so at least at the nearest corner of its box; its texels are those whose centres its
//! box's projection may cover, widened by [`FOOTPRINT_MARGIN_TEXELS`] for the rasterizer's
//! vertex snapping (to a sixteenth of a texel at the coarsest, SwiftShader's 4 bits).

use std::ops::Range;

use glam::{Mat4, Vec3};
use texel_probes::cube::Face;
use texel_probes::visibility::TexelRect;

use crate::context::{GpuContext, GpuError};
use crate::gpu_scene::{DrawRange, GpuScene};
use crate::probe_store::SlotTextures;
use crate::target::read_texture_region;

/// What the stored depth of a texel is multiplied by to bound the depth the rasterizer
/// tested there (`4/3`: see the module's notes), with room for rounding and for the depth
/// buffer's resolution (32-bit float depth from `CAPTURE_NEAR`: 0.15 % of the depth at
/// `CAPTURE_FAR`), so that what is skipped lies strictly behind, never level with it.
pub const DEPTH_MARGIN: f32 = 4.0 / 3.0 * 1.01;

/// How far around a box's projection a texel's centre is counted as covered by it (eight
/// times the rasterizer's coarsest snapping).
pub const FOOTPRINT_MARGIN_TEXELS: f32 = 0.5;

/// The depths and ids a stable face held over the rectangle it is captured again in, as
/// bounds on what the objects an edit left alone can show there.
#[derive(Debug, Clone)]
pub struct HeldFace {
    rect: TexelRect,
    n: u32,
    origin: Vec3,
    axis: Vec3,
    view_proj: Mat4,
    /// Per texel of `rect`, by rows: the depth beyond which nothing left alone can show
    /// (infinite where anything may).
    bound: Vec<f32>,
    /// Indices in the scene's ranges of the edited objects' ranges, drawn whatever lies
    /// in front of them.
    edited: Vec<Range<u32>>,
}

impl HeldFace {
    /// Reads back the depths and ids face `face` of `slot` holds over `rect` (waits for the
    /// GPU's work so far), for a capture at `origin` with `view_proj` whose edits since the
    /// face was last captured rewrote the scene's objects `edited`.
    pub fn read(
        ctx: &GpuContext,
        slot: &SlotTextures,
        (face, origin, view_proj): (Face, Vec3, Mat4),
        rect: TexelRect,
        scene: &GpuScene,
        edited: &[u32],
    ) -> Result<HeldFace, GpuError> {
        let n = slot.n;
        let rect = TexelRect {
            x0: rect.x0.min(n),
            y0: rect.y0.min(n),
            x1: rect.x1.min(n),
            y1: rect.y1.min(n),
        };
        let (at, size) = (
            glam::UVec2::new(rect.x0, rect.y0),
            glam::UVec2::new(
                rect.x1.saturating_sub(rect.x0),
                rect.y1.saturating_sub(rect.y0),
            ),
        );
        let layer = face.index() as u32;
        let (geo, ids) = match size.x * size.y {
            0 => (Vec::new(), Vec::new()),
            _ => (
                read_texture_region(ctx, &slot.geo.texture, layer, at, size, 16)?,
                read_texture_region(ctx, &slot.ids.texture, layer, at, size, 4)?,
            ),
        };
        let geo: &[[f32; 4]] = bytemuck::cast_slice(&geo);
        let ids: &[u32] = bytemuck::cast_slice(&ids);
        let draws = |id: u32| scene.object_draws(id as usize);
        let bound = (geo.iter().zip(ids))
            .map(|(g, &id)| {
                let open = id == 0
                    || edited.contains(&(id - 1))
                    || draws(id - 1).is_none_or(|(_, fixed)| fixed);
                match open || !(g[3].is_finite() && g[3] > 0.0) {
                    true => f32::INFINITY,
                    false => g[3] * DEPTH_MARGIN,
                }
            })
            .collect();
        Ok(HeldFace {
            rect,
            n,
            origin,
            axis: face.axis(),
            view_proj,
            bound,
            edited: (edited.iter()).filter_map(|&o| Some(draws(o)?.0)).collect(),
        })
    }

    /// Whether range `r` of `ranges` (the scene's) lies behind what the face holds at every
    /// texel of the rectangle it may cover (or covers none of them): drawn again, it would
    /// show nowhere in the rectangle.
    pub fn hides(&self, ranges: &[DrawRange], r: &DrawRange) -> bool {
        let at = (std::ptr::from_ref(r) as usize).wrapping_sub(ranges.as_ptr() as usize)
            / size_of::<DrawRange>().max(1);
        if at >= ranges.len() || self.edited.iter().any(|e| e.contains(&(at as u32))) {
            return false;
        }
        let corners: [Vec3; 8] = std::array::from_fn(|i| {
            Vec3::select(
                glam::BVec3::new(i & 1 != 0, i & 2 != 0, i & 4 != 0),
                r.max,
                r.min,
            )
        });
        let near = (corners.iter())
            .map(|&p| (p - self.origin).dot(self.axis))
            .fold(f32::INFINITY, f32::min);
        // A box reaching the probe's plane (or not a box) may cover anything.
        if near.is_nan() || near <= 0.0 {
            return false;
        }
        let (mut lo, mut hi) = (glam::Vec2::splat(f32::INFINITY), glam::Vec2::NEG_INFINITY);
        let n = self.n as f32;
        for p in corners {
            let clip = self.view_proj * p.extend(1.0);
            if clip.w.is_nan() || clip.w <= 0.0 {
                return false;
            }
            let t = glam::Vec2::new(clip.x / clip.w + 1.0, 1.0 - clip.y / clip.w) * (0.5 * n);
            (lo, hi) = (lo.min(t), hi.max(t));
        }
        if !(lo.is_finite() && hi.is_finite()) {
            return false;
        }
        // Texels whose centres (at half-integers) the widened projection may reach: `i`
        // with `lo - margin <= i + 0.5 <= hi + margin`.
        let span = |lo: f32, hi: f32, from: u32, to: u32| {
            let m = FOOTPRINT_MARGIN_TEXELS;
            let a = (lo - m - 0.5).ceil().max(from as f32) as u32;
            let b = ((hi + m - 0.5).floor() + 1.0).clamp(0.0, to as f32) as u32;
            a..b.max(a)
        };
        let xs = span(lo.x, hi.x, self.rect.x0, self.rect.x1);
        let ys = span(lo.y, hi.y, self.rect.y0, self.rect.y1);
        let w = (self.rect.x1 - self.rect.x0) as usize;
        ys.into_iter().all(|y| {
            let row = (y - self.rect.y0) as usize * w;
            let row = &self.bound[row..row + w];
            (xs.clone()).all(|x| near > row[(x - self.rect.x0) as usize])
        })
    }

    /// Texels of the rectangle where something left alone bounds what may show.
    pub fn bounded_texels(&self) -> usize {
        self.bound.iter().filter(|b| b.is_finite()).count()
    }
}
