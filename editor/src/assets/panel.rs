//! Drawing the asset panel: a row of filters, then the assets as tiles (a thumbnail and the
//! file name). A tile can be dragged into the viewport (an egui drag-and-drop payload,
//! [`AssetDrag`]); a click selects it, and the header's button, or the tile's context menu,
//! adds it at the view's centre.

use egui::{Color32, CornerRadius, Pos2, Rect, Sense, Stroke, Ui, vec2};

use super::scan::AssetFile;
use super::thumbs::{Thumb, Thumbnails};
use super::{AssetDrag, AssetKind, AssetPanel};
use crate::ui::menu::Action;

/// A tile's size, points.
const TILE: egui::Vec2 = vec2(64.0, 70.0);
/// The thumbnail's side, points.
const THUMB: f32 = 48.0;

/// Draws the panel's contents. Returns what the person asked for (an asset added at the
/// view's centre).
pub fn show(ui: &mut Ui, panel: &mut AssetPanel, playing: bool) -> Option<Action> {
    let mut out = None;
    panel.thumbs.collect(ui.ctx());
    header(ui, panel, playing, &mut out);
    let Some(scan) = &panel.scan else {
        if panel.walking() {
            ui.weak("Looking through the project's folders…");
        } else {
            ui.weak("Save the level: its project's assets are listed from its folder.");
        }
        return out;
    };
    let files: Vec<&AssetFile> = (scan.files.iter())
        .filter(|f| panel.only.is_none_or(|k| k == f.kind))
        .collect();
    if files.is_empty() {
        ui.weak(format!("No assets under {}", scan.root.display()));
    }
    let (thumbs, selected) = (&mut panel.thumbs, &mut panel.selected);
    egui::ScrollArea::vertical()
        .auto_shrink([false, false])
        .show(ui, |ui| {
            ui.horizontal_wrapped(|ui| {
                for file in files {
                    if let Some(a) = tile(ui, thumbs, selected, file, playing) {
                        out = Some(a);
                    }
                }
            });
        });
    out
}

fn header(ui: &mut Ui, panel: &mut AssetPanel, playing: bool, out: &mut Option<Action>) {
    ui.horizontal(|ui| {
        ui.strong("Assets");
        if ui.selectable_label(panel.only.is_none(), "All").clicked() {
            panel.only = None;
        }
        for kind in AssetKind::ALL {
            if ui
                .selectable_label(panel.only == Some(kind), kind.label())
                .clicked()
            {
                panel.only = Some(kind);
            }
        }
        if ui.button("Rescan").clicked() {
            panel.rescan = true;
        }
        ui.separator();
        if let Some(s) = &panel.selected {
            let name = s.path.file_name().unwrap_or_default().to_string_lossy();
            let add = egui::Button::new(format!("Add {name} at view centre"));
            if ui.add_enabled(!playing, add).clicked() {
                *out = Some(place(s.clone()));
            }
        }
        if let Some(scan) = &panel.scan {
            let mut note = scan.root.display().to_string();
            if scan.truncated {
                note += " (stopped after a few thousand files)";
            }
            ui.weak(note);
        }
    });
}

fn place(drag: AssetDrag) -> Action {
    Action::PlaceAsset(drag, None)
}

/// One tile; a context-menu choice comes back as an action.
fn tile(
    ui: &mut Ui,
    thumbs: &mut Thumbnails,
    selected: &mut Option<AssetDrag>,
    file: &AssetFile,
    playing: bool,
) -> Option<Action> {
    let drag = AssetDrag {
        path: file.path.clone(),
        kind: file.kind,
    };
    let name = (file.path.file_name().unwrap_or_default())
        .to_string_lossy()
        .into_owned();
    let is_selected = selected.as_ref() == Some(&drag);
    let (rect, response) = ui.allocate_exact_size(TILE, Sense::click_and_drag());
    // Dragged, the tile carries its file to whatever takes it (the viewport).
    response.dnd_set_drag_payload(drag.clone());
    let mut broken = None;
    if ui.is_rect_visible(rect) {
        let thumb = thumbs.get(ui.ctx(), &file.path, file.kind);
        if let Some(Thumb::Broken(e)) = &thumb {
            broken = Some(e.clone());
        }
        paint_tile(
            ui,
            rect,
            &name,
            thumb.as_ref(),
            is_selected || response.hovered(),
        );
        if response.dragged()
            && let Some(at) = ui.ctx().pointer_interact_pos()
        {
            // The tile follows the pointer, over everything.
            let layer = egui::LayerId::new(egui::Order::Tooltip, response.id);
            let moved = egui::Painter::new(ui.ctx().clone(), layer, ui.ctx().content_rect());
            let shifted = Rect::from_center_size(at, rect.size());
            paint_tile_on(&moved, ui, shifted, &name, thumb.as_ref(), true);
        }
    }
    let response = response.accessible_name(&name);
    let hover = match &broken {
        Some(e) => format!("{}\n{}: broken: {e}", file.shown, file.kind.label()),
        None => format!(
            "{}\n{}: drag into the viewport",
            file.shown,
            file.kind.label()
        ),
    };
    let response = response.on_hover_text(hover);
    if response.clicked() {
        *selected = Some(drag.clone());
    }
    let mut out = None;
    response.context_menu(|ui| {
        let add = egui::Button::new("Add at view centre");
        if ui.add_enabled(!playing, add).clicked() {
            out = Some(place(drag.clone()));
            ui.close();
        }
        if file.kind == AssetKind::Texture {
            let sprite = egui::Button::new("Add as a sprite at view centre");
            if ui.add_enabled(!playing, sprite).clicked() {
                out = Some(place(AssetDrag {
                    kind: AssetKind::Sprite,
                    ..drag.clone()
                }));
                ui.close();
            }
        }
    });
    out
}

