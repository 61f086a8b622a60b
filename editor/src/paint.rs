//! Terrain paint on the CPU: the colour layer a terrain's Paint brush lays over its gradient
//! (`texel_scene::terrain::PaintLayer`, an RGBA8 PNG beside the level), where its pixels lie
//! ([`PaintPlace`]), a stroke ([`PaintStroke`]: each pixel covered up to the brush's
//! opacity, once per stroke however often the brush passes), the change an undo step keeps
//! ([`PaintChange`]), the blank layer a terrain without one gets on its first stroke, and the
//! file a layer is saved to. The edits through the editor state (a stroke's starting layer,
//! "Clear paint") are `crate::terrain_edits`'.
//!
//! Pixels hold sRGB colour and a linear alpha (the paint's cover); a stroke composites its
//! colour over them in linear light, so what the renderer blends over the gradient is what
//! the brush showed.

use std::path::Path;
use std::sync::Arc;

use glam::{Vec2, Vec3};
use texel_render::textures::{linear_to_srgb, srgb_to_linear};
use texel_scene::terrain::Heightfield;
use texel_scene::texture::{Image, encode_png};

use crate::terrain::{Region, falloff_weight, level_file_name};

/// Largest edge of a paint layer the editor makes (a layer takes the heightmap's grid size
/// up to this).
pub const PAINT_MAX: u32 = 1024;

/// The size of the layer a terrain with heights `field` gets on its first stroke: one pixel
/// per height sample, at most [`PAINT_MAX`] per edge.
pub fn layer_size(field: &Heightfield) -> (u32, u32) {
    (
        field.width.clamp(1, PAINT_MAX),
        field.depth.clamp(1, PAINT_MAX),
    )
}

/// A layer of `width` × `height` pixels painted nowhere (alpha 0 everywhere).
pub fn blank_layer(name: &str, width: u32, height: u32) -> Image {
    Image::solid(name, width, height, [0; 4])
}

/// Where a paint layer's pixels lie: pixel (i, j) covers the cell of the terrain's extent
/// whose centre is at ((i + 0.5) / w, (j + 0.5) / h) of it along X and Z.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PaintPlace {
    /// World X and Z of the terrain's −X −Z corner.
    pub corner: Vec2,
    /// World extent along X and Z.
    pub size: Vec2,
    /// Pixels along X.
    pub width: u32,
    /// Pixels along Z (rows).
    pub height: u32,
}

impl PaintPlace {
    /// The layer `image` over a terrain of `size` centred on `origin`.
    pub fn new(origin: Vec3, size: Vec2, image: &Image) -> Self {
        PaintPlace {
            corner: Vec2::new(origin.x, origin.z) - 0.5 * size,
            size,
            width: image.width.max(1),
            height: image.height.max(1),
        }
    }

    /// World size of a pixel along X and Z.
    pub fn pixel(&self) -> Vec2 {
        self.size / Vec2::new(self.width as f32, self.height as f32)
    }

    /// World X and Z of the centre of pixel (`i`, `j`).
    pub fn centre(&self, i: u32, j: u32) -> Vec2 {
        self.corner + (Vec2::new(i as f32, j as f32) + 0.5) * self.pixel()
    }

    /// The pixels whose cells lie in the world box `min..max` (X and Z), as a region
    /// clamped to the layer; empty when the box misses it.
    fn pixels_in(&self, min: Vec2, max: Vec2) -> Region {
        let lo = ((min - self.corner) / self.pixel()).floor();
        let hi = ((max - self.corner) / self.pixel()).floor() + 1.0;
        let (w, h) = (self.width as f32, self.height as f32);
        Region {
            x0: lo.x.clamp(0.0, w) as u32,
            z0: lo.y.clamp(0.0, h) as u32,
            x1: hi.x.clamp(0.0, w) as u32,
            z1: hi.y.clamp(0.0, h) as u32,
        }
    }

    /// The world box (X and Z) of the cells of the pixels `r`.
    pub fn bounds(&self, r: Region) -> (Vec2, Vec2) {
        let at = |i: u32, j: u32| self.corner + Vec2::new(i as f32, j as f32) * self.pixel();
        (at(r.x0, r.z0), at(r.x1, r.z1))
    }
}

