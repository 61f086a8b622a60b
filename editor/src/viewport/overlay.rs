//! What the viewport draws over the scene: the ground grid (as lines the renderer draws,
//! depth-tested), and with the egui painter icons for lights and the player start,
//! probe-grid override volumes as boxes, the selection.

use egui::{Color32, Painter, Pos2, Stroke};
use glam::Vec3;
use texel_render::passes::lines::LineVertex;
use texel_scene::{DirectionalLight, PlayerStart, PointLight, ProbeGridOverride, Scene, Transform};

use crate::camera::Projector;

/// Half extent of the ground grid, world units.
const GRID_HALF: i32 = 20;

/// Draws a 3D segment, skipping it when an end is behind the camera.
pub fn segment(p: &Painter, proj: &Projector, a: Vec3, b: Vec3, stroke: Stroke) {
    if let (Some(a), Some(b)) = (proj.project(a), proj.project(b)) {
        p.line_segment([a, b], stroke);
    }
}

/// The ground grid on y = 0, one line per world unit, with the X and Z axes coloured: line
/// segments the renderer draws depth-tested into the frame (`Renderer::set_lines`), so the
/// scene hides them.
pub fn grid_lines() -> Vec<LineVertex> {
    let faint = [255, 255, 255, 28];
    let (axis_x, axis_z) = ([220, 60, 60, 120], [60, 90, 230, 120]);
    let half = GRID_HALF as f32;
    let mut out = Vec::with_capacity((GRID_HALF as usize * 2 + 1) * 4);
    for i in -GRID_HALF..=GRID_HALF {
        let f = i as f32;
        let (sx, sz) = if i == 0 {
            (axis_x, axis_z)
        } else {
            (faint, faint)
        };
        let v = |position, colour| LineVertex { position, colour };
        out.extend([v([-half, 0.0, f], sx), v([half, 0.0, f], sx)]);
        out.extend([v([f, 0.0, -half], sz), v([f, 0.0, half], sz)]);
    }
    out
}

/// The 12 edges of an axis-aligned box.
pub fn wire_box(p: &Painter, proj: &Projector, min: Vec3, max: Vec3, stroke: Stroke) {
    let c = |i: usize| {
        Vec3::new(
            if i & 1 == 0 { min.x } else { max.x },
            if i & 2 == 0 { min.y } else { max.y },
            if i & 4 == 0 { min.z } else { max.z },
        )
    };
    for i in 0..8 {
        for bit in [1, 2, 4] {
            if i & bit == 0 {
                segment(p, proj, c(i), c(i | bit), stroke);
            }
        }
    }
}

/// Icons for lights and player starts, and boxes for probe-grid override volumes.
/// The `selected` positions (ascending) are highlighted.
pub fn markers(
    p: &Painter,
    proj: &Projector,
    scene: &Scene,
    selected: &[usize],
    shown: impl Fn(usize) -> bool,
) {
    let w = scene.world();
    for (i, e) in scene.entities().enumerate().filter(|(i, _)| shown(*i)) {
        let t = w.get::<&Transform>(e).map(|t| *t).unwrap_or_default();
        let hot = selected.binary_search(&i).is_ok();
        let colour = if hot {
            super::select::SELECTED
        } else {
            Color32::from_rgb(240, 240, 240)
        };
        if let Ok(o) = w.get::<&ProbeGridOverride>(e) {
            let half = o.size * t.scale * 0.5;
            let stroke = Stroke::new(if hot { 2.0 } else { 1.0 }, Color32::from_rgb(80, 220, 200));
            wire_box(p, proj, t.translation - half, t.translation + half, stroke);
        }
        let icon = if w.get::<&PlayerStart>(e).is_ok() {
            Some("P")
        } else if w.get::<&PointLight>(e).is_ok() {
            Some("L")
        } else if w.get::<&DirectionalLight>(e).is_ok() {
            Some("S")
        } else {
            None
        };
        if let (Some(icon), Some(at)) = (icon, proj.project(t.translation)) {
            label(p, at, icon, colour);
        }
    }
}

fn label(p: &Painter, at: Pos2, text: &str, colour: Color32) {
    p.circle_filled(at, 11.0, Color32::from_black_alpha(140));
    p.text(
        at,
        egui::Align2::CENTER_CENTER,
        text,
        egui::FontId::proportional(14.0),
        colour,
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_lines_cover_the_ground_with_coloured_axes() {
        let lines = grid_lines();
        assert_eq!(lines.len(), 41 * 4);
        assert!(lines.iter().all(|v| v.position[1] == 0.0));
        let extent = lines
            .iter()
            .map(|v| v.position[0].abs().max(v.position[2].abs()))
            .fold(0.0, f32::max);
        assert_eq!(extent, GRID_HALF as f32);
        // The lines through the origin are the coloured axes, drawn stronger.
        let axes: Vec<_> = lines.iter().filter(|v| v.colour[3] == 120).collect();
        assert_eq!(axes.len(), 4);
        assert!(
            axes.iter()
                .all(|v| v.position[0] == 0.0 || v.position[2] == 0.0)
        );
    }
}
