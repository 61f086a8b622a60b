//! **Colour error**: whether a method's colours are right, not only whether they hold still.
//!
//! A method's frame and a truth frame of the same camera and lighting (the `raster` method:
//! the full-resolution raster, every pixel lit on its own) are both reduced to the art-pixel
//! grid (a box filter in linear light over the output pixels each art pixel covers, the
//! grid `naive` renders at), and each art pixel where the truth shows an object on at least
//! half its pixels scores the OKLab distance (ΔE) between the two. A frame scores the mean
//! and the 95th percentile over those art pixels. Dark streaks, light leaks, wrong shadows
//! or a sprite drawn too dark raise it even when they hold still; a picture shifted by less
//! than an art pixel raises it little, as the box filter blends what moved.
//! [`colour_error_overlay`] paints where it comes from (`texel-eval compare --colour`).

use glam::UVec2;

use crate::metrics::{linear_from_srgb8, oklab_distance, oklab_from_linear, percentile};
use crate::runner::{EvalError, Method};

/// A frame's colour error.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ColourError {
    /// Mean OKLab ΔE over the art pixels showing an object.
    pub mean: f64,
    /// Its 95th percentile.
    pub p95: f64,
}

impl ColourError {
    /// The mean of frames' means and of their 95th percentiles (zero for none).
    pub fn mean_of(frames: &[ColourError]) -> ColourError {
        let n = frames.len().max(1) as f64;
        ColourError {
            mean: frames.iter().map(|f| f.mean).sum::<f64>() / n,
            p95: frames.iter().map(|f| f.p95).sum::<f64>() / n,
        }
    }
}

/// The art-pixel grid of a `size` frame at faces of `face_res` and a vertical field of view
/// `fov_y`: the low-resolution size `naive` renders at.
pub fn art_pixel_grid(size: UVec2, face_res: u32, fov_y: f32) -> Result<UVec2, EvalError> {
    let height = texel_render::baselines::art_pixel_height(face_res, fov_y)
        .map_err(|e| EvalError::Input(e.to_string()))?;
    Ok(texel_render::baselines::low_res_size(size, height))
}

/// `methods` with the raster first (when it is among them), so its frames are the truth of
/// the colour error of the methods after it.
pub fn raster_first(methods: &[Method]) -> Vec<Method> {
    let mut order = methods.to_vec();
    order.sort_by_key(|m| *m != Method::Raster);
    order
}

/// The raster's frames of a path, in order: colour (RGBA8) and object ids.
pub type Truth = Vec<(Vec<u8>, Vec<u32>)>;

/// Per art pixel of a `grid` over a `size` frame: the mean linear colour of `rgba` and the
/// share of its pixels whose `ids` are not 0.
fn reduce(rgba: &[u8], ids: &[u32], size: UVec2, grid: UVec2) -> Vec<([f32; 3], f32)> {
    let cells = (grid.x * grid.y) as usize;
    let mut sum = vec![([0f32; 3], 0u32, 0u32); cells];
    for y in 0..size.y {
        let gy = (u64::from(y) * u64::from(grid.y) / u64::from(size.y)) as u32;
        for x in 0..size.x {
            let gx = (u64::from(x) * u64::from(grid.x) / u64::from(size.x)) as u32;
            let i = (y * size.x + x) as usize;
            let cell = &mut sum[(gy * grid.x + gx) as usize];
            for c in 0..3 {
                cell.0[c] += linear_from_srgb8(rgba[4 * i + c]);
            }
            cell.1 += 1;
            cell.2 += u32::from(ids[i] != 0);
        }
    }
    sum.into_iter()
        .map(|(c, n, objects)| {
            let n = n.max(1) as f32;
            (c.map(|v| v / n), objects as f32 / n)
        })
        .collect()
}

