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
