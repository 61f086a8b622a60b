//! The inspector: every component of the selected entity, and the level settings. Edits are
//! made on a copy of the entity's row and applied as one command per gesture.

use egui::Ui;
use glam::{Vec2, Vec3};
use texel_scene::{
    BANDS, DirectionalLight, EntityRow, FACE_RESOLUTIONS, Geometry, LevelSettings, Material, Name,
    PixelScale, PlayerStart, PointLight, ProbeGridOverride, SEGMENTS, Transform,
};

use crate::command::{Command, CommandError};
use crate::history::MergeKey;
use crate::state::EditorState;
use crate::ui::widgets::{colour, integer, scalar, vec2, vec3};

const BIG: f32 = 1.0e6;
const MIN_SIZE: f32 = 0.001;

/// The selected entity's components. A command that fails is returned, for the caller to
/// show.
pub fn entity(ui: &mut Ui, state: &mut EditorState) -> Result<(), CommandError> {
    let Some((index, before)) = state.selected_row() else {
        ui.label("Nothing selected");
        return Ok(());
    };
    let mut row = before.clone();
    edit_row(ui, &mut row);
    if row != before {
        let key = gesture_widget(ui.ctx()).map(|widget| MergeKey::Row { index, widget });
        state.set_row(index, row, key)?;
    }
    Ok(())
}

fn edit_row(ui: &mut Ui, row: &mut EntityRow) {
    let mut name = row.name.as_ref().map(|n| n.0.clone()).unwrap_or_default();
    ui.horizontal(|ui| {
        ui.label("Name");
        if ui
            .text_edit_singleline(&mut name)
            .accessible_name("Name")
            .changed()
        {
            row.name = (!name.is_empty()).then(|| Name(name.clone()));
        }
    });
    section(ui, "Transform", &mut row.transform, transform);
    section_with(
        ui,
        "Geometry",
        &mut row.geometry,
        || geometry_of_kind(0),
        geometry,
    );
    section(ui, "Material", &mut row.material, material);
    section(ui, "Directional light", &mut row.directional_light, sun);
    section(ui, "Point light", &mut row.point_light, point);
    section(
        ui,
        "Probe-grid override",
        &mut row.probe_grid_override,
        probe,
    );
    section(ui, "Player start", &mut row.player_start, start);
}

/// A collapsible component with a remove button, or an add button when absent.
fn section<T: Default>(ui: &mut Ui, title: &str, c: &mut Option<T>, body: fn(&mut Ui, &mut T)) {
    section_with(ui, title, c, T::default, body);
}

fn section_with<T>(
    ui: &mut Ui,
    title: &str,
    c: &mut Option<T>,
    make: fn() -> T,
    body: fn(&mut Ui, &mut T),
) {
    match c {
        Some(v) => {
            let mut remove = false;
            egui::CollapsingHeader::new(title)
                .default_open(true)
                .show(ui, |ui| {
                    body(ui, v);
                    remove = ui.small_button(format!("Remove {title}")).clicked();
                });
            if remove {
                *c = None;
            }
        }
        None => {
            if ui.small_button(format!("Add {title}")).clicked() {
                *c = Some(make());
            }
        }
    }
}

fn transform(ui: &mut Ui, t: &mut Transform) {
    vec3(ui, "Translation", &mut t.translation, 0.05, -BIG);
    vec3(ui, "Rotation", &mut t.rotation, 1.0, -BIG);
    vec3(ui, "Scale", &mut t.scale, 0.01, MIN_SIZE);
}

const KINDS: [&str; 6] = ["Box", "Sphere", "Cylinder", "Plane", "Wedge", "Mesh"];

fn kind_of(g: &Geometry) -> usize {
    match g {
        Geometry::Box { .. } => 0,
        Geometry::Sphere { .. } => 1,
        Geometry::Cylinder { .. } => 2,
        Geometry::Plane { .. } => 3,
        Geometry::Wedge { .. } => 4,
        Geometry::Mesh { .. } => 5,
    }
}

/// A default geometry of kind `k` (an index into the kinds list).
pub fn geometry_of_kind(k: usize) -> Geometry {
    match k {
        1 => Geometry::Sphere {
            radius: 0.5,
            segments: 16,
        },
        2 => Geometry::Cylinder {
            radius: 0.5,
            height: 1.0,
            segments: 16,
        },
        3 => Geometry::Plane {
            size: Vec2::splat(4.0),
        },
        4 => Geometry::Wedge { size: Vec3::ONE },
        5 => Geometry::Mesh {
            path: String::new(),
        },
        _ => Geometry::Box { size: Vec3::ONE },
    }
}