/// `colour` (sRGB) laid over the paint pixel `pixel` with cover `cover` (0..=1), composited
/// in linear light: what the result shows over any gradient colour is `colour` over what
/// `pixel` showed, by `cover`.
pub fn paint_over(pixel: [u8; 4], colour: [u8; 3], cover: f32) -> [u8; 4] {
    let k = cover.clamp(0.0, 1.0);
    if k <= 0.0 {
        return pixel;
    }
    let a = f32::from(pixel[3]) / 255.0;
    let out_a = k + a * (1.0 - k);
    let channel = |c: usize| {
        let lin = srgb_to_linear(colour[c]) * k + srgb_to_linear(pixel[c]) * a * (1.0 - k);
        linear_to_srgb(lin / out_a)
    };
    [
        channel(0),
        channel(1),
        channel(2),
        (out_a * 255.0).round() as u8,
    ]
}

/// The paint pixel `pixel` with `cover` (0..=1) of it wiped away: its alpha falls toward 0,
/// its colour stays.
pub fn erase(pixel: [u8; 4], cover: f32) -> [u8; 4] {
    let k = cover.clamp(0.0, 1.0);
    let a = f32::from(pixel[3]) * (1.0 - k);
    [pixel[0], pixel[1], pixel[2], a.round() as u8]
}

/// A paint stroke in progress on a copy of a layer: each pixel's cover is the largest the
/// brush gave it during the stroke (`opacity` × its falloff weight), and the pixel is the
/// layer's before the stroke with that cover of the stroke's colour over it (or wiped). So a
/// stroke never paints beyond its opacity, however often it passes, and the result does not
/// depend on the frame rate.
#[derive(Debug, Clone)]
pub struct PaintStroke {
    start: Arc<Image>,
    work: Image,
    cover: Vec<f32>,
    colour: [u8; 3],
    erase: bool,
    touched: Option<Region>,
}

impl PaintStroke {
    /// A stroke of `colour` (sRGB; `erase`: wiping instead) over the layer `start`.
    pub fn new(start: Arc<Image>, colour: [u8; 3], erase: bool) -> Self {
        let cover = vec![0.0; (start.width as usize) * (start.height as usize)];
        PaintStroke {
            work: (*start).clone(),
            start,
            cover,
            colour,
            erase,
            touched: None,
        }
    }

    /// The layer as painted so far.
    pub fn image(&self) -> &Image {
        &self.work
    }

    /// The layer before the stroke.
    pub fn start(&self) -> &Arc<Image> {
        &self.start
    }

    /// The pixels the stroke has covered so far.
    pub fn touched(&self) -> Option<Region> {
        self.touched
    }

    /// Stamps the brush (`radius` world units, `opacity` and `falloff` 0..=1) centred on the
    /// world point `centre` (its X and Z) on a layer placed at `place`; returns the pixels
    /// whose cover grew, `None` when none did.
    pub fn dab(
        &mut self,
        place: &PaintPlace,
        centre: Vec3,
        radius: f32,
        opacity: f32,
        falloff: f32,
    ) -> Option<Region> {
        if (place.width, place.height) != (self.work.width, self.work.height)
            || radius.is_nan()
            || radius <= 0.0
            || !centre.is_finite()
        {
            return None;
        }
        let c = Vec2::new(centre.x, centre.z);
        let region = place.pixels_in(c - radius, c + radius);
        let opacity = opacity.clamp(0.0, 1.0);
        let w = self.work.width as usize;
        let mut grown: Option<Region> = None;
        for j in region.z0..region.z1 {
            for i in region.x0..region.x1 {
                let d = place.centre(i, j).distance(c) / radius;
                let k = opacity * falloff_weight(d, falloff);
                let at = j as usize * w + i as usize;
                if k <= self.cover[at] {
                    continue;
                }
                self.cover[at] = k;
                let before = self.start.pixel(i, j);
                let next = match self.erase {
                    true => erase(before, k),
                    false => paint_over(before, self.colour, k),
                };
                self.work.pixels[4 * at..4 * at + 4].copy_from_slice(&next);
                let here = Region {
                    x0: i,
                    z0: j,
                    x1: i + 1,
                    z1: j + 1,
                };
                grown = Some(grown.map_or(here, |g| g.union(here)));
            }
        }
        if let Some(g) = grown {
            self.touched = Some(self.touched.map_or(g, |t| t.union(g)));
        }
        grown
    }

