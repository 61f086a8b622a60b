//! Sprites on the GPU: every frame of every sheet (and of its maps) as one layer of one
//! `rgba8unorm` 2D array (so a frame never bleeds into its neighbour, and a frame is picked
//! by a layer index), and one 96-byte instance record per sprite (`Sprite` in
//! `shaders/lib/sprite.wgsl`), expanded to a quad in the vertex stage. Static sprites are
//! uploaded once; [`GpuSprites::update`] writes only the records a frame changes.

use std::sync::Arc;

use bytemuck::{Pod, Zeroable};
use glam::{UVec2, Vec3};
use texel_geom::texture::Image;

use crate::context::GpuContext;
use crate::input::{SpriteBillboard, SpriteInput, SpriteState};

/// No layer (a map the sprite lacks).
pub const NO_LAYER: u32 = u32::MAX;

/// Flag bits of [`GpuSprite::flags`] (`shaders/lib/sprite.wgsl`).
pub mod flags {
    /// Billboard mode in bits 0–1: 0 spherical, 1 upright, 2 fixed.
    pub const BILLBOARD_MASK: u32 = 3;
    /// 8 view directions.
    pub const EIGHT: u32 = 4;
    /// Outlined at alpha edges.
    pub const OUTLINED: u32 = 8;
    /// Matched size (`size` unused).
    pub const MATCHED: u32 = 16;
}

/// One sprite's record (`Sprite` in `shaders/lib/sprite.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable, Debug, PartialEq)]
pub struct GpuSprite {
    /// Pivot point in the world.
    pub position: [f32; 3],
    /// Frame shown (direction 0's).
    pub frame: u32,
    /// The fixed orientation (quaternion xyzw).
    pub rotation: [f32; 4],
    /// World size (unused when matched).
    pub size: [f32; 2],
    /// Pivot in fractions of the frame.
    pub pivot: [f32; 2],
    /// Frame size in pixels.
    pub frame_px: [u32; 2],
    /// Frames across the sheet.
    pub columns: u32,
    /// [`flags`].
    pub flags: u32,
    /// First layer of the sheet's frames, of the normal map's, the depth map's and the back
    /// depth map's ([`NO_LAYER`] where missing).
    pub layers: [u32; 4],
    /// Relief depth in world units (0: flat).
    pub relief_depth: f32,
    /// Refraction's index ratio (0: none).
    pub index_ratio: f32,
    /// Frames on the sheet (the last is shown for a frame past it).
    pub frames: u32,
    /// Where its lit texels start in [`GpuSprites::lit`]: two frames' worth (the grid probe's
    /// copy, then the previous probe's).
    pub lit_base: u32,
}

/// Why the sprites cannot be uploaded.
#[derive(Debug, thiserror::Error)]
pub enum SpriteError {
    /// A sprite's frame size does not divide its sheet or a map's size differs.
    #[error("sprite {id}: {message}")]
    Sheet {
        /// The entity id.
        id: u32,
        /// What is wrong.
        message: String,
    },
    /// The sprites' texels, lit once per frame, need a larger buffer than the device binds.
    #[error(
        "the sprites' lit texels need {bytes} bytes (8 per texel, two frames' worth per \
         sprite), more than this device binds ({max}): use fewer or smaller sprites"
    )]
    TooManyTexels {
        /// Bytes needed.
        bytes: u64,
        /// The device's binding limit.
        max: u64,
    },
    /// More frame layers or a larger frame than the device allows.
    #[error(
        "the sprites need {layers} frame layers of {width}×{height} pixels, more than this \
         device allows ({max_layers} layers of at most {max_size} pixels)"
    )]
    TooLarge {
        /// Layers needed.
        layers: u32,
        /// Largest frame width.
        width: u32,
        /// Largest frame height.
        height: u32,
        /// The device's layer limit.
        max_layers: u32,
        /// The device's 2D size limit.
        max_size: u32,
    },
}

