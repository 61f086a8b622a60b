//! Sprites: flat pictures placed in the 3D world, cut from a sprite sheet, animated, seen
//! from one or eight directions, with the maps that give a flat picture depth (after the
//! sprite-effects paper in `../shared/seeds`: bump mapping with a normal map, relief mapping
//! with a depth map, and refraction through a volume bounded by two depth maps).
//!
//! This module holds the level component ([`Sprite`]) and the frame arithmetic the renderer
//! will use ([`Sprite::frame_rect`], [`Sprite::frame_at`], [`direction_index`]); the images
//! are loaded with the level by [`crate::assets`], which checks them against the sprite
//! ([`Sprite::check_sheet`]). No GPU.
//!
//! # The sheet
//!
//! The sheet is a PNG (or JPEG) beside the level cut into frames of `frame_size` pixels,
//! `columns = width / frame_width` across and `rows = height / frame_height` down; both must
//! divide exactly. Frames are numbered row-major: frame `i` is at column `i % columns`, row
//! `i / columns`. A sprite without animations shows frame 0.
//!
//! With `directions: 8`, the picture depends on where the viewer stands: row `r + d` holds,
//! column for column, what a viewer in direction `d` (see [`direction_index`]) sees of the
//! frame in row `r`. Animations list their frames as direction 0 (the front) sees them;
//! direction `d`'s frame is the listed index plus `d × columns`, `d` rows further down. So a
//! sheet holds one block of 8 rows per set of poses (the bundled walker: 5 columns, idle
//! then 4 walking frames, and 8 rows, front, front-left, …), and every listed frame's row
//! plus 7 must be on the sheet.
//!
//! # The maps
//!
//! Every map is the sheet's size and is cut into the same frames, so it animates with it:
//! the `normal_map` is tangent-space in the sprite's own frame (glTF convention: red toward
//! the image's right, green toward its top, blue toward the viewer); a relief's `depth_map`
//! and a refraction's `back_depth` are greyscale (red channel): 0 at the sprite's quad, 255
//! at `relief.depth` world units behind it. Where the sheet's alpha is 0 there is nothing.
//! Refraction follows the paper: the ray enters through the relief's depth map (the front
//! surface), bends by `index_ratio`, and leaves through the back depth map, in the same
//! depth units; so a refraction needs a relief.

use std::ops::RangeInclusive;

use glam::{UVec2, Vec2, Vec3};
use serde::{Deserialize, Serialize};

use crate::components::Validate;
use crate::num;

/// Most frames per second an animation may play.
pub const MAX_FPS: f32 = 1000.0;
/// Deepest relief, world units.
pub const MAX_RELIEF_DEPTH: f32 = 100.0;
/// Ratios of refractive indices a refraction may use (outside over inside: air into glass is
/// about 0.67, into diamond 0.41).
pub const INDEX_RATIOS: RangeInclusive<f32> = 0.2..=5.0;
/// Most animations a sprite may hold.
pub const MAX_ANIMATIONS: usize = 256;
/// Most frames an animation may list.
pub const MAX_ANIMATION_FRAMES: usize = 4096;
/// The number of view directions of a sprite with more than one.
pub const DIRECTIONS: u32 = 8;

/// A picture in the world, cut from a sprite sheet. Placed by its entity's transform: the
/// translation is where the [`pivot`](Sprite::pivot) sits; the rotation turns a
/// [`Billboard::Fixed`] sprite and is the facing 8 directions are measured from; the scale's
/// x and y multiply a [`SpriteSize::World`] size. A sprite entity has no geometry (the
/// sprite is its only surface) and is not a terrain.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Sprite {
    /// The sprite sheet: PNG (RGBA; alpha 0 is empty) path relative to the level.
    #[serde(deserialize_with = "de_path")]
    pub sheet: String,
    /// One frame's size in pixels, `(width, height)`; it must divide the sheet.
    #[serde(with = "num::frame_size")]
    pub frame_size: UVec2,
    /// Named loops of frames; empty (the default, not written): frame 0 stands still. The
    /// first plays unless the caller picks another.
    #[serde(
        default,
        skip_serializing_if = "Vec::is_empty",
        deserialize_with = "de_animations"
    )]
    pub animations: Vec<SpriteAnimation>,
    /// The point of the frame the transform's translation places, as fractions of the frame:
    /// x to the right, y down from the top. Default (0.5, 1.0): the bottom centre, so a
    /// sprite stands on the ground at its translation.
    #[serde(
        default = "default_pivot",
        skip_serializing_if = "is_default_pivot",
        with = "num::unit2"
    )]
    pub pivot: Vec2,
    /// How large the quad is.
    pub size: SpriteSize,
    /// How the quad turns toward the viewer; default [`Billboard::Upright`].
    #[serde(default, skip_serializing_if = "is_upright")]
    pub billboard: Billboard,
    /// 1 (default) or 8 view directions (see the module's documentation for the sheet).
    #[serde(
        default = "one",
        skip_serializing_if = "is_one",
        with = "num::directions"
    )]
    pub directions: u32,
    /// Tangent-space normal map, the sheet's size (bump mapping).
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "de_opt_path"
    )]
    pub normal_map: Option<String>,
    /// Depth behind the quad (relief mapping).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub relief: Option<Relief>,
    /// A refracting volume between the relief's depth map and a back depth map (needs
    /// `relief`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub refraction: Option<Refraction>,
    /// Whether it blocks shadow rays; default false (not written).
    #[serde(default, skip_serializing_if = "is_false")]
    pub casts_shadows: bool,
    /// Whether outlines are drawn around it; default true (not written).
    #[serde(default = "yes", skip_serializing_if = "is_true")]
    pub outlined: bool,
}