fn geometry(ui: &mut Ui, g: &mut Geometry) {
    let mut k = kind_of(g);
    egui::ComboBox::from_label("Kind")
        .selected_text(KINDS[k])
        .show_ui(ui, |ui| {
            for (i, name) in KINDS.iter().enumerate() {
                ui.selectable_value(&mut k, i, *name);
            }
        });
    if k != kind_of(g) {
        *g = geometry_of_kind(k);
    }
    match g {
        Geometry::Box { size } | Geometry::Wedge { size } => {
            vec3(ui, "Size", size, 0.02, MIN_SIZE);
        }
        Geometry::Sphere { radius, segments } => {
            scalar(ui, "Radius", radius, 0.01, MIN_SIZE, BIG);
            integer(ui, "Segments", segments, SEGMENTS);
        }
        Geometry::Cylinder {
            radius,
            height,
            segments,
        } => {
            scalar(ui, "Radius", radius, 0.01, MIN_SIZE, BIG);
            scalar(ui, "Height", height, 0.02, MIN_SIZE, BIG);
            integer(ui, "Segments", segments, SEGMENTS);
        }
        Geometry::Plane { size } => {
            vec2(ui, "Size", size, 0.05, MIN_SIZE);
        }
        Geometry::Mesh { path } => {
            ui.horizontal(|ui| {
                ui.label("Path");
                ui.text_edit_singleline(path).accessible_name("Mesh path");
            });
        }
    }
}

fn material(ui: &mut Ui, m: &mut Material) {
    colour(ui, "Albedo", &mut m.albedo);
    colour(ui, "Emissive", &mut m.emissive);
    ui.checkbox(&mut m.casts_shadows, "Casts shadows");
    ui.checkbox(&mut m.outlined, "Outlined");
}

fn sun(ui: &mut Ui, s: &mut DirectionalLight) {
    let mut d = s.direction;
    if vec3(ui, "Direction", &mut d, 0.01, -BIG) && d.length_squared() > 1e-6 {
        s.direction = d;
    }
    colour(ui, "Colour", &mut s.colour);
    scalar(ui, "Intensity", &mut s.intensity, 0.01, 0.0, 1000.0);
}

fn point(ui: &mut Ui, p: &mut PointLight) {
    colour(ui, "Colour", &mut p.colour);
    scalar(ui, "Intensity", &mut p.intensity, 0.01, 0.0, 1000.0);
    scalar(ui, "Radius", &mut p.radius, 0.05, MIN_SIZE, BIG);
}

fn probe(ui: &mut Ui, o: &mut ProbeGridOverride) {
    vec3(ui, "Volume", &mut o.size, 0.05, MIN_SIZE);
    scalar(ui, "Cell size", &mut o.cell_size, 0.01, 0.01, BIG);
    let mut own = o.face_resolution.is_some();
    ui.checkbox(&mut own, "Own face resolution");
    match (own, o.face_resolution) {
        (true, None) => o.face_resolution = Some(128),
        (false, Some(_)) => o.face_resolution = None,
        _ => {}
    }
    if let Some(n) = &mut o.face_resolution {
        integer(ui, "Face resolution", n, FACE_RESOLUTIONS);
    }
    ui.horizontal(|ui| {
        ui.label("Priority");
        ui.add(egui::DragValue::new(&mut o.priority))
            .accessible_name("Priority");
    });
}

fn start(ui: &mut Ui, p: &mut PlayerStart) {
    scalar(ui, "Yaw", &mut p.yaw, 1.0, -360.0, 360.0);
    scalar(ui, "Pitch", &mut p.pitch, 1.0, -89.0, 89.0);
    scalar(ui, "Eye height", &mut p.eye_height, 0.01, 0.01, 100.0);
}

/// The level settings. A command that fails is returned, for the caller to show.
pub fn settings(ui: &mut Ui, state: &mut EditorState) -> Result<(), CommandError> {
    let before: LevelSettings = state.scene().settings;
    let mut s = before;
    colour(ui, "Sky", &mut s.sky);
    colour(ui, "Ambient", &mut s.ambient);
    integer(ui, "Bands", &mut s.bands, BANDS);
    let mut fixed = matches!(s.pixel_scale, PixelScale::FaceResolution(_));
    ui.horizontal(|ui| {
        ui.radio_value(&mut fixed, false, "Pixel size");
        ui.radio_value(&mut fixed, true, "Face resolution");
    });
    s.pixel_scale = match (fixed, s.pixel_scale) {
        (true, PixelScale::PixelSize(_)) => PixelScale::FaceResolution(128),
        (false, PixelScale::FaceResolution(_)) => PixelScale::PixelSize(2.5),
        (_, p) => p,
    };
    match &mut s.pixel_scale {
        PixelScale::PixelSize(k) => {
            scalar(ui, "Pixel size", k, 0.05, 0.1, 64.0);
        }
        PixelScale::FaceResolution(n) => {
            integer(ui, "Face resolution", n, FACE_RESOLUTIONS);
        }
    }
    scalar(ui, "Default cell size", &mut s.cell_size, 0.01, 0.01, BIG);
    if s != before {
        let key = gesture_widget(ui.ctx()).map(|widget| MergeKey::Settings { widget });
        state.apply(Command::SetSettings { before, after: s }, key)?;
    }
    Ok(())
}

/// The widget of a continuing gesture (the one being dragged or typed into), for the merge
/// key that makes a drag or typing one undo step; `None` for one-shot changes.
pub fn gesture_widget(ctx: &egui::Context) -> Option<egui::Id> {
    ctx.dragged_id().or_else(|| ctx.memory(|m| m.focused()))
}