/// The sprites' GPU data.
pub struct GpuSprites {
    /// Every frame, one layer each.
    pub frames: wgpu::Texture,
    /// Its view (`texture_2d_array<f32>`).
    pub frames_view: wgpu::TextureView,
    /// Instance records (at least one).
    pub records: wgpu::Buffer,
    /// Each sprite texel's colour as lit this frame and its relief hit (`vec2<u32>`), two
    /// frames' worth per sprite (`GpuSprite::lit_base`), written by the sprite shade pass.
    pub lit: wgpu::Buffer,
    /// Per sprite and copy, what its lit texels were lit for (a probe origin and a hash of
    /// its position, frame, the look and the frame epoch): the shade pass skips a copy whose
    /// key has not changed, so still sprites are lit once, not every frame.
    pub lit_keys: wgpu::Buffer,
    /// The records as last written.
    pub cpu: Vec<GpuSprite>,
}

/// A sheet cut into frames, and where its frames start in the array.
struct Cut<'a> {
    image: &'a Arc<Image>,
    frame: UVec2,
    first: u32,
}

/// The sprites' sheets and maps cut into frames (each image once per frame size), their
/// records, and the texels their lighting needs.
struct Sheets<'a> {
    /// Every image cut, in layer order.
    cuts: Vec<Cut<'a>>,
    /// Layers used (the next free one).
    layers: u32,
    /// One record per sprite.
    records: Vec<GpuSprite>,
    /// Lit texels of every sprite (two frames' worth each).
    lit_texels: u64,
}

impl<'a> Sheets<'a> {
    /// Cuts every sprite's sheet and maps, failing on a frame size that does not divide its
    /// sheet or a map of another size than its sheet.
    fn cut(sprites: &'a [SpriteInput]) -> Result<Self, SpriteError> {
        let mut sheets = Sheets {
            cuts: Vec::new(),
            layers: 0,
            records: Vec::with_capacity(sprites.len()),
            lit_texels: 0,
        };
        for s in sprites {
            let f = s.frame_size;
            let layers = sheets.sprite_layers(s)?;
            let base = u32::try_from(sheets.lit_texels).unwrap_or(u32::MAX);
            sheets.records.push(GpuSprite::new(s, layers, base));
            sheets.lit_texels += 2 * u64::from(f.x) * u64::from(f.y);
        }
        Ok(sheets)
    }

    /// The first layer of `s`'s sheet, normal map, depth map and back depth map
    /// ([`NO_LAYER`] where missing), cutting those not cut yet.
    fn sprite_layers(&mut self, s: &'a SpriteInput) -> Result<[u32; 4], SpriteError> {
        let f = s.frame_size;
        let fail = |message: String| SpriteError::Sheet { id: s.id, message };
        if f.x == 0
            || f.y == 0
            || !s.sheet.width.is_multiple_of(f.x)
            || !s.sheet.height.is_multiple_of(f.y)
        {
            return Err(fail(format!(
                "frame size {}×{} does not divide its sheet `{}` ({}×{})",
                f.x, f.y, s.sheet.name, s.sheet.width, s.sheet.height
            )));
        }
        let maps = [
            s.normal_map.as_ref(),
            s.relief.as_ref().map(|r| &r.0),
            s.refraction.as_ref().map(|r| &r.0),
        ];
        let mut layers = [NO_LAYER; 4];
        for (k, image) in std::iter::once(Some(&s.sheet)).chain(maps).enumerate() {
            let Some(image) = image else { continue };
            if (image.width, image.height) != (s.sheet.width, s.sheet.height) {
                return Err(fail(format!(
                    "map `{}` is {}×{}, its sheet `{}` {}×{}",
                    image.name,
                    image.width,
                    image.height,
                    s.sheet.name,
                    s.sheet.width,
                    s.sheet.height
                )));
            }
            layers[k] = self.layer_of(image, f);
        }
        Ok(layers)
    }

    /// The first layer of `image` cut into `frame`-sized frames, cut now if it was not.
    fn layer_of(&mut self, image: &'a Arc<Image>, frame: UVec2) -> u32 {
        let found = (self.cuts.iter()).find(|c| Arc::ptr_eq(c.image, image) && c.frame == frame);
        match found {
            Some(c) => c.first,
            None => {
                let first = self.layers;
                self.layers += (image.width / frame.x) * (image.height / frame.y);
                self.cuts.push(Cut {
                    image,
                    frame,
                    first,
                });
                first
            }
        }
    }

