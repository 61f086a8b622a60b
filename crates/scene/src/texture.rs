//! Decoding texture images (PNG or JPEG) from files or bytes into [`Image`]s, bounded: the file
//! through [`crate::read`], the decoded size by [`MAX_TEXTURE_SIZE`] per edge before any
//! pixel is allocated.

use std::path::{Path, PathBuf};

pub use texel_geom::texture::Image;
use texel_geom::texture::MAX_TEXTURE_SIZE;

use crate::read::{FileKind, ReadError, read_bounded};

/// Why a texture could not be loaded; the message starts with the file (or image) name.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum TextureError {
    /// The file could not be read.
    #[error("{}: cannot read image: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// Not a regular file, or over the size cap.
    #[error(transparent)]
    Read(ReadError),
    /// The bytes are not a PNG or JPEG this build decodes, or the image is too large.
    #[error("{name}: {detail}")]
    Decode {
        /// The file or image name.
        name: String,
        /// What is wrong.
        detail: String,
    },
}

/// Reads and decodes the PNG or JPEG at `path`.
pub fn load_texture(path: &Path) -> Result<Image, TextureError> {
    let bytes = read_bounded(path, FileKind::Texture).map_err(|e| match e {
        ReadError::Io { path, source, .. } => TextureError::Io { path, source },
        other => TextureError::Read(other),
    })?;
    decode_texture(&bytes, &path.display().to_string())
}

/// Decodes PNG or JPEG bytes (`name` names them in errors and in the image); the format is
/// recognised from the bytes, whatever the file is called. PNG: 8- and 16-bit, grey, grey +
/// alpha, RGB, RGBA and palette images; JPEG: grey or colour. All become RGBA8 (JPEG pixels
/// are opaque).
pub fn decode_texture(bytes: &[u8], name: &str) -> Result<Image, TextureError> {
    let fail = |detail: String| TextureError::Decode {
        name: name.to_owned(),
        detail,
    };
    let format = image::guess_format(bytes)
        .map_err(|_| fail("not a PNG or JPEG image (unrecognised bytes)".to_owned()))?;
    let label = match format {
        image::ImageFormat::Png => "PNG",
        image::ImageFormat::Jpeg => "JPEG",
        other => {
            return Err(fail(format!(
                "{} images are not supported; save it as PNG or JPEG",
                other.extensions_str().first().unwrap_or(&"this kind of")
            )));
        }
    };
    let mut reader = image::ImageReader::with_format(std::io::Cursor::new(bytes), format);
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(MAX_TEXTURE_SIZE);
    limits.max_image_height = Some(MAX_TEXTURE_SIZE);
    limits.max_alloc = Some(4 * u64::from(MAX_TEXTURE_SIZE).pow(2) * 2);
    reader.limits(limits);
    let decoded = reader.decode().map_err(|e| match e {
        image::ImageError::Limits(_) => fail(format!(
            "the image is larger than {MAX_TEXTURE_SIZE}×{MAX_TEXTURE_SIZE} pixels"
        )),
        other => fail(format!("cannot decode {label}: {other}")),
    })?;
    let rgba = decoded.into_rgba8();
    let (width, height) = rgba.dimensions();
    if width == 0 || height == 0 {
        return Err(fail("the image is empty".to_owned()));
    }
    Ok(Image {
        name: name.to_owned(),
        width,
        height,
        pixels: rgba.into_raw(),
    })
}

/// Decodes a terrain paint layer: a PNG (any colour type, converted to RGBA8; alpha is the
/// paint's cover) of at most [`MAX_TEXTURE_SIZE`] pixels per edge. JPEG is refused: it has
/// no alpha.
pub fn decode_paint(bytes: &[u8], name: &str) -> Result<Image, TextureError> {
    if image::guess_format(bytes).ok() != Some(image::ImageFormat::Png) {
        return Err(TextureError::Decode {
            name: name.to_owned(),
            detail: "a paint layer must be a PNG image (RGBA, alpha = cover)".to_owned(),
        });
    }
    decode_texture(bytes, name)
}

