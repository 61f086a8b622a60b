//! The components a level is made of, and no more.
//!
//! Each is a plain struct stored in the hecs world and written by name in a level file.
//! Numbers are checked on the way in (see [`crate::num`]); [`Validate`] runs the same checks
//! on values built in code, before a level is saved.

use glam::{EulerRot, Mat4, Quat, Vec2, Vec3};
use serde::{Deserialize, Serialize};

use crate::num;

/// A person-readable name, shown in the editor's hierarchy.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(transparent)]
pub struct Name(pub String);

/// Where an entity is: translation, rotation and scale.
///
/// `rotation` holds Euler angles in degrees `(pitch about X, yaw about Y, roll about Z)`,
/// applied yaw first, then pitch, then roll (`R = Ry · Rx · Rz`, as in Godot). Angles are kept
/// as written so that a level file round-trips exactly.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Transform {
    /// Position in world units.
    #[serde(with = "num::vec3")]
    pub translation: Vec3,
    /// Euler angles in degrees (X, Y, Z); see the type's docs for the order.
    #[serde(with = "num::vec3")]
    pub rotation: Vec3,
    /// Per-axis scale; every component positive.
    #[serde(with = "num::scale3")]
    pub scale: Vec3,
}

impl Default for Transform {
    fn default() -> Self {
        Self {
            translation: Vec3::ZERO,
            rotation: Vec3::ZERO,
            scale: Vec3::ONE,
        }
    }
}

impl Transform {
    /// A transform at `translation` with no rotation and unit scale.
    pub fn from_translation(translation: Vec3) -> Self {
        Self {
            translation,
            ..Self::default()
        }
    }

    /// The rotation as a quaternion.
    pub fn quat(&self) -> Quat {
        let r = self.rotation * (std::f32::consts::PI / 180.0);
        Quat::from_euler(EulerRot::YXZ, r.y, r.x, r.z)
    }

    /// Object → world matrix.
    pub fn matrix(&self) -> Mat4 {
        Mat4::from_scale_rotation_translation(self.scale, self.quat(), self.translation)
    }
}

/// Default subdivision of round primitives.
const fn default_segments() -> u32 {
    16
}

/// What an entity looks like: a primitive with its parameters, or a glTF mesh.
///
/// Primitives are centred on the origin of their transform, except `Plane`, which lies in the
/// XZ plane facing +Y, and `Wedge`, whose slope rises from +Z (front, height 0) to −Z (back).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Geometry {
    /// An axis-aligned box.
    Box {
        /// Full size along X, Y, Z.
        #[serde(with = "num::size3")]
        size: Vec3,
    },
    /// A UV sphere.
    Sphere {
        /// Radius.
        #[serde(with = "num::positive")]
        radius: f32,
        /// Segments around the Y axis (rings are half as many).
        #[serde(default = "default_segments", with = "num::segments")]
        segments: u32,
    },
    /// A cylinder along Y, capped.
    Cylinder {
        /// Radius.
        #[serde(with = "num::positive")]
        radius: f32,
        /// Full height.
        #[serde(with = "num::positive")]
        height: f32,
        /// Segments around the Y axis.
        #[serde(default = "default_segments", with = "num::segments")]
        segments: u32,
    },
    /// A one-sided rectangle in XZ facing +Y.
    Plane {
        /// Size along X and Z.
        #[serde(with = "num::size2")]
        size: Vec2,
    },
    /// A ramp: a box whose top slopes from the back (−Z, full height) to the front (+Z).
    Wedge {
        /// Full size along X, Y, Z.
        #[serde(with = "num::size3")]
        size: Vec3,
    },
    /// A glTF mesh (`.gltf` or `.glb`), path relative to the level file.
    Mesh {
        /// Path relative to the level file, with `/` separators.
        path: String,
    },
}