/// A named loop of frames.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpriteAnimation {
    /// Its name, unique within the sprite and not empty.
    pub name: String,
    /// Frame indices (row-major over the sheet; direction 0's with 8 directions), shown in
    /// turn: at least 1, at most [`MAX_ANIMATION_FRAMES`].
    #[serde(deserialize_with = "de_frames")]
    pub frames: Vec<u32>,
    /// Frames per second, in (0, [`MAX_FPS`]].
    #[serde(with = "num::fps")]
    pub fps: f32,
}

/// How large a sprite's quad is.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum SpriteSize {
    /// `(width, height)` in world units (times the transform's scale x and y).
    World(#[serde(with = "num::size2")] Vec2),
    /// One sprite pixel covers one probe texel at the sprite's distance, so its pixels are
    /// the size of the world's art pixels there; the renderer works the size out.
    Matched,
}

/// How a sprite's quad turns toward the viewer.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum Billboard {
    /// Faces the viewer fully (turns about every axis).
    Spherical,
    /// Stands upright and turns about the world's Y axis only (characters, foliage).
    #[default]
    Upright,
    /// Does not turn: the quad lies in the transform's XY plane, facing its +Z.
    Fixed,
}

/// The depth behind a sprite's quad, for relief mapping.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Relief {
    /// Greyscale PNG, the sheet's size: 0 at the quad, 255 at `depth`.
    #[serde(deserialize_with = "de_path")]
    pub depth_map: String,
    /// World units behind the quad of the deepest texel (255), in (0, [`MAX_RELIEF_DEPTH`]].
    #[serde(with = "num::relief_depth")]
    pub depth: f32,
}

/// A refracting volume: from the relief's depth map (the front surface) to `back_depth`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Refraction {
    /// Greyscale PNG, the sheet's size: the back surface, in the relief's depth units.
    #[serde(deserialize_with = "de_path")]
    pub back_depth: String,
    /// Refractive index outside over inside (air into glass: about 0.67), within
    /// [`INDEX_RATIOS`].
    #[serde(with = "num::index_ratio")]
    pub index_ratio: f32,
}

/// Which animation [`Sprite::frame_at`] plays: by position or by name.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AnimationRef<'a> {
    /// The animation at this position in [`Sprite::animations`].
    Index(usize),
    /// The animation of this name.
    Name(&'a str),
}

impl From<usize> for AnimationRef<'_> {
    fn from(i: usize) -> Self {
        AnimationRef::Index(i)
    }
}

impl<'a> From<&'a str> for AnimationRef<'a> {
    fn from(name: &'a str) -> Self {
        AnimationRef::Name(name)
    }
}

/// Why a sheet does not fit its sprite ([`Sprite::check_sheet`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SheetError {
    /// The sprite's field at fault: `frame_size`, `directions` or `animations`.
    pub field: &'static str,
    /// The animation at fault, if any.
    pub animation: Option<String>,
    /// What is wrong, for people.
    pub message: String,
}

fn default_pivot() -> Vec2 {
    Vec2::new(0.5, 1.0)
}
fn is_default_pivot(v: &Vec2) -> bool {
    v.x.to_bits() == 0.5f32.to_bits() && v.y.to_bits() == 1.0f32.to_bits()
}
fn is_upright(b: &Billboard) -> bool {
    *b == Billboard::Upright
}
const fn one() -> u32 {
    1
}
fn is_one(v: &u32) -> bool {
    *v == 1
}
const fn yes() -> bool {
    true
}
fn is_true(v: &bool) -> bool {
    *v
}
fn is_false(v: &bool) -> bool {
    !*v
}

