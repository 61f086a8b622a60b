//! The scene hierarchy: every entity with its kind icon and name; select (Ctrl-click
//! toggles, Shift-click selects a range), rename, duplicate, delete; a filter by name and by
//! component; each row's hide (H) and lock (L) toggles ([`crate::visibility`]).

use egui::Ui;
use texel_scene::{EntityRow, Name};

use crate::command::CommandError;
use crate::selection::Pick;
use crate::state::EditorState;
use crate::ui::widgets::{display_name, kind_icon};

/// Which rows the outliner shows: those whose name holds `text` (any case) and that have
/// the component `kind` names.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct OutlinerFilter {
    /// Part of the name, any case (empty: every name).
    pub text: String,
    /// The component asked for.
    pub kind: KindFilter,
}

/// The component filter of the outliner.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum KindFilter {
    /// Every entity.
    #[default]
    Any,
    /// A shape (geometry).
    Geometry,
    /// A sun or a point light.
    Light,
    /// A sprite.
    Sprite,
    /// A terrain.
    Terrain,
    /// A probe-grid override.
    ProbeOverride,
    /// An animator.
    Animated,
}

impl KindFilter {
    /// Every choice, in the combo's order.
    pub const ALL: [KindFilter; 7] = [
        KindFilter::Any,
        KindFilter::Geometry,
        KindFilter::Light,
        KindFilter::Sprite,
        KindFilter::Terrain,
        KindFilter::ProbeOverride,
        KindFilter::Animated,
    ];

    /// Its name in the combo.
    pub fn label(self) -> &'static str {
        match self {
            KindFilter::Any => "any",
            KindFilter::Geometry => "geometry",
            KindFilter::Light => "light",
            KindFilter::Sprite => "sprite",
            KindFilter::Terrain => "terrain",
            KindFilter::ProbeOverride => "probe override",
            KindFilter::Animated => "animated",
        }
    }

    /// Whether `row` has the component.
    pub fn matches(self, row: &EntityRow) -> bool {
        match self {
            KindFilter::Any => true,
            KindFilter::Geometry => row.geometry.is_some(),
            KindFilter::Light => row.directional_light.is_some() || row.point_light.is_some(),
            KindFilter::Sprite => row.sprite.is_some(),
            KindFilter::Terrain => row.terrain.is_some(),
            KindFilter::ProbeOverride => row.probe_grid_override.is_some(),
            KindFilter::Animated => row.animator.is_some(),
        }
    }
}

impl OutlinerFilter {
    /// Whether the row shown as `name` passes.
    pub fn passes(&self, name: &str, row: &EntityRow) -> bool {
        let text = self.text.trim().to_lowercase();
        self.kind.matches(row) && (text.is_empty() || name.to_lowercase().contains(&text))
    }

    /// The search box and the component combo.
    fn ui(&mut self, ui: &mut Ui) {
        ui.horizontal(|ui| {
            ui.add(
                egui::TextEdit::singleline(&mut self.text)
                    .hint_text("filter by name")
                    .desired_width(120.0),
            )
            .accessible_name("Filter by name");
            egui::ComboBox::from_id_salt("outliner kind")
                .selected_text(self.kind.label())
                .show_ui(ui, |ui| {
                    for k in KindFilter::ALL {
                        ui.selectable_value(&mut self.kind, k, k.label());
                    }
                })
                .response
                .accessible_name("Component filter");
        });
    }
}

/// The hide toggle's label (the default fonts have no eye nor padlock): highlighted while
/// the entity is hidden.
pub const HIDE: &str = "H";
/// The lock toggle's label, highlighted while the entity is locked.
pub const LOCK: &str = "L";

/// Draws the list. `rename` holds the entity being renamed and its edited name; `filter`
/// which rows show. A command that fails is returned, for the caller to show.
pub fn show(
    ui: &mut Ui,
    state: &mut EditorState,
    rename: &mut Option<(usize, String)>,
    filter: &mut OutlinerFilter,
) -> Result<(), CommandError> {
    ui.heading("Scene");
    filter.ui(ui);
    let rows: Vec<_> = {
        let scene = state.scene();
        scene.entities().filter_map(|e| scene.row(e)).collect()
    };
    let flags = state.hidden_and_locked();
    let mut action: Option<Action> = None;
    egui::ScrollArea::vertical().show(ui, |ui| {
        for (i, row) in rows.iter().enumerate() {
            let name = display_name(row, i);
            if !filter.passes(&name, row) {
                continue;
            }
            let (hidden, locked) = flags.get(i).copied().unwrap_or_default();
            if let Some((ri, text)) = rename.as_mut()
                && *ri == i
            {
                let r = ui.text_edit_singleline(text).accessible_name("Rename");
                r.request_focus();
                if r.lost_focus() {
                    action = Some(Action::Rename(i, text.clone()));
                }
                continue;
            }
            let selected = state.is_selected(i);
            let mut text = egui::RichText::new(format!("{} {}", kind_icon(row), name));
            if state.selection == Some(i) && !state.also_selected.is_empty() {
                // The active one of several: the inspector shows its components.
                text = text.strong().underline();
            }
            if hidden {
                text = text.weak().italics();
            }
            let r = ui
                .horizontal(|ui| {
                    let eye = ui
                        .selectable_label(hidden, HIDE)
                        .accessible_name(format!("Hide {name}"))
                        .on_hover_text("Hide: not drawn in the viewport (still saved)");
                    if eye.clicked() {
                        action = Some(Action::Hide(i, !hidden));
                    }
                    let lock = ui
                        .selectable_label(locked, LOCK)
                        .accessible_name(format!("Lock {name}"))
                        .on_hover_text("Lock: not picked nor moved in the viewport");
                    if lock.clicked() {
                        action = Some(Action::Lock(i, !locked));
                    }
                    ui.selectable_label(selected, text)
                })
                .inner;
            if r.clicked() {
                let how = Pick::from_modifiers(ui.input(|inp| inp.modifiers), Pick::Range);
                action = Some(Action::Select(i, how));
            }
            if r.double_clicked() {
                *rename = Some((i, name.clone()));
            }
            r.context_menu(|ui| {
                if ui.button("Rename").clicked() {
                    *rename = Some((i, name.clone()));
                }
                if ui.button("Duplicate").clicked() {
                    action = Some(Action::Duplicate(i));
                }
                if ui.button("Delete").clicked() {
                    action = Some(Action::Delete(i));
                }
            });
        }
    });
    match action {
        Some(Action::Select(i, how)) => state.pick(Some(i), how),
        Some(Action::Hide(i, on)) => state.set_hidden(i, on),
        Some(Action::Lock(i, on)) => state.set_locked(i, on),
        // On a selected row: the whole selection.
        Some(Action::Duplicate(i)) if state.is_selected(i) => state.duplicate_selection()?,
        Some(Action::Delete(i)) if state.is_selected(i) => state.delete_selection()?,
        Some(Action::Duplicate(i)) => state.duplicate(i)?,
        Some(Action::Delete(i)) => state.delete(i)?,
        Some(Action::Rename(i, text)) => {
            *rename = None;
            if let Some(mut row) = state.row_at(i) {
                row.name = (!text.trim().is_empty()).then(|| Name(text.trim().to_owned()));
                state.set_row(i, row, None)?;
            }
        }
        None => {}
    }
    Ok(())
}

enum Action {
    Select(usize, Pick),
    Duplicate(usize),
    Delete(usize),
    Rename(usize, String),
    Hide(usize, bool),
    Lock(usize, bool),
}