    /// The size of one layer: the largest frame.
    fn layer_size(&self) -> UVec2 {
        self.cuts.iter().fold(UVec2::ONE, |m, c| m.max(c.frame))
    }
}

/// Fails when the sprites' lit texels (`lit_bytes`) or their frames do not fit `limits`.
fn check_limits(limits: &wgpu::Limits, sheets: &Sheets, lit_bytes: u64) -> Result<(), SpriteError> {
    let layer = sheets.layer_size();
    if lit_bytes
        > limits
            .max_storage_buffer_binding_size
            .min(limits.max_buffer_size)
    {
        return Err(SpriteError::TooManyTexels {
            bytes: lit_bytes,
            max: limits.max_storage_buffer_binding_size,
        });
    }
    if sheets.layers > limits.max_texture_array_layers
        || layer.x > limits.max_texture_dimension_2d
        || layer.y > limits.max_texture_dimension_2d
    {
        return Err(SpriteError::TooLarge {
            layers: sheets.layers,
            width: layer.x,
            height: layer.y,
            max_layers: limits.max_texture_array_layers,
            max_size: limits.max_texture_dimension_2d,
        });
    }
    Ok(())
}

/// The frames' array texture, every cut frame written to its layer, and its view.
fn upload_frames(ctx: &GpuContext, sheets: &Sheets) -> (wgpu::Texture, wgpu::TextureView) {
    let layer = sheets.layer_size();
    let frames = ctx.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("sprites::frames"),
        size: wgpu::Extent3d {
            width: layer.x,
            height: layer.y,
            depth_or_array_layers: sheets.layers.max(1),
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba8Unorm,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    for c in &sheets.cuts {
        let count = (c.image.width / c.frame.x) * (c.image.height / c.frame.y);
        for i in 0..count {
            ctx.queue.write_texture(
                wgpu::TexelCopyTextureInfo {
                    texture: &frames,
                    mip_level: 0,
                    origin: wgpu::Origin3d {
                        x: 0,
                        y: 0,
                        z: c.first + i,
                    },
                    aspect: wgpu::TextureAspect::All,
                },
                &frame_pixels(c.image, c.frame, i, layer),
                wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(layer.x * 4),
                    rows_per_image: Some(layer.y),
                },
                wgpu::Extent3d {
                    width: layer.x,
                    height: layer.y,
                    depth_or_array_layers: 1,
                },
            );
        }
    }
    let frames_view = frames.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    });
    (frames, frames_view)
}

/// Frame `i` of `image` cut into `frame`-sized frames, padded to `layer` with transparent
/// pixels.
fn frame_pixels(image: &Image, frame: UVec2, i: u32, layer: UVec2) -> Vec<u8> {
    let columns = (image.width / frame.x).max(1);
    let (x0, y0) = ((i % columns) * frame.x, (i / columns) * frame.y);
    let mut out = vec![0u8; (layer.x * layer.y * 4) as usize];
    for y in 0..frame.y.min(layer.y) {
        let src = (((y0 + y) * image.width + x0) * 4) as usize;
        let dst = (y * layer.x * 4) as usize;
        let n = (frame.x.min(layer.x) * 4) as usize;
        if let Some(row) = image.pixels.get(src..src + n) {
            out[dst..dst + n].copy_from_slice(row);
        }
    }
    out
}

impl GpuSprite {
    /// The record of `s` whose images start at `layers` and lit texels at `lit_base`.
    pub fn new(s: &SpriteInput, layers: [u32; 4], lit_base: u32) -> GpuSprite {
        let columns = (s.sheet.width / s.frame_size.x.max(1)).max(1);
        let rows = (s.sheet.height / s.frame_size.y.max(1)).max(1);
        let billboard = match s.billboard {
            SpriteBillboard::Spherical => 0,
            SpriteBillboard::Upright => 1,
            SpriteBillboard::Fixed => 2,
        };
        let mut f = billboard;
        if s.eight_directions {
            f |= flags::EIGHT;
        }
        if s.outlined {
            f |= flags::OUTLINED;
        }
        if s.size.is_none() {
            f |= flags::MATCHED;
        }
        GpuSprite {
            position: s.position.to_array(),
            frame: s.frame,
            rotation: s.rotation.normalize().to_array(),
            size: s.size.unwrap_or(glam::Vec2::ONE).to_array(),
            pivot: s.pivot.to_array(),
            frame_px: s.frame_size.to_array(),
            columns,
            flags: f,
            layers,
            relief_depth: s.relief.as_ref().map_or(0.0, |r| r.1),
            index_ratio: s.refraction.as_ref().map_or(0.0, |r| r.1),
            frames: columns * rows,
            lit_base,
        }
    }
}

