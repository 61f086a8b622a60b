//! The scene's textures on the GPU without bindless: every image, with its mip chain, packed
//! into the layers of one `rgba8unorm` 2D array (the atlas), uploaded once per scene change.
//! Shaders read it with `textureLoad` only (`shaders/lib/texture.wgsl`): wrap modes, the mip
//! level and the filter are applied by hand inside each image's rectangle, so nothing bleeds
//! between neighbours and no sampler or filtering feature is needed.
//!
//! An image's block holds mip 0 at its origin and mips 1.. stacked in a column to its right:
//!
//! ```text
//! +--------+----+
//! |        | 1  |
//! |   0    +--+-+
//! |        |2 |3|...
//! +--------+--+-+
//! ```
//!
//! (mip `k ≥ 1` at x = w₀, y = h₁ + … + h_(k−1)). sRGB images are filtered in linear light
//! and stored as sRGB bytes; the shader decodes them.

use std::collections::HashMap;
use std::sync::Arc;

use bytemuck::{Pod, Zeroable};
use glam::Vec2;
use texel_geom::texture::{Filter, Image, SurfaceMaps, TextureRef, Wrap};

use crate::context::GpuContext;

/// "No texture" in a [`GpuSurface`].
pub const NO_TEXTURE: u32 = u32::MAX;

/// Flag bits of a [`GpuTexInfo`].
pub mod flags {
    /// Stored as sRGB: decode to linear after the fetch.
    pub const SRGB: u32 = 1;
    /// Bilinear (and between mip levels); nearest otherwise.
    pub const LINEAR: u32 = 2;
    /// Wrap mode along U in bits 2-3, along V in bits 4-5 (0 repeat, 1 mirror, 2 clamp).
    pub const WRAP_U_SHIFT: u32 = 2;
    /// See [`WRAP_U_SHIFT`].
    pub const WRAP_V_SHIFT: u32 = 4;
}

/// One image in the atlas (32 bytes; WGSL `TexInfo` in `lib/texture.wgsl`).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable, PartialEq)]
pub struct GpuTexInfo {
    /// Top-left of mip 0 in its layer.
    pub origin: [u32; 2],
    /// Size of mip 0.
    pub size: [u32; 2],
    /// Atlas layer.
    pub layer: u32,
    /// Number of mip levels.
    pub mips: u32,
    /// [`flags`].
    pub flags: u32,
    /// Padding.
    pub _pad: u32,
}

/// The textures of one surface (16 bytes; WGSL `Surface`).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable, PartialEq)]
pub struct GpuSurface {
    /// Albedo texture index, or [`NO_TEXTURE`].
    pub albedo: u32,
    /// Normal map index, or [`NO_TEXTURE`].
    pub normal: u32,
    /// UV multiplier.
    pub uv_scale: [f32; 2],
}

/// Mip level sizes of a `w × h` image, down to 1 × 1.
pub fn mip_sizes(w: u32, h: u32) -> Vec<(u32, u32)> {
    let mut out = vec![(w, h)];
    let (mut a, mut b) = (w, h);
    while a > 1 || b > 1 {
        a = (a / 2).max(1);
        b = (b / 2).max(1);
        out.push((a, b));
    }
    out
}

/// Size of an image's block in the atlas (mip 0 plus the column of smaller mips).
pub fn block_size(w: u32, h: u32) -> (u32, u32) {
    let mips = mip_sizes(w, h);
    if mips.len() == 1 {
        return (w, h);
    }
    let column_w = mips[1].0;
    let column_h: u32 = mips[1..].iter().map(|m| m.1).sum();
    (w + column_w, h.max(column_h))
}

/// An sRGB-encoded byte as linear light in 0..=1.
pub fn srgb_to_linear(c: u8) -> f32 {
    let c = f32::from(c) / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Linear light (clamped to 0..=1) as an sRGB-encoded byte.
pub fn linear_to_srgb(c: f32) -> u8 {
    let c = c.clamp(0.0, 1.0);
    let s = if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0).round() as u8
}