    /// The stroke as an undo step: the pixels it touched before and after; `None` when it
    /// changed nothing.
    pub fn change(&self) -> Option<PaintChange> {
        let region = self.touched?;
        let change = PaintChange::patch(&self.start, &self.work, region);
        match &change {
            PaintChange::Patch { before, after, .. } if before == after => None,
            _ => Some(change),
        }
    }
}

/// The RGBA bytes of `region` of `image`, row by row.
fn copy_pixels(image: &Image, region: Region) -> Vec<u8> {
    let w = image.width as usize;
    let mut out = Vec::with_capacity(4 * region.len());
    for j in region.z0..region.z1 {
        let row = j as usize * w;
        let (a, b) = (row + region.x0 as usize, row + region.x1 as usize);
        out.extend_from_slice(&image.pixels[4 * a..4 * b]);
    }
    out
}

/// Writes `bytes` (row by row, as [`copy_pixels`] gives them) into `region` of `image`.
fn paste_pixels(image: &mut Image, region: Region, bytes: &[u8]) {
    let (w, rw) = (image.width as usize, 4 * (region.x1 - region.x0) as usize);
    for (k, j) in (region.z0..region.z1).enumerate() {
        let at = 4 * (j as usize * w + region.x0 as usize);
        image.pixels[at..at + rw].copy_from_slice(&bytes[k * rw..(k + 1) * rw]);
    }
}

/// What an undo step keeps of a change to a terrain's paint.
#[derive(Debug, Clone, PartialEq)]
pub enum PaintChange {
    /// A stroke: the pixels of `region` before and after (RGBA, row by row) on a layer of
    /// `width` × `height`. A terrain with no layer before it starts from a blank one.
    Patch {
        /// Layer width, pixels.
        width: u32,
        /// Layer height, pixels.
        height: u32,
        /// The pixels changed.
        region: Region,
        /// Their bytes before.
        before: Vec<u8>,
        /// Their bytes after.
        after: Vec<u8>,
    },
    /// The whole layer, before and after (`None`: no layer, as after "Clear paint").
    Layer {
        /// Before.
        before: Option<Arc<Image>>,
        /// After.
        after: Option<Arc<Image>>,
    },
}

impl PaintChange {
    /// The change from `before` to `after` (the same size) confined to `region`.
    pub fn patch(before: &Image, after: &Image, region: Region) -> Self {
        PaintChange::Patch {
            width: before.width,
            height: before.height,
            region,
            before: copy_pixels(before, region),
            after: copy_pixels(after, region),
        }
    }

    /// The layer after the change (`forward`) or before it, made from `from`, the layer on
    /// the other side (`None`: the terrain had none). An error when `from` is not the layer
    /// the change was made on.
    pub fn apply(&self, from: Option<&Image>, forward: bool) -> Result<Option<Image>, String> {
        match self {
            PaintChange::Patch {
                width,
                height,
                region,
                before,
                after,
            } => {
                let mut out = match from {
                    Some(f) => f.clone(),
                    None => blank_layer("paint", *width, *height),
                };
                let bytes = if forward { after } else { before };
                if (out.width, out.height) != (*width, *height)
                    || !region.fits(*width, *height)
                    || bytes.len() != 4 * region.len()
                {
                    return Err(format!(
                        "the terrain's paint is {}×{}, the stroke was made on {width}×{height}",
                        out.width, out.height
                    ));
                }
                paste_pixels(&mut out, *region, bytes);
                Ok(Some(out))
            }
            PaintChange::Layer { before, after } => {
                let to = if forward { after } else { before };
                Ok(to.as_deref().cloned())
            }
        }
    }

