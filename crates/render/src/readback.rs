//! Reading a rendered frame back to the CPU, for tests, the editor's picking and the
//! evaluator: the splat list, the entity under a pixel, per-pixel provenance, and a probe
//! slot's lit faces as sRGB8 images (the editor's debug view).
//! The GPU copies themselves are `crate::target`'s (`read_texture_region`, `read_buffer`):
//! that module is below the renderer, this one above it.

use texel_probes::probe_set::Slot;

use crate::context::{GpuContext, GpuError};
use crate::frame::Renderer;
use crate::passes::cull::{DrawArgs, SPLAT_BYTES};
use crate::passes::present::source_pixel;
use crate::target::{read_buffer, read_texture_layer, read_texture_region};

/// One splat quad of a frame, as read back by [`Renderer::read_splats`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SplatRecord {
    /// Dense texel index `((slot · 6 + face) · max_n + y) · max_n + x`.
    pub key: u32,
    /// 0 eye, 1 grid, 2 previous.
    pub role: u32,
    /// Texels the quad draws: a run from `key` along its face row, or down its column when
    /// `column` (1 outside runs).
    pub texels: u32,
    /// The run goes down a column.
    pub column: bool,
    /// Which piece of its texel's quad it is: 0 the whole quad or an outlined quad's body,
    /// k + 1 the outline strip along side k (cull.wgsl `emit_outlined`).
    pub part: u32,
    /// World-space corners (top-left, top-right, bottom-right, bottom-left in face space).
    pub corners: [[f32; 3]; 4],
}

/// Per-pixel provenance of a frame ([`Renderer::read_frame_ids`]).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FrameIds {
    /// Frame size.
    pub size: glam::UVec2,
    /// Entity id per pixel, row-major (0 = sky or nothing).
    pub entity: Vec<u32>,
    /// Whether each pixel came from the eye probe.
    pub from_eye: Vec<bool>,
}

impl FrameIds {
    /// The same ids at `output` size, each output pixel taking its internal pixel (the
    /// present pass's nearest upscale).
    fn upscaled(self, output: glam::UVec2) -> FrameIds {
        if output == self.size || self.size.x == 0 || self.size.y == 0 {
            return self;
        }
        let (internal, out) = ((self.size.x, self.size.y), (output.x, output.y));
        let mut up = FrameIds {
            size: output,
            entity: Vec::with_capacity((output.x * output.y) as usize),
            from_eye: Vec::with_capacity((output.x * output.y) as usize),
        };
        for y in 0..output.y {
            for x in 0..output.x {
                let (sx, sy) = source_pixel(x, y, internal, out);
                let i = (sy * internal.0 + sx) as usize;
                up.entity.push(self.entity[i]);
                up.from_eye.push(self.from_eye[i]);
            }
        }
        up
    }
}

