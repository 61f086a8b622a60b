//! The menu bar. It only reports what was chosen; the app carries it out.

use std::path::PathBuf;

use egui::Ui;
use glam::Vec3;
use texel_render::input::Schedule;
use texel_scene::{
    DirectionalLight, EntityRow, Material, Name, PlayerStart, PointLight, ProbeGridOverride,
    Transform,
};

use crate::palette_edits::Slot;
use crate::ui::inspector::geometry_of_kind;
use crate::viewport::debug::{DebugFlags, DebugView};

/// Something the person asked for from the menu, a shortcut or a button.
#[derive(Debug, Clone, PartialEq)]
pub enum Action {
    /// New empty level.
    New,
    /// Open a level (asks where).
    Open,
    /// Open this level.
    OpenPath(PathBuf),
    /// Save to the current path (or ask).
    Save,
    /// Save under a new path.
    SaveAs,
    /// Undo.
    Undo,
    /// Redo.
    Redo,
    /// Add this entity.
    Add(Box<EntityRow>),
    /// Add a glTF mesh (asks which).
    AddMesh,
    /// Add a glTF mesh from this file.
    AddMeshPath(PathBuf),
    /// Add a terrain at the view's focus.
    AddTerrain,
    /// Add a sprite (asks for its sheet).
    AddSprite,
    /// Add a sprite of this sheet at the view's focus.
    AddSpritePath(PathBuf),
    /// Switch the terrain tool on or off.
    ToggleTerrainTool,
    /// Replace the selected terrain's heights with a 16-bit heightmap (asks which).
    ImportHeightmap,
    /// Replace the selected terrain's heights with this 16-bit heightmap.
    ImportHeightmapPath(PathBuf),
    /// Write the selected terrain's heights as a 16-bit heightmap (asks where).
    ExportHeightmap,
    /// Write the selected terrain's heights to this file.
    ExportHeightmapPath(PathBuf),
    /// Duplicate the selection.
    Duplicate,
    /// Delete the selection.
    Delete,
    /// Make the selection the children of a new group (Ctrl+G).
    Group,
    /// Put the selected groups' children in their place and delete the groups
    /// (Ctrl+Shift+G).
    Ungroup,
    /// Put the selection on the clipboard.
    Copy,
    /// Put the selection on the clipboard and delete it (one undo step).
    Cut,
    /// Ask the window for the clipboard's text (it comes back as [`Action::Paste`]).
    RequestPaste,
    /// Add the entities this clipboard text holds, or say why it holds none.
    Paste(String),
    /// Select every entity.
    SelectAll,
    /// Select nothing.
    SelectNone,
    /// Start or stop Play.
    TogglePlay,
    /// Use this schedule in the viewport.
    Schedule(Schedule),
    /// Switch this debug view on or off.
    ToggleDebug(DebugView),
    /// Move the editor camera to see the selected entity's texture 1:1.
    FrameOneToOne,
    /// Switch the editor camera between perspective and orthographic.
    ToggleOrtho,
    /// Pick a palette file for the level (or its alternate) with a dialog.
    PickPalette(Slot),
    /// Make this palette file the level's palette (or its alternate).
    PalettePath(Slot, PathBuf),
    /// Take the level's palette (with its alternate) or only its alternate off.
    ClearPalette(Slot),
    /// Map frames to the level's alternate palette (night) or back (key N).
    ToggleNight,
    /// Show or hide the asset panel.
    ToggleAssetPanel,
    /// Place this asset file at this point (a drop on the viewport), or where Add places
    /// things (`None`: the view's centre).
    PlaceAsset(crate::assets::AssetDrag, Option<Vec3>),
    /// Quit.
    Quit,
}

/// The entities the Add menu offers, by label.
pub fn presets() -> Vec<(&'static str, EntityRow)> {
    let at = Transform::from_translation(Vec3::new(0.0, 0.5, 0.0));
    let shape = |name: &str, k: usize| EntityRow {
        name: Some(Name(name.into())),
        transform: Some(at),
        geometry: Some(geometry_of_kind(k)),
        material: Some(Material::default()),
        ..EntityRow::default()
    };
    vec![
        ("Box", shape("Box", 0)),
        ("Sphere", shape("Sphere", 1)),
        ("Cylinder", shape("Cylinder", 2)),
        ("Plane", shape("Plane", 3)),
        ("Wedge", shape("Wedge", 4)),
        (
            "Directional light",
            EntityRow {
                name: Some(Name("Sun".into())),
                directional_light: Some(DirectionalLight::default()),
                ..EntityRow::default()
            },
        ),
        (
            "Point light",
            EntityRow {
                name: Some(Name("Point light".into())),
                transform: Some(Transform::from_translation(Vec3::new(0.0, 2.0, 0.0))),
                point_light: Some(PointLight::default()),
                ..EntityRow::default()
            },
        ),
        (
            "Probe-grid override",
            EntityRow {
                name: Some(Name("Probe-grid override".into())),
                transform: Some(Transform::from_translation(Vec3::new(0.0, 2.0, 0.0))),
                probe_grid_override: Some(ProbeGridOverride::default()),
                ..EntityRow::default()
            },
        ),
        (
            "Player start",
            EntityRow {
                name: Some(Name("Player start".into())),
                transform: Some(Transform::default()),
                player_start: Some(PlayerStart::default()),
                ..EntityRow::default()
            },
        ),
    ]
}

