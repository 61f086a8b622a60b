//! Face resolution from a wanted on-screen pixel size, and the pixel-perfect distance.
//!
//! **The rule.** Compare a probe texel and a screen pixel at the centre of the view, the
//! camera looking along a face axis from the probe's distance. A texel at face centre spans
//! `2 / N` tangent units (`N` texels across a face that spans `[-1, 1]`); a screen pixel
//! spans `2 · tan(fov_y / 2) / H` (`H` pixels across the vertical field of view). So a
//! texel covers `k = H / (N · tan(fov_y / 2))` pixels, and for `k` wanted pixels per texel
//! `N = H / (k · tan(fov_y / 2))`. The reference's 555 px at 60° with `k = 2.5` gives
//! `N ≈ 384`, its face size.
//!
//! This is the pixel-perfect-texture relation of David Frerichs with the camera at the
//! probe's distance: a texture of `res` texels over `extent` world units maps 1:1 to screen
//! pixels at `Zdist = size_px · extent / (2 · res · tan(fov / 2))`; a face at Chebyshev
//! distance `d` spans `extent = 2d` with `res = N`, so `Zdist = d · k`.

use std::fmt;

/// How a raw face resolution is rounded and clamped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ResolutionRange {
    /// Resolutions are multiples of this (> 0); 8 matches 8×8 compute groups.
    pub multiple: u32,
    /// Smallest resolution (a positive multiple of `multiple`).
    pub min: u32,
    /// Largest resolution (a multiple of `multiple`, >= `min`).
    pub max: u32,
}

impl Default for ResolutionRange {
    fn default() -> Self {
        ResolutionRange {
            multiple: 8,
            min: 16,
            max: *texel_geom::limits::FACE_RESOLUTIONS.end(),
        }
    }
}

/// An input the resolution relations cannot use.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ResolutionError {
    /// A quantity that must be finite and positive is not.
    NotPositive {
        /// Name of the argument.
        name: &'static str,
        /// Its value.
        value: f32,
    },
    /// The field of view is outside `(0, π)`.
    FieldOfView(f32),
    /// The range is empty or not made of multiples of `multiple`.
    Range(ResolutionRange),
}

impl fmt::Display for ResolutionError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ResolutionError::NotPositive { name, value } => {
                write!(f, "{name} = {value} must be finite and > 0")
            }
            ResolutionError::FieldOfView(v) => write!(f, "field of view {v} must be in (0, pi)"),
            ResolutionError::Range(r) => write!(
                f,
                "resolution range {}..={} must be non-empty multiples of {}",
                r.min, r.max, r.multiple
            ),
        }
    }
}

impl std::error::Error for ResolutionError {}

fn positive(name: &'static str, value: f32) -> Result<f32, ResolutionError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(ResolutionError::NotPositive { name, value })
    }
}

/// `tan(fov / 2)`, validating `fov`.
fn half_tan(fov: f32) -> Result<f32, ResolutionError> {
    if fov.is_finite() && fov > 0.0 && fov < std::f32::consts::PI {
        Ok((fov * 0.5).tan())
    } else {
        Err(ResolutionError::FieldOfView(fov))
    }
}

impl ResolutionRange {
    /// Checks that the range is usable.
    pub fn validate(&self) -> Result<(), ResolutionError> {
        let m = self.multiple;
        let ok = m > 0 && self.min > 0 && self.min <= self.max;
        if ok && self.min.is_multiple_of(m) && self.max.is_multiple_of(m) {
            Ok(())
        } else {
            Err(ResolutionError::Range(*self))
        }
    }

    /// `raw` rounded to the nearest multiple and clamped into the range.
    pub fn snap(&self, raw: f32) -> Result<u32, ResolutionError> {
        self.validate()?;
        positive("raw resolution", raw)?;
        let m = self.multiple as f32;
        let rounded = (raw / m).round() * m;
        Ok(rounded.clamp(self.min as f32, self.max as f32) as u32)
    }
}

/// Unrounded face resolution giving `pixels_per_texel` screen pixels per texel at the view
/// centre: `H / (k · tan(fov_y / 2))`.
pub fn exact_face_resolution(
    screen_height: u32,
    fov_y: f32,
    pixels_per_texel: f32,
) -> Result<f32, ResolutionError> {
    let h = positive("screen_height", screen_height as f32)?;
    let k = positive("pixels_per_texel", pixels_per_texel)?;
    Ok(h / (k * half_tan(fov_y)?))
}

