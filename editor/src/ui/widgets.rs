//! Small widgets shared by the panels: labelled vectors, colours, kind icons.

use std::ops::RangeInclusive;

use egui::{DragValue, Ui};
use glam::{Vec2, Vec3};
use texel_scene::EntityRow;

/// The largest magnitude a panel's number fields take (they clamp to `-BIG..=BIG`).
pub const BIG: f32 = 1.0e6;
/// The smallest size or scale a panel's fields take.
pub const MIN_SIZE: f32 = 0.001;

/// A row of three drag values named `"{name} X"` etc. Returns true when one changed.
pub fn vec3(ui: &mut Ui, name: &str, v: &mut Vec3, speed: f32, min: f32) -> bool {
    vec3_mixed(ui, name, v, speed, min, [false; 3])
}

/// [`vec3`] where the `mixed` components differ across a selection: they show "—" (and
/// their value once dragged or typed).
pub fn vec3_mixed(
    ui: &mut Ui,
    name: &str,
    v: &mut Vec3,
    speed: f32,
    min: f32,
    mixed: [bool; 3],
) -> bool {
    let mut changed = false;
    ui.horizontal(|ui| {
        ui.label(name);
        let axes = ["X", "Y", "Z"].iter().zip([&mut v.x, &mut v.y, &mut v.z]);
        for ((axis, c), mixed) in axes.zip(mixed) {
            let mut drag = DragValue::new(c).speed(speed).range(min..=f32::MAX);
            if mixed {
                drag = drag.custom_formatter(|_, _| MIXED.to_owned());
            }
            changed |= ui
                .add(drag)
                .accessible_name(format!("{name} {axis}"))
                .changed();
        }
    });
    changed
}

/// What a field shows when its value differs across the selection.
pub const MIXED: &str = "\u{2014}";

/// Two drag values named `"{name} X"`, `"{name} Z"` (sizes in the XZ plane).
pub fn vec2(ui: &mut Ui, name: &str, v: &mut Vec2, speed: f32, min: f32) -> bool {
    let mut changed = false;
    ui.horizontal(|ui| {
        ui.label(name);
        for (axis, c) in ["X", "Z"].iter().zip([&mut v.x, &mut v.y]) {
            changed |= ui
                .add(DragValue::new(c).speed(speed).range(min..=f32::MAX))
                .accessible_name(format!("{name} {axis}"))
                .changed();
        }
    });
    changed
}

/// One labelled drag value.
pub fn scalar(ui: &mut Ui, name: &str, v: &mut f32, speed: f32, min: f32, max: f32) -> bool {
    ui.horizontal(|ui| {
        ui.label(name);
        ui.add(DragValue::new(v).speed(speed).range(min..=max))
            .accessible_name(name)
            .changed()
    })
    .inner
}

/// One labelled integer drag value.
pub fn integer(ui: &mut Ui, name: &str, v: &mut u32, range: RangeInclusive<u32>) -> bool {
    ui.horizontal(|ui| {
        ui.label(name);
        ui.add(DragValue::new(v).range(range))
            .accessible_name(name)
            .changed()
    })
    .inner
}

/// A linear RGB colour picker (components 0..=1 and above, as levels allow).
pub fn colour(ui: &mut Ui, name: &str, c: &mut Vec3) -> bool {
    ui.horizontal(|ui| {
        ui.label(name);
        let mut rgb = c.to_array();
        let r = ui.color_edit_button_rgb(&mut rgb).accessible_name(name);
        if r.changed() {
            *c = Vec3::from_array(rgb).max(Vec3::ZERO);
            true
        } else {
            false
        }
    })
    .inner
}

/// An icon for what an entity is.
pub fn kind_icon(row: &EntityRow) -> &'static str {
    use texel_scene::Geometry as G;
    if row.player_start.is_some() {
        "[start]"
    } else if row.directional_light.is_some() {
        "[sun]"
    } else if row.point_light.is_some() {
        "[light]"
    } else if row.probe_grid_override.is_some() {
        "[probes]"
    } else if row.terrain.is_some() && row.geometry.is_none() {
        "[terrain]"
    } else if row.sprite.is_some() {
        "[sprite]"
    } else {
        match &row.geometry {
            Some(G::Box { .. }) => "[box]",
            Some(G::Sphere { .. }) => "[sphere]",
            Some(G::Cylinder { .. }) => "[cyl]",
            Some(G::Plane { .. }) => "[plane]",
            Some(G::Wedge { .. }) => "[wedge]",
            Some(G::Mesh { .. }) => "[mesh]",
            None => "[empty]",
        }
    }
}

/// The name shown for an entity: its name or "(unnamed N)".
pub fn display_name(row: &EntityRow, index: usize) -> String {
    row.name
        .as_ref()
        .map(|n| n.0.clone())
        .unwrap_or_else(|| format!("(unnamed {index})"))
}