    /// The change that undoes this one.
    pub fn reversed(&self) -> PaintChange {
        match self {
            PaintChange::Patch {
                width,
                height,
                region,
                before,
                after,
            } => PaintChange::Patch {
                width: *width,
                height: *height,
                region: *region,
                before: after.clone(),
                after: before.clone(),
            },
            PaintChange::Layer { before, after } => PaintChange::Layer {
                before: after.clone(),
                after: before.clone(),
            },
        }
    }

    /// A short description for the Undo menu.
    pub fn describe(&self) -> &'static str {
        match self {
            PaintChange::Patch { .. } => "paint",
            PaintChange::Layer { after: None, .. } => "clear paint",
            PaintChange::Layer { .. } => "paint layer",
        }
    }
}

/// The paint file (relative to the level) a terrain's new layer is saved to:
/// `<level stem>_<entity name or index>_paint.png`, unique while `taken` says a name is used.
pub fn paint_file_name(
    level: &Path,
    entity: Option<&str>,
    index: usize,
    taken: impl Fn(&str) -> bool,
) -> String {
    level_file_name(level, entity, index, "_paint", taken)
}

/// Writes `image` to `file` as an RGBA8 PNG, atomically (a failed write leaves the old
/// file as it was), creating its folder.
pub fn write_paint(file: &Path, image: &Image) -> Result<(), String> {
    if image.pixels.len() != 4 * (image.width as usize) * (image.height as usize) {
        return Err(format!(
            "{}: the paint does not fill the layer",
            file.display()
        ));
    }
    if let Some(dir) = file.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    texel_scene::save::write_atomic(file, &encode_png(image))
        .map_err(|e| format!("cannot write the paint layer {}: {e}", file.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A blank 16 × 8 layer over a 32 × 16 terrain centred on the origin (2 units a pixel).
    fn layer() -> (Arc<Image>, PaintPlace) {
        let image = Arc::new(blank_layer("paint", 16, 8));
        let place = PaintPlace::new(Vec3::ZERO, Vec2::new(32.0, 16.0), &image);
        (image, place)
    }

    #[test]
    fn pixels_sit_on_the_cells_of_the_extent() {
        let (_, place) = layer();
        assert_eq!(place.centre(0, 0), Vec2::new(-15.0, -7.0));
        assert_eq!(place.centre(15, 7), Vec2::new(15.0, 7.0));
        let r = place.pixels_in(Vec2::new(-1.0, -1.0), Vec2::new(1.0, 1.0));
        assert_eq!((r.x0, r.z0, r.x1, r.z1), (7, 3, 9, 5));
        let off = place.pixels_in(Vec2::splat(100.0), Vec2::splat(101.0));
        assert!(off.is_empty());
        assert_eq!(
            place.bounds(r),
            (Vec2::new(-2.0, -2.0), Vec2::new(2.0, 2.0))
        );
    }

    #[test]
    fn painting_over_composites_in_linear_light() {
        assert_eq!(paint_over([0; 4], [200, 10, 20], 1.0), [200, 10, 20, 255]);
        assert_eq!(
            paint_over([9, 9, 9, 255], [200, 10, 20], 0.0),
            [9, 9, 9, 255]
        );
        // Half cover of white over a blank pixel: white at half alpha.
        assert_eq!(paint_over([0; 4], [255; 3], 0.5), [255, 255, 255, 128]);
        // Half cover of white over opaque black: linear 0.5 grey, opaque.
        assert_eq!(
            paint_over([0, 0, 0, 255], [255; 3], 0.5),
            [188, 188, 188, 255]
        );
        assert_eq!(erase([10, 20, 30, 200], 0.5), [10, 20, 30, 100]);
        assert_eq!(erase([10, 20, 30, 200], 1.0), [10, 20, 30, 0]);
    }

    #[test]
    fn a_dab_paints_its_core_eases_to_its_rim_and_never_passes_its_opacity() {
        let (start, place) = layer();
        let mut s = PaintStroke::new(start.clone(), [255, 0, 0], false);
        // Radius 6 with half of it fading, centred on pixel (8, 4)'s centre (1, 1).
        let c = Vec3::new(1.0, 5.0, 1.0);
        let r = s.dab(&place, c, 6.0, 1.0, 0.5).expect("painted");
        assert!(r.x0 >= 5 && r.x1 <= 12 && r.z0 >= 1 && r.z1 <= 8, "{r:?}");
        assert_eq!(
            s.image().pixel(8, 4),
            [255, 0, 0, 255],
            "the core is painted"
        );
        // 4 units out: in the fading ring.
        let ring = s.image().pixel(10, 4);
        assert!(ring[3] > 0 && ring[3] < 255, "{ring:?}");
        assert_eq!(s.image().pixel(0, 0), [0; 4], "far pixels stay blank");
        // Passing again changes nothing: the cover is already there.
        let again = s.image().clone();
        assert!(s.dab(&place, c, 6.0, 1.0, 0.5).is_none());
        assert_eq!(*s.image(), again);
        // A stroke of opacity 0.5 covers at most half, however many dabs.
        let mut half = PaintStroke::new(start, [255, 0, 0], false);
        for _ in 0..10 {
            half.dab(&place, c, 6.0, 0.5, 0.5);
        }
        assert_eq!(half.image().pixel(8, 4)[3], 128);
    }

    #[test]
    fn erasing_lowers_alpha_and_a_patch_undoes_and_redoes_exactly() {
        let (blank, place) = layer();
        let mut paint = PaintStroke::new(blank.clone(), [0, 128, 255], false);
        paint.dab(&place, Vec3::ZERO, 5.0, 1.0, 0.0);
        let first = paint.change().expect("a change");
        let painted = first
            .apply(None, true)
            .expect("from no layer")
            .expect("a layer");
        assert_eq!(painted, *paint.image());
        assert_eq!(
            first.apply(Some(&painted), false).expect("undo"),
            Some((*blank).clone())
        );
        // Ctrl: half the cover wiped where the brush passes.
        let mut wipe = PaintStroke::new(Arc::new(painted.clone()), [0; 3], true);
        wipe.dab(&place, Vec3::ZERO, 2.0, 0.5, 0.0);
        assert_eq!(wipe.image().pixel(8, 4), [0, 128, 255, 128]);
        assert_eq!(
            wipe.image().pixel(4, 4),
            painted.pixel(4, 4),
            "outside the brush"
        );
        let change = wipe.change().expect("a change");
        let wiped = change.apply(Some(&painted), true).expect("redo");
        assert_eq!(wiped.as_ref(), Some(wipe.image()));
        let back = change.reversed().apply(wiped.as_ref(), true).expect("undo");
        assert_eq!(back, Some(painted));
        // Another size is refused; a stroke that changed nothing is no step.
        assert!(change.apply(Some(&blank_layer("x", 3, 3)), true).is_err());
        let idle = PaintStroke::new(blank, [1, 2, 3], false);
        assert!(idle.change().is_none());
        // Clearing keeps the layer to bring back.
        let clear = PaintChange::Layer {
            before: Some(Arc::new(wipe.image().clone())),
            after: None,
        };
        assert_eq!(clear.apply(Some(wipe.image()), true), Ok(None));
        assert_eq!(clear.apply(None, false), Ok(Some(wipe.image().clone())));
        assert_eq!(clear.describe(), "clear paint");
    }

    #[test]
    fn new_layers_follow_the_heightmap_grid_up_to_a_cap() {
        assert_eq!(layer_size(&Heightfield::flat(129, 65, 0.0)), (129, 65));
        assert_eq!(layer_size(&Heightfield::flat(4097, 2, 0.0)), (PAINT_MAX, 2));
        let level = Path::new("dir/hills.ron");
        assert_eq!(
            paint_file_name(level, Some("Island"), 0, |_| false),
            "hills_Island_paint.png"
        );
        assert_eq!(
            paint_file_name(level, None, 3, |n| n == "hills_3_paint.png"),
            "hills_3_paint_2.png"
        );
    }
}