/// Reads and decodes the paint layer at `path` ([`decode_paint`]).
pub fn load_paint(path: &Path) -> Result<Image, TextureError> {
    let bytes = read_bounded(path, FileKind::Texture).map_err(|e| match e {
        ReadError::Io { path, source, .. } => TextureError::Io { path, source },
        other => TextureError::Read(other),
    })?;
    decode_paint(&bytes, &path.display().to_string())
}

/// Decodes a heightmap: a 16-bit greyscale PNG of 2..=4097 samples per edge, as
/// `(width, height, samples)` rows top to bottom (rows run along +Z, columns along +X).
pub fn decode_heightmap(bytes: &[u8], name: &str) -> Result<(u32, u32, Vec<u16>), TextureError> {
    use crate::terrain::MAX_HEIGHTMAP;
    let fail = |detail: String| TextureError::Decode {
        name: name.to_owned(),
        detail,
    };
    let format = image::guess_format(bytes)
        .map_err(|_| fail("not a PNG heightmap (unrecognised bytes)".to_owned()))?;
    if format != image::ImageFormat::Png {
        return Err(fail(
            "heightmaps must be 16-bit greyscale PNG files".to_owned(),
        ));
    }
    let mut reader = image::ImageReader::with_format(std::io::Cursor::new(bytes), format);
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(MAX_HEIGHTMAP);
    limits.max_image_height = Some(MAX_HEIGHTMAP);
    limits.max_alloc = Some(2 * u64::from(MAX_HEIGHTMAP).pow(2) * 2);
    reader.limits(limits);
    let decoded = reader.decode().map_err(|e| match e {
        image::ImageError::Limits(_) => fail(format!(
            "the heightmap is larger than {MAX_HEIGHTMAP}×{MAX_HEIGHTMAP} samples"
        )),
        other => fail(format!("cannot decode PNG: {other}")),
    })?;
    let image::DynamicImage::ImageLuma16(grey) = decoded else {
        return Err(fail(format!(
            "a heightmap must be a 16-bit greyscale PNG, this one is {:?}",
            decoded.color()
        )));
    };
    let (w, h) = grey.dimensions();
    if w < 2 || h < 2 {
        return Err(fail(format!(
            "a heightmap needs at least 2×2 samples, this one has {w}×{h}"
        )));
    }
    Ok((w, h, grey.into_raw()))
}

/// Reads and decodes the heightmap at `path` ([`decode_heightmap`]).
pub fn load_heightmap(path: &Path) -> Result<(u32, u32, Vec<u16>), TextureError> {
    let bytes = read_bounded(path, FileKind::Texture).map_err(|e| match e {
        ReadError::Io { path, source, .. } => TextureError::Io { path, source },
        other => TextureError::Read(other),
    })?;
    decode_heightmap(&bytes, &path.display().to_string())
}

/// Encodes 16-bit samples as a greyscale PNG.
pub fn encode_heightmap(width: u32, height: u32, samples: &[u16]) -> Vec<u8> {
    let mut out = Vec::new();
    let buffer: image::ImageBuffer<image::Luma<u16>, Vec<u16>> =
        image::ImageBuffer::from_raw(width, height, samples.to_vec()).expect("samples match");
    buffer
        .write_to(&mut std::io::Cursor::new(&mut out), image::ImageFormat::Png)
        .expect("PNG encoding to memory does not fail");
    out
}

/// Encodes `image` as PNG bytes (for tests and generated assets).
pub fn encode_png(image: &Image) -> Vec<u8> {
    let mut out = Vec::new();
    let buffer = image::RgbaImage::from_raw(image.width, image.height, image.pixels.clone())
        .expect("pixels match the size");
    buffer
        .write_to(&mut std::io::Cursor::new(&mut out), image::ImageFormat::Png)
        .expect("PNG encoding to memory does not fail");
    out
}