/// Per art pixel of a `grid` (row-major), the OKLab ΔE of `frame` against `truth`, or `None`
/// where fewer than half the truth's pixels show an object.
pub fn colour_error_map(
    frame: &[u8],
    truth: &[u8],
    truth_ids: &[u32],
    size: UVec2,
    grid: UVec2,
) -> Vec<Option<f64>> {
    let pixels = (size.x * size.y) as usize;
    assert!(
        frame.len() == 4 * pixels && truth.len() == 4 * pixels && truth_ids.len() == pixels,
        "colour_error: frames of {size} pixels expected"
    );
    let grid = grid.clamp(UVec2::ONE, size);
    let ones = vec![1u32; pixels];
    let a = reduce(frame, &ones, size, grid);
    let b = reduce(truth, truth_ids, size, grid);
    (a.iter().zip(&b))
        .map(|((ca, _), (cb, objects))| {
            (*objects >= 0.5).then(|| {
                f64::from(oklab_distance(
                    oklab_from_linear(*ca),
                    oklab_from_linear(*cb),
                ))
            })
        })
        .collect()
}

/// The colour error of `frame` (RGBA8 sRGB) against `truth` and its ids, both `size`,
/// reduced to art pixels on a `grid`; `None` when the truth shows no object.
pub fn colour_error(
    frame: &[u8],
    truth: &[u8],
    truth_ids: &[u32],
    size: UVec2,
    grid: UVec2,
) -> Option<ColourError> {
    let mut errors: Vec<f64> = colour_error_map(frame, truth, truth_ids, size, grid)
        .into_iter()
        .flatten()
        .collect();
    if errors.is_empty() {
        return None;
    }
    errors.sort_by(f64::total_cmp);
    Some(ColourError {
        mean: errors.iter().sum::<f64>() / errors.len() as f64,
        p95: percentile(&errors, 0.95),
    })
}

/// `frame` dimmed to grey, each art pixel of a `grid` tinted by its colour error against
/// `truth`: red to full strength at ΔE [`MAP_FULL`] (a lightness band is 0.031). RGBA8
/// like the frames.
pub fn colour_error_overlay(
    frame: &[u8],
    truth: &[u8],
    truth_ids: &[u32],
    size: UVec2,
    grid: UVec2,
) -> Vec<u8> {
    let map = colour_error_map(frame, truth, truth_ids, size, grid);
    let grid = grid.clamp(UVec2::ONE, size);
    let mut out = frame.to_vec();
    for y in 0..size.y {
        let gy = (u64::from(y) * u64::from(grid.y) / u64::from(size.y)) as u32;
        for x in 0..size.x {
            let gx = (u64::from(x) * u64::from(grid.x) / u64::from(size.x)) as u32;
            let i = 4 * (y * size.x + x) as usize;
            let px = &mut out[i..i + 3];
            let grey = (u32::from(px[0]) * 3 + u32::from(px[1]) * 6 + u32::from(px[2])) / 20;
            let grey = grey as f64;
            let e = map[(gy * grid.x + gx) as usize].unwrap_or(0.0);
            let t = (e / MAP_FULL).min(1.0);
            let rgb = [
                grey + (255.0 - grey) * t,
                grey * (1.0 - t),
                grey * (1.0 - t),
            ];
            for (c, v) in px.iter_mut().zip(rgb) {
                *c = v.round() as u8;
            }
        }
    }
    out
}

/// ΔE at which [`colour_error_overlay`] paints an art pixel full red: three lightness bands.
pub const MAP_FULL: f64 = 0.1;

#[cfg(test)]
mod tests {
    use super::*;

    const SIZE: UVec2 = UVec2::new(64, 64);
    /// Art pixels of 4 × 4 output pixels.
    const GRID: UVec2 = UVec2::new(16, 16);

    fn srgb8(linear: f32) -> u8 {
        let c = if linear <= 0.003_130_8 {
            linear * 12.92
        } else {
            1.055 * linear.powf(1.0 / 2.4) - 0.055
        };
        (c * 255.0).round() as u8
    }

    /// A frame of linear greys `f(x, y)`, every pixel an object.
    fn grey(f: impl Fn(u32, u32) -> f32) -> (Vec<u8>, Vec<u32>) {
        let mut px = Vec::new();
        for y in 0..SIZE.y {
            for x in 0..SIZE.x {
                let v = srgb8(f(x, y));
                px.extend([v, v, v, 255]);
            }
        }
        (px, vec![1; (SIZE.x * SIZE.y) as usize])
    }

