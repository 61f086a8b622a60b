//! The inspector's sprite section: every field of the selected entity's sprite, and a preview
//! of its frames. It edits the inspector's copy of the row, so each gesture is one undo step
//! like any other component's. A value the level would refuse is not taken, and the section
//! says why: the sprite's own validation, and against the loaded sheet
//! [`Sprite::check_sheet`] (a frame size that does not divide it, an animation frame off it,
//! 8 directions on too few rows) and the maps' sizes. Paths, names and frame lists are typed
//! and taken when the field is left (Enter or a click elsewhere); a new path is then loaded
//! by the app, which undoes the edit if the file does not fit.
//!
//! The preview uploads a sheet once (cached by path, uploaded again when the library holds
//! another image for it) and draws the frame [`Sprite::frame_at`] gives, cropped by UV rect
//! with nearest filtering at an integer zoom on whole screen pixels, so each sprite pixel is
//! a square block. It plays at the animation's fps, asking egui to repaint only when the next
//! frame is due.

use std::collections::HashMap;
use std::sync::Arc;
use std::time::Duration;

use egui::emath::GuiRounding;
use egui::{Color32, DragValue, Rect, Ui, pos2};
use glam::{UVec2, Vec2};
use texel_scene::assets::AssetLibrary;
use texel_scene::level::check_sprite_row;
use texel_scene::sprite::{
    Billboard, DIRECTIONS, INDEX_RATIOS, MAX_ANIMATIONS, MAX_FPS, MAX_RELIEF_DEPTH, Refraction,
    Relief, Sprite, SpriteAnimation, SpriteSize,
};
use texel_scene::texture::Image;
use texel_scene::{EntityRow, Validate};

/// The relief depth a depth map typed into an entity without one starts with, world units.
const DEFAULT_RELIEF_DEPTH: f32 = 0.5;
/// The index ratio a new refraction starts with (air into glass).
const DEFAULT_INDEX_RATIO: f32 = 0.67;
/// The largest side of the preview, points.
const PREVIEW_SIDE: f32 = 192.0;
/// Sheets kept uploaded; more, and the cache starts again.
const MAX_CACHED_SHEETS: usize = 16;
/// The longest step the preview's clock takes in one UI frame, seconds (after a pause in
/// repainting, the animation carries on rather than jumping).
const MAX_STEP: f32 = 0.25;

/// What each view direction of an 8-direction sprite is, as [`texel_scene::sprite::direction_index`]
/// numbers them (where the viewer stands).
pub const DIRECTION_NAMES: [&str; 8] = [
    "front",
    "front-left",
    "left",
    "back-left",
    "back",
    "back-right",
    "right",
    "front-right",
];

/// The sprite section's state between frames: which entity it shows, why the last edit was
/// refused, the preview's clock and choices, and the uploaded sheets.
#[derive(Default)]
pub struct SpritePanel {
    entity: Option<usize>,
    /// Why the last edit was refused; shown until an edit is taken or another entity is
    /// selected.
    pub refused: Option<String>,
    /// The preview's choices and clock.
    pub preview: Preview,
    sheets: HashMap<String, (Arc<Image>, egui::TextureHandle)>,
    /// Sheets uploaded to egui so far.
    pub uploads: u64,
}

/// The preview's choices and clock.
#[derive(Debug, Clone, PartialEq)]
pub struct Preview {
    /// The animation played, by position (one the sprite lacks shows frame 0).
    pub animation: usize,
    /// The view direction shown (0..8, see [`DIRECTION_NAMES`]; ignored with 1 direction).
    pub direction: u32,
    /// Whether the clock runs.
    pub playing: bool,
    /// Seconds into the animation.
    pub time: f64,
    /// What was drawn last.
    pub shown: Option<Shown>,
}

impl Default for Preview {
    fn default() -> Self {
        Preview {
            animation: 0,
            direction: 0,
            playing: true,
            time: 0.0,
            shown: None,
        }
    }
}

