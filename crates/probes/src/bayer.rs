//! The 4×4 Bayer matrix that dithers the crossfade between the previous and grid probes.
//!
//! A screen pixel `(x, y)` gets the threshold `b = (M[y mod 4][x mod 4] + 0.5) / 16`, one of
//! 16 distinct values strictly inside `(0, 1)`. With crossfade amount `fade_t`, the **grid**
//! probe draws the pixel when `b < fade_t` and the **previous** probe draws it otherwise:
//! the two patterns are complementary, every pixel is drawn by exactly one of them, at
//! `fade_t = 0` only the previous probe draws and at `fade_t = 1` only the grid probe. In a
//! 4×4 tile the grid probe owns `round_half_down(16 · fade_t)` pixels (exactly `k` at
//! `fade_t = k / 16`), and raising `fade_t` only ever hands pixels from previous to grid.
//! The pattern is fixed to the screen (ordered dither is temporally stable); the eye probe
//! is never dithered. Shaders must use the same matrix and the same strict `<`.

/// The classic recursive 4×4 Bayer matrix, indexed `[y][x]`, values `0..16`.
pub const BAYER_4X4: [[u8; 4]; 4] = [[0, 8, 2, 10], [12, 4, 14, 6], [3, 11, 1, 9], [15, 7, 13, 5]];

/// Which stable probe draws a pixel during a crossfade.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum DitherOwner {
    /// The grid probe (the one being faded in).
    Grid,
    /// The previous probe (the one being faded out).
    Previous,
}

/// The raw Bayer value `0..16` of screen pixel `(x, y)`.
pub fn bayer_value(x: u32, y: u32) -> u8 {
    BAYER_4X4[(y % 4) as usize][(x % 4) as usize]
}

/// The normalized threshold `(value + 0.5) / 16` of screen pixel `(x, y)`.
pub fn bayer_threshold(x: u32, y: u32) -> f32 {
    threshold_of(bayer_value(x, y))
}

/// The normalized threshold of a raw Bayer value.
pub fn threshold_of(value: u8) -> f32 {
    (f32::from(value) + 0.5) / 16.0
}

/// Who draws a pixel of threshold `threshold` at crossfade amount `fade_t`.
pub fn owner_at_threshold(threshold: f32, fade_t: f32) -> DitherOwner {
    if threshold < fade_t {
        DitherOwner::Grid
    } else {
        DitherOwner::Previous
    }
}

/// Who draws screen pixel `(x, y)` at crossfade amount `fade_t`.
pub fn dither_owner(x: u32, y: u32, fade_t: f32) -> DitherOwner {
    owner_at_threshold(bayer_threshold(x, y), fade_t)
}

/// Whether the grid probe draws screen pixel `(x, y)` at crossfade amount `fade_t`.
pub fn grid_draws(x: u32, y: u32, fade_t: f32) -> bool {
    dither_owner(x, y, fade_t) == DitherOwner::Grid
}

/// Whether the previous probe draws screen pixel `(x, y)`; always `!grid_draws(..)`.
pub fn previous_draws(x: u32, y: u32, fade_t: f32) -> bool {
    dither_owner(x, y, fade_t) == DitherOwner::Previous
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid_pixels(fade_t: f32) -> usize {
        (0..4)
            .flat_map(|y| (0..4).map(move |x| (x, y)))
            .filter(|&(x, y)| grid_draws(x, y, fade_t))
            .count()
    }

    #[test]
    fn matrix_is_a_permutation_of_0_to_15() {
        let mut seen = [false; 16];
        for row in BAYER_4X4 {
            for v in row {
                assert!(!seen[v as usize], "{v} twice");
                seen[v as usize] = true;
            }
        }
        assert!(seen.iter().all(|s| *s));
    }

    #[test]
    fn thresholds_are_normalized_and_tile() {
        assert_eq!(bayer_threshold(0, 0), 0.5 / 16.0);
        assert_eq!(bayer_threshold(0, 3), 15.5 / 16.0);
        assert_eq!(bayer_threshold(5, 6), bayer_threshold(1, 2));
        assert_eq!(bayer_value(1, 0), 8);
        assert!((0..16).all(|v| {
            let t = threshold_of(v);
            t > 0.0 && t < 1.0
        }));
    }

    #[test]
    fn patterns_are_complementary() {
        for t in [0.0, 0.1, 0.5, 0.77, 1.0] {
            for y in 0..8 {
                for x in 0..8 {
                    assert_ne!(grid_draws(x, y, t), previous_draws(x, y, t));
                }
            }
        }
    }

    #[test]
    fn coverage_follows_fade_t() {
        assert_eq!(grid_pixels(0.0), 0, "fade start: previous only");
        assert_eq!(grid_pixels(1.0), 16, "fade end: grid only");
        for k in 0..=16 {
            assert_eq!(grid_pixels(k as f32 / 16.0), k);
        }
    }

    #[test]
    fn raising_fade_t_only_adds_grid_pixels() {
        let steps: Vec<f32> = (0..=40).map(|i| i as f32 / 40.0).collect();
        for w in steps.windows(2) {
            for y in 0..4 {
                for x in 0..4 {
                    assert!(!grid_draws(x, y, w[0]) || grid_draws(x, y, w[1]));
                }
            }
        }
    }

    #[test]
    fn halfway_is_a_checker_of_the_2x2_level() {
        // At 0.5 the grid owns values 0..8: one per 2x2 block, in a regular pattern.
        for by in 0..2 {
            for bx in 0..2 {
                let owned = (0..2)
                    .flat_map(|y| (0..2).map(move |x| (2 * bx + x, 2 * by + y)))
                    .filter(|&(x, y)| grid_draws(x, y, 0.5))
                    .count();
                assert_eq!(owned, 2, "block {bx},{by}");
            }
        }
    }
}