impl Renderer {
    /// The splat list of the last frame, read back (for tests and debugging): which texel
    /// each quad draws and its world-space corners.
    pub fn read_splats(&self, ctx: &GpuContext) -> Result<Vec<SplatRecord>, GpuError> {
        let copy = |src: &wgpu::Buffer, bytes: u64| {
            let dst = ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("frame::splat_readback"),
                size: bytes.max(4),
                usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
                mapped_at_creation: false,
            });
            let mut enc = ctx.device.create_command_encoder(&Default::default());
            enc.copy_buffer_to_buffer(src, 0, &dst, 0, bytes);
            ctx.queue.submit([enc.finish()]);
            read_buffer(ctx, &dst)
        };
        let args_bytes = copy(self.cull.list().args, size_of::<DrawArgs>() as u64)?;
        let args: DrawArgs = *bytemuck::from_bytes(&args_bytes);
        let count =
            u64::from(args.instance_count).min(self.cull.list().splats.size() / SPLAT_BYTES);
        if count == 0 {
            return Ok(Vec::new());
        }
        let raw = copy(self.cull.list().splats, count * SPLAT_BYTES)?;
        let words: &[[f32; 16]] = bytemuck::cast_slice(&raw);
        Ok(words
            .iter()
            .map(|w| SplatRecord {
                key: w[3].to_bits() - 1,
                role: w[11].to_bits() & 0xff,
                texels: ((w[11].to_bits() & 0xffff) >> 8).max(1),
                column: w[11].to_bits() & 0x8000_0000 != 0,
                part: (w[11].to_bits() >> 20) & 7,
                corners: [0, 4, 8, 12].map(|i| [w[i], w[i + 1], w[i + 2]]),
            })
            .collect())
    }

    /// The entity id (`ObjectInput::id`) shown at `pixel` of the last frame, or `None` for
    /// sky or outside the frame: the pixel's texel key names a probe texel, whose captured
    /// object index names the object.
    pub fn pick(&self, ctx: &GpuContext, pixel: glam::UVec2) -> Result<Option<u32>, GpuError> {
        let (Some(screen), Some(scene)) = (self.screen.as_ref(), self.scene.as_ref()) else {
            return Ok(None);
        };
        if pixel.x >= screen.output.0 || pixel.y >= screen.output.1 {
            return Ok(None);
        }
        let (x, y) = source_pixel(pixel.x, pixel.y, screen.size, screen.output);
        let internal = glam::UVec2::new(x, y);
        let key = read_texel_u32(ctx, &screen.keys, 0, internal)?;
        if key == 0 {
            return Ok(None);
        }
        if let Some(object) = moving_object(key) {
            return Ok(scene.object_ids.get(object as usize).copied());
        }
        let max_n = Slot::ALL
            .map(|s| self.store.slot(s).n)
            .into_iter()
            .max()
            .unwrap_or(1);
        let k = key - 1;
        let (x, y) = (k % max_n, (k / max_n) % max_n);
        let layer = k / (max_n * max_n);
        let (slot, face) = (Slot::ALL[(layer / 6) as usize % 3], layer % 6);
        let ids = &self.store.slot(slot).ids.texture;
        let object = read_texel_u32(ctx, ids, face, glam::UVec2::new(x, y))?;
        Ok(object
            .checked_sub(1)
            .and_then(|i| scene.object_ids.get(i as usize).copied()))
    }

    /// The entity id (`ObjectInput::id`) that texel `texel` of face `face` of `slot` holds,
    /// or `None` for sky.
    pub fn probe_texel_entity(
        &self,
        ctx: &GpuContext,
        slot: Slot,
        face: u32,
        texel: glam::UVec2,
    ) -> Result<Option<u32>, GpuError> {
        let Some(scene) = self.scene.as_ref() else {
            return Ok(None);
        };
        let ids = &self.store.slot(slot).ids.texture;
        let object = read_texel_u32(ctx, ids, face, texel)?;
        Ok(object
            .checked_sub(1)
            .and_then(|i| scene.object_ids.get(i as usize).copied()))
    }

    /// Per pixel of the last frame: the entity id shown (0 = sky or nothing) and whether the
    /// pixel's colour came from the eye probe (its quads or the background fill). Reads the
    /// key target and the probes' id textures back to the CPU (for the evaluator).
    pub fn read_frame_ids(&self, ctx: &GpuContext) -> Result<FrameIds, GpuError> {
        let (Some(screen), Some(scene)) = (self.screen.as_ref(), self.scene.as_ref()) else {
            return Ok(FrameIds::default());
        };
        let keys = read_texture_layer(ctx, &screen.keys, 0, 4)?;
        let max_n = Slot::ALL
            .map(|s| self.store.slot(s).n)
            .into_iter()
            .max()
            .unwrap_or(1);
        // ids[slot][face] read lazily: only layers some pixel refers to.
        let mut layers: Vec<Option<Vec<u8>>> = vec![None; 18];
        let mut out = FrameIds {
            size: glam::UVec2::new(screen.size.0, screen.size.1),
            entity: Vec::with_capacity(keys.len() / 4),
            from_eye: Vec::with_capacity(keys.len() / 4),
        };
        for k in keys.chunks_exact(4) {
            let key = u32::from_le_bytes([k[0], k[1], k[2], k[3]]);
            if key == 0 {
                out.entity.push(0);
                out.from_eye.push(false);
                continue;
            }
            if let Some(object) = moving_object(key) {
                out.entity
                    .push(scene.object_ids.get(object as usize).copied().unwrap_or(0));
                out.from_eye.push(false);
                continue;
            }
            let k = key - 1;
            let (x, y) = (k % max_n, (k / max_n) % max_n);
            let layer = (k / (max_n * max_n)) as usize % 18;
            let slot = Slot::ALL[layer / 6];
            let tex = self.store.slot(slot);
            if layers[layer].is_none() {
                let face = (layer % 6) as u32;
                layers[layer] = Some(read_texture_layer(ctx, &tex.ids.texture, face, 4)?);
            }
            let ids = layers[layer].as_deref().unwrap_or_default();
            let i = ((y * tex.n + x) * 4) as usize;
            let object = ids
                .get(i..i + 4)
                .map_or(0, |b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]));
            let entity = object
                .checked_sub(1)
                .and_then(|o| scene.object_ids.get(o as usize).copied())
                .unwrap_or(0);
            out.entity.push(entity);
            out.from_eye.push(slot == Slot::Eye);
        }
        Ok(out.upscaled(glam::UVec2::new(screen.output.0, screen.output.1)))
    }
}