/// The next mip of an RGBA8 image: each pixel the mean of the 2×2 (or 2×1, 1×2) pixels it
/// covers, in linear light when `srgb` (alpha always linear).
fn downsample(src: &[u8], w: u32, h: u32, srgb: bool) -> (Vec<u8>, u32, u32) {
    let (dw, dh) = ((w / 2).max(1), (h / 2).max(1));
    let mut out = Vec::with_capacity((dw * dh * 4) as usize);
    let decode = |v: u8, channel: usize| {
        if srgb && channel < 3 {
            srgb_to_linear(v)
        } else {
            f32::from(v) / 255.0
        }
    };
    for y in 0..dh {
        for x in 0..dw {
            let xs: &[u32] = if w > 1 { &[2 * x, 2 * x + 1] } else { &[0] };
            let ys: &[u32] = if h > 1 { &[2 * y, 2 * y + 1] } else { &[0] };
            let n = (xs.len() * ys.len()) as f32;
            for c in 0..4 {
                let mut sum = 0.0;
                for &sy in ys {
                    for &sx in xs {
                        sum += decode(src[((sy * w + sx) * 4) as usize + c], c);
                    }
                }
                let mean = sum / n;
                out.push(if srgb && c < 3 {
                    linear_to_srgb(mean)
                } else {
                    (mean * 255.0).round() as u8
                });
            }
        }
    }
    (out, dw, dh)
}

/// Every mip level of `image`, level 0 first.
pub fn mip_chain(image: &Image, srgb: bool) -> Vec<(Vec<u8>, u32, u32)> {
    let mut out = vec![(image.pixels.clone(), image.width, image.height)];
    while {
        let (_, w, h) = out.last().expect("level 0");
        *w > 1 || *h > 1
    } {
        let (src, w, h) = out.last().expect("a level");
        let next = downsample(src, *w, *h, srgb);
        out.push(next);
    }
    out
}

/// Why the scene's textures do not fit the GPU.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error(
    "the scene's textures do not fit this GPU: {detail} (limits: {max_size}² pixels per layer, \
     {max_layers} layers)"
)]
pub struct AtlasError {
    /// What did not fit.
    pub detail: String,
    /// The device's largest 2D texture edge.
    pub max_size: u32,
    /// The device's most array layers.
    pub max_layers: u32,
}

/// Where every image went: its record, and the atlas size.
#[derive(Debug, Clone, PartialEq)]
pub struct AtlasLayout {
    /// Edge of each (square) layer.
    pub page: u32,
    /// Number of layers.
    pub layers: u32,
    /// One record per distinct (image, colour space) pair, in first-use order.
    pub infos: Vec<GpuTexInfo>,
}

/// Where a block went: its layer and top-left corner.
pub type Placement = (u32, [u32; 2]);

/// Packs blocks of `sizes` into as few square layers as fit: the layer edge is the smallest
/// power of two that holds the largest block and, if the limits allow, all of them at once
/// (so a small scene gets a small atlas). Returns the layer edge and each block's place.
pub fn pack(
    sizes: &[(u32, u32)],
    max_size: u32,
    max_layers: u32,
) -> Result<(u32, Vec<Placement>), AtlasError> {
    let fail = |detail: String| AtlasError {
        detail,
        max_size,
        max_layers,
    };
    if sizes.is_empty() {
        return Ok((1, Vec::new()));
    }
    let largest = sizes.iter().map(|&(w, h)| w.max(h)).max().unwrap_or(1);
    if largest > max_size {
        return Err(fail(format!(
            "an image's mip chain needs a block {largest} pixels wide"
        )));
    }
    let area: u64 = sizes
        .iter()
        .map(|&(w, h)| u64::from(w) * u64::from(h))
        .sum();
    // Room for packing losses.
    let want = ((area as f64 * 1.3).sqrt().ceil() as u32).max(largest);
    let mut page = want.next_power_of_two().min(max_size);
    loop {
        if let Some(placed) = try_pack(sizes, page, max_layers) {
            return Ok((page, placed));
        }
        if page >= max_size {
            return Err(fail(format!(
                "{} images ({area} pixels with their mips) need more than {max_layers} layers",
                sizes.len()
            )));
        }
        page = (page * 2).min(max_size);
    }
}