/// The shadow a sprite casts: frame 0's opaque texels, row by row, as thin quads (two
/// triangles per run of opaque texels) on an upright quad at its base position facing
/// `toward` (the horizontal direction of the first sun), so its shadow has the picture's
/// outline. A matched sprite (whose size depends on the viewer) is taken at one world unit
/// per 32 pixels. The proxy is fixed: animation frames and moves do not change the shadow.
pub fn shadow_triangles(s: &SpriteInput, toward: Vec3) -> Vec<[Vec3; 3]> {
    let f = s.frame_size;
    let size = s
        .size
        .unwrap_or(glam::Vec2::new(f.x as f32, f.y as f32) / 32.0);
    let front = match s.billboard {
        SpriteBillboard::Fixed => s.rotation * Vec3::Z,
        _ => toward,
    };
    let (right, up) = match s.billboard {
        SpriteBillboard::Fixed => (s.rotation * Vec3::X, s.rotation * Vec3::Y),
        _ => {
            let right = Vec3::Y.cross(front).try_normalize().unwrap_or(Vec3::X);
            (right, front.cross(right))
        }
    };
    let px = glam::Vec2::new(size.x / f.x.max(1) as f32, size.y / f.y.max(1) as f32);
    let corner = s.position - right * (s.pivot.x * size.x) + up * (s.pivot.y * size.y);
    let point = |x: u32, y: u32| corner + right * (x as f32 * px.x) - up * (y as f32 * px.y);
    let opaque = |x: u32, y: u32| {
        let i = ((y * s.sheet.width + x) * 4 + 3) as usize;
        s.sheet.pixels.get(i).is_some_and(|&a| a >= 128)
    };
    let mut out = Vec::new();
    for y in 0..f.y.min(s.sheet.height) {
        let mut x = 0;
        while x < f.x.min(s.sheet.width) {
            if !opaque(x, y) {
                x += 1;
                continue;
            }
            let start = x;
            while x < f.x.min(s.sheet.width) && opaque(x, y) {
                x += 1;
            }
            let (a, b, c, d) = (
                point(start, y),
                point(x, y),
                point(x, y + 1),
                point(start, y + 1),
            );
            out.push([a, b, c]);
            out.push([a, c, d]);
        }
    }
    out
}

impl GpuSprites {
    /// Cuts and uploads the sheets and maps of `sprites` (sheets shared between sprites are
    /// cut once) and their records; `None` without sprites.
    pub fn upload(ctx: &GpuContext, sprites: &[SpriteInput]) -> Result<Option<Self>, SpriteError> {
        if sprites.is_empty() {
            return Ok(None);
        }
        let sheets = Sheets::cut(sprites)?;
        let lit_bytes = sheets.lit_texels * 8;
        check_limits(&ctx.device.limits(), &sheets, lit_bytes)?;
        let (frames, frames_view) = upload_frames(ctx, &sheets);
        let records = sheets.records;
        use wgpu::util::DeviceExt;
        let buffer = ctx
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("sprites::records"),
                contents: bytemuck::cast_slice(&records),
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            });
        let lit = ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sprites::lit"),
            size: lit_bytes.max(8),
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        });
        let lit_keys = ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sprites::lit_keys"),
            size: 32 * records.len() as u64,
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        });
        Ok(Some(GpuSprites {
            frames,
            frames_view,
            records: buffer,
            lit,
            lit_keys,
            cpu: records,
        }))
    }

    /// Number of sprites.
    pub fn len(&self) -> u32 {
        self.cpu.len() as u32
    }

    /// Whether there are none (never: an upload without sprites makes no `GpuSprites`).
    pub fn is_empty(&self) -> bool {
        self.cpu.is_empty()
    }

    /// Applies this frame's changes, writing the span of records that changed (one write,
    /// whatever the number of sprites).
    pub fn update(&mut self, ctx: &GpuContext, states: &[SpriteState]) {
        let mut span: Option<(usize, usize)> = None;
        for s in states {
            let Some(r) = self.cpu.get_mut(s.sprite) else {
                continue;
            };
            let position = if s.position.is_finite() {
                s.position
            } else {
                Vec3::from_array(r.position)
            };
            if r.position == position.to_array() && r.frame == s.frame {
                continue;
            }
            r.position = position.to_array();
            r.frame = s.frame;
            span = Some(span.map_or((s.sprite, s.sprite), |(a, b)| {
                (a.min(s.sprite), b.max(s.sprite))
            }));
        }
        if let Some((a, b)) = span {
            let stride = size_of::<GpuSprite>() as u64;
            ctx.queue.write_buffer(
                &self.records,
                a as u64 * stride,
                bytemuck::cast_slice(&self.cpu[a..=b]),
            );
        }
    }
}

