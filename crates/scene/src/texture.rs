//! Decoding texture images (PNG) from files or bytes into [`Image`]s, bounded: the file
//! through [`crate::read`], the decoded size by [`MAX_TEXTURE_SIZE`] per edge before any
//! pixel is allocated.

use std::path::{Path, PathBuf};

use texel_geom::texture::{Image, MAX_TEXTURE_SIZE};

use crate::read::{FileKind, ReadError, read_bounded};

/// Why a texture could not be loaded; the message starts with the file (or image) name.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum TextureError {
    /// The file could not be read.
    #[error("{}: cannot read texture: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// Not a regular file, or over the size cap.
    #[error(transparent)]
    Read(ReadError),
    /// The bytes are not a PNG this build decodes, or the image is too large.
    #[error("{name}: {detail}")]
    Decode {
        /// The file or image name.
        name: String,
        /// What is wrong.
        detail: String,
    },
}

/// Reads and decodes the PNG at `path`.
pub fn load_texture(path: &Path) -> Result<Image, TextureError> {
    let bytes = read_bounded(path, FileKind::Texture).map_err(|e| match e {
        ReadError::Io { path, source, .. } => TextureError::Io { path, source },
        other => TextureError::Read(other),
    })?;
    decode_texture(&bytes, &path.display().to_string())
}

/// Decodes PNG bytes (`name` names them in errors and in the image). 8- and 16-bit, grey,
/// grey + alpha, RGB, RGBA and palette images all become RGBA8.
pub fn decode_texture(bytes: &[u8], name: &str) -> Result<Image, TextureError> {
    let fail = |detail: String| TextureError::Decode {
        name: name.to_owned(),
        detail,
    };
    let format = image::guess_format(bytes)
        .map_err(|_| fail("not a PNG image (unrecognised bytes)".to_owned()))?;
    if format != image::ImageFormat::Png {
        return Err(fail(format!(
            "{} images are not supported; save it as PNG",
            format.extensions_str().first().unwrap_or(&"this kind of")
        )));
    }
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
        other => fail(format!("cannot decode PNG: {other}")),
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
        assert!(e.starts_with("a.png: not a PNG"), "{e}");
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
    fn oversized_images_are_refused_before_decoding() {
        // A valid PNG header claiming 100000 × 1 pixels.
        let img = Image::solid("t", MAX_TEXTURE_SIZE + 1, 1, [0; 4]);
        let e = decode_texture(&encode_png(&img), "big.png")
            .unwrap_err()
            .to_string();
        assert!(e.contains("larger than 2048"), "{e}");
    }
}