fn try_pack(sizes: &[(u32, u32)], page: u32, max_layers: u32) -> Option<Vec<Placement>> {
    use guillotiere::{AtlasAllocator, size2};
    // Largest first packs tighter; results go back in input order.
    let mut order: Vec<usize> = (0..sizes.len()).collect();
    order.sort_by_key(|&i| std::cmp::Reverse(sizes[i].0.max(sizes[i].1)));
    let mut pages: Vec<AtlasAllocator> = Vec::new();
    let mut out = vec![(0, [0, 0]); sizes.len()];
    for i in order {
        let (w, h) = sizes[i];
        let want = size2(w as i32, h as i32);
        let mut placed = None;
        for (layer, alloc) in pages.iter_mut().enumerate() {
            if let Some(a) = alloc.allocate(want) {
                placed = Some((layer as u32, a.rectangle.min));
                break;
            }
        }
        if placed.is_none() {
            if pages.len() as u32 >= max_layers {
                return None;
            }
            let mut alloc = AtlasAllocator::new(size2(page as i32, page as i32));
            let a = alloc.allocate(want)?;
            placed = Some((pages.len() as u32, a.rectangle.min));
            pages.push(alloc);
        }
        let (layer, min) = placed.expect("placed");
        out[i] = (layer, [min.x as u32, min.y as u32]);
    }
    Some(out)
}

/// A texture's identity in the atlas: the image, whether it is sRGB colour and whether it
/// keeps a mip chain. The same image used as colour and as data is stored twice (its mips
/// differ), and once more when it is also read at one level only.
type Key = (*const Image, bool, bool);

/// The scene's textures, gathered and packed on the CPU.
#[derive(Default)]
pub struct TextureSet {
    images: Vec<(Arc<Image>, Key, Filter, [Wrap; 2])>,
    index: HashMap<(Key, Filter, [Wrap; 2]), u32>,
    image_index: HashMap<Key, usize>,
    /// Distinct surfaces, deduplicated.
    pub surfaces: Vec<GpuSurface>,
    surface_index: HashMap<(u32, u32, [u32; 2]), u32>,
}

impl TextureSet {
    fn texture(&mut self, t: &TextureRef, srgb: bool) -> u32 {
        self.record(t, (Arc::as_ptr(&t.image), srgb, true))
    }

    fn record(&mut self, t: &TextureRef, key: Key) -> u32 {
        let full = (key, t.sampler.filter, t.sampler.wrap);
        if let Some(&i) = self.index.get(&full) {
            return i;
        }
        let i = self.images.len() as u32;
        self.images
            .push((t.image.clone(), key, t.sampler.filter, t.sampler.wrap));
        self.index.insert(full, i);
        i
    }

    /// The record index of a data texture (linear, not sRGB: a displacement map).
    pub fn data_texture(&mut self, t: &TextureRef) -> u32 {
        self.texture(t, false)
    }

    /// The record index of a terrain paint layer: sRGB colour with alpha, read one pixel at
    /// a time (nearest, clamped to the edge) at its full size only, so no mip chain is built
    /// or stored.
    pub fn paint_texture(&mut self, image: &Arc<Image>) -> u32 {
        let t = TextureRef {
            image: image.clone(),
            sampler: texel_geom::texture::Sampler {
                filter: Filter::Nearest,
                wrap: [Wrap::ClampToEdge; 2],
            },
        };
        self.record(&t, (Arc::as_ptr(image), true, false))
    }

    /// The surface index of `maps` (0 is "untextured", always present).
    pub fn surface(&mut self, maps: &SurfaceMaps) -> u32 {
        if self.surfaces.is_empty() {
            self.surfaces.push(GpuSurface {
                albedo: NO_TEXTURE,
                normal: NO_TEXTURE,
                uv_scale: [1.0, 1.0],
            });
            self.surface_index.insert(
                (
                    NO_TEXTURE,
                    NO_TEXTURE,
                    Vec2::ONE.to_array().map(f32::to_bits),
                ),
                0,
            );
        }
        let albedo = maps
            .albedo
            .as_ref()
            .map_or(NO_TEXTURE, |t| self.texture(t, true));
        let normal = maps
            .normal
            .as_ref()
            .map_or(NO_TEXTURE, |t| self.texture(t, false));
        let scale = maps.uv_scale.to_array();
        let key = (albedo, normal, scale.map(f32::to_bits));
        if albedo == NO_TEXTURE && normal == NO_TEXTURE {
            return 0;
        }
        *self.surface_index.entry(key).or_insert_with(|| {
            self.surfaces.push(GpuSurface {
                albedo,
                normal,
                uv_scale: scale,
            });
            self.surfaces.len() as u32 - 1
        })
    }

