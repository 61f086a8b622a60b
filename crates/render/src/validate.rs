//! One check of what a frame is asked to draw, shared by texel splatting ([`frame`]) and the
//! baselines ([`view`], [`face_resolution`]), so the two cannot disagree.

use glam::UVec2;
use texel_geom::limits::{FACE_RESOLUTIONS, face_resolution_error};

use crate::frame::RenderError;
use crate::input::{Camera, FrameInput};

/// Largest output side, in pixels.
pub const MAX_OUTPUT_SIDE: u32 = 8192;

fn bad<T>(message: impl Into<String>) -> Result<T, RenderError> {
    Err(RenderError::InvalidFrame(message.into()))
}

/// An output of `size` seen by `camera`: sides within 1..=[`MAX_OUTPUT_SIDE`], a finite
/// position, a finite non-zero direction, and an orthographic height (if any) finite and > 0.
pub fn view(camera: &Camera, size: UVec2) -> Result<(), RenderError> {
    if size.x == 0 || size.y == 0 || size.x > MAX_OUTPUT_SIDE || size.y > MAX_OUTPUT_SIDE {
        return bad(format!(
            "output size must be 1..={MAX_OUTPUT_SIDE} on each side"
        ));
    }
    let c = camera;
    if !c.position.is_finite() || !c.forward.is_finite() || c.forward.length_squared() < 1e-12 {
        return bad("camera position and direction must be finite, direction non-zero");
    }
    if c.ortho_height.is_some_and(|h| !(h.is_finite() && h > 0.0)) {
        return bad("orthographic height must be finite and > 0");
    }
    Ok(())
}

/// An output of `size` this device can hold: each side within the device's
/// `max_texture_dimension_2d` (as well as [`MAX_OUTPUT_SIDE`], see [`view`]), and the
/// read-back buffer of an RGBA8 frame (rows padded to 256 bytes) within `max_buffer_size`.
/// Checked before any target of that size is created, so a size the device refuses is an
/// error rather than a wgpu validation panic.
pub fn device_output(limits: &wgpu::Limits, size: UVec2) -> Result<(), RenderError> {
    device_texture(limits, size)?;
    let bytes = readback_bytes(size);
    if bytes > limits.max_buffer_size {
        return bad(format!(
            "output size {}x{} needs a {bytes}-byte read-back buffer, more than this device's \
             largest buffer ({} bytes)",
            size.x, size.y, limits.max_buffer_size
        ));
    }
    Ok(())
}

/// Textures of `size` fit this device: each side within its `max_texture_dimension_2d` and
/// [`MAX_OUTPUT_SIDE`].
pub fn device_texture(limits: &wgpu::Limits, size: UVec2) -> Result<(), RenderError> {
    let side = limits.max_texture_dimension_2d.min(MAX_OUTPUT_SIDE);
    if size.x == 0 || size.y == 0 || size.x > side || size.y > side {
        return bad(format!(
            "output size {}x{} is out of range: each side must be 1..={side} (renderer limit \
             {MAX_OUTPUT_SIDE}, this device's largest texture {})",
            size.x, size.y, limits.max_texture_dimension_2d
        ));
    }
    Ok(())
}

/// Bytes of the buffer an RGBA8 frame of `size` is read back through (rows padded to
/// `COPY_BYTES_PER_ROW_ALIGNMENT`).
pub fn readback_bytes(size: UVec2) -> u64 {
    let align = u64::from(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
    (u64::from(size.x) * 4).div_ceil(align) * align * u64::from(size.y)
}

/// A face resolution within [`FACE_RESOLUTIONS`].
pub fn face_resolution(n: u32) -> Result<(), RenderError> {
    if FACE_RESOLUTIONS.contains(&n) {
        Ok(())
    } else {
        bad(face_resolution_error("face resolution", n))
    }
}

/// A texel-splatting frame: its view, an internal size within the output, and every probe's
/// and capture's face resolution.
pub fn frame(input: &FrameInput) -> Result<(), RenderError> {
    view(&input.camera, input.size)?;
    let (i, o) = (input.internal_size, input.size);
    if i.x == 0 || i.y == 0 || i.x > o.x || i.y > o.y {
        return bad("internal size must be non-zero and at most the output size");
    }
    [input.eye.face_resolution, input.grid.face_resolution]
        .into_iter()
        .chain(input.previous.map(|p| p.face_resolution))
        .chain(input.captures.iter().map(|c| c.face_resolution))
        .try_for_each(face_resolution)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn device_limits_refuse_before_creation() {
        let limits = wgpu::Limits {
            max_texture_dimension_2d: 4096,
            max_buffer_size: 1 << 24,
            ..wgpu::Limits::default()
        };
        assert!(device_output(&limits, UVec2::new(1280, 720)).is_ok());
        let e = device_output(&limits, UVec2::new(4097, 16)).unwrap_err();
        assert!(e.to_string().contains("1..=4096"), "{e}");
        let e = device_output(&limits, UVec2::new(8193, 8192)).unwrap_err();
        assert!(e.to_string().contains("out of range"), "{e}");
        // 4096 x 4096 x 4 = 64 MiB > 16 MiB: the texture fits, its read-back does not.
        let e = device_output(&limits, UVec2::new(4096, 4096)).unwrap_err();
        assert!(e.to_string().contains("read-back buffer"), "{e}");
        assert_eq!(readback_bytes(UVec2::new(1, 2)), 512);
        let big = wgpu::Limits {
            max_texture_dimension_2d: 16384,
            ..wgpu::Limits::default()
        };
        assert!(device_output(&big, UVec2::new(16384, 16384)).is_err());
    }
}