    /// A checker of 16-pixel squares (four art pixels), linear greys 0.4 and 0.6, moved
    /// `dx` pixels to the right.
    fn checker(dx: u32) -> (Vec<u8>, Vec<u32>) {
        grey(|x, y| {
            if ((x + 64 - dx) / 16 + y / 16).is_multiple_of(2) {
                0.6
            } else {
                0.4
            }
        })
    }

    #[test]
    fn the_truth_against_itself_scores_zero() {
        let (t, ids) = checker(0);
        let e = colour_error(&t, &t, &ids, SIZE, GRID).expect("objects");
        assert_eq!((e.mean, e.p95), (0.0, 0.0));
    }

    #[test]
    fn a_frame_ten_percent_darker_scores_what_oklab_says() {
        // For a grey, OKLab's L is the cube root of the linear value (a and b are 0), so 10 %
        // less light lowers L by (1 - 0.9^(1/3)) L = 0.0345 L: here L lies between
        // 0.4^(1/3) = 0.737 and 0.6^(1/3) = 0.843, so ΔE lies in [0.0254, 0.0291] (widened
        // by sRGB8's rounding).
        let (t, ids) = checker(0);
        let (dark, _) = grey(|x, y| {
            0.9 * if (x / 16 + y / 16).is_multiple_of(2) {
                0.6
            } else {
                0.4
            }
        });
        let e = colour_error(&dark, &t, &ids, SIZE, GRID).expect("objects");
        assert!((0.024..=0.031).contains(&e.mean), "{e:?}");
        assert!((0.024..=0.031).contains(&e.p95), "{e:?}");
    }

    #[test]
    fn a_one_art_pixel_shift_of_a_checker_scores_less_than_a_wrong_shadow() {
        let (t, ids) = checker(0);
        // One art pixel to the right: one column in four of art pixels changes square.
        let (shifted, _) = checker(4);
        let shift = colour_error(&shifted, &t, &ids, SIZE, GRID).expect("objects");
        // Half a texel: the art pixels at the squares' edges blend the two greys.
        let (half, _) = checker(2);
        let half = colour_error(&half, &t, &ids, SIZE, GRID).expect("objects");
        // A wrong shadow: a quarter of the frame (a 32 × 32 square) at half the light.
        let (shadow, _) = grey(|x, y| {
            let base = if (x / 16 + y / 16).is_multiple_of(2) {
                0.6
            } else {
                0.4
            };
            if x < 32 && y < 32 { base * 0.5 } else { base }
        });
        let shadow = colour_error(&shadow, &t, &ids, SIZE, GRID).expect("objects");
        assert!(half.mean < shift.mean, "{half:?} {shift:?}");
        assert!(shift.mean < shadow.mean, "{shift:?} {shadow:?}");
        assert!(shift.p95 < shadow.p95, "{shift:?} {shadow:?}");
    }

    #[test]
    fn the_map_paints_only_the_art_pixels_in_error() {
        let (t, ids) = checker(0);
        let (shadow, _) = grey(|x, y| {
            let base = if (x / 16 + y / 16).is_multiple_of(2) {
                0.6
            } else {
                0.4
            };
            if x < 32 && y < 32 { base * 0.5 } else { base }
        });
        let map = colour_error_overlay(&shadow, &t, &ids, SIZE, GRID);
        let px = |x: usize, y: usize| &map[4 * (y * 64 + x)..4 * (y * 64 + x) + 3];
        let shaded = px(5, 5);
        assert!(
            shaded[0] > shaded[1],
            "the shadow is tinted red: {shaded:?}"
        );
        let clear = px(50, 50);
        assert_eq!(clear[0], clear[1], "the rest stays grey: {clear:?}");
    }

    #[test]
    fn only_art_pixels_mostly_on_objects_count() {
        let (t, mut ids) = checker(0);
        let (wrong, _) = grey(|_, _| 0.0);
        ids.iter_mut().for_each(|i| *i = 0);
        assert_eq!(colour_error(&wrong, &t, &ids, SIZE, GRID), None);
        // One art pixel of objects: only it counts.
        for y in 0..4 {
            for x in 0..4 {
                ids[y * 64 + x] = 7;
            }
        }
        let e = colour_error(&t, &t, &ids, SIZE, GRID).expect("one art pixel");
        assert_eq!(e.mean, 0.0);
    }
}