/// The CPU twin of `snap_to_probe_texel` in `shaders/lib/sprite.wgsl`: `p` moved to the
/// centre of the texel of a face of `n` texels around `origin` that holds it, at the same
/// Chebyshev distance (where a sprite's anchor is drawn).
pub fn snap_to_probe_texel(p: Vec3, origin: Vec3, n: u32) -> Vec3 {
    let d = p - origin;
    let a = d.abs();
    let m = a.max_element();
    if m < 1.0e-6 || n == 0 {
        return p;
    }
    let nf = n as f32;
    let q = d / m;
    let c = (((q * 0.5 + 0.5) * nf).floor() + 0.5) / nf * 2.0 - 1.0;
    let c = c.clamp(Vec3::splat(-1.0), Vec3::ONE);
    let q = if a.x >= a.y && a.x >= a.z {
        Vec3::new(q.x, c.y, c.z)
    } else if a.y >= a.z {
        Vec3::new(c.x, q.y, c.z)
    } else {
        Vec3::new(c.x, c.y, q.z)
    };
    origin + q * m
}

/// The CPU twin of `shaders/lib/sprite.wgsl`'s relief march and self-shadow, step for step,
/// for tests: a relief sprite's quad (unit axes, world size) over a depth map (`depth(t)`:
/// world units behind the quad at texel `t`, infinite where the sheet is empty).
pub struct ReliefQuad<'a> {
    /// Unit right, up and front (toward the viewer) axes.
    pub axes: [Vec3; 3],
    /// World size of the frame.
    pub size: glam::Vec2,
    /// Frame size in pixels.
    pub frame_px: UVec2,
    /// Deepest relief, world units.
    pub relief_depth: f32,
    /// Depth behind the quad at a texel.
    pub depth: &'a dyn Fn(UVec2) -> f32,
}

impl ReliefQuad<'_> {
    /// The depth the march meets at `t`: the deepest a hair above the relief's floor (as
    /// `sprite_depth` in the shader).
    fn floor_depth(&self, t: UVec2) -> f32 {
        (self.depth)(t).min(0.999 * self.relief_depth)
    }
}