    /// Number of texture records (an image sampled two ways counts twice).
    pub fn len(&self) -> usize {
        self.images.len()
    }

    /// Whether no surface samples a texture.
    pub fn is_empty(&self) -> bool {
        self.images.is_empty()
    }

    /// Uploads the atlas, its records and the surfaces.
    pub fn upload(mut self, ctx: &GpuContext) -> Result<GpuTextures, AtlasError> {
        self.surface(&SurfaceMaps::default());
        let limits = ctx.device.limits();
        let (max_size, max_layers) = (
            limits.max_texture_dimension_2d,
            limits.max_texture_array_layers,
        );
        // One block per distinct (image, colour space, mips); samplers only change the record.
        let mut blocks: Vec<(Arc<Image>, Key)> = Vec::new();
        for (image, key, _, _) in &self.images {
            if let std::collections::hash_map::Entry::Vacant(e) = self.image_index.entry(*key) {
                e.insert(blocks.len());
                blocks.push((image.clone(), *key));
            }
        }
        let sizes: Vec<(u32, u32)> = blocks
            .iter()
            .map(|(i, (_, _, mipped))| match mipped {
                true => block_size(i.width, i.height),
                false => (i.width, i.height),
            })
            .collect();
        let (page, placed) = pack(&sizes, max_size, max_layers)?;
        let layers = placed.iter().map(|p| p.0 + 1).max().unwrap_or(1);
        let texture = ctx.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("scene::textures"),
            size: wgpu::Extent3d {
                width: page,
                height: page,
                depth_or_array_layers: layers,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba8Unorm,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        for ((image, (_, srgb, mipped)), &(layer, origin)) in blocks.iter().zip(&placed) {
            let mut at = [origin[0], origin[1]];
            let levels = match mipped {
                true => mip_chain(image, *srgb),
                false => vec![(image.pixels.clone(), image.width, image.height)],
            };
            for (k, (pixels, w, h)) in levels.into_iter().enumerate() {
                if k == 1 {
                    at = [origin[0] + image.width, origin[1]];
                }
                ctx.queue.write_texture(
                    wgpu::TexelCopyTextureInfo {
                        texture: &texture,
                        mip_level: 0,
                        origin: wgpu::Origin3d {
                            x: at[0],
                            y: at[1],
                            z: layer,
                        },
                        aspect: wgpu::TextureAspect::All,
                    },
                    &pixels,
                    wgpu::TexelCopyBufferLayout {
                        offset: 0,
                        bytes_per_row: Some(4 * w),
                        rows_per_image: Some(h),
                    },
                    wgpu::Extent3d {
                        width: w,
                        height: h,
                        depth_or_array_layers: 1,
                    },
                );
                if k >= 1 {
                    at[1] += h;
                }
            }
        }
        let infos: Vec<GpuTexInfo> = self
            .images
            .iter()
            .map(|(image, key, filter, wrap)| {
                let (layer, origin) = placed[self.image_index[key]];
                let (_, srgb, mipped) = key;
                let wrap_bits = |w: Wrap| match w {
                    Wrap::Repeat => 0,
                    Wrap::MirroredRepeat => 1,
                    Wrap::ClampToEdge => 2,
                };
                GpuTexInfo {
                    origin,
                    size: [image.width, image.height],
                    layer,
                    mips: match mipped {
                        true => mip_sizes(image.width, image.height).len() as u32,
                        false => 1,
                    },
                    flags: u32::from(*srgb) * flags::SRGB
                        + u32::from(*filter == Filter::Linear) * flags::LINEAR
                        + (wrap_bits(wrap[0]) << flags::WRAP_U_SHIFT)
                        + (wrap_bits(wrap[1]) << flags::WRAP_V_SHIFT),
                    _pad: 0,
                }
            })
            .collect();
        let view = texture.create_view(&wgpu::TextureViewDescriptor {
            label: Some("scene::textures"),
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });
        let buffer = |label: &str, bytes: &[u8]| {
            use wgpu::util::DeviceExt;
            ctx.device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(label),
                    contents: bytes,
                    usage: wgpu::BufferUsages::STORAGE,
                })
        };
        let info_bytes: Vec<GpuTexInfo> = if infos.is_empty() {
            vec![GpuTexInfo::zeroed()]
        } else {
            infos.clone()
        };
        Ok(GpuTextures {
            infos_buffer: buffer("scene::texture_infos", bytemuck::cast_slice(&info_bytes)),
            surfaces: buffer("scene::surfaces", bytemuck::cast_slice(&self.surfaces)),
            view,
            _texture: texture,
            layout: AtlasLayout {
                page,
                layers,
                infos,
            },
            images: blocks.len(),
        })
    }
}

