//! What the viewport paints over the render with the egui painter: the ground grid, icons
//! for lights and the player start, probe-grid override volumes as boxes, the selection.

use egui::{Color32, Painter, Pos2, Stroke};
use glam::Vec3;
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

/// The ground grid on y = 0, one line per world unit, split into short pieces so lines
/// passing behind the camera still show their visible part.
pub fn grid(p: &Painter, proj: &Projector) {
    let faint = Stroke::new(1.0, Color32::from_white_alpha(28));
    let axis_x = Stroke::new(1.5, Color32::from_rgba_unmultiplied(220, 60, 60, 120));
    let axis_z = Stroke::new(1.5, Color32::from_rgba_unmultiplied(60, 90, 230, 120));
    for i in -GRID_HALF..=GRID_HALF {
        let f = i as f32;
        for j in -GRID_HALF..GRID_HALF {
            let (g0, g1) = (j as f32, j as f32 + 1.0);
            let sx = if i == 0 { axis_x } else { faint };
            let sz = if i == 0 { axis_z } else { faint };
            segment(p, proj, Vec3::new(g0, 0.0, f), Vec3::new(g1, 0.0, f), sx);
            segment(p, proj, Vec3::new(f, 0.0, g0), Vec3::new(f, 0.0, g1), sz);
        }
    }
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
/// `selected` is highlighted.
pub fn markers(p: &Painter, proj: &Projector, scene: &Scene, selected: Option<usize>) {
    let w = scene.world();
    for (i, e) in scene.entities().enumerate() {
        let t = w.get::<&Transform>(e).map(|t| *t).unwrap_or_default();
        let hot = selected == Some(i);
        let colour = if hot {
            Color32::from_rgb(255, 200, 40)
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