/// How a surface is shaded.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Material {
    /// Linear RGB base colour (multiplies the texture).
    #[serde(with = "num::colour")]
    pub albedo: Vec3,
    /// Linear RGB emitted light, added unlit.
    #[serde(with = "num::colour", default = "zero3")]
    pub emissive: Vec3,
    /// Whether the surface blocks shadow rays.
    #[serde(default = "yes")]
    pub casts_shadows: bool,
    /// Whether silhouette and crease outlines are drawn on it.
    #[serde(default = "yes")]
    pub outlined: bool,
    /// An albedo texture (sRGB PNG or JPEG). On a glTF mesh it replaces the file's own textures.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub texture: Option<TextureMap>,
    /// A tangent-space normal map (linear PNG or JPEG, glTF convention), sampled like `texture`
    /// (with its UV scale, density and sampling when there is one).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub normal_map: Option<String>,
    /// A highlight from the lights (none: matte; left out of the file).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub specular: Option<Specular>,
}

/// A highlight from the lights, as the probe that captured a texel sees it (so it is cached
/// with the texel's shading and changes only where the probe does; `ARCHITECTURE.md`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Specular {
    /// How bright the highlight is, 0–4 (times the light's colour).
    #[serde(with = "num::strength")]
    pub strength: f32,
    /// How tight it is: the Blinn-Phong exponent, 1–1024 (default 32).
    #[serde(default = "default_shininess", with = "num::shininess")]
    pub shininess: f32,
}

fn default_shininess() -> f32 {
    32.0
}

/// How texture pixels are filtered.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum Sampling {
    /// The nearest texture pixel: pixel art.
    #[default]
    Nearest,
    /// Bilinear between pixels.
    Linear,
}

/// Texture pixels per world unit when a material does not say (a 16-pixel tile per unit).
pub const DEFAULT_TEXEL_DENSITY: f32 = 16.0;

/// A texture as a material uses it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TextureMap {
    /// PNG or JPEG path relative to the level file, with `/` separators.
    pub path: String,
    /// Filtering.
    #[serde(default, skip_serializing_if = "is_default")]
    pub sampling: Sampling,
    /// Texture pixels per world unit on primitives, whose UVs are in world units along the
    /// surface: 16 puts one 16-pixel image on every unit square. (glTF meshes bring their
    /// own UVs; `uv_scale` applies to both.)
    #[serde(
        default = "default_density",
        skip_serializing_if = "is_default_density",
        with = "num::positive"
    )]
    pub density: f32,
    /// Multiplies the UVs.
    #[serde(default = "one2", skip_serializing_if = "is_one2", with = "num::size2")]
    pub uv_scale: Vec2,
}

impl TextureMap {
    /// `path` at the default density, nearest sampling, no UV scale.
    pub fn new(path: &str) -> Self {
        TextureMap {
            path: path.to_owned(),
            sampling: Sampling::Nearest,
            density: DEFAULT_TEXEL_DENSITY,
            uv_scale: Vec2::ONE,
        }
    }
}

fn is_default<T: Default + PartialEq>(v: &T) -> bool {
    *v == T::default()
}
const fn default_density() -> f32 {
    DEFAULT_TEXEL_DENSITY
}
fn is_default_density(v: &f32) -> bool {
    *v == DEFAULT_TEXEL_DENSITY
}
const fn one2() -> Vec2 {
    Vec2::ONE
}
fn is_one2(v: &Vec2) -> bool {
    *v == Vec2::ONE
}

const fn yes() -> bool {
    true
}
const fn zero3() -> Vec3 {
    Vec3::ZERO
}

impl Default for Material {
    fn default() -> Self {
        Self {
            albedo: Vec3::splat(0.7),
            emissive: Vec3::ZERO,
            casts_shadows: true,
            outlined: true,
            texture: None,
            normal_map: None,
            specular: None,
        }
    }
}

/// A sun: parallel light from one direction, with ray-traced shadows.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DirectionalLight {
    /// The direction the light travels (from the sun toward the ground); normalised on use.
    #[serde(with = "num::direction")]
    pub direction: Vec3,
    /// Linear RGB colour.
    #[serde(with = "num::colour")]
    pub colour: Vec3,
    /// Multiplier on `colour`.
    #[serde(with = "num::intensity")]
    pub intensity: f32,
}

impl Default for DirectionalLight {
    fn default() -> Self {
        Self {
            direction: Vec3::new(-0.4, -1.0, -0.3),
            colour: Vec3::new(1.0, 0.95, 0.85),
            intensity: 1.0,
        }
    }
}