/// The uploaded textures.
pub struct GpuTextures {
    _texture: wgpu::Texture,
    /// The atlas, all layers.
    pub view: wgpu::TextureView,
    /// One [`GpuTexInfo`] per texture record (at least one).
    pub infos_buffer: wgpu::Buffer,
    /// One [`GpuSurface`] per distinct surface; surface 0 is untextured.
    pub surfaces: wgpu::Buffer,
    /// Where everything went.
    pub layout: AtlasLayout,
    /// Distinct images stored.
    pub images: usize,
}

impl GpuTextures {
    /// Bytes of GPU memory the atlas takes.
    pub fn bytes(&self) -> u64 {
        4 * u64::from(self.layout.page).pow(2) * u64::from(self.layout.layers)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mips_go_down_to_one_pixel_and_fit_their_block() {
        assert_eq!(
            mip_sizes(16, 4),
            vec![(16, 4), (8, 2), (4, 1), (2, 1), (1, 1)]
        );
        assert_eq!(block_size(16, 16), (24, 16));
        // A strip's mips stack taller than itself.
        assert_eq!(block_size(16, 1), (24, 4));
        assert_eq!(block_size(1, 1), (1, 1));
    }

    #[test]
    fn srgb_mips_average_in_linear_light() {
        let mut img = Image::solid("c", 2, 1, [0, 0, 0, 255]);
        img.pixels[4..8].copy_from_slice(&[255, 255, 255, 255]);
        let chain = mip_chain(&img, true);
        assert_eq!(chain.len(), 2);
        // Mean of black and white is linear 0.5, sRGB 188.
        assert_eq!(chain[1].0, vec![188, 188, 188, 255]);
        let data = mip_chain(&img, false);
        assert_eq!(data[1].0, vec![128, 128, 128, 255]);
    }

    #[test]
    fn packing_keeps_blocks_apart_and_inside_their_layer() {
        let sizes = [(24, 16), (48, 32), (3, 2), (24, 16), (96, 64)];
        let (page, placed) = pack(&sizes, 2048, 8).unwrap();
        assert!(
            page.is_power_of_two() && page <= 256,
            "small scenes get a small atlas: {page}"
        );
        for (i, &(l, o)) in placed.iter().enumerate() {
            assert!(o[0] + sizes[i].0 <= page && o[1] + sizes[i].1 <= page);
            for (j, &(m, p)) in placed.iter().enumerate().skip(i + 1) {
                let apart = l != m
                    || o[0] + sizes[i].0 <= p[0]
                    || p[0] + sizes[j].0 <= o[0]
                    || o[1] + sizes[i].1 <= p[1]
                    || p[1] + sizes[j].1 <= o[1];
                assert!(apart, "blocks {i} and {j} overlap");
            }
        }
        // When one layer is too small, more layers are used; past the limit, a clear error.
        let many = vec![(64, 64); 20];
        let (page, placed) = pack(&many, 128, 8).unwrap();
        assert_eq!(page, 128);
        assert_eq!(placed.iter().map(|p| p.0).max(), Some(4));
        let e = pack(&many, 128, 2).unwrap_err().to_string();
        assert!(e.contains("more than 2 layers"), "{e}");
        let e = pack(&[(300, 10)], 256, 8).unwrap_err().to_string();
        assert!(e.contains("300 pixels wide"), "{e}");
    }
}