/// A frame the preview drew.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shown {
    /// The sheet's frame index.
    pub frame: u32,
    /// Its rectangle on the sheet, in UV (0..1 from the top-left corner).
    pub uv: Rect,
    /// Screen pixels per sprite pixel.
    pub zoom: u32,
}

impl SpritePanel {
    /// Starts over when another entity is selected.
    fn select(&mut self, index: usize) {
        if self.entity != Some(index) {
            self.entity = Some(index);
            self.refused = None;
            self.preview = Preview::default();
        }
    }

    /// The egui texture of `image`, the sheet the level names `path`: uploaded the first time,
    /// or again when the library's image is another (a reload); `None` when it is larger than
    /// egui's textures may be.
    fn texture(
        &mut self,
        ctx: &egui::Context,
        path: &str,
        image: &Arc<Image>,
    ) -> Option<egui::TextureId> {
        if let Some((cached, texture)) = self.sheets.get(path)
            && Arc::ptr_eq(cached, image)
        {
            return Some(texture.id());
        }
        let max = ctx.input(|i| i.max_texture_side);
        let (w, h) = (image.width as usize, image.height as usize);
        if w > max || h > max || image.pixels.len() != w * h * 4 {
            return None;
        }
        if self.sheets.len() >= MAX_CACHED_SHEETS {
            self.sheets.clear();
        }
        let colour = egui::ColorImage::from_rgba_unmultiplied([w, h], &image.pixels);
        let options = egui::TextureOptions::NEAREST;
        let texture = ctx.load_texture(format!("sprite sheet {path}"), colour, options);
        let id = texture.id();
        self.sheets
            .insert(path.to_owned(), (image.clone(), texture));
        self.uploads += 1;
        Some(id)
    }
}

/// The sprite of `row` (the entity at `index`), if it has one: its fields and preview. The
/// sheet and maps are looked up in `assets`.
pub fn section(
    ui: &mut Ui,
    index: usize,
    row: &mut EntityRow,
    assets: &AssetLibrary,
    panel: &mut SpritePanel,
) {
    panel.select(index);
    let Some(sprite) = &mut row.sprite else {
        return;
    };
    let mut remove = false;
    egui::CollapsingHeader::new("Sprite")
        .default_open(true)
        .show(ui, |ui| {
            let before = sprite.clone();
            let typed = edit(ui, index, sprite);
            let checked = typed.and_then(|()| {
                if *sprite == before {
                    Ok(())
                } else {
                    check(sprite, assets)
                }
            });
            match checked {
                Ok(()) if *sprite != before => panel.refused = None,
                Ok(()) => {}
                Err(why) => {
                    *sprite = before;
                    panel.refused = Some(why);
                }
            }
            if let Some(why) = &panel.refused {
                ui.colored_label(Color32::from_rgb(255, 130, 130), format!("Refused: {why}"));
            }
            egui::CollapsingHeader::new("Preview")
                .default_open(true)
                .show(ui, |ui| preview(ui, sprite, assets, panel));
            remove = ui.small_button("Remove Sprite").clicked();
        });
    if remove {
        row.sprite = None;
    }
}

/// After the other sections' edits: a sprite entity keeps its transform and gets no geometry
/// or terrain (the level could not hold it), so such a change is taken back (with the
/// animator, which leaves with the transform) and the sprite section says why (in the next
/// frame, asked for at once).
pub fn keep_row_valid(
    ctx: &egui::Context,
    before: &EntityRow,
    row: &mut EntityRow,
    panel: &mut SpritePanel,
) {
    if row.sprite.is_none() {
        return;
    }
    if let Err((_, why)) = check_sprite_row(row) {
        row.transform = before.transform;
        row.geometry = before.geometry.clone();
        row.terrain = before.terrain.clone();
        row.animator = before.animator.clone();
        panel.refused = Some(why);
        ctx.request_repaint();
    }
}

