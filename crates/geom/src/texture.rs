//! Texture images and how a surface samples them: the data a material or a glTF primitive
//! hands the renderer. Decoding lives in `texel_scene`; packing and sampling in
//! `texel_render`.

use std::sync::Arc;

use glam::Vec2;

/// Largest texture edge, in pixels, the engine accepts (a pixel-art texture is far smaller;
/// this bounds memory and atlas packing).
pub const MAX_TEXTURE_SIZE: u32 = 2048;

/// A decoded image: RGBA8, rows top to bottom.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Image {
    /// Where it came from (a file path, or a glTF image name), for messages and stats.
    pub name: String,
    /// Width in pixels (1..=[`MAX_TEXTURE_SIZE`]).
    pub width: u32,
    /// Height in pixels (1..=[`MAX_TEXTURE_SIZE`]).
    pub height: u32,
    /// `width * height * 4` bytes.
    pub pixels: Vec<u8>,
}

impl Image {
    /// A `width` × `height` image filled with one RGBA8 colour.
    pub fn solid(name: &str, width: u32, height: u32, rgba: [u8; 4]) -> Image {
        Image {
            name: name.to_owned(),
            width,
            height,
            pixels: rgba.repeat((width * height) as usize),
        }
    }

    /// The RGBA8 pixel at column `x`, row `y` (0 = top).
    pub fn pixel(&self, x: u32, y: u32) -> [u8; 4] {
        let i = ((y * self.width + x) * 4) as usize;
        [
            self.pixels[i],
            self.pixels[i + 1],
            self.pixels[i + 2],
            self.pixels[i + 3],
        ]
    }
}

/// How texture pixels are filtered.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
pub enum Filter {
    /// The nearest pixel (pixel art).
    #[default]
    Nearest,
    /// Bilinear between the four nearest pixels.
    Linear,
}

/// What happens outside `0..1` texture coordinates.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
pub enum Wrap {
    /// Tiles.
    #[default]
    Repeat,
    /// Tiles, every other tile mirrored.
    MirroredRepeat,
    /// The edge pixel continues.
    ClampToEdge,
}

/// How one texture is sampled.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
pub struct Sampler {
    /// Filter within and between mip levels.
    pub filter: Filter,
    /// Wrap along U and V.
    pub wrap: [Wrap; 2],
}

/// One image as a surface uses it.
#[derive(Debug, Clone, PartialEq)]
pub struct TextureRef {
    /// The image, shared between every surface that uses it.
    pub image: Arc<Image>,
    /// How it is sampled.
    pub sampler: Sampler,
}

/// The textures of a surface. Texture coordinates are the mesh's UVs times `uv_scale`
/// (1 = the whole image once).
#[derive(Debug, Clone, PartialEq)]
pub struct SurfaceMaps {
    /// Base colour (sRGB), multiplied with the albedo and the vertex colour.
    pub albedo: Option<TextureRef>,
    /// Tangent-space normal map (linear; red toward +U, green toward the image's top, that is
    /// −V with V growing down the image: the glTF and OpenGL convention).
    pub normal: Option<TextureRef>,
    /// Multiplies the mesh's UVs.
    pub uv_scale: Vec2,
}

impl Default for SurfaceMaps {
    fn default() -> Self {
        SurfaceMaps {
            albedo: None,
            normal: None,
            uv_scale: Vec2::ONE,
        }
    }
}

impl SurfaceMaps {
    /// Whether the surface samples no texture.
    pub fn is_empty(&self) -> bool {
        self.albedo.is_none() && self.normal.is_none()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solid_images_hold_their_colour() {
        let i = Image::solid("x", 3, 2, [1, 2, 3, 4]);
        assert_eq!(i.pixels.len(), 24);
        assert_eq!(i.pixel(2, 1), [1, 2, 3, 4]);
        assert!(SurfaceMaps::default().is_empty());
    }
}
