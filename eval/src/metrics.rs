//! Exact stability and accuracy metrics, computed on the CPU from a method's frames and a
//! reference G-buffer per frame (world position and object id per pixel at the same camera).
//! No optical flow: every correspondence comes from projecting a known world point.
//!
//! - **Shimmer** ([`flicker`]): for each pixel of frame t that shows geometry in the
//!   reference, its world point is projected into frame t−1 with t−1's camera. The point is
//!   kept if it was visible there (the same object id in t−1's reference, view depth agreeing
//!   within [`MetricParams::depth_tolerance`]) and lies away from id edges (a one-pixel
//!   margin in both frames). It counts as flicker if the method's colour at t differs, by more
//!   than [`MetricParams::oklab_threshold`] in OKLab, from every one of the four t−1 pixels
//!   whose centres surround the projected point. Taking the closest of the four makes the
//!   metric blind to resampling alone: a colour edge fixed in the world always has one of the
//!   four on the same side, so a world-stable image scores 0 while screen-locked noise
//!   scores about 1.
//!
//!   **Intended change is not shimmer.** When the frames carry the truth's colours (the
//!   full-resolution `raster` at the same cameras: [`FrameView::truth`]), a tested pixel
//!   whose truth changed by the same test (a sprite's next frame, a turning part's shading,
//!   anything the scene moves on purpose) is left out of the shimmer ([`FlickerCount::fraction`]);
//!   every tested pixel still counts in [`FlickerCount::all_fraction`], the number before
//!   this rule. Without a truth both are the same.
//! - **Coverage error** ([`coverage`]): the fraction of pixels whose method id differs from
//!   the reference id; **hole rate**: pixels where the reference shows geometry and the
//!   method shows sky or nothing.

use glam::{Mat4, UVec2, Vec2, Vec3, Vec4Swizzles};
use texel_render::input::Camera;

/// A reference G-buffer: what a plain full-resolution raster sees at one camera.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Reference {
    /// Width and height in pixels.
    pub size: UVec2,
    /// World position per pixel, row-major (unused where `id` is 0).
    pub world: Vec<[f32; 3]>,
    /// Object id per pixel (0 = sky or nothing).
    pub id: Vec<u32>,
    /// The moving objects at this frame: entity id and object → world transform. A pixel of
    /// one is followed to where that point of the object was in the previous frame.
    pub poses: Vec<(u32, glam::Mat4)>,
    /// Entity ids of the sprites: their pixels' shimmer is counted apart too.
    pub sprites: Vec<u32>,
}

/// One frame of a method together with its reference.
#[derive(Debug, Clone, Copy)]
pub struct FrameView<'a> {
    /// The camera of the frame.
    pub camera: Camera,
    /// The reference G-buffer at that camera.
    pub reference: &'a Reference,
    /// The method's colour, RGBA8 sRGB, row-major, the reference's size.
    pub colour: &'a [u8],
    /// The method's object id per pixel (0 = sky or nothing).
    pub ids: &'a [u32],
    /// Per pixel, whether the method took it from the eye probe (splat methods only).
    pub from_eye: Option<&'a [bool]>,
    /// The truth's colour at this camera (RGBA8 sRGB, the reference's size): where it
    /// changed at a world point, so may the method's.
    pub truth: Option<&'a [u8]>,
}

/// Thresholds of the metrics.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MetricParams {
    /// OKLab distance above which a colour counts as changed. One of 32 lightness bands is
    /// 0.031, so a single band step counts.
    pub oklab_threshold: f32,
    /// Relative view-depth tolerance of the visibility test in t−1.
    pub depth_tolerance: f32,
}

impl Default for MetricParams {
    fn default() -> Self {
        MetricParams {
            oklab_threshold: 0.02,
            depth_tolerance: 0.02,
        }
    }
}

/// Why two frames cannot be compared.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MetricError {
    /// Buffers disagree with the reference size.
    #[error("frame buffers do not match the reference size {0}×{1}")]
    SizeMismatch(u32, u32),
    /// Consecutive frames differ in size.
    #[error("consecutive frames differ in size")]
    SizeChanged,
}