/// A JPEG of `width` × `height` pixels, every pixel `rgb` (for tests).
#[cfg(test)]
pub(crate) fn encode_jpeg(width: u32, height: u32, rgb: [u8; 3]) -> Vec<u8> {
    let mut out = Vec::new();
    let pixels = rgb.repeat((width * height) as usize);
    image::codecs::jpeg::JpegEncoder::new_with_quality(&mut out, 95)
        .encode(&pixels, width, height, image::ExtendedColorType::Rgb8)
        .expect("JPEG encoding to memory does not fail");
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decodes_what_it_encodes() {
        let mut img = Image::solid("t", 3, 2, [10, 20, 30, 255]);
        img.pixels[0] = 200;
        let back = decode_texture(&encode_png(&img), "t").unwrap();
        assert_eq!(back, img);
    }

    #[test]
    fn bad_bytes_are_named_errors() {
        let e = decode_texture(b"", "a.png").unwrap_err().to_string();
        assert!(e.starts_with("a.png: not a PNG or JPEG"), "{e}");
        let e = decode_texture(b"GIF89a\x01\x00\x01\x00", "g.gif")
            .unwrap_err()
            .to_string();
        assert!(e.contains("gif images are not supported"), "{e}");
        let mut png = encode_png(&Image::solid("t", 4, 4, [1; 4]));
        png.truncate(png.len() / 2);
        let e = decode_texture(&png, "b.png").unwrap_err().to_string();
        assert!(e.starts_with("b.png: cannot decode PNG"), "{e}");
        let e = load_texture(Path::new("/nonexistent/c.png"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("/nonexistent/c.png"), "{e}");
    }

    #[test]
    fn jpeg_decodes_to_opaque_rgba() {
        let img = decode_texture(&encode_jpeg(8, 4, [200, 100, 50]), "j.jpg").unwrap();
        assert_eq!((img.width, img.height, img.name.as_str()), (8, 4, "j.jpg"));
        let [r, g, b, a] = img.pixel(3, 2);
        // Lossy: close to the colour, fully opaque.
        assert!(r.abs_diff(200) <= 4 && g.abs_diff(100) <= 4 && b.abs_diff(50) <= 4);
        assert_eq!(a, 255);
        let mut jpeg = encode_jpeg(8, 8, [1, 2, 3]);
        jpeg.truncate(jpeg.len() / 3);
        let e = decode_texture(&jpeg, "cut.jpg").unwrap_err().to_string();
        assert!(e.starts_with("cut.jpg: cannot decode JPEG"), "{e}");
    }

    #[test]
    fn heightmaps_are_16_bit_grey_and_round_trip() {
        let samples: Vec<u16> = (0..12).map(|i| i * 5000).collect();
        let png = encode_heightmap(4, 3, &samples);
        assert_eq!(decode_heightmap(&png, "h").unwrap(), (4, 3, samples));
        let rgba = encode_png(&Image::solid("t", 4, 4, [1; 4]));
        let e = decode_heightmap(&rgba, "c.png").unwrap_err().to_string();
        assert!(e.contains("16-bit greyscale") && e.contains("Rgba8"), "{e}");
        let e = decode_heightmap(&encode_heightmap(1, 5, &[0; 5]), "d.png")
            .unwrap_err()
            .to_string();
        assert!(e.contains("at least 2×2"), "{e}");
    }

    #[test]
    fn paint_layers_are_pngs_within_the_texture_limit() {
        let img = Image::solid("p", 5, 3, [200, 10, 20, 128]);
        assert_eq!(decode_paint(&encode_png(&img), "p").unwrap(), img);
        let e = decode_paint(&encode_jpeg(4, 4, [1, 2, 3]), "p.jpg")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("p.jpg: a paint layer must be a PNG"), "{e}");
        let big = Image::solid("t", MAX_TEXTURE_SIZE + 1, 1, [0; 4]);
        let e = decode_paint(&encode_png(&big), "big.png")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("big.png:") && e.contains("larger than 2048"),
            "{e}"
        );
        let e = load_paint(Path::new("/nonexistent/paint.png"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("/nonexistent/paint.png"), "{e}");
    }

    #[test]
    fn oversized_images_are_refused_before_decoding() {
        // A valid PNG header claiming 100000 × 1 pixels.
        let img = Image::solid("t", MAX_TEXTURE_SIZE + 1, 1, [0; 4]);
        let e = decode_texture(&encode_png(&img), "big.png")
            .unwrap_err()
            .to_string();
        assert!(e.contains("larger than 2048"), "{e}");
        let e = decode_texture(&encode_jpeg(MAX_TEXTURE_SIZE + 1, 1, [0; 3]), "big.jpg")
            .unwrap_err()
            .to_string();
        assert!(e.contains("larger than 2048"), "{e}");
    }
}
