//! From the hecs world to the plain data the probe system and the renderer consume.

use texel_probes::grid::{GridDefaults, GridOverride};
use texel_probes::resolution::{ResolutionRange, face_resolution_for_pixel_size};
use texel_scene::{PixelScale, ProbeGridOverride, Scene, Transform};

/// The screen a level is viewed on: what turns a wanted pixel size into a face resolution.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Viewport {
    /// Output height in pixels.
    pub height: u32,
    /// Vertical field of view in radians.
    pub fov_y: f32,
}

/// The level's face resolution on `viewport`: the fixed one, or the one whose texels cover
/// the wanted number of screen pixels at the view centre.
pub fn level_face_resolution(scene: &Scene, viewport: Viewport) -> u32 {
    face_resolution(scene.settings.pixel_scale, viewport)
}

/// The face resolution `pixel_scale` asks for on `viewport`.
pub fn face_resolution(pixel_scale: PixelScale, viewport: Viewport) -> u32 {
    match pixel_scale {
        PixelScale::FaceResolution(n) => n,
        PixelScale::PixelSize(k) => face_resolution_for_pixel_size(
            viewport.height,
            viewport.fov_y,
            k,
            &ResolutionRange::default(),
        )
        // Level values are validated on load; fall back to a safe middle value otherwise.
        .unwrap_or(128),
    }
}

/// The level's grid defaults and override volumes, in level order (later wins ties).
pub fn grid_settings(scene: &Scene, viewport: Viewport) -> (GridDefaults, Vec<GridOverride>) {
    let defaults = GridDefaults {
        cell_size: scene.settings.cell_size,
        face_resolution: level_face_resolution(scene, viewport),
    };
    (defaults, grid_overrides(scene))
}

/// The level's probe-grid override volumes, in level order (they do not depend on the
/// viewport).
pub fn grid_overrides(scene: &Scene) -> Vec<GridOverride> {
    let world = scene.world();
    scene
        .entities()
        .filter_map(|e| {
            let o = *world.get::<&ProbeGridOverride>(e).ok()?;
            let t = world.get::<&Transform>(e).map(|t| *t).unwrap_or_default();
            let half = o.size * t.scale * 0.5;
            Some(GridOverride {
                min: t.translation - half,
                max: t.translation + half,
                cell_size: o.cell_size,
                face_resolution: o.face_resolution,
                priority: o.priority,
            })
        })
        .collect()
}