/// Flicker between two consecutive frames.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct FlickerCount {
    /// Pixels of frame t whose world point was visible in t−1 (the denominator).
    pub tested: u64,
    /// Of those, pixels whose colour changed.
    pub flicker: u64,
    /// Of the flickering pixels, those the method took from the eye probe at t.
    pub flicker_eye: u64,
    /// Of the tested pixels, those showing a moving object.
    pub tested_moving: u64,
    /// Of those, pixels whose colour changed.
    pub flicker_moving: u64,
    /// Of the tested pixels, those showing a sprite.
    pub tested_sprite: u64,
    /// Of those, pixels whose colour changed.
    pub flicker_sprite: u64,
    /// Of the tested pixels, those whose truth did not change (all of them without a truth).
    pub tested_held: u64,
    /// Of those, pixels whose colour changed: the shimmer.
    pub flicker_held: u64,
}

impl FlickerCount {
    /// The shimmer: the flicker fraction of the pixels whose truth held (of every tested
    /// pixel without a truth), 0 when nothing could be tested.
    pub fn fraction(&self) -> f64 {
        ratio(self.flicker_held, self.tested_held).unwrap_or(0.0)
    }

    /// The flicker fraction of every tested pixel, the truth's changes included.
    pub fn all_fraction(&self) -> f64 {
        ratio(self.flicker, self.tested).unwrap_or(0.0)
    }

    /// The flicker fraction of the moving objects' pixels, `None` when none was tested.
    pub fn moving_fraction(&self) -> Option<f64> {
        ratio(self.flicker_moving, self.tested_moving)
    }

    /// The flicker fraction of sprites' pixels, `None` when none was tested.
    pub fn sprite_fraction(&self) -> Option<f64> {
        ratio(self.flicker_sprite, self.tested_sprite)
    }

    /// The flicker fraction of the still world's pixels, `None` when none was tested.
    pub fn still_fraction(&self) -> Option<f64> {
        ratio(
            self.flicker - self.flicker_moving,
            self.tested - self.tested_moving,
        )
    }
}

fn ratio(a: u64, b: u64) -> Option<f64> {
    (b > 0).then(|| a as f64 / b as f64)
}

pub use texel_geom::colour::{linear_from_srgb8, oklab_from_linear, oklab_from_srgb8};

/// Euclidean distance in OKLab (ΔE).
pub fn oklab_distance(a: [f32; 3], b: [f32; 3]) -> f32 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// The camera's world → clip matrix for a `size` frame.
pub fn view_proj(camera: &Camera, size: UVec2) -> Mat4 {
    camera.projection(size.x as f32 / size.y.max(1) as f32) * camera.view()
}

/// Projects `p` to continuous pixel coordinates (pixel centres at `x + 0.5`, row 0 at the
/// top), or `None` behind the camera or outside the depth range.
pub fn project(vp: &Mat4, size: UVec2, p: Vec3) -> Option<Vec2> {
    let c = *vp * p.extend(1.0);
    if c.w <= 1e-6 {
        return None;
    }
    let n = c.xyz() / c.w;
    if !(0.0..=1.0).contains(&n.z) {
        return None;
    }
    Some(Vec2::new(
        (n.x * 0.5 + 0.5) * size.x as f32,
        (0.5 - n.y * 0.5) * size.y as f32,
    ))
}

fn check(f: &FrameView<'_>) -> Result<usize, MetricError> {
    let size = f.reference.size;
    let n = (size.x * size.y) as usize;
    let eye_ok = f.from_eye.is_none_or(|e| e.len() == n);
    let truth_ok = f.truth.is_none_or(|t| t.len() == n * 4);
    if !truth_ok
        || f.reference.world.len() != n
        || f.reference.id.len() != n
        || f.colour.len() != n * 4
        || f.ids.len() != n
        || !eye_ok
    {
        return Err(MetricError::SizeMismatch(size.x, size.y));
    }
    Ok(n)
}