/// A point light at the entity's translation, fading to zero at `radius`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PointLight {
    /// Linear RGB colour.
    #[serde(with = "num::colour")]
    pub colour: Vec3,
    /// Multiplier on `colour`.
    #[serde(with = "num::intensity")]
    pub intensity: f32,
    /// Distance at which the light reaches zero.
    #[serde(with = "num::positive")]
    pub radius: f32,
}

impl Default for PointLight {
    fn default() -> Self {
        Self {
            colour: Vec3::new(1.0, 0.8, 0.5),
            intensity: 2.0,
            radius: 8.0,
        }
    }
}

/// An axis-aligned volume with its own probe-grid cell size.
///
/// The volume is centred on the entity's translation with full size `size × scale`;
/// rotation is ignored (the grid is world-aligned). Where volumes overlap, the highest
/// `priority` wins; among equal priorities, the one later in the level wins.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProbeGridOverride {
    /// Full size of the volume along X, Y, Z (before the transform's scale).
    #[serde(with = "num::size3")]
    pub size: Vec3,
    /// Grid cell size inside the volume, in world units.
    #[serde(with = "num::positive")]
    pub cell_size: f32,
    /// Cube-face resolution inside the volume; the level's when absent.
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        with = "num::opt_face_resolution"
    )]
    pub face_resolution: Option<u32>,
    /// Which volume wins where several overlap (higher wins).
    #[serde(default)]
    pub priority: i32,
}

impl Default for ProbeGridOverride {
    fn default() -> Self {
        Self {
            size: Vec3::splat(4.0),
            cell_size: 0.5,
            face_resolution: None,
            priority: 0,
        }
    }
}

/// Where the player starts: position from the entity's translation (the feet), view angles
/// and eye height here.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlayerStart {
    /// Heading in degrees; 0 looks along −Z, positive turns toward −X (counter-clockwise
    /// seen from above, like the Y rotation of a transform).
    #[serde(with = "num::finite")]
    pub yaw: f32,
    /// Pitch in degrees; positive looks up. Must lie within ±89.
    #[serde(with = "num::pitch")]
    pub pitch: f32,
    /// Height of the eye above the feet.
    #[serde(with = "num::positive")]
    pub eye_height: f32,
}

impl Default for PlayerStart {
    fn default() -> Self {
        Self {
            yaw: 0.0,
            pitch: 0.0,
            eye_height: 1.6,
        }
    }
}

pub use texel_geom::limits::{BANDS, FACE_RESOLUTIONS, SEGMENTS};

/// How big the art pixels are: a fixed cube-face resolution, or a wanted on-screen size of
/// a texel at the view centre (in screen pixels), from which the resolution follows.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum PixelScale {
    /// Texels per cube-face edge.
    FaceResolution(#[serde(with = "num::face_resolution")] u32),
    /// Screen pixels per texel at the view centre.
    PixelSize(#[serde(with = "num::positive")] f32),
}

/// Level-wide settings.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LevelSettings {
    /// Linear RGB sky colour (background and sky texels).
    #[serde(with = "num::colour")]
    pub sky: Vec3,
    /// Linear RGB ambient light added to every lit texel.
    #[serde(with = "num::colour")]
    pub ambient: Vec3,
    /// Number of OKLab lightness bands for posterization.
    #[serde(with = "num::bands")]
    pub bands: u32,
    /// Art-pixel size.
    pub pixel_scale: PixelScale,
    /// Default probe-grid cell size, in world units.
    #[serde(with = "num::positive")]
    pub cell_size: f32,
    /// Distance haze: the share of sky colour mixed in at distance `d` is `1 − e^(−haze·d)`
    /// (0 = none; left out of the file when 0).
    #[serde(default, skip_serializing_if = "is_zero", with = "num::haze")]
    pub haze: f32,
    /// The distance at which textures are meant to be seen pixel-perfect (one texture pixel
    /// per art pixel), in world units: what `texel-run check --density` and the inspector
    /// measure texture densities against (left out of the file at its default, 4).
    #[serde(
        default = "default_reference_distance",
        skip_serializing_if = "is_default_reference_distance",
        with = "num::positive"
    )]
    pub reference_distance: f32,
    /// Light spilling from bright pixels, on the art pixels (none: left out of the file).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bloom: Option<Bloom>,
}