/// Whether the level would take `sprite`: its own validation, then, with its sheet loaded,
/// the frames against the sheet and every loaded map's size against the sheet's.
pub fn check(sprite: &Sprite, assets: &AssetLibrary) -> Result<(), String> {
    sprite
        .validate()
        .map_err(|(field, message)| format!("{field}: {message}"))?;
    let Some(sheet) = assets.sprite_sheet(sprite) else {
        return Ok(());
    };
    sprite
        .check_sheet(UVec2::new(sheet.width, sheet.height))
        .map_err(|e| e.message)?;
    let size_of = |p: &str| (assets.texture(p)).map(|m| UVec2::new(m.width, m.height));
    sprite
        .check_map_sizes(UVec2::new(sheet.width, sheet.height), size_of)
        .map_err(|(path, message)| format!("{path:?}: {message}"))
}

/// Every field. Returns why a typed value could not be read (a frame list that is not
/// numbers), leaving the field as it was.
fn edit(ui: &mut Ui, index: usize, s: &mut Sprite) -> Result<(), String> {
    ui.label("Sheet");
    if let Some(p) = text_field(ui, index, "Sprite sheet path", &s.sheet, "sheet.png") {
        s.sheet = p;
    }
    ui.horizontal(|ui| {
        ui.label("Frame");
        for (name, v) in [
            ("Frame width", &mut s.frame_size.x),
            ("Frame height", &mut s.frame_size.y),
        ] {
            ui.add(
                DragValue::new(v)
                    .range(1..=u32::from(u16::MAX))
                    .suffix(" px"),
            )
            .accessible_name(name);
        }
    });
    ui.horizontal(|ui| {
        ui.label("Pivot");
        for (name, v) in [("Pivot X", &mut s.pivot.x), ("Pivot Y", &mut s.pivot.y)] {
            ui.add(DragValue::new(v).speed(0.01).range(0.0..=1.0))
                .on_hover_text(
                    "The point the translation places: fractions of the frame, x right, y down",
                )
                .accessible_name(name);
        }
    });
    size(ui, s);
    ui.horizontal(|ui| {
        ui.label("Billboard");
        for (b, name) in [
            (Billboard::Spherical, "Spherical"),
            (Billboard::Upright, "Upright"),
            (Billboard::Fixed, "Fixed"),
        ] {
            ui.radio_value(&mut s.billboard, b, name)
                .accessible_name(format!("Billboard {name}"));
        }
    });
    ui.horizontal(|ui| {
        ui.label("Directions");
        ui.radio_value(&mut s.directions, 1, "1")
            .accessible_name("1 direction");
        ui.radio_value(&mut s.directions, DIRECTIONS, "8")
            .on_hover_text(
                "Each row of frames has the 7 rows below it as seen from the other directions",
            )
            .accessible_name("8 directions");
    });
    ui.checkbox(&mut s.casts_shadows, "Sprite casts shadows");
    ui.checkbox(&mut s.outlined, "Sprite outlined");
    maps(ui, index, s);
    animations(ui, index, &mut s.animations)
}

/// World units, or matched to the probe texels.
fn size(ui: &mut Ui, s: &mut Sprite) {
    let mut matched = s.size == SpriteSize::Matched;
    ui.horizontal(|ui| {
        ui.label("Size");
        ui.radio_value(&mut matched, false, "World")
            .on_hover_text("Width and height in world units (times the transform's scale)")
            .accessible_name("Size World");
        ui.radio_value(&mut matched, true, "Matched")
            .on_hover_text("One sprite pixel is one probe texel at the sprite's distance")
            .accessible_name("Size Matched");
    });
    match (matched, &mut s.size) {
        (true, SpriteSize::World(_)) => s.size = SpriteSize::Matched,
        (false, SpriteSize::Matched) => {
            let f = s.frame_size.max(UVec2::ONE).as_vec2();
            s.size = SpriteSize::World(Vec2::new(f.x / f.y, 1.0));
        }
        (false, SpriteSize::World(v)) => {
            ui.horizontal(|ui| {
                ui.label("World size");
                for (name, c) in [("Sprite width", &mut v.x), ("Sprite height", &mut v.y)] {
                    ui.add(DragValue::new(c).speed(0.01).range(0.0..=1.0e6))
                        .accessible_name(name);
                }
            });
        }
        (true, SpriteSize::Matched) => {}
    }
}