impl Sprite {
    /// A still, upright sprite of `sheet` cut into `frame_size` frames, `size` large, with
    /// every other field at its default.
    pub fn new(sheet: &str, frame_size: UVec2, size: SpriteSize) -> Self {
        Sprite {
            sheet: sheet.to_owned(),
            frame_size,
            animations: Vec::new(),
            pivot: default_pivot(),
            size,
            billboard: Billboard::Upright,
            directions: 1,
            normal_map: None,
            relief: None,
            refraction: None,
            casts_shadows: false,
            outlined: true,
        }
    }

    /// Frames across a sheet of `sheet` pixels (0 if a frame is wider than the sheet).
    pub fn columns(&self, sheet: UVec2) -> u32 {
        sheet.x.checked_div(self.frame_size.x).unwrap_or(0)
    }

    /// Rows of frames down a sheet of `sheet` pixels.
    pub fn rows(&self, sheet: UVec2) -> u32 {
        sheet.y.checked_div(self.frame_size.y).unwrap_or(0)
    }

    /// Frames on a sheet of `sheet` pixels: columns × rows (with 8 directions, every
    /// direction's frames are counted).
    pub fn frame_count(&self, sheet: UVec2) -> u32 {
        self.columns(sheet).saturating_mul(self.rows(sheet))
    }

    /// Where frame `index` lies on a sheet of `sheet` pixels: `(x, y, width, height)` in
    /// pixels from the sheet's top-left corner. An index past the last frame gives the last.
    pub fn frame_rect(&self, sheet: UVec2, index: u32) -> (u32, u32, u32, u32) {
        let (w, h) = (self.frame_size.x, self.frame_size.y);
        let columns = self.columns(sheet).max(1);
        let index = index.min(self.frame_count(sheet).saturating_sub(1));
        let (x, y) = (index % columns, index / columns);
        (x.saturating_mul(w), y.saturating_mul(h), w, h)
    }