/// What the View menu shows as chosen.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ViewChoice {
    /// The viewport's schedule.
    pub schedule: Schedule,
    /// The debug views that are on.
    pub debug: DebugFlags,
    /// Whether the selection has a loaded texture (Frame 1:1 is offered).
    pub textured_selection: bool,
    /// Whether the selection is a terrain with loaded heights.
    pub terrain_selection: bool,
    /// Whether the terrain tool is on.
    pub terrain_tool: bool,
    /// Whether the editor camera is orthographic.
    pub ortho: bool,
    /// Whether frames show the level's alternate palette (night); `None` when the level
    /// has no alternate.
    pub night: Option<bool>,
    /// Whether the asset panel is shown.
    pub assets: bool,
}

/// Draws the menu bar and returns what was chosen.
pub fn show(
    ui: &mut Ui,
    recent: &[PathBuf],
    undo: Option<&str>,
    redo: Option<&str>,
    playing: bool,
    view: ViewChoice,
) -> Option<Action> {
    let mut out = None;
    egui::MenuBar::new().ui(ui, |ui| {
        ui.menu_button("File", |ui| file_menu(ui, recent, &mut out));
        ui.menu_button("Edit", |ui| edit_menu(ui, undo, redo, &mut out));
        ui.menu_button("Add", |ui| add_menu(ui, &mut out));
        ui.menu_button("Tools", |ui| tools_menu(ui, playing, view, &mut out));
        ui.menu_button("View", |ui| view_menu(ui, playing, view, &mut out));
        sculpt_and_play_buttons(ui, playing, view, &mut out);
    });
    out
}

/// The File menu: new, open, save, the recent levels, quit.
fn file_menu(ui: &mut Ui, recent: &[PathBuf], out: &mut Option<Action>) {
    for (label, a) in [
        ("New", Action::New),
        ("Open…", Action::Open),
        ("Save  (Ctrl+S)", Action::Save),
        ("Save As…", Action::SaveAs),
    ] {
        if ui.button(label).clicked() {
            *out = Some(a);
        }
    }
    ui.menu_button("Recent", |ui| {
        if recent.is_empty() {
            ui.label("(none)");
        }
        for p in recent {
            if ui.button(p.display().to_string()).clicked() {
                *out = Some(Action::OpenPath(p.clone()));
            }
        }
    });
    ui.separator();
    if ui.button("Quit").clicked() {
        *out = Some(Action::Quit);
    }
}

/// The Edit menu: undo and redo (named after what they undo or redo), cut, copy, paste,
/// duplicate, delete, select all and none.
fn edit_menu(ui: &mut Ui, undo: Option<&str>, redo: Option<&str>, out: &mut Option<Action>) {
    let u = undo.map_or("Undo".to_owned(), |d| format!("Undo {d}  (Ctrl+Z)"));
    if ui
        .add_enabled(undo.is_some(), egui::Button::new(u))
        .clicked()
    {
        *out = Some(Action::Undo);
    }
    let r = redo.map_or("Redo".to_owned(), |d| format!("Redo {d}  (Ctrl+Y)"));
    if ui
        .add_enabled(redo.is_some(), egui::Button::new(r))
        .clicked()
    {
        *out = Some(Action::Redo);
    }
    ui.separator();
    for (label, a) in [
        ("Cut  (Ctrl+X)", Action::Cut),
        ("Copy  (Ctrl+C)", Action::Copy),
        ("Paste  (Ctrl+V)", Action::RequestPaste),
        ("Duplicate  (Ctrl+D)", Action::Duplicate),
        ("Delete  (Del)", Action::Delete),
        ("Group  (Ctrl+G)", Action::Group),
        ("Ungroup  (Ctrl+Shift+G)", Action::Ungroup),
    ] {
        if ui.button(label).clicked() {
            *out = Some(a);
        }
    }
    ui.separator();
    if ui.button("Select all  (Ctrl+A)").clicked() {
        *out = Some(Action::SelectAll);
    }
    if ui.button("Select none  (Esc)").clicked() {
        *out = Some(Action::SelectNone);
    }
}