impl Renderer {
    /// The six lit faces of `slot` (in [`texel_probes::cube::Face`] order), read back and
    /// converted to opaque sRGB8 RGBA, `n × n` texels each with rows top to bottom, and the
    /// slot's face resolution `n`. The probe store's internal format (linear half floats,
    /// neighbour bits in alpha) stays the renderer's business.
    pub fn read_lit_faces(
        &self,
        ctx: &GpuContext,
        slot: Slot,
    ) -> Result<(u32, Vec<Vec<u8>>), GpuError> {
        self.read_lit_layers(ctx, slot, rgba32f_to_srgb8)
    }

    /// The six lit faces' neighbour bits of `slot` (`n × n` per face, rows top to bottom, in
    /// [`texel_probes::cube::Face`] order): the similar bits, silhouette edges and corner cuts
    /// the shade pass found and the cull pass reads (`lib/common.wgsl`).
    pub fn read_lit_bits(
        &self,
        ctx: &GpuContext,
        slot: Slot,
    ) -> Result<(u32, Vec<Vec<u32>>), GpuError> {
        self.read_lit_layers(ctx, slot, |raw| {
            raw.chunks_exact(16)
                .map(|t| f32::from_le_bytes([t[12], t[13], t[14], t[15]]) as u32)
                .collect()
        })
    }

    /// The six layers of `slot`'s lit texture (`Rgba32Float`), each converted by `convert`,
    /// and the slot's face resolution.
    fn read_lit_layers<T>(
        &self,
        ctx: &GpuContext,
        slot: Slot,
        convert: impl Fn(&[u8]) -> Vec<T>,
    ) -> Result<(u32, Vec<Vec<T>>), GpuError> {
        let textures = self.store.slot(slot);
        let faces = (0..6)
            .map(|layer| {
                read_texture_layer(ctx, &textures.lit.texture, layer, 16).map(|raw| convert(&raw))
            })
            .collect::<Result<_, _>>()?;
        Ok((textures.n, faces))
    }
}

/// `Rgba32Float` texels (linear colour) to opaque sRGB8 RGBA (the lit texture's alpha holds
/// neighbour bits, not coverage, so it is dropped).
fn rgba32f_to_srgb8(raw: &[u8]) -> Vec<u8> {
    raw.chunks_exact(16)
        .flat_map(|t| {
            let ch =
                |i: usize| f32::from_le_bytes([t[4 * i], t[4 * i + 1], t[4 * i + 2], t[4 * i + 3]]);
            [
                linear_to_srgb8(ch(0)),
                linear_to_srgb8(ch(1)),
                linear_to_srgb8(ch(2)),
                255,
            ]
        })
        .collect()
}

/// Linear colour in 0..1 to an sRGB byte (clamped; non-finite values give 0).
fn linear_to_srgb8(c: f32) -> u8 {
    let c = if c.is_finite() {
        c.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let s = if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0).round() as u8
}

/// One `u32` texel of an `R32Uint` texture layer.
fn read_texel_u32(
    ctx: &GpuContext,
    texture: &wgpu::Texture,
    layer: u32,
    at: glam::UVec2,
) -> Result<u32, GpuError> {
    let bytes = read_texture_region(ctx, texture, layer, at, glam::UVec2::ONE, 4)?;
    Ok(u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]))
}

/// The key a moving-pass pixel holds: this bit and the object's index (`shaders/moving.wgsl`);
/// texel keys stay below it.
pub const MOVING_KEY: u32 = 0x8000_0000;

/// The object index a moving-pass pixel's `key` names, if it is one.
pub fn moving_object(key: u32) -> Option<u32> {
    (key & MOVING_KEY != 0).then_some(key & !MOVING_KEY)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn float_texels_convert_to_opaque_srgb_bytes() {
        // 1.0, 0.5, 0.0, then neighbour bits in alpha (dropped); then 2.0, -2.0, NaN.
        let mut raw = Vec::new();
        for c in [1.0f32, 0.5, 0.0, 1234.0, 2.0, -2.0, f32::NAN, 0.0] {
            raw.extend_from_slice(&c.to_le_bytes());
        }
        assert_eq!(
            rgba32f_to_srgb8(&raw),
            vec![255, 188, 0, 255, 255, 0, 0, 255]
        );
    }
}
