//! Checked numbers for level files.
//!
//! Every float a level holds passes through one of these checks, both when a file is read
//! (as `#[serde(with = ...)]` helpers, so the parser's error carries the line and column of
//! the bad value) and when a level built in code is validated before it is saved. A level
//! never holds NaN, an infinity, or a value so large that the renderer's math breaks down.

use glam::{Vec2, Vec3};
use serde::{Deserialize, Deserializer, Serialize, Serializer, de::Error as _};

/// Largest magnitude of any coordinate or size, in world units. Levels are at most a few
/// kilometres across; past this, f32 positions lose the precision a texel needs.
pub const MAX_COORD: f32 = 1.0e6;
/// Largest colour channel or light intensity (linear units).
pub const MAX_INTENSITY: f32 = 1.0e4;

/// Checks one float is finite and within `±MAX_COORD`.
pub fn check_coord(v: f32) -> Result<f32, String> {
    if !v.is_finite() {
        Err(format!("NaN or infinite number ({v})"))
    } else if v.abs() > MAX_COORD {
        Err(format!("number {v} is too large (limit ±{MAX_COORD})"))
    } else {
        Ok(v)
    }
}

/// Checks a length, size or radius: finite, > 0 and at most `MAX_COORD`.
pub fn check_positive(v: f32, what: &str) -> Result<f32, String> {
    let v = check_coord(v)?;
    if v <= 0.0 {
        Err(format!("{what} must be positive, got {v:?}"))
    } else {
        Ok(v)
    }
}

/// Checks a colour channel or an intensity: finite, >= 0 and at most `MAX_INTENSITY`.
pub fn check_intensity(v: f32, what: &str) -> Result<f32, String> {
    if !v.is_finite() {
        return Err(format!("NaN or infinite number ({v})"));
    }
    if !(0.0..=MAX_INTENSITY).contains(&v) {
        return Err(format!("{what} must be in 0..={MAX_INTENSITY}, got {v:?}"));
    }
    Ok(v)
}

/// Checks an integer lies in `range`.
pub fn check_range<T: PartialOrd + std::fmt::Display + Copy>(
    v: T,
    range: std::ops::RangeInclusive<T>,
    what: &str,
) -> Result<T, String> {
    if range.contains(&v) {
        Ok(v)
    } else {
        Err(format!(
            "{what} must be in {}..={}, got {v}",
            range.start(),
            range.end()
        ))
    }
}

fn check3(v: Vec3, f: impl Fn(f32) -> Result<f32, String>) -> Result<Vec3, String> {
    Ok(Vec3::new(f(v.x)?, f(v.y)?, f(v.z)?))
}

/// Checks every component with [`check_coord`].
pub fn check_vec3(v: Vec3) -> Result<Vec3, String> {
    check3(v, check_coord)
}

/// Checks every component with [`check_positive`].
pub fn check_positive3(v: Vec3, what: &str) -> Result<Vec3, String> {
    check3(v, |c| check_positive(c, what))
}

/// Checks every component with [`check_intensity`].
pub fn check_colour(v: Vec3) -> Result<Vec3, String> {
    check3(v, |c| check_intensity(c, "colour channel"))
}

/// Checks a direction: finite and not (near) zero.
pub fn check_direction(v: Vec3) -> Result<Vec3, String> {
    let v = check_vec3(v)?;
    if v.length_squared() < 1e-12 {
        Err("direction must not be zero".to_owned())
    } else {
        Ok(v)
    }
}

fn ser3<S: Serializer>(v: &Vec3, s: S) -> Result<S::Ok, S::Error> {
    (v.x, v.y, v.z).serialize(s)
}

fn de3<'de, D: Deserializer<'de>>(
    d: D,
    check: impl Fn(Vec3) -> Result<Vec3, String>,
) -> Result<Vec3, D::Error> {
    let (x, y, z) = <(f32, f32, f32)>::deserialize(d)?;
    check(Vec3::new(x, y, z)).map_err(D::Error::custom)
}

