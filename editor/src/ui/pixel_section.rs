//! The inspector's pixel-perfect section: a textured entity's texture density against the
//! level's art pixels, Frame 1:1, and a calculator of the face resolution that makes a
//! density 1:1 at a distance.

use egui::Ui;
use texel_scene::{LevelSettings, PixelScale};

use crate::command::{Command, CommandError};
use crate::pixel::{PixelInfo, face_resolution_for_one_to_one};
use crate::state::EditorState;
use crate::ui::widgets::BIG;

/// What the face-resolution calculator was given for the selected entity (`None`: follow
/// the default, the material's density and the level's reference distance).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PixelCalc {
    index: Option<usize>,
    density: Option<f32>,
    distance: Option<f32>,
}

/// The pixel-perfect section of a textured entity: its texture density, the distance at
/// which one texture pixel is one art pixel, texture pixels per art pixel at the level's
/// reference distance, Frame 1:1, and a calculator of the face resolution that makes a
/// density 1:1 at a distance, which can be applied to the level. `info` is the selected
/// entity's [`PixelInfo`] on the viewport. Returns whether Frame 1:1 was asked for; a command
/// that fails is returned, for the caller to show.
pub fn pixel_perfect(
    ui: &mut Ui,
    state: &mut EditorState,
    info: Option<&PixelInfo>,
    calc: &mut PixelCalc,
) -> Result<bool, CommandError> {
    let Some((index, row)) = state.selected_row() else {
        return Ok(false);
    };
    let Some(material) = row.material.as_ref().filter(|_| row.geometry.is_some()) else {
        return Ok(false);
    };
    if calc.index != Some(index) {
        *calc = PixelCalc {
            index: Some(index),
            ..PixelCalc::default()
        };
    }
    let mut frame = false;
    let mut apply = None;
    egui::CollapsingHeader::new("Pixel-perfect")
        .default_open(true)
        .show(ui, |ui| {
            let Some(info) = info else {
                ui.label(match &material.texture {
                    Some(t) if t.path.trim().is_empty() => "Type the texture's path.",
                    Some(_) if state.document.path.is_none() => {
                        "The texture is not loaded: save the level first (paths are relative to it)."
                    }
                    Some(_) => "The texture is not loaded.",
                    None => "Untextured: nothing to compare with the art pixel.",
                });
                return;
            };
            egui::Grid::new("pixel-perfect").num_columns(2).show(ui, |ui| {
                ui.label("Texture");
                ui.label(&info.texture);
                ui.end_row();
                ui.label("Density");
                ui.label(format!("{:.2} px/unit", info.density));
                ui.end_row();
                ui.label("Face resolution");
                ui.label(format!("{} texels", info.face_resolution)).on_hover_text(
                    "The level's face resolution at the viewport's height and field of view",
                );
                ui.end_row();
                ui.label("1:1 distance");
                ui.label(format!("{:.2} units", info.one_to_one))
                    .on_hover_text("Where one texture pixel is one art pixel (probe texel), seen head-on");
                ui.end_row();
                ui.label(format!("At {:.2} units", info.reference_distance))
                    .on_hover_text("The level's reference distance");
                let (ratio, how) = ratio_text(info.at_reference);
                ui.label(ratio);
                ui.end_row();
                ui.label("");
                ui.label(how);
                ui.end_row();
            });
            frame = ui
                .button("Frame 1:1")
                .on_hover_text(
                    "Look straight at the face turned most toward the camera from the 1:1 distance",
                )
                .clicked();
            ui.separator();
            ui.label("Face resolution for 1:1");
            let mut density = calc.density.unwrap_or(info.density);
            let mut distance = calc.distance.unwrap_or(info.reference_distance);
            ui.horizontal(|ui| {
                ui.label("Density");
                if ui
                    .add(egui::DragValue::new(&mut density).speed(0.1).range(0.01..=BIG).suffix(" px/unit"))
                    .accessible_name("Calculator density")
                    .changed()
                {
                    calc.density = Some(density);
                }
            });
            ui.horizontal(|ui| {
                ui.label("Distance");
                if ui
                    .add(egui::DragValue::new(&mut distance).speed(0.05).range(0.01..=BIG).suffix(" units"))
                    .accessible_name("Calculator distance")
                    .changed()
                {
                    calc.distance = Some(distance);
                }
            });
            match face_resolution_for_one_to_one(density, distance) {
                Ok((raw, n)) => {
                    ui.label(format!("{n} texels (exactly {raw:.1})")).on_hover_text(
                        "Rounded to a multiple of 8 and clamped to the engine's 16..=2048",
                    );
                    let current = state.scene().settings.pixel_scale;
                    let fresh = current != PixelScale::FaceResolution(n);
                    if ui
                        .add_enabled(fresh, egui::Button::new(format!("Apply {n} to the level")))
                        .on_hover_text("Sets the level's pixel scale to this face resolution")
                        .clicked()
                    {
                        apply = Some(n);
                    }
                }
                Err(e) => {
                    ui.label(e);
                }
            }
        });
    if let Some(n) = apply {
        let before = state.scene().settings;
        let after = LevelSettings {
            pixel_scale: PixelScale::FaceResolution(n),
            ..before
        };
        state.apply(Command::SetSettings { before, after }, None)?;
    }
    Ok(frame)
}

/// "0.50 texture px per art px" and "magnified ×2.00" (or "1:1", or minified).
fn ratio_text(k: f32) -> (String, String) {
    let how = if (k - 1.0).abs() < 0.005 {
        "1:1".to_owned()
    } else if k < 1.0 {
        format!("magnified ×{:.2}", 1.0 / k)
    } else {
        format!("minified ×{k:.2}")
    };
    (format!("{k:.2} texture px per art px"), how)
}
