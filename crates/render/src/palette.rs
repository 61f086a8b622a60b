//! The palette a frame's colours are mapped to (`shaders/lib/palette.wgsl`), as the present
//! pass (texel splatting) and the baselines' upscale write their output: each pixel takes
//! the nearest palette colour in OKLab, or with dithering the second nearest where a
//! threshold falls below how far toward it the colour lies. The splat frame's threshold is
//! the Bayer cell of the texel its key names (anchored to the world: a texel keeps its
//! choice as the camera moves); the baselines' is their art pixel's (anchored to the
//! screen, as theirs are).

use bytemuck::{Pod, Zeroable};
use texel_geom::colour::{linear_from_srgb8, oklab_from_linear};

/// The most colours the mapping takes (`texel_scene::palette::MAX_COLOURS`).
pub const MAX_PALETTE_COLOURS: usize = 256;

/// A palette for the renderer: sRGB colours and a dither strength.
#[derive(Debug, Clone, PartialEq)]
pub struct PaletteInput {
    /// The colours, sRGB bytes; at most [`MAX_PALETTE_COLOURS`] are used.
    pub colours: Vec<[u8; 3]>,
    /// Ordered dithering between the two nearest colours: 0 none, 1 full.
    pub dither: f32,
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct Header {
    count: u32,
    dither: f32,
    max_n: u32,
    _pad: u32,
}

/// The size of WGSL `Palette`.
pub const PALETTE_UNIFORM_SIZE: u64 = (size_of::<Header>() + 2 * MAX_PALETTE_COLOURS * 16) as u64;

/// The bytes of WGSL `Palette` for `palette` (none: a count of 0, colours pass through);
/// `max_n` is the side of the faces the caller's texel keys are dense over (0: its keys are
/// not texel keys).
pub(crate) fn uniform_bytes(palette: Option<&PaletteInput>, max_n: u32) -> Vec<u8> {
    let colours = palette.map_or(&[][..], |p| {
        &p.colours[..p.colours.len().min(MAX_PALETTE_COLOURS)]
    });
    let dither = palette.map_or(0.0, |p| p.dither);
    let header = Header {
        count: colours.len() as u32,
        dither: if dither.is_finite() {
            dither.clamp(0.0, 1.0)
        } else {
            0.0
        },
        max_n,
        _pad: 0,
    };
    let mut lab = vec![[0.0f32; 4]; MAX_PALETTE_COLOURS];
    let mut srgb = vec![[0.0f32; 4]; MAX_PALETTE_COLOURS];
    for (i, c) in colours.iter().enumerate() {
        let [l, a, b] = oklab_from_linear(c.map(linear_from_srgb8));
        lab[i] = [l, a, b, 0.0];
        srgb[i] = [c[0], c[1], c[2], 255].map(|v| f32::from(v) / 255.0);
    }
    let mut bytes = bytemuck::bytes_of(&header).to_vec();
    bytes.extend_from_slice(bytemuck::cast_slice(&lab));
    bytes.extend_from_slice(bytemuck::cast_slice(&srgb));
    bytes
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_uniform_is_the_wgsl_struct_and_clamps_what_it_is_given() {
        assert_eq!(uniform_bytes(None, 64).len() as u64, PALETTE_UNIFORM_SIZE);
        let p = PaletteInput {
            colours: vec![[255, 0, 0]; 300],
            dither: f32::NAN,
        };
        let bytes = uniform_bytes(Some(&p), 64);
        assert_eq!(bytes.len() as u64, PALETTE_UNIFORM_SIZE);
        let header: Header = bytemuck::pod_read_unaligned(&bytes[..16]);
        assert_eq!((header.count, header.dither, header.max_n), (256, 0.0, 64));
    }
}