/// The normal map, the relief (depth map and depth) and the refraction (back depth map and
/// index ratio). An empty path means none.
fn maps(ui: &mut Ui, index: usize, s: &mut Sprite) {
    let hint = "none (a PNG the sheet's size)";
    let normal = s.normal_map.as_deref().unwrap_or_default();
    ui.label("Normal map");
    if let Some(p) = text_field(ui, index, "Sprite normal map path", normal, hint) {
        s.normal_map = non_empty(p);
    }
    ui.label("Relief depth map");
    let depth = s.relief.as_ref().map_or("", |r| r.depth_map.as_str());
    if let Some(p) = text_field(ui, index, "Relief depth map path", depth, hint) {
        s.relief = non_empty(p).map(|depth_map| Relief {
            depth_map,
            depth: s.relief.as_ref().map_or(DEFAULT_RELIEF_DEPTH, |r| r.depth),
        });
    }
    if let Some(r) = &mut s.relief {
        ui.horizontal(|ui| {
            ui.label("Depth");
            ui.add(
                DragValue::new(&mut r.depth)
                    .speed(0.01)
                    .range(0.0..=MAX_RELIEF_DEPTH)
                    .suffix(" units"),
            )
            .on_hover_text("World units behind the quad of the deepest texel (255)")
            .accessible_name("Relief depth");
        });
    }
    ui.label("Refraction back depth map");
    let back = s.refraction.as_ref().map_or("", |r| r.back_depth.as_str());
    if let Some(p) = text_field(ui, index, "Refraction back depth path", back, hint) {
        s.refraction = non_empty(p).map(|back_depth| Refraction {
            back_depth,
            index_ratio: (s.refraction.as_ref()).map_or(DEFAULT_INDEX_RATIO, |r| r.index_ratio),
        });
    }
    if let Some(r) = &mut s.refraction {
        ui.horizontal(|ui| {
            ui.label("Index ratio");
            ui.add(
                DragValue::new(&mut r.index_ratio)
                    .speed(0.01)
                    .range(0.0..=*INDEX_RATIOS.end()),
            )
            .on_hover_text("Refractive index outside over inside (air into glass: about 0.67)")
            .accessible_name("Index ratio");
        });
    }
}

fn non_empty(p: String) -> Option<String> {
    (!p.trim().is_empty()).then_some(p)
}

/// The animations: each one's name, frames (a comma list) and fps, removed, or a new one
/// added. Returns why a typed frame list could not be read.
fn animations(ui: &mut Ui, index: usize, list: &mut Vec<SpriteAnimation>) -> Result<(), String> {
    ui.label("Animations");
    let mut result = Ok(());
    let mut remove = None;
    for (i, a) in list.iter_mut().enumerate() {
        let k = i + 1;
        ui.horizontal(|ui| {
            let name = format!("Animation {k} name");
            if let Some(n) = text_field(ui, index, &name, &a.name, "name") {
                a.name = n;
            }
            ui.add(
                DragValue::new(&mut a.fps)
                    .speed(0.1)
                    .range(0.0..=MAX_FPS)
                    .suffix(" fps"),
            )
            .accessible_name(format!("Animation {k} fps"));
            if ui
                .small_button("−")
                .on_hover_text("Remove this animation")
                .accessible_name(format!("Remove animation {k}"))
                .clicked()
            {
                remove = Some(i);
            }
        });
        let name = format!("Animation {k} frames");
        if let Some(text) = text_field(ui, index, &name, &frames_text(&a.frames), "0, 1, 2") {
            match parse_frames(&text) {
                Ok(frames) => a.frames = frames,
                Err(e) => result = Err(format!("animation `{}`: {e}", a.name)),
            }
        }
    }
    if let Some(i) = remove {
        list.remove(i);
    }
    let add = egui::Button::new("Add animation").small();
    if ui
        .add_enabled(list.len() < MAX_ANIMATIONS, add)
        .on_hover_text("A new animation showing frame 0")
        .clicked()
    {
        let name = (list.len() + 1..)
            .map(|n| format!("animation {n}"))
            .find(|n| list.iter().all(|a| &a.name != n))
            .unwrap_or_default();
        list.push(SpriteAnimation {
            name,
            frames: vec![0],
            fps: crate::add_sprite::DEFAULT_FPS,
        });
    }
    result
}