impl ReliefQuad<'_> {
    fn texel_at(&self, uv: glam::Vec2) -> UVec2 {
        let t = (uv * self.frame_px.as_vec2()).floor().max(glam::Vec2::ZERO);
        t.as_uvec2().min(self.frame_px - UVec2::ONE)
    }

    fn steps(&self) -> u32 {
        self.frame_px.max_element().clamp(8, 64)
    }

    /// Where the ray from frame coordinate `uv0` along unit `dir` meets the relief: its
    /// frame coordinate and its depth behind the quad, `None` when it leaves the frame.
    pub fn hit(&self, uv0: glam::Vec2, dir: Vec3) -> Option<(glam::Vec2, f32)> {
        let [right, up, front] = self.axes;
        let dc = -dir.dot(front);
        if dc <= 1.0e-4 {
            return None;
        }
        let duv = glam::Vec2::new(dir.dot(right) / self.size.x, -dir.dot(up) / self.size.y);
        let t_max = self.relief_depth / dc;
        let steps = self.steps();
        let (mut lo, mut hi) = (0.0f32, -1.0f32);
        for i in 0..=steps {
            let t = t_max * i as f32 / steps as f32;
            let uv = uv0 + duv * t;
            if uv.cmplt(glam::Vec2::ZERO).any() || uv.cmpge(glam::Vec2::ONE).any() {
                return None;
            }
            if dc * t >= self.floor_depth(self.texel_at(uv)) {
                hi = t;
                break;
            }
            lo = t;
        }
        if hi < 0.0 {
            return None;
        }
        for _ in 0..6 {
            let mid = 0.5 * (lo + hi);
            if dc * mid >= self.floor_depth(self.texel_at(uv0 + duv * mid)) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        let uv = (uv0 + duv * hi).clamp(glam::Vec2::ZERO, glam::Vec2::splat(0.999_999));
        Some((uv, dc * hi))
    }

    /// Whether the relief blocks unit direction `l` (toward a light) from the surface point
    /// at `uv`, `c` deep; a light behind the quad is blocked.
    pub fn shadowed(&self, uv: glam::Vec2, c: f32, l: Vec3) -> bool {
        let [right, up, front] = self.axes;
        let lc = -l.dot(front);
        if lc >= -1.0e-4 {
            return true;
        }
        let duv = glam::Vec2::new(l.dot(right) / self.size.x, -l.dot(up) / self.size.y);
        let t_max = c / -lc;
        let steps = self.steps();
        for i in 1..steps {
            let t = t_max * (i as f32 + 0.5) / steps as f32;
            let p = uv + duv * t;
            if p.cmplt(glam::Vec2::ZERO).any() || p.cmpge(glam::Vec2::ONE).any() {
                return false;
            }
            let depth = c + lc * t;
            let d = (self.depth)(self.texel_at(p));
            if d.is_finite() && depth > d + 1.0e-4 {
                return true;
            }
        }
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_frame_is_cut_from_its_cell_and_padded() {
        // 4×2 sheet of 2×2 frames: frame 1 is the right half.
        let mut pixels = Vec::new();
        for y in 0..2u8 {
            for x in 0..4u8 {
                pixels.extend([x, y, 0, 255]);
            }
        }
        let image = Image {
            name: "t".into(),
            width: 4,
            height: 2,
            pixels,
        };
        let f = frame_pixels(&image, UVec2::new(2, 2), 1, UVec2::new(3, 2));
        assert_eq!(&f[0..4], &[2, 0, 0, 255]);
        assert_eq!(&f[4..8], &[3, 0, 0, 255]);
        assert_eq!(&f[8..12], &[0, 0, 0, 0], "padding is transparent");
        assert_eq!(&f[12..16], &[2, 1, 0, 255]);
    }

    #[test]
    fn a_moving_anchor_steps_from_texel_centre_to_texel_centre() {
        // A probe of 64 texels at the origin; a sprite sliding along x at 5 units down -Z.
        let (origin, n) = (Vec3::ZERO, 64);
        let texel = 2.0 * 5.0 / n as f32;
        let mut steps = Vec::new();
        for i in 0..200 {
            let p = Vec3::new(-1.0 + i as f32 * 0.01, 0.3, -5.0);
            let q = snap_to_probe_texel(p, origin, n);
            // Same Chebyshev distance, on a texel centre of the −Z face.
            assert!((q.z + 5.0).abs() < 1e-5, "{q}");
            let u = (q.x / 5.0 * 0.5 + 0.5) * n as f32;
            assert!((u - u.floor() - 0.5).abs() < 1e-3, "{u}");
            assert!((q - p).truncate().abs().max_element() <= 0.5 * texel + 1e-5);
            if steps.last() != Some(&q) {
                steps.push(q);
            }
        }
        // Two units of travel (12.8 texels), whole texels at a time: 13 or 14 positions.
        let texels = 2.0 / texel;
        assert!(
            (texels..texels + 1.5).contains(&(steps.len() as f32)),
            "{} positions over {texels} texels",
            steps.len()
        );
    }

    #[test]
    fn records_are_the_shader_struct_size() {
        assert_eq!(size_of::<GpuSprite>(), 96);
    }
}