fn paint_tile(ui: &Ui, rect: Rect, name: &str, thumb: Option<&Thumb>, lit: bool) {
    paint_tile_on(&ui.painter_at(rect), ui, rect, name, thumb, lit);
}

fn paint_tile_on(
    painter: &egui::Painter,
    ui: &Ui,
    rect: Rect,
    name: &str,
    thumb: Option<&Thumb>,
    lit: bool,
) {
    let visuals = ui.visuals();
    if lit {
        painter.rect_filled(rect, CornerRadius::same(3), visuals.selection.bg_fill);
    }
    let area = Rect::from_center_size(
        Pos2::new(rect.center().x, rect.top() + 2.0 + THUMB * 0.5),
        vec2(THUMB, THUMB),
    );
    let text = visuals.text_color();
    match thumb {
        None => mesh_icon(painter, area, text),
        Some(Thumb::Pending) => {
            painter.rect_filled(area, CornerRadius::same(2), visuals.faint_bg_color);
            painter.text(
                area.center(),
                egui::Align2::CENTER_CENTER,
                "…",
                egui::FontId::proportional(16.0),
                text,
            );
        }
        Some(Thumb::Image(tex)) => {
            let size = tex.size_vec2();
            let fit = (THUMB / size.x.max(size.y)).min(THUMB);
            let shown = Rect::from_center_size(area.center(), size * fit);
            let uv = Rect::from_min_max(Pos2::ZERO, Pos2::new(1.0, 1.0));
            painter.image(tex.id(), shown, uv, Color32::WHITE);
        }
        Some(Thumb::Swatches(colours)) => swatches(painter, area, colours),
        Some(Thumb::Broken(_)) => {
            painter.rect_stroke(
                area.shrink(2.0),
                CornerRadius::same(2),
                Stroke::new(2.0, Color32::from_rgb(200, 60, 60)),
                egui::StrokeKind::Inside,
            );
            painter.text(
                area.center(),
                egui::Align2::CENTER_CENTER,
                "broken",
                egui::FontId::proportional(11.0),
                Color32::from_rgb(220, 80, 80),
            );
        }
    }
    let label = Pos2::new(rect.center().x, rect.bottom() - 2.0);
    let font = egui::FontId::proportional(10.0);
    let short: String = if name.chars().count() > 11 {
        name.chars().take(10).chain(['…']).collect()
    } else {
        name.to_owned()
    };
    painter.text(label, egui::Align2::CENTER_BOTTOM, short, font, text);
}

/// A mesh's icon: a little cube in three shades.
fn mesh_icon(painter: &egui::Painter, area: Rect, text: Color32) {
    let c = area.center();
    let r = THUMB * 0.36;
    let (dx, dy) = (r * 0.87, r * 0.5);
    let top = Pos2::new(c.x, c.y - r);
    let up_l = Pos2::new(c.x - dx, c.y - dy);
    let up_r = Pos2::new(c.x + dx, c.y - dy);
    let lo_l = Pos2::new(c.x - dx, c.y + dy);
    let lo_r = Pos2::new(c.x + dx, c.y + dy);
    let bottom = Pos2::new(c.x, c.y + r);
    let faces = [
        (vec![top, up_r, c, up_l], Color32::from_gray(190)),
        (vec![up_l, c, bottom, lo_l], Color32::from_gray(130)),
        (vec![c, up_r, lo_r, bottom], Color32::from_gray(90)),
    ];
    for (points, fill) in faces {
        painter.add(egui::Shape::convex_polygon(
            points,
            fill,
            Stroke::new(1.0, text),
        ));
    }
}

/// A palette's colours as a grid of small squares filling `area`.
fn swatches(painter: &egui::Painter, area: Rect, colours: &[[u8; 3]]) {
    let shown = colours.len().min(64);
    if shown == 0 {
        return;
    }
    let per_row = (shown as f32).sqrt().ceil() as usize;
    let rows = shown.div_ceil(per_row);
    let cell = vec2(area.width() / per_row as f32, area.height() / rows as f32);
    for (i, [r, g, b]) in colours.iter().take(shown).enumerate() {
        let min = area.min + vec2((i % per_row) as f32 * cell.x, (i / per_row) as f32 * cell.y);
        let colour = Color32::from_rgb(*r, *g, *b);
        painter.rect_filled(Rect::from_min_size(min, cell), CornerRadius::ZERO, colour);
    }
}
