//! The inspector's Palette section (under the level settings): the level's palette and its
//! alternate picked from files or taken off, the dither strength, and each palette's
//! colours as swatches, each one editable with a colour picker. Every change is one undo
//! step per gesture; the viewport maps the next frame to the new colours without shading
//! anything again.

use egui::Ui;

use crate::command::CommandError;
use crate::history::MergeKey;
use crate::palette_edits::Slot;
use crate::state::EditorState;
use crate::ui::inspector::gesture_widget;
use crate::ui::menu::Action;

/// Swatches a row.
const SWATCHES_A_ROW: usize = 8;

/// Draws the section. Returns a command that failed (for the caller to show) and what the
/// person asked of the app (a file dialog to pick a palette).
pub fn show(ui: &mut Ui, state: &mut EditorState) -> (Result<(), CommandError>, Option<Action>) {
    let mut action = None;
    let result = body(ui, state, &mut action);
    (result, action)
}

fn body(
    ui: &mut Ui,
    state: &mut EditorState,
    action: &mut Option<Action>,
) -> Result<(), CommandError> {
    let setting = state.scene().palette.clone();
    file_row(
        ui,
        "Palette",
        setting.as_ref().map(|s| &s.file),
        Slot::Main,
        action,
    );
    let Some(setting) = setting else {
        ui.weak("None: frames are posterized by the level's bands alone.");
        return Ok(());
    };
    let mut dither = setting.dither;
    let r = ui.add(egui::Slider::new(&mut dither, 0.0..=1.0).text("Dither"));
    let r = r.accessible_name("Dither");
    if r.changed() {
        let mut next = state.palette_state();
        if let Some(s) = &mut next.setting {
            s.dither = dither.clamp(0.0, 1.0);
        }
        let key = gesture_widget(ui.ctx()).map(|widget| MergeKey::Palette { widget });
        state.set_palette(next, key)?;
    }
    swatches(ui, state, &setting.file, "Day")?;
    ui.separator();
    let alternate = setting.alternate.as_ref();
    file_row(ui, "Alternate", alternate, Slot::Alternate, action);
    if let Some(alt) = alternate {
        swatches(ui, state, alt, "Night")?;
    } else {
        ui.weak("No alternate: Night (N) shows the level's own palette.");
    }
    if state.document.palettes_edited() {
        ui.weak("Edited colours are written to their palette files when the level is saved.");
    }
    Ok(())
}

/// A palette file named (or none), with Pick… and None buttons.
fn file_row(
    ui: &mut Ui,
    what: &str,
    file: Option<&String>,
    slot: Slot,
    action: &mut Option<Action>,
) {
    ui.horizontal(|ui| {
        ui.label(format!("{what}:"));
        ui.monospace(file.map_or("none", |f| f.as_str()));
    });
    ui.horizontal(|ui| {
        let pick = ui.button("Pick…").accessible_name(format!("Pick {what}"));
        if pick.on_hover_text("A .gpl, .hex or .pal file").clicked() {
            *action = Some(Action::PickPalette(slot));
        }
        let none = ui.add_enabled(file.is_some(), egui::Button::new("None"));
        if none.accessible_name(format!("No {what}")).clicked() {
            *action = Some(Action::ClearPalette(slot));
        }
    });
}

/// The colours of the palette file `file` as swatches, each a colour picker (named
/// "`label` swatch i" for tests and screen readers).
fn swatches(
    ui: &mut Ui,
    state: &mut EditorState,
    file: &str,
    label: &str,
) -> Result<(), CommandError> {
    let Some(palette) = state.document.level.assets.palette(file).cloned() else {
        ui.weak("(not loaded)");
        return Ok(());
    };
    let mut edit = None;
    ui.label(format!("{label}: {} colours", palette.colours.len()));
    for (row, chunk) in palette.colours.chunks(SWATCHES_A_ROW).enumerate() {
        ui.horizontal(|ui| {
            ui.spacing_mut().item_spacing.x = 2.0;
            for (k, c) in chunk.iter().enumerate() {
                let i = row * SWATCHES_A_ROW + k;
                let mut rgb = *c;
                let r = egui::color_picker::color_edit_button_srgb(ui, &mut rgb);
                let r = r.accessible_name(format!("{label} swatch {i}"));
                let r =
                    r.on_hover_text(format!("{i}: #{:02x}{:02x}{:02x}", rgb[0], rgb[1], rgb[2]));
                if r.changed() && rgb != *c {
                    edit = Some((i, rgb));
                }
            }
        });
    }
    if let Some((i, rgb)) = edit {
        let key = gesture_widget(ui.ctx()).map(|widget| MergeKey::Palette { widget });
        state.set_swatch(file, i, rgb, key)?;
    }
    Ok(())
}