/// `[1, 2, 3]` as `1, 2, 3`.
pub fn frames_text(frames: &[u32]) -> String {
    let text: Vec<String> = frames.iter().map(u32::to_string).collect();
    text.join(", ")
}

/// A comma list of frame numbers (spaces and a trailing comma allowed).
pub fn parse_frames(text: &str) -> Result<Vec<u32>, String> {
    text.split(',')
        .map(str::trim)
        .filter(|t| !t.is_empty())
        .map(|t| {
            t.parse::<u32>()
                .map_err(|_| format!("`{t}` is not a frame number"))
        })
        .collect()
}

/// A line of text named `name` showing `current`, taken when the field is left (or set whole
/// without the focus): returns the text then if it changed. While it has the focus, what is typed is kept in egui's memory
/// (with the entity it is typed for, so it never lands on another).
fn text_field(ui: &mut Ui, index: usize, name: &str, current: &str, hint: &str) -> Option<String> {
    let id = egui::Id::unique(("sprite field", name));
    let typed = ui
        .data(|d| d.get_temp::<(usize, String)>(id))
        .filter(|(i, _)| *i == index);
    let mut text = typed.map_or_else(|| current.to_owned(), |(_, t)| t);
    let r = ui
        .add(
            egui::TextEdit::singleline(&mut text)
                .id(id)
                .hint_text(hint)
                .desired_width(220.0),
        )
        .accessible_name(name);
    // Left, or set whole without the focus (as assistive technologies set a value).
    if r.lost_focus() || (r.changed() && !r.has_focus()) {
        ui.data_mut(|d| d.remove::<(usize, String)>(id));
        return (text != current).then_some(text);
    }
    if r.has_focus() {
        ui.data_mut(|d| d.insert_temp(id, (index, text)));
    } else {
        ui.data_mut(|d| d.remove::<(usize, String)>(id));
    }
    None
}

/// The position in `animation` that [`Sprite::frame_at`] shows at `t`: asked of an animation
/// whose frames are their own positions, so the timing arithmetic stays in one place.
pub fn step_at(animation: &SpriteAnimation, t: f64) -> u32 {
    let n = animation.frames.len() as u32;
    let positions = Sprite {
        animations: vec![SpriteAnimation {
            name: String::new(),
            frames: (0..n).collect(),
            fps: animation.fps,
        }],
        ..Sprite::new("", UVec2::ONE, SpriteSize::Matched)
    };
    positions.frame_at(UVec2::ONE, 0, t, 0)
}

/// The preview: animation, direction, play/pause and frame steps, the frame counter and the
/// current frame.
fn preview(ui: &mut Ui, sprite: &Sprite, assets: &AssetLibrary, panel: &mut SpritePanel) {
    let Some(image) = assets.sprite_sheet(sprite) else {
        panel.preview.shown = None;
        ui.weak("The sheet is not loaded (a new path loads once typing stops; an unsaved level has nowhere to look).");
        return;
    };
    let sheet = UVec2::new(image.width, image.height);
    let p = &mut panel.preview;
    controls(ui, sprite, p);
    let animation = sprite
        .animation(p.animation)
        .filter(|a| !a.frames.is_empty());
    if let Some(a) = animation {
        step_buttons(ui, a, p);
        if p.playing {
            let dt = ui.input(|i| i.unstable_dt).clamp(0.0, MAX_STEP);
            p.time += f64::from(dt);
            // Repaint when the next frame is due, not every frame.
            let period = 1.0 / f64::from(a.fps);
            let due = period - p.time.rem_euclid(period);
            ui.ctx()
                .request_repaint_after(Duration::from_secs_f64(due.clamp(0.001, 1.0)));
        }
    }
    let frame = sprite.frame_at(sheet, p.animation, p.time, p.direction);
    let counter = match animation {
        Some(a) => format!(
            "Frame {}/{} · sheet frame {frame}",
            step_at(a, p.time) + 1,
            a.frames.len()
        ),
        None => format!("Still · sheet frame {frame}"),
    };
    ui.label(counter);
    let Some(texture) = panel.texture(ui.ctx(), &sprite.sheet, image) else {
        panel.preview.shown = None;
        ui.weak("The sheet is larger than the preview can show.");
        return;
    };
    let shown = draw_frame(ui, sprite, sheet, frame, texture);
    panel.preview.shown = Some(shown);
}