/// Light spilling from bright pixels (`settings.bloom`), computed on the art pixels so it
/// holds as still as they do.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Bloom {
    /// Relative luminance (linear, 0–1) above which a pixel spills light.
    #[serde(default = "default_bloom_threshold", with = "num::unit")]
    pub threshold: f32,
    /// How much of the spilled light is added, 0–4.
    #[serde(default = "default_bloom_strength", with = "num::strength")]
    pub strength: f32,
    /// How far it spills, in art pixels, 1–16.
    #[serde(default = "default_bloom_radius", with = "num::bloom_radius")]
    pub radius: u32,
}

fn default_bloom_threshold() -> f32 {
    0.7
}
fn default_bloom_strength() -> f32 {
    0.8
}
fn default_bloom_radius() -> u32 {
    4
}

impl Default for Bloom {
    fn default() -> Self {
        Bloom {
            threshold: default_bloom_threshold(),
            strength: default_bloom_strength(),
            radius: default_bloom_radius(),
        }
    }
}

/// The palette a level's frames are mapped to: every pixel takes the nearest of its colours
/// in OKLab, optionally dithered between the two nearest (`crate::palette`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PaletteSetting {
    /// The palette file (`.gpl`, `.hex` or `.pal`), relative to the level.
    pub file: String,
    /// Ordered dithering between the two nearest colours, anchored to the texel: 0 (none;
    /// left out of the file) to 1.
    #[serde(default, skip_serializing_if = "is_zero", with = "num::unit")]
    pub dither: f32,
    /// A second palette (night, say) that `texel-run play` swaps to with a key.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub alternate: Option<String>,
}

impl Validate for PaletteSetting {
    fn validate(&self) -> Result<(), (&'static str, String)> {
        let named = |p: &str| {
            if p.trim().is_empty() {
                Err("must name a palette file".to_owned())
            } else {
                Ok(())
            }
        };
        field("file", named(&self.file))?;
        if let Some(a) = &self.alternate {
            field("alternate", named(a))?;
        }
        field("dither", num::check_unit(self.dither).map(|_| ()))
    }
}

fn is_zero(v: &f32) -> bool {
    *v == 0.0
}

/// [`LevelSettings::reference_distance`] when a level does not say.
pub const DEFAULT_REFERENCE_DISTANCE: f32 = 4.0;

const fn default_reference_distance() -> f32 {
    DEFAULT_REFERENCE_DISTANCE
}
fn is_default_reference_distance(v: &f32) -> bool {
    *v == DEFAULT_REFERENCE_DISTANCE
}

impl Default for LevelSettings {
    fn default() -> Self {
        Self {
            sky: Vec3::new(0.45, 0.62, 0.85),
            ambient: Vec3::new(0.18, 0.2, 0.26),
            bands: 32,
            pixel_scale: PixelScale::PixelSize(2.5),
            cell_size: 1.0,
            haze: 0.0,
            reference_distance: DEFAULT_REFERENCE_DISTANCE,
            bloom: None,
        }
    }
}

