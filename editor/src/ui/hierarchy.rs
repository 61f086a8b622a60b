//! The scene hierarchy: every entity with its kind icon and name; select (Ctrl-click
//! toggles, Shift-click selects a range), rename, duplicate, delete.

use egui::Ui;
use texel_scene::Name;

use crate::command::CommandError;
use crate::selection::Pick;
use crate::state::EditorState;
use crate::ui::widgets::{display_name, kind_icon};

/// Draws the list. `rename` holds the entity being renamed and its edited name. A command
/// that fails is returned, for the caller to show.
pub fn show(
    ui: &mut Ui,
    state: &mut EditorState,
    rename: &mut Option<(usize, String)>,
) -> Result<(), CommandError> {
    ui.heading("Scene");
    let rows: Vec<_> = {
        let scene = state.scene();
        scene.entities().filter_map(|e| scene.row(e)).collect()
    };
    let mut action: Option<Action> = None;
    egui::ScrollArea::vertical().show(ui, |ui| {
        for (i, row) in rows.iter().enumerate() {
            let name = display_name(row, i);
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
            let r = ui.selectable_label(selected, text);
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
}