    /// The animation `which` names, if the sprite has it.
    pub fn animation<'a>(&self, which: impl Into<AnimationRef<'a>>) -> Option<&SpriteAnimation> {
        match which.into() {
            AnimationRef::Index(i) => self.animations.get(i),
            AnimationRef::Name(name) => self.animations.iter().find(|a| a.name == name),
        }
    }

    /// The frame to show `t` seconds into `animation`, seen from `direction` (0..8, from
    /// [`direction_index`]; ignored with 1 direction), on a sheet of `sheet` pixels: the
    /// animation's frame `floor(t × fps)` modulo its length, computed in f64, so it loops,
    /// negative times wrap, and the same time always gives the same frame. An animation the
    /// sprite lacks (or none at all) shows frame 0; a time that is not finite counts as 0.
    pub fn frame_at<'a>(
        &self,
        sheet: UVec2,
        animation: impl Into<AnimationRef<'a>>,
        t: f64,
        direction: u32,
    ) -> u32 {
        let base = match self.animation(animation) {
            Some(a) if !a.frames.is_empty() => {
                let t = if t.is_finite() { t } else { 0.0 };
                let n = a.frames.len() as f64;
                // A hair over, so a time on a frame's boundary (0.25 s at 8 fps) is that
                // frame whatever the rounding of t × fps.
                let step = (t * f64::from(a.fps) + 1e-9).floor().rem_euclid(n);
                let k = if step.is_finite() { step as usize } else { 0 };
                a.frames[k.min(a.frames.len() - 1)]
            }
            _ => 0,
        };
        if self.directions == DIRECTIONS {
            base.saturating_add((direction % DIRECTIONS).saturating_mul(self.columns(sheet)))
        } else {
            base
        }
    }

    /// Whether a sheet of `sheet` pixels fits this sprite: the frame size divides it, an
    /// 8-direction sprite has at least 8 rows, and every animation's frames (with their 7
    /// rows below, for 8 directions) are on it.
    pub fn check_sheet(&self, sheet: UVec2) -> Result<(), SheetError> {
        let fail = |field, animation: Option<&str>, message| SheetError {
            field,
            animation: animation.map(str::to_owned),
            message,
        };
        let f = self.frame_size;
        if f.x == 0 || f.y == 0 || !sheet.x.is_multiple_of(f.x) || !sheet.y.is_multiple_of(f.y) {
            return Err(fail(
                "frame_size",
                None,
                format!(
                    "frame size {}×{} does not divide the sheet's {}×{} pixels",
                    f.x, f.y, sheet.x, sheet.y
                ),
            ));
        }
        let (columns, rows) = (self.columns(sheet), self.rows(sheet));
        let count = self.frame_count(sheet);
        if columns == 0 || rows == 0 {
            return Err(fail(
                "frame_size",
                None,
                format!(
                    "frame size {}×{} is larger than the sheet's {}×{} pixels",
                    f.x, f.y, sheet.x, sheet.y
                ),
            ));
        }
        let eight = self.directions == DIRECTIONS;
        if eight && rows < DIRECTIONS {
            return Err(fail(
                "directions",
                None,
                format!(
                    "8 directions need at least 8 rows of frames, the sheet has {rows} \
                     ({} pixels high, frames {} high)",
                    sheet.y, f.y
                ),
            ));
        }
        for a in &self.animations {
            for &frame in &a.frames {
                if frame >= count {
                    return Err(fail(
                        "animations",
                        Some(&a.name),
                        format!(
                            "animation `{}`: frame {frame} is out of range: the sheet holds \
                             {count} frames (0..={})",
                            a.name,
                            count - 1
                        ),
                    ));
                }
                let row = frame / columns;
                if eight && row + DIRECTIONS > rows {
                    return Err(fail(
                        "animations",
                        Some(&a.name),
                        format!(
                            "animation `{}`: frame {frame} is in row {row}, so with 8 directions \
                             it needs rows {row}..={}, but the sheet has {rows} rows",
                            a.name,
                            row + DIRECTIONS - 1
                        ),
                    ));
                }
            }
        }
        Ok(())
    }

    /// Whether every map is the size of the sheet (`sheet` pixels); `size_of` gives a loaded
    /// image's size (maps not loaded are not checked). `Err((path, message))`: the first map
    /// that differs, and what is wrong with it (the path is the caller's to show).
    pub fn check_map_sizes(
        &self,
        sheet: UVec2,
        size_of: impl Fn(&str) -> Option<UVec2>,
    ) -> Result<(), (String, String)> {
        for (what, path) in self.files().skip(1) {
            if let Some(map) = size_of(path)
                && map != sheet
            {
                let message = format!(
                    "the {what} is {}×{} pixels, but the sheet {:?} is {}×{}: a sprite's maps \
                     must be the size of its sheet",
                    map.x, map.y, self.sheet, sheet.x, sheet.y
                );
                return Err((path.to_owned(), message));
            }
        }
        Ok(())
    }

    /// The image files this sprite names: the sheet, then its maps, in field order, as
    /// `(field, path)`.
    pub fn files(&self) -> impl Iterator<Item = (&'static str, &str)> {
        [
            Some(("sheet", self.sheet.as_str())),
            self.normal_map.as_deref().map(|p| ("normal map", p)),
            self.relief
                .as_ref()
                .map(|r| ("depth map", r.depth_map.as_str())),
            self.refraction
                .as_ref()
                .map(|r| ("back depth map", r.back_depth.as_str())),
        ]
        .into_iter()
        .flatten()
    }
}

/// Which of the 8 directions a viewer looking along `view_dir` sees a sprite from.
/// `view_dir` points from the viewer toward the sprite, in the sprite's own frame (its
/// transform's rotation undone). The viewer stands at `-view_dir`; its azimuth about +Y,
/// measured from the sprite's front (+Z) toward +X (counter-clockwise seen from above),
/// rounded to the nearest 45°, is the direction: 0 front (the viewer at +Z), 1 at +Z+X, 2 at
/// +X (the sprite's left side), 3 at −Z+X, 4 behind, 5 at −Z−X, 6 at −X (its right side),
/// 7 at +Z−X. A bearing exactly between two takes the next counter-clockwise; a view straight
/// down or up (no horizontal part), or one that is not finite, gives 0.
pub fn direction_index(view_dir: Vec3) -> u32 {
    let v = view_dir.as_dvec3();
    let (x, z) = (-v.x, -v.z);
    let horizontal = x * x + z * z;
    if !v.is_finite() || horizontal <= 1e-12 * v.length_squared() || horizontal == 0.0 {
        return 0;
    }
    let sector = std::f64::consts::FRAC_PI_4;
    let d = (x.atan2(z) / sector + 0.5).floor() as i64;
    d.rem_euclid(i64::from(DIRECTIONS)) as u32
}