/// Whether the 3×3 neighbourhood of `(x, y)` (clamped to the frame) all holds `id`.
fn interior(ids: &[u32], size: UVec2, x: u32, y: u32, id: u32) -> bool {
    let (w, h) = (size.x as i64, size.y as i64);
    for dy in -1..=1 {
        for dx in -1..=1 {
            let (nx, ny) = (x as i64 + dx, y as i64 + dy);
            if nx < 0 || ny < 0 || nx >= w || ny >= h {
                continue;
            }
            if ids[(ny * w + nx) as usize] != id {
                return false;
            }
        }
    }
    true
}

fn view_depth(camera: &Camera, p: Vec3) -> f32 {
    (p - camera.position).dot(camera.forward)
}

/// Motion-compensated flicker of `cur` (frame t) against `prev` (frame t−1); see the module
/// documentation for the exact test.
pub fn flicker(
    prev: &FrameView<'_>,
    cur: &FrameView<'_>,
    params: &MetricParams,
) -> Result<FlickerCount, MetricError> {
    flicker_into(prev, cur, params, None)
}

/// What [`flicker_map`] says of one pixel.
pub mod map {
    /// Not tested (sky, an id edge, not visible in the previous frame).
    pub const UNTESTED: u8 = 0;
    /// Tested, unchanged.
    pub const STABLE: u8 = 1;
    /// Changed.
    pub const FLICKER: u8 = 2;
    /// Changed, and the method took it from the eye probe.
    pub const FLICKER_EYE: u8 = 3;
    /// Changed where the truth changed too: intended, not shimmer.
    pub const INTENDED: u8 = 4;
}

/// [`flicker`], and per pixel of `cur` what it found ([`map`]): where a method shimmers.
pub fn flicker_map(
    prev: &FrameView<'_>,
    cur: &FrameView<'_>,
    params: &MetricParams,
) -> Result<(FlickerCount, Vec<u8>), MetricError> {
    let mut out = vec![map::UNTESTED; cur.reference.id.len()];
    let count = flicker_into(prev, cur, params, Some(&mut out))?;
    Ok((count, out))
}

fn flicker_into(
    prev: &FrameView<'_>,
    cur: &FrameView<'_>,
    params: &MetricParams,
    mut mask: Option<&mut Vec<u8>>,
) -> Result<FlickerCount, MetricError> {
    check(prev)?;
    check(cur)?;
    let size = cur.reference.size;
    if prev.reference.size != size {
        return Err(MetricError::SizeChanged);
    }
    let vp = view_proj(&prev.camera, size);
    // Per moving object: world now → world at t−1 (objects absent from t−1 are still).
    let moving_to_prev: Vec<(u32, glam::Mat4)> = (cur.reference.poses.iter())
        .map(|&(id, now)| {
            let before = (prev.reference.poses.iter())
                .find(|(p, _)| *p == id)
                .map_or(now, |(_, m)| *m);
            (id, before * now.inverse())
        })
        .collect();
    let (w, h) = (size.x, size.y);
    let rgb = |c: &[u8], i: usize| [c[i * 4], c[i * 4 + 1], c[i * 4 + 2]];
    let mut out = FlickerCount::default();
    for y in 0..h {
        for x in 0..w {
            let i = (y * w + x) as usize;
            let id = cur.reference.id[i];
            if id == 0 || !interior(&cur.reference.id, size, x, y, id) {
                continue;
            }
            // A moving object's point: where it was on the object in t−1.
            let moving = moving_to_prev
                .iter()
                .find(|(m, _)| *m == id)
                .map(|(_, m)| *m);
            let p = match moving {
                Some(m) => m.transform_point3(Vec3::from(cur.reference.world[i])),
                None => Vec3::from(cur.reference.world[i]),
            };
            let Some(q) = project(&vp, size, p) else {
                continue;
            };
            // The four pixel centres around q: columns x0, x0+1 and rows y0, y0+1.
            let (fx, fy) = ((q.x - 0.5).floor(), (q.y - 0.5).floor());
            if fx < 0.0 || fy < 0.0 || fx + 1.0 >= w as f32 || fy + 1.0 >= h as f32 {
                continue;
            }
            let (x0, y0) = (fx as u32, fy as u32);
            let (nx, ny) = (
                (q.x.floor() as u32).min(w - 1),
                (q.y.floor() as u32).min(h - 1),
            );
            let j = (ny * w + nx) as usize;
            if prev.reference.id[j] != id || !interior(&prev.reference.id, size, nx, ny, id) {
                continue;
            }
            let d_point = view_depth(&prev.camera, p);
            let d_seen = view_depth(&prev.camera, Vec3::from(prev.reference.world[j]));
            if (d_point - d_seen).abs() > params.depth_tolerance * d_point.abs().max(1e-3) {
                continue;
            }
            out.tested += 1;
            out.tested_moving += u64::from(moving.is_some());
            let sprite = cur.reference.sprites.contains(&id);
            out.tested_sprite += u64::from(sprite);
            let changed_in = |now: &[u8], before: &[u8]| {
                let c = oklab_from_srgb8(rgb(now, i));
                [(0, 0), (1, 0), (0, 1), (1, 1)].iter().all(|(dx, dy)| {
                    let k = ((y0 + dy) * w + x0 + dx) as usize;
                    oklab_distance(c, oklab_from_srgb8(rgb(before, k))) > params.oklab_threshold
                })
            };
            let changed = changed_in(cur.colour, prev.colour);
            let held = match (cur.truth, prev.truth) {
                (Some(now), Some(before)) => !changed_in(now, before),
                _ => true,
            };
            out.tested_held += u64::from(held);
            out.flicker_held += u64::from(held && changed);
            let eye = cur.from_eye.is_some_and(|e| e[i]);
            if let Some(mask) = mask.as_deref_mut() {
                mask[i] = match (changed, held, eye) {
                    (false, _, _) => map::STABLE,
                    (true, false, _) => map::INTENDED,
                    (true, true, false) => map::FLICKER,
                    (true, true, true) => map::FLICKER_EYE,
                };
            }
            if changed {
                out.flicker += 1;
                out.flicker_moving += u64::from(moving.is_some());
                out.flicker_sprite += u64::from(sprite);
                out.flicker_eye += u64::from(eye);
            }
        }
    }
    Ok(out)
}

