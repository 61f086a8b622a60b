//! The engine's limits: the one source for ranges that levels, command lines, the renderer
//! and the editor all check (`texel_scene` re-exports them with the components they bound).

use std::ops::RangeInclusive;

/// Range of cube-face resolutions (texels per face edge) a level, a command line or a frame
/// may ask for.
pub const FACE_RESOLUTIONS: RangeInclusive<u32> = 8..=2048;
/// Range of posterization band counts.
pub const BANDS: RangeInclusive<u32> = 2..=256;
/// Range of segment counts for round primitives.
pub const SEGMENTS: RangeInclusive<u32> = 3..=256;
/// The Chebyshev (probe) or view-axis (G-buffer) depth stored for sky texels and pixels,
/// beyond any geometry; the shaders get it from here (`shader::constants_wgsl`).
pub const SKY_DEPTH: f32 = 1.0e9;

/// Whether `n` is a face resolution the engine accepts.
pub fn face_resolution_ok(n: u32) -> bool {
    FACE_RESOLUTIONS.contains(&n)
}

/// The error text for a face resolution outside [`FACE_RESOLUTIONS`].
pub fn face_resolution_error(what: &str, n: u32) -> String {
    format!(
        "{what} must be within {}..={}, got {n}",
        FACE_RESOLUTIONS.start(),
        FACE_RESOLUTIONS.end()
    )
}
