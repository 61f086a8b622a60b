//! The camera math of the low-resolution baselines: the art-pixel rule (how tall a
//! low-resolution target must be for its pixels to match a cube texel's on-screen size), and
//! the screen-snap method of the Unity "3D Pixel Art Renderer": the camera moves in whole
//! texels of view space, the target has a one-texel margin, and the sub-texel remainder is
//! restored when the image is drawn at full size.

use glam::{Mat4, UVec2, Vec2, Vec3};

use crate::error::RenderError;
use crate::input::Camera;

/// For a perspective camera, the depth (world units along the view axis) at which snapping
/// moves the image by whole texels: nearer points still slide, farther ones less so (a
/// perspective camera has no single texel size in world units).
pub const PERSPECTIVE_SNAP_DEPTH: f32 = 10.0;

/// Height in pixels of a low-resolution target whose pixel at the view centre has the
/// on-screen size of a cube texel of `face_res` texels per face edge.
///
/// A texel at face centre spans `2 / N` tangent units, a pixel `2 · tan(fov_y / 2) / h`, so
/// they match for `h = N · tan(fov_y / 2)` (rounded) — [`texel_probes::resolution`]'s
/// `pixels_per_texel(h, fov_y, N) = 1`. An orthographic camera uses its `fov_y` too, so every
/// method of one comparison draws art pixels of one size.
pub fn art_pixel_height(face_res: u32, fov_y: f32) -> Result<u32, RenderError> {
    if face_res == 0 || !(fov_y.is_finite() && fov_y > 0.0 && fov_y < std::f32::consts::PI) {
        return Err(RenderError::InvalidFrame(format!(
            "art pixel size needs a face resolution > 0 (got {face_res}) and a field of view \
             in (0, pi) (got {fov_y})"
        )));
    }
    let h = (face_res as f32 * (fov_y * 0.5).tan()).round();
    Ok((h as u32).max(1))
}

/// The low-resolution size for an output of `size` with art pixels `height` tall: the width
/// keeps the output's aspect ratio.
pub fn low_res_size(size: UVec2, height: u32) -> UVec2 {
    let w = (height as f32 * size.x as f32 / size.y.max(1) as f32).round();
    UVec2::new((w as u32).max(1), height.max(1))
}

/// How one snapped frame is drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SnapPlan {
    /// The camera moved to whole texels of view space.
    pub snapped: Camera,
    /// View-projection of the snapped camera onto the target with its one-texel margin.
    pub view_proj: Mat4,
    /// Target size: the low-resolution size plus one texel on every side.
    pub target: UVec2,
    /// Where the true camera's top-left corner falls in the target, in texels (x right,
    /// y down): `1 + remainder`, the margin plus the restored sub-texel motion.
    pub origin: Vec2,
}

/// World units per texel in the snap plane: the ortho height over the texel rows, or for a
/// perspective camera the footprint of a texel at [`PERSPECTIVE_SNAP_DEPTH`].
pub fn snap_texel_size(camera: &Camera, low: UVec2) -> f32 {
    let h = low.y.max(1) as f32;
    match camera.ortho_height {
        Some(v) => v / h,
        None => 2.0 * (camera.fov_y * 0.5).tan() * PERSPECTIVE_SNAP_DEPTH / h,
    }
}

/// Plans a snapped frame of `camera` for a low-resolution size `low` (without margin).
pub fn snap_plan(camera: &Camera, low: UVec2) -> SnapPlan {
    let view = camera.view();
    let right = view.row(0).truncate();
    let up = view.row(1).truncate();
    let s = snap_texel_size(camera, low);
    // The camera position in texels along the view's right and up axes, and its remainder.
    let xc = camera.position.dot(right) / s;
    let yc = camera.position.dot(up) / s;
    let rem = Vec2::new(xc - xc.round(), yc - yc.round());
    let snapped = Camera {
        position: camera.position - (rem.x * s) * right - (rem.y * s) * up,
        ..*camera
    };
    let (w, h) = (low.x.max(1) as f32, low.y.max(1) as f32);
    let margin = Mat4::from_scale(Vec3::new(w / (w + 2.0), h / (h + 2.0), 1.0));
    let view_proj = margin * camera.projection(w / h) * snapped.view();
    // The true camera is `rem` texels right of and above the snapped one, so the scene sits
    // `rem.x` texels further right and `rem.y` texels higher in the snapped image.
    SnapPlan {
        snapped,
        view_proj,
        target: low + UVec2::splat(2),
        origin: Vec2::new(1.0 + rem.x, 1.0 - rem.y),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn art_pixel_height_matches_hand_computation() {
        // 64 · tan(30°) = 36.95 → 37 rows; 90 · tan(45°) = 90.
        assert_eq!(art_pixel_height(64, 60f32.to_radians()).unwrap(), 37);
        assert_eq!(art_pixel_height(90, 90f32.to_radians()).unwrap(), 90);
        // The pixel-perfect relation from the other side: one pixel per texel.
        let k = texel_probes::resolution::pixels_per_texel(37, 60f32.to_radians(), 64).unwrap();
        assert!((k - 1.0).abs() < 0.02, "{k}");
        assert!(art_pixel_height(0, 1.0).is_err());
        assert!(art_pixel_height(64, f32::NAN).is_err());
        assert!(art_pixel_height(64, 3.5).is_err());
    }

    #[test]
    fn low_res_keeps_aspect() {
        assert_eq!(low_res_size(UVec2::new(640, 360), 37), UVec2::new(66, 37));
        assert_eq!(low_res_size(UVec2::new(144, 96), 32), UVec2::new(48, 32));
    }

    #[test]
    fn snapping_moves_by_whole_texels_and_keeps_the_remainder() {
        let mut cam = Camera::looking(Vec3::new(0.3, 5.0, 7.0), Vec3::new(0.2, -0.6, -1.0));
        cam.ortho_height = Some(8.0);
        let low = UVec2::new(48, 32);
        let s = snap_texel_size(&cam, low);
        assert!((s - 0.25).abs() < 1e-6);
        let a = snap_plan(&cam, low);
        let right = cam.view().row(0).truncate();
        cam.position += right * (3.0 * s);
        let b = snap_plan(&cam, low);
        let moved = b.snapped.position - a.snapped.position;
        assert!((moved - right * (3.0 * s)).length() < 1e-4, "{moved}");
        assert!((a.origin - b.origin).length() < 1e-3);
        assert!(a.origin.min_element() >= 0.5 && a.origin.max_element() <= 1.5);
        assert_eq!(a.target, UVec2::new(50, 34));
        // The snapped camera sits on the texel grid of its own axes.
        let xs = a.snapped.position.dot(right) / s;
        assert!((xs - xs.round()).abs() < 1e-3, "{xs}");
    }
}