/// Coverage of one frame.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Coverage {
    /// Fraction of pixels whose method id differs from the reference id.
    pub error: f64,
    /// Fraction of pixels where the reference shows geometry and the method does not.
    pub holes: f64,
    /// Fraction of pixels taken from the eye probe (0 without provenance).
    pub eye: f64,
}

/// Coverage error, hole rate and eye fraction of one frame.
pub fn coverage(frame: &FrameView<'_>) -> Result<Coverage, MetricError> {
    let n = check(frame)?;
    if n == 0 {
        return Ok(Coverage::default());
    }
    let r = &frame.reference.id;
    let wrong = r.iter().zip(frame.ids).filter(|(a, b)| a != b).count();
    let holes = r
        .iter()
        .zip(frame.ids)
        .filter(|(a, b)| **a != 0 && **b == 0)
        .count();
    let eye = frame
        .from_eye
        .map_or(0, |e| e.iter().filter(|e| **e).count());
    Ok(Coverage {
        error: wrong as f64 / n as f64,
        holes: holes as f64 / n as f64,
        eye: eye as f64 / n as f64,
    })
}

/// Mean, 95th percentile and maximum of per-frame values.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Summary {
    /// Mean.
    pub mean: f64,
    /// 95th percentile (nearest rank).
    pub p95: f64,
    /// Maximum.
    pub max: f64,
}

impl Summary {
    /// The summary of `values` (all zero when empty).
    pub fn of(values: &[f64]) -> Self {
        if values.is_empty() {
            return Summary::default();
        }
        let mut v = values.to_vec();
        v.sort_by(f64::total_cmp);
        Summary {
            mean: v.iter().sum::<f64>() / v.len() as f64,
            p95: percentile(&v, 0.95),
            max: v[v.len() - 1],
        }
    }
}

/// The `q` quantile (0..=1, nearest rank) of sorted `v`, 0 when empty.
pub fn percentile(v: &[f64], q: f64) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    let rank = (q * v.len() as f64).ceil() as usize;
    v[rank.clamp(1, v.len()) - 1]
}

#[cfg(test)]
mod tests;