/// Which animation, which direction, play or pause.
fn controls(ui: &mut Ui, sprite: &Sprite, p: &mut Preview) {
    if sprite.animations.is_empty() {
        ui.weak("No animations: frame 0 stands still.");
    } else {
        let chosen = sprite.animation(p.animation).map_or("(none)", |a| &a.name);
        egui::ComboBox::from_label("Animation")
            .selected_text(chosen)
            .show_ui(ui, |ui| {
                for (i, a) in sprite.animations.iter().enumerate() {
                    if ui.selectable_label(p.animation == i, &a.name).clicked() {
                        p.animation = i;
                        p.time = 0.0;
                    }
                }
            });
    }
    if sprite.directions == DIRECTIONS {
        let d = p.direction.min(DIRECTIONS - 1);
        egui::ComboBox::from_label("Direction")
            .selected_text(format!("{d} {}", DIRECTION_NAMES[d as usize]))
            .show_ui(ui, |ui| {
                for (i, name) in (0..DIRECTIONS).zip(DIRECTION_NAMES) {
                    ui.selectable_value(&mut p.direction, i, format!("{i} {name}"));
                }
            });
    }
}

/// Play or pause, and one frame back or on (pausing).
fn step_buttons(ui: &mut Ui, a: &SpriteAnimation, p: &mut Preview) {
    ui.horizontal(|ui| {
        let label = if p.playing {
            "Pause preview"
        } else {
            "Play preview"
        };
        if ui.button(label).clicked() {
            p.playing = !p.playing;
        }
        let n = a.frames.len() as u32;
        let k = step_at(a, p.time);
        for (label, name, to) in [
            ("<", "Previous frame", (k + n - 1) % n),
            (">", "Next frame", (k + 1) % n),
        ] {
            if ui.small_button(label).accessible_name(name).clicked() {
                p.playing = false;
                p.time = f64::from(to) / f64::from(a.fps);
            }
        }
    });
}

/// Draws frame `frame` of the sheet (uploaded as `texture`) at the largest whole zoom that
/// fits, on whole screen pixels.
fn draw_frame(
    ui: &mut Ui,
    sprite: &Sprite,
    sheet: UVec2,
    frame: u32,
    texture: egui::TextureId,
) -> Shown {
    let (x, y, w, h) = sprite.frame_rect(sheet, frame);
    let (w, h) = (w.max(1), h.max(1));
    let ppp = ui.ctx().pixels_per_point();
    let side = (ui.available_width().min(PREVIEW_SIDE) * ppp).max(1.0);
    let zoom = (side / w.max(h) as f32).floor().max(1.0) as u32;
    let size = egui::vec2((w * zoom) as f32, (h * zoom) as f32) / ppp;
    let (rect, _) = ui.allocate_exact_size(size, egui::Sense::hover());
    let rect = Rect::from_min_size(rect.min.round_to_pixels(ppp), size);
    let (sw, sh) = (sheet.x as f32, sheet.y as f32);
    let uv = Rect::from_min_max(
        pos2(x as f32 / sw, y as f32 / sh),
        pos2((x + w) as f32 / sw, (y + h) as f32 / sh),
    );
    let painter = ui.painter();
    painter.rect_filled(rect, 0.0, Color32::from_gray(48));
    painter.image(texture, rect, uv, Color32::WHITE);
    ui.weak(format!("{w}×{h} px, ×{zoom}"));
    Shown { frame, uv, zoom }
}

#[cfg(test)]
mod tests;