/// Face resolution for `pixels_per_texel`, snapped by `range`.
pub fn face_resolution_for_pixel_size(
    screen_height: u32,
    fov_y: f32,
    pixels_per_texel: f32,
    range: &ResolutionRange,
) -> Result<u32, ResolutionError> {
    range.snap(exact_face_resolution(
        screen_height,
        fov_y,
        pixels_per_texel,
    )?)
}

/// Screen pixels per texel at the view centre for face resolution `face_resolution`:
/// `H / (N · tan(fov_y / 2))` (the inverse of [`exact_face_resolution`]).
pub fn pixels_per_texel(
    screen_height: u32,
    fov_y: f32,
    face_resolution: u32,
) -> Result<f32, ResolutionError> {
    let h = positive("screen_height", screen_height as f32)?;
    let n = positive("face_resolution", face_resolution as f32)?;
    Ok(h / (n * half_tan(fov_y)?))
}

/// Internal render height giving `pixels_per_texel` pixels per texel with faces of
/// `face_resolution`: `ceil(k · N · tan(fov_y / 2))` (the reference picks 555 this way).
pub fn screen_height_for(
    face_resolution: u32,
    fov_y: f32,
    pixels_per_texel: f32,
) -> Result<u32, ResolutionError> {
    let n = positive("face_resolution", face_resolution as f32)?;
    let k = positive("pixels_per_texel", pixels_per_texel)?;
    Ok((k * n * half_tan(fov_y)?).ceil() as u32)
}

/// Distance at which a texture of `resolution` texels spread over `extent` world units maps
/// 1:1 to screen pixels on a view `size_px` pixels across the field of view `fov`:
/// `Zdist = size_px · extent / (2 · resolution · tan(fov / 2))`.
pub fn pixel_perfect_distance(
    size_px: f32,
    extent: f32,
    resolution: f32,
    fov: f32,
) -> Result<f32, ResolutionError> {
    let size = positive("size_px", size_px)?;
    let extent = positive("extent", extent)?;
    let res = positive("resolution", resolution)?;
    Ok(size * extent / (2.0 * res * half_tan(fov)?))
}

// ---- Texture density against art pixels --------------------------------------------------
//
// In a texel-splat world the art pixel is the probe texel. Seen head-on from the probe at
// Chebyshev distance `d`, a texel of a face of `N` texels spans `2d / N` world units (the
// relation above with the camera at the probe). A texture of `ρ` pixels per world unit
// shows `ρ · 2d / N` texture pixels per art pixel, 1:1 at `d = N / (2ρ)`: Frerichs' distance
// with the probe face as the screen (extent `2d`, resolution `N`).

/// World size of a probe texel seen head-on at Chebyshev distance `distance` on faces of
/// `face_resolution` texels: `2d / N`.
pub fn texel_world_size(distance: f32, face_resolution: u32) -> f32 {
    2.0 * distance / face_resolution as f32
}

/// Texture pixels per art pixel (probe texel) for a texture of `density` pixels per world
/// unit seen head-on at `distance` with faces of `face_resolution`: `ρ · 2d / N` (1 is
/// pixel-perfect; below 1 the texture is magnified, above minified).
pub fn texture_pixels_per_art_pixel(density: f32, distance: f32, face_resolution: u32) -> f32 {
    density * texel_world_size(distance, face_resolution)
}

/// Distance from the probe at which a texture of `density` pixels per world unit shows one
/// texture pixel per art pixel on faces of `face_resolution`: `N / (2ρ)`.
pub fn one_to_one_distance(face_resolution: u32, density: f32) -> Result<f32, ResolutionError> {
    let density = positive("density", density)?;
    Ok(face_resolution as f32 / (2.0 * density))
}