/// Checks values built in code against the same rules the loader applies.
pub trait Validate {
    /// Returns `(field, message)` for the first bad value.
    fn validate(&self) -> Result<(), (&'static str, String)>;
}

fn field<T>(name: &'static str, r: Result<T, String>) -> Result<(), (&'static str, String)> {
    r.map(|_| ()).map_err(|m| (name, m))
}

impl Validate for Transform {
    fn validate(&self) -> Result<(), (&'static str, String)> {
        field("translation", num::check_vec3(self.translation))?;
        field("rotation", num::check_vec3(self.rotation))?;
        field("scale", num::check_positive3(self.scale, "scale"))
    }
}

impl Validate for Geometry {
    fn validate(&self) -> Result<(), (&'static str, String)> {
        let segs = |s: u32| field("segments", num::check_range(s, SEGMENTS, "segments"));
        match self {
            Geometry::Box { size } | Geometry::Wedge { size } => {
                field("size", num::check_positive3(*size, "size"))
            }
            Geometry::Sphere { radius, segments } => {
                field("radius", num::check_positive(*radius, "radius"))?;
                segs(*segments)
            }
            Geometry::Cylinder {
                radius,
                height,
                segments,
            } => {
                field("radius", num::check_positive(*radius, "radius"))?;
                field("height", num::check_positive(*height, "height"))?;
                segs(*segments)
            }
            Geometry::Plane { size } => {
                field("size", num::check_positive(size.x, "size"))?;
                field("size", num::check_positive(size.y, "size"))
            }
            Geometry::Mesh { path } if path.trim().is_empty() => {
                Err(("path", "mesh path is empty".to_owned()))
            }
            Geometry::Mesh { .. } => Ok(()),
        }
    }
}

impl Validate for Material {
    fn validate(&self) -> Result<(), (&'static str, String)> {
        field("albedo", num::check_colour(self.albedo))?;
        if let Some(s) = self.specular {
            field("specular", num::check_strength(s.strength))?;
            field("specular", num::check_shininess(s.shininess))?;
        }
        field("emissive", num::check_colour(self.emissive))?;
        if let Some(t) = &self.texture {
            if t.path.trim().is_empty() {
                return Err(("texture", "texture path is empty".to_owned()));
            }
            field("density", num::check_positive(t.density, "density"))?;
            field("uv_scale", num::check_positive(t.uv_scale.x, "uv_scale"))?;
            field("uv_scale", num::check_positive(t.uv_scale.y, "uv_scale"))?;
        }
        if self
            .normal_map
            .as_ref()
            .is_some_and(|p| p.trim().is_empty())
        {
            return Err(("normal_map", "normal map path is empty".to_owned()));
        }
        Ok(())
    }
}

impl Validate for DirectionalLight {
    fn validate(&self) -> Result<(), (&'static str, String)> {
        field("direction", num::check_direction(self.direction))?;
        field("colour", num::check_colour(self.colour))?;
        field(
            "intensity",
            num::check_intensity(self.intensity, "intensity"),
        )
    }
}

impl Validate for PointLight {
    fn validate(&self) -> Result<(), (&'static str, String)> {
        field("colour", num::check_colour(self.colour))?;
        field(
            "intensity",
            num::check_intensity(self.intensity, "intensity"),
        )?;
        field("radius", num::check_positive(self.radius, "radius"))
    }
}

impl Validate for ProbeGridOverride {
    fn validate(&self) -> Result<(), (&'static str, String)> {
        field("size", num::check_positive3(self.size, "size"))?;
        field(
            "cell_size",
            num::check_positive(self.cell_size, "cell size"),
        )?;
        match self.face_resolution {
            Some(n) => field(
                "face_resolution",
                num::check_range(n, FACE_RESOLUTIONS, "face resolution"),
            ),
            None => Ok(()),
        }
    }
}

impl Validate for PlayerStart {
    fn validate(&self) -> Result<(), (&'static str, String)> {
        field("yaw", num::check_coord(self.yaw))?;
        field("pitch", num::check_pitch(self.pitch))?;
        field(
            "eye_height",
            num::check_positive(self.eye_height, "eye height"),
        )
    }
}

impl Validate for LevelSettings {
    fn validate(&self) -> Result<(), (&'static str, String)> {
        field("sky", num::check_colour(self.sky))?;
        field("ambient", num::check_colour(self.ambient))?;
        field("bands", num::check_range(self.bands, BANDS, "bands"))?;
        field(
            "cell_size",
            num::check_positive(self.cell_size, "cell size"),
        )?;
        match self.pixel_scale {
            PixelScale::FaceResolution(n) => field(
                "pixel_scale",
                num::check_range(n, FACE_RESOLUTIONS, "face resolution"),
            ),
            PixelScale::PixelSize(s) => field("pixel_scale", num::check_positive(s, "pixel size")),
        }?;
        field(
            "reference_distance",
            num::check_positive(self.reference_distance, "reference distance"),
        )?;
        if let Some(b) = self.bloom {
            field("bloom", num::check_unit(b.threshold))?;
            field("bloom", num::check_strength(b.strength))?;
            field("bloom", num::check_range(b.radius, 1..=16, "bloom radius"))?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests;