/// The Add menu: the preset entities, a glTF mesh, a terrain, a sprite.
fn add_menu(ui: &mut Ui, out: &mut Option<Action>) {
    for (label, row) in presets() {
        if ui.button(label).clicked() {
            *out = Some(Action::Add(Box::new(row)));
        }
    }
    if ui.button("glTF mesh…").clicked() {
        *out = Some(Action::AddMesh);
    }
    if ui.button("Terrain").clicked() {
        *out = Some(Action::AddTerrain);
    }
    if ui.button("Sprite…").clicked() {
        *out = Some(Action::AddSprite);
    }
}

/// The Tools menu: the terrain tool and the selected terrain's heightmap import and export
/// (not in Play, but for export).
fn tools_menu(ui: &mut Ui, playing: bool, view: ViewChoice, out: &mut Option<Action>) {
    let mut on = view.terrain_tool;
    if ui
        .add_enabled(!playing, egui::Checkbox::new(&mut on, "Terrain tool  (T)"))
        .clicked()
    {
        *out = Some(Action::ToggleTerrainTool);
    }
    let hint = "Select a terrain";
    let enabled = view.terrain_selection && !playing;
    if ui
        .add_enabled(enabled, egui::Button::new("Import heightmap…"))
        .on_disabled_hover_text(hint)
        .clicked()
    {
        *out = Some(Action::ImportHeightmap);
    }
    if ui
        .add_enabled(
            view.terrain_selection,
            egui::Button::new("Export heightmap…"),
        )
        .on_disabled_hover_text(hint)
        .clicked()
    {
        *out = Some(Action::ExportHeightmap);
    }
}

/// The View menu: the render method, orthographic view, Frame 1:1 and the debug views.
fn view_menu(ui: &mut Ui, playing: bool, view: ViewChoice, out: &mut Option<Action>) {
    ui.label("Render method");
    for (label, s) in [
        ("Ours: cached shading, per-texel culling", Schedule::Ours),
        ("Paper: every texel of every drawn face", Schedule::Paper),
    ] {
        if ui.radio(view.schedule == s, label).clicked() {
            *out = Some(Action::Schedule(s));
        }
    }
    ui.separator();
    let mut ortho = view.ortho;
    let check = egui::Checkbox::new(&mut ortho, "Orthographic view  (5)");
    if ui
        .add_enabled(!playing, check)
        .on_disabled_hover_text("Play always walks with the perspective camera")
        .clicked()
    {
        *out = Some(Action::ToggleOrtho);
    }
    let mut assets = view.assets;
    if ui.checkbox(&mut assets, "Asset panel").clicked() {
        *out = Some(Action::ToggleAssetPanel);
    }
    let frame = egui::Button::new("Frame 1:1 (selected texture)");
    if ui
        .add_enabled(view.textured_selection && !playing, frame)
        .on_disabled_hover_text("Select an entity with a loaded texture")
        .clicked()
    {
        *out = Some(Action::FrameOneToOne);
    }
    ui.separator();
    ui.label("Debug views");
    for v in DebugView::ALL {
        let mut on = view.debug.get(v);
        if ui.checkbox(&mut on, v.label()).clicked() {
            *out = Some(Action::ToggleDebug(v));
        }
    }
}

/// The buttons on the bar itself: the terrain tool's (not in Play) and Play / Stop.
fn sculpt_and_play_buttons(ui: &mut Ui, playing: bool, view: ViewChoice, out: &mut Option<Action>) {
    ui.separator();
    let sculpt = egui::Button::selectable(view.terrain_tool, "Sculpt (T)");
    if ui
        .add_enabled(!playing, sculpt)
        .on_hover_text("The terrain tool: brushes for the selected terrain")
        .clicked()
    {
        *out = Some(Action::ToggleTerrainTool);
    }
    let night = egui::Button::selectable(view.night == Some(true), "Night (N)");
    if ui
        .add_enabled(view.night.is_some(), night)
        .on_hover_text("Show the level's alternate palette, in edit and in Play")
        .on_disabled_hover_text("The level names no alternate palette")
        .clicked()
    {
        *out = Some(Action::ToggleNight);
    }
    let play = if playing { "Stop (Esc)" } else { "Play (F5)" };
    if ui.button(play).clicked() {
        *out = Some(Action::TogglePlay);
    }
}