macro_rules! vec3_with {
    ($(#[$doc:meta])* $name:ident, $check:expr) => {
        $(#[$doc])*
        pub mod $name {
            use super::*;
            /// Writes the vector as a tuple `(x, y, z)`.
            pub fn serialize<S: Serializer>(v: &Vec3, s: S) -> Result<S::Ok, S::Error> {
                ser3(v, s)
            }
            /// Reads a tuple `(x, y, z)` and checks it.
            pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec3, D::Error> {
                de3(d, $check)
            }
        }
    };
}

vec3_with!(
    /// A position or offset: finite, within `±MAX_COORD`.
    vec3,
    check_vec3
);
vec3_with!(
    /// A scale or size: every component positive.
    scale3,
    |v| check_positive3(v, "scale")
);
vec3_with!(
    /// A box-like size: every component positive.
    size3,
    |v| check_positive3(v, "size")
);
vec3_with!(
    /// A linear RGB colour.
    colour,
    check_colour
);
vec3_with!(
    /// A direction, normalised on use.
    direction,
    check_direction
);

/// A 2D size: both components positive.
pub mod size2 {
    use super::*;
    /// Writes `(x, y)`.
    pub fn serialize<S: Serializer>(v: &Vec2, s: S) -> Result<S::Ok, S::Error> {
        (v.x, v.y).serialize(s)
    }
    /// Reads `(x, y)` and checks both are positive.
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec2, D::Error> {
        let (x, y) = <(f32, f32)>::deserialize(d)?;
        let c = |v| check_positive(v, "size").map_err(D::Error::custom);
        Ok(Vec2::new(c(x)?, c(y)?))
    }
}

macro_rules! f32_with {
    ($(#[$doc:meta])* $name:ident, $check:expr) => {
        $(#[$doc])*
        pub mod $name {
            use super::*;
            /// Writes the number.
            pub fn serialize<S: Serializer>(v: &f32, s: S) -> Result<S::Ok, S::Error> {
                v.serialize(s)
            }
            /// Reads the number and checks it.
            pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<f32, D::Error> {
                let v = f32::deserialize(d)?;
                let check: fn(f32) -> Result<f32, String> = $check;
                check(v).map_err(D::Error::custom)
            }
        }
    };
}

f32_with!(
    /// Any finite number within `±MAX_COORD` (angles, offsets).
    finite,
    check_coord
);
f32_with!(
    /// A positive amount: a length (radius, height, cell size), a density, a tile size.
    positive,
    |v| check_positive(v, "value")
);
f32_with!(
    /// A light intensity or other non-negative amount.
    intensity,
    |v| check_intensity(v, "intensity")
);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_non_finite_and_huge() {
        assert!(check_coord(f32::NAN).unwrap_err().contains("NaN"));
        assert!(check_coord(f32::INFINITY).unwrap_err().contains("infinite"));
        assert!(check_coord(2.0e6).unwrap_err().contains("too large"));
        assert_eq!(check_coord(-3.5), Ok(-3.5));
    }

    #[test]
    fn positive_rejects_zero_and_negative() {
        assert!(
            check_positive(0.0, "scale")
                .unwrap_err()
                .contains("positive")
        );
        assert!(check_positive(-1.0, "scale").is_err());
        assert!(check_positive3(Vec3::new(1.0, 0.0, 1.0), "scale").is_err());
        assert_eq!(check_positive(0.25, "scale"), Ok(0.25));
    }

    #[test]
    fn colours_and_directions() {
        assert!(check_colour(Vec3::new(0.5, -0.1, 0.0)).is_err());
        assert!(check_direction(Vec3::ZERO).is_err());
        assert!(check_direction(Vec3::Y).is_ok());
        assert!(check_range(300u32, 2..=256, "bands").is_err());
        assert_eq!(check_range(32u32, 2..=256, "bands"), Ok(32));
    }
}

macro_rules! u32_with {
    ($(#[$doc:meta])* $name:ident, $range:expr, $what:literal) => {
        $(#[$doc])*
        pub mod $name {
            use super::*;
            /// Writes the number.
            pub fn serialize<S: Serializer>(v: &u32, s: S) -> Result<S::Ok, S::Error> {
                v.serialize(s)
            }
            /// Reads the number and checks its range.
            pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<u32, D::Error> {
                let v = u32::deserialize(d)?;
                check_range(v, $range, $what).map_err(D::Error::custom)
            }
        }
    };
}

u32_with!(
    /// Segments of a round primitive.
    segments,
    crate::components::SEGMENTS,
    "segments"
);
u32_with!(
    /// Posterization bands.
    bands,
    crate::components::BANDS,
    "bands"
);
u32_with!(
    /// A cube-face resolution.
    face_resolution,
    crate::components::FACE_RESOLUTIONS,
    "face resolution"
);

/// An optional cube-face resolution.
pub mod opt_face_resolution {
    use super::*;
    /// Writes the number (the field is skipped when absent).
    pub fn serialize<S: Serializer>(v: &Option<u32>, s: S) -> Result<S::Ok, S::Error> {
        v.serialize(s)
    }
    /// Reads the number and checks its range.
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Option<u32>, D::Error> {
        Option::<u32>::deserialize(d)?
            .map(|v| {
                check_range(v, crate::components::FACE_RESOLUTIONS, "face resolution")
                    .map_err(D::Error::custom)
            })
            .transpose()
    }
}

/// Checks a pitch angle in degrees: finite and within ±89.
pub fn check_pitch(v: f32) -> Result<f32, String> {
    let v = check_coord(v)?;
    if v.abs() > 89.0 {
        Err(format!("pitch must be within ±89 degrees, got {v:?}"))
    } else {
        Ok(v)
    }
}

f32_with!(
    /// A pitch angle in degrees, within ±89.
    pitch,
    check_pitch
);

/// Checks a haze density per world unit: finite, within 0..=10.
pub fn check_haze(v: f32) -> Result<f32, String> {
    if !v.is_finite() {
        return Err(format!("NaN or infinite number ({v})"));
    }
    if !(0.0..=10.0).contains(&v) {
        return Err(format!("haze must be in 0..=10, got {v:?}"));
    }
    Ok(v)
}

f32_with!(
    /// A haze density per world unit, within 0..=10.
    haze,
    check_haze
);

u32_with!(
    /// Samples per edge of a baked heightmap.
    heightmap_resolution,
    2..=crate::terrain::MAX_HEIGHTMAP,
    "heightmap resolution"
);
u32_with!(
    /// Octaves of fractal noise.
    octaves,
    1..=8,
    "octaves"
);

/// Checks a fraction: finite and within 0..=1.
pub fn check_unit(v: f32) -> Result<f32, String> {
    if v.is_finite() && (0.0..=1.0).contains(&v) {
        Ok(v)
    } else {
        Err(format!("must be within 0..=1, got {v:?}"))
    }
}

f32_with!(
    /// A fraction within 0..=1.
    unit,
    check_unit
);

/// Checks a strength (a bloom's, a highlight's): finite, within 0..=4.
pub fn check_strength(v: f32) -> Result<f32, String> {
    if v.is_finite() && (0.0..=4.0).contains(&v) {
        Ok(v)
    } else {
        Err(format!("strength must be in 0..=4, got {v:?}"))
    }
}

f32_with!(
    /// A strength (a bloom's, a highlight's), within 0..=4.
    strength,
    check_strength
);

/// Checks a highlight's shininess (the Blinn-Phong exponent): finite, within 1..=1024.
pub fn check_shininess(v: f32) -> Result<f32, String> {
    if v.is_finite() && (1.0..=1024.0).contains(&v) {
        Ok(v)
    } else {
        Err(format!("shininess must be in 1..=1024, got {v:?}"))
    }
}

f32_with!(
    /// A highlight's shininess, within 1..=1024.
    shininess,
    check_shininess
);

u32_with!(
    /// A bloom's radius in art pixels.
    bloom_radius,
    1..=16,
    "bloom radius"
);

/// Checks a length of time in seconds (a loop's period): finite, > 0, at most `MAX_COORD`.
pub fn check_period(v: f32) -> Result<f32, String> {
    check_positive(v, "period")
}

f32_with!(
    /// A period in seconds, > 0.
    period,
    check_period
);

/// Checks a turning speed in degrees per second: finite, not zero, within `±MAX_COORD`.
pub fn check_speed(v: f32) -> Result<f32, String> {
    let v = check_coord(v)?;
    if v == 0.0 {
        Err("speed must not be zero (degrees per second)".to_owned())
    } else {
        Ok(v)
    }
}

f32_with!(
    /// A turning speed in degrees per second, not zero.
    speed,
    check_speed
);

/// Checks an axis of rotation: finite and not (near) zero.
pub fn check_axis(v: Vec3) -> Result<Vec3, String> {
    let v = check_vec3(v)?;
    if v.length_squared() < 1e-12 {
        Err("axis must not be zero".to_owned())
    } else {
        Ok(v)
    }
}

vec3_with!(
    /// An axis of rotation, normalised on use.
    axis,
    check_axis
);

/// Checks a pair of fractions (a sprite's pivot): both within 0..=1.
pub fn check_unit2(v: Vec2) -> Result<Vec2, String> {
    Ok(Vec2::new(check_unit(v.x)?, check_unit(v.y)?))
}

/// A point inside a frame as fractions of it: both components within 0..=1.
pub mod unit2 {
    use super::*;
    /// Writes `(x, y)`.
    pub fn serialize<S: Serializer>(v: &Vec2, s: S) -> Result<S::Ok, S::Error> {
        (v.x, v.y).serialize(s)
    }
    /// Reads `(x, y)` and checks both are within 0..=1.
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec2, D::Error> {
        let (x, y) = <(f32, f32)>::deserialize(d)?;
        check_unit2(Vec2::new(x, y)).map_err(D::Error::custom)
    }
}

/// Checks a sprite's frame size in pixels: each side within
/// 1..=[`MAX_TEXTURE_SIZE`](texel_geom::texture::MAX_TEXTURE_SIZE).
pub fn check_frame_size(v: glam::UVec2) -> Result<glam::UVec2, String> {
    let max = texel_geom::texture::MAX_TEXTURE_SIZE;
    if (1..=max).contains(&v.x) && (1..=max).contains(&v.y) {
        Ok(v)
    } else {
        Err(format!(
            "frame size must be in 1..={max} pixels per side, got ({}, {})",
            v.x, v.y
        ))
    }
}

/// A sprite's frame size in pixels, `(width, height)`.
pub mod frame_size {
    use super::*;
    /// Writes `(width, height)`.
    pub fn serialize<S: Serializer>(v: &glam::UVec2, s: S) -> Result<S::Ok, S::Error> {
        (v.x, v.y).serialize(s)
    }
    /// Reads `(width, height)` and checks both.
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<glam::UVec2, D::Error> {
        let (x, y) = <(u32, u32)>::deserialize(d)?;
        check_frame_size(glam::UVec2::new(x, y)).map_err(D::Error::custom)
    }
}

/// Checks an animation's frames per second: finite, > 0, at most
/// [`MAX_FPS`](crate::sprite::MAX_FPS).
pub fn check_fps(v: f32) -> Result<f32, String> {
    let max = crate::sprite::MAX_FPS;
    if !v.is_finite() {
        Err(format!("NaN or infinite number ({v})"))
    } else if v <= 0.0 || v > max {
        Err(format!(
            "fps must be positive and at most {max:?}, got {v:?}"
        ))
    } else {
        Ok(v)
    }
}

f32_with!(
    /// Frames per second of a sprite animation, > 0.
    fps,
    check_fps
);

/// Checks a sprite's number of view directions: 1 or 8.
pub fn check_directions(v: u32) -> Result<u32, String> {
    if v == 1 || v == 8 {
        Ok(v)
    } else {
        Err(format!("directions must be 1 or 8, got {v}"))
    }
}

/// A sprite's number of view directions, 1 or 8.
pub mod directions {
    use super::*;
    /// Writes the number.
    pub fn serialize<S: Serializer>(v: &u32, s: S) -> Result<S::Ok, S::Error> {
        v.serialize(s)
    }
    /// Reads the number and checks it is 1 or 8.
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<u32, D::Error> {
        check_directions(u32::deserialize(d)?).map_err(D::Error::custom)
    }
}

/// Checks a relief's depth in world units: finite, > 0, at most
/// [`MAX_RELIEF_DEPTH`](crate::sprite::MAX_RELIEF_DEPTH).
pub fn check_relief_depth(v: f32) -> Result<f32, String> {
    let max = crate::sprite::MAX_RELIEF_DEPTH;
    let v = check_positive(v, "relief depth")?;
    if v > max {
        Err(format!(
            "relief depth must be at most {max:?} world units, got {v:?}"
        ))
    } else {
        Ok(v)
    }
}

f32_with!(
    /// A relief's depth in world units, in (0, `MAX_RELIEF_DEPTH`].
    relief_depth,
    check_relief_depth
);

/// Checks a ratio of refractive indices (outside over inside, as GLSL's `refract` takes it):
/// finite and within [`INDEX_RATIOS`](crate::sprite::INDEX_RATIOS).
pub fn check_index_ratio(v: f32) -> Result<f32, String> {
    let range = crate::sprite::INDEX_RATIOS;
    if !v.is_finite() {
        Err(format!("NaN or infinite number ({v})"))
    } else if !range.contains(&v) {
        Err(format!(
            "index ratio must be in {:?}..={:?}, got {v:?}",
            range.start(),
            range.end()
        ))
    } else {
        Ok(v)
    }
}

f32_with!(
    /// A ratio of refractive indices, within `INDEX_RATIOS`.
    index_ratio,
    check_index_ratio
);