/// A refraction needs the relief whose depth map is its front surface.
fn check_refraction(sprite: &Sprite) -> Result<(), String> {
    if sprite.refraction.is_some() && sprite.relief.is_none() {
        return Err(
            "a refraction needs a relief: its depth map is the front surface the ray enters \
             and its depth the scale of the back depth map"
                .to_owned(),
        );
    }
    Ok(())
}

/// Reads an entity's sprite and checks its fields against each other, so the error points
/// at the sprite's end.
pub(crate) fn de_sprite<'de, D: serde::Deserializer<'de>>(
    d: D,
) -> Result<Option<Sprite>, D::Error> {
    let sprite = Option::<Sprite>::deserialize(d)?;
    if let Some(s) = &sprite {
        check_refraction(s).map_err(serde::de::Error::custom)?;
    }
    Ok(sprite)
}

fn check_path(path: &str, what: &str) -> Result<(), String> {
    if path.trim().is_empty() {
        Err(format!("{what} path is empty"))
    } else {
        Ok(())
    }
}

fn de_path<'de, D: serde::Deserializer<'de>>(d: D) -> Result<String, D::Error> {
    let path = String::deserialize(d)?;
    check_path(&path, "image").map_err(serde::de::Error::custom)?;
    Ok(path)
}

fn de_opt_path<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Option<String>, D::Error> {
    let path = Option::<String>::deserialize(d)?;
    if let Some(p) = &path {
        check_path(p, "image").map_err(serde::de::Error::custom)?;
    }
    Ok(path)
}

fn de_frames<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Vec<u32>, D::Error> {
    let frames = Vec::<u32>::deserialize(d)?;
    check_frames(&frames).map_err(serde::de::Error::custom)?;
    Ok(frames)
}

fn de_animations<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Vec<SpriteAnimation>, D::Error> {
    let animations = Vec::<SpriteAnimation>::deserialize(d)?;
    check_animations(&animations).map_err(serde::de::Error::custom)?;
    Ok(animations)
}

/// An animation lists 1..=[`MAX_ANIMATION_FRAMES`] frames.
pub fn check_frames(frames: &[u32]) -> Result<(), String> {
    if frames.is_empty() {
        Err("an animation needs at least one frame".to_owned())
    } else if frames.len() > MAX_ANIMATION_FRAMES {
        Err(format!(
            "an animation lists {} frames, at most {MAX_ANIMATION_FRAMES} are allowed",
            frames.len()
        ))
    } else {
        Ok(())
    }
}

/// At most [`MAX_ANIMATIONS`] animations, each named, no name twice.
pub fn check_animations(animations: &[SpriteAnimation]) -> Result<(), String> {
    if animations.len() > MAX_ANIMATIONS {
        return Err(format!(
            "a sprite has {} animations, at most {MAX_ANIMATIONS} are allowed",
            animations.len()
        ));
    }
    for (i, a) in animations.iter().enumerate() {
        if a.name.trim().is_empty() {
            return Err(format!("animation {i} has no name"));
        }
        if animations[..i].iter().any(|b| b.name == a.name) {
            return Err(format!("two animations are called `{}`", a.name));
        }
    }
    Ok(())
}

impl Validate for Sprite {
    fn validate(&self) -> Result<(), (&'static str, String)> {
        let field = |name, r: Result<(), String>| r.map_err(|m| (name, m));
        field("sheet", check_path(&self.sheet, "sheet"))?;
        field(
            "frame_size",
            num::check_frame_size(self.frame_size).map(drop),
        )?;
        field("animations", check_animations(&self.animations))?;
        for a in &self.animations {
            field("animations", check_frames(&a.frames))?;
            field("animations", num::check_fps(a.fps).map(drop))?;
        }
        field("pivot", num::check_unit2(self.pivot).map(drop))?;
        if let SpriteSize::World(size) = self.size {
            field("size", num::check_positive(size.x, "size").map(drop))?;
            field("size", num::check_positive(size.y, "size").map(drop))?;
        }
        field(
            "directions",
            num::check_directions(self.directions).map(drop),
        )?;
        if let Some(p) = &self.normal_map {
            field("normal_map", check_path(p, "normal map"))?;
        }
        if let Some(r) = &self.relief {
            field("relief", check_path(&r.depth_map, "depth map"))?;
            field("relief", num::check_relief_depth(r.depth).map(drop))?;
        }
        if let Some(r) = &self.refraction {
            field("refraction", check_path(&r.back_depth, "back depth map"))?;
            field(
                "refraction",
                num::check_index_ratio(r.index_ratio).map(drop),
            )?;
        }
        field("refraction", check_refraction(self))
    }
}

#[cfg(test)]
mod tests;