/// The (unsnapped) face resolution that makes a texture of `density` pixels per world unit
/// 1:1 with art pixels at `distance`: `2dρ`.
pub fn face_resolution_for_density(density: f32, distance: f32) -> Result<f32, ResolutionError> {
    Ok(2.0 * positive("distance", distance)? * positive("density", density)?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f32::consts::FRAC_PI_3;

    #[test]
    fn texture_density_relations_agree() {
        // 16 px per unit on 128-texel faces: 1:1 at 4 units.
        let d = one_to_one_distance(128, 16.0).unwrap();
        assert_eq!(d, 4.0);
        assert_eq!(texture_pixels_per_art_pixel(16.0, d, 128), 1.0);
        assert_eq!(texture_pixels_per_art_pixel(16.0, 8.0, 128), 2.0);
        assert_eq!(face_resolution_for_density(16.0, 4.0).unwrap(), 128.0);
        assert!(one_to_one_distance(128, 0.0).is_err());
        assert!(face_resolution_for_density(16.0, f32::NAN).is_err());
        // Frerichs' relation with the face as the screen: extent 2d, resolution N, and a
        // 90° face: the same distance.
        let z = pixel_perfect_distance(
            128.0,
            2.0 * d,
            128.0 * 16.0 * 2.0 * d / 128.0,
            std::f32::consts::FRAC_PI_2,
        )
        .unwrap();
        assert!((z - d).abs() < 1e-4, "{z}");
    }

    #[test]
    fn matches_the_source_document_example() {
        // 300 px, geometry from -1 to 1, 256 texels, fov 0.785398 (π/4): 2.829157172164.
        let z = pixel_perfect_distance(300.0, 2.0, 256.0, std::f32::consts::FRAC_PI_4).unwrap();
        assert!((z - 2.829_157).abs() < 1e-5, "{z}");
    }

    #[test]
    fn reproduces_the_reference_face_size() {
        let h = screen_height_for(384, FRAC_PI_3, 2.5).unwrap();
        assert_eq!(h, 555);
        let n = exact_face_resolution(555, FRAC_PI_3, 2.5).unwrap();
        assert!((n - 384.5).abs() < 0.1, "{n}");
        let snapped =
            face_resolution_for_pixel_size(555, FRAC_PI_3, 2.5, &ResolutionRange::default());
        assert_eq!(snapped, Ok(384));
    }

    #[test]
    fn inverse_relations_agree() {
        for (h, n) in [(360, 64), (555, 384), (1080, 200)] {
            let k = pixels_per_texel(h, 1.1, n).unwrap();
            let back = exact_face_resolution(h, 1.1, k).unwrap();
            assert!((back - n as f32).abs() < 1e-2, "{h} {n}");
        }
    }

    #[test]
    fn pixel_perfect_distance_is_probe_distance_times_pixel_size() {
        // A face at Chebyshev distance d spans 2d with N texels.
        let (h, n, fov, d) = (480, 96, 1.2, 3.0);
        let z = pixel_perfect_distance(h as f32, 2.0 * d, n as f32, fov).unwrap();
        let k = pixels_per_texel(h, fov, n).unwrap();
        assert!((z / d - k).abs() < 1e-4);
    }

    #[test]
    fn snapping_rounds_to_multiples_and_clamps() {
        let r = ResolutionRange {
            multiple: 8,
            min: 16,
            max: 256,
        };
        assert_eq!(r.snap(99.0), Ok(96));
        assert_eq!(r.snap(100.0), Ok(104));
        assert_eq!(r.snap(3.0), Ok(16));
        assert_eq!(r.snap(9000.0), Ok(256));
        assert!(r.snap(f32::NAN).is_err());
    }

    #[test]
    fn rejects_bad_inputs() {
        let bad_range = ResolutionRange {
            multiple: 8,
            min: 20,
            max: 256,
        };
        assert_eq!(bad_range.snap(64.0), Err(ResolutionError::Range(bad_range)));
        let empty = ResolutionRange {
            multiple: 0,
            min: 8,
            max: 8,
        };
        assert!(empty.validate().is_err());
        assert!(matches!(
            exact_face_resolution(0, 1.0, 2.0),
            Err(ResolutionError::NotPositive {
                name: "screen_height",
                ..
            })
        ));
        assert_eq!(
            exact_face_resolution(100, 3.5, 2.0),
            Err(ResolutionError::FieldOfView(3.5))
        );
        assert!(pixels_per_texel(100, 1.0, 0).is_err());
        assert!(pixel_perfect_distance(100.0, -1.0, 8.0, 1.0).is_err());
        assert!(ResolutionError::FieldOfView(4.0).to_string().contains("4"));
    }
}
