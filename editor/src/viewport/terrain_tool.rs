//! The terrain tool: while it is on and a terrain is selected, the primary button sculpts
//! (or paints) the terrain under the pointer with the chosen brush (Ctrl inverts, or
//! erases paint), and a circle on the surface shows the brush. The hit is found by marching
//! the view ray over the heights on the CPU ([`texel_scene::sculpt::ray_hit`]).
//!
//! A stroke (press to release) works on a copy of the heights (or of the paint layer),
//! shown by putting the copy in the asset library and marking the region it touched changed
//! at most every [`REFRESH_EVERY`] (the session updates what sees it then); on release the
//! heights (or paint) before the stroke go back and the stroke lands as one
//! [`Command::SetHeights`] (or [`Command::SetPaint`]) holding the touched samples (or
//! pixels) before and after. A terrain painted for the first time names its new layer
//! during the stroke, so the view shows it; the command then makes that change too.

use std::sync::Arc;
use std::time::{Duration, Instant};

use egui::{Color32, Painter, Response, Stroke as Line, Ui};
use glam::Vec3;
use texel_scene::EntityRow;
use texel_scene::sculpt::{Brush, BrushKind, Dab, Placement, Region, copy_region, dab, ray_hit};
use texel_scene::terrain::{Heightfield, Terrain};

use crate::camera::Projector;
use crate::command::{Command, CommandError, entity_at};
use crate::paint::{PaintPlace, PaintStroke};
use crate::state::EditorState;
use crate::terrain::HeightChange;
use crate::terrain_edits::{
    TerrainTarget, file_backed, paint_backed, selected_terrain, stroke_start,
};

/// Shortest time between two refreshes of the view during a stroke (each rebuilds the
/// session's level); longer when the last rebuild was slow ([`refresh_interval`]).
pub const REFRESH_EVERY: Duration = Duration::from_millis(100);

/// How long a stroke waits between refreshes of the view when the last scene upload took
/// `upload_ms` (`None`: none yet since the renderer started): [`REFRESH_EVERY`], or three
/// uploads when that is longer, so rebuilding the level takes at most about a quarter of the
/// stroke's time.
pub fn refresh_interval(upload_ms: Option<f64>) -> Duration {
    let ms = upload_ms.unwrap_or(0.0);
    let slow = Duration::from_secs_f64((ms * 3.0 / 1e3).clamp(0.0, 10.0));
    slow.max(REFRESH_EVERY)
}
/// Segments of the brush circle.
const CIRCLE_SEGMENTS: usize = 64;

/// The terrain tool's state.
#[derive(Debug, Default)]
pub struct TerrainTool {
    /// Whether the tool is on.
    pub active: bool,
    /// The brush.
    pub brush: Brush,
    /// The terrain surface point under the pointer in the last frame.
    pub hover: Option<Vec3>,
    stroke: Option<Stroke>,
    painting: Option<Painting>,
}

/// A paint stroke in progress.
#[derive(Debug)]
struct Painting {
    index: usize,
    /// The entity's components before the stroke.
    row: EntityRow,
    /// Its components with the layer the stroke paints (`row` unless the terrain had no
    /// layer of its own; then the scene holds these during the stroke).
    after: EntityRow,
    /// The layer's path.
    path: String,
    place: PaintPlace,
    /// Where the terrain's heights lie (the height range of a refreshed region).
    heights: Placement,
    stroke: PaintStroke,
    refreshed: Option<Instant>,
    /// Whether the stroke has pixels the view does not show yet.
    pending: bool,
    /// The pixels painted since the last refresh.
    fresh: Option<Region>,
}

/// A stroke in progress.
#[derive(Debug)]
struct Stroke {
    index: usize,
    row: EntityRow,
    terrain: Terrain,
    /// The heights before the stroke (the library's).
    start: Arc<Heightfield>,
    /// The heights being sculpted.
    work: Heightfield,
    place: Placement,
    touched: Option<Region>,
    /// The height under the stroke's start, above the terrain's origin (what Flatten pulls to).
    target: f32,
    refreshed: Option<Instant>,
    /// Whether `work` has changes the view does not show yet.
    pending: bool,
}

impl TerrainTool {
    /// Whether a stroke is in progress.
    pub fn stroking(&self) -> bool {
        self.stroke.is_some() || self.painting.is_some()
    }

    /// Switches the tool on or off (a stroke in progress lands first).
    pub fn toggle(&mut self, state: &mut EditorState) -> Result<(), CommandError> {
        self.finish(state)?;
        self.active = !self.active;
        self.hover = None;
        Ok(())
    }

    /// One frame of the tool over the viewport, when it is on and a terrain is selected:
    /// finds the surface under the pointer, sculpts while the primary button is down on the
    /// viewport, lands the stroke on release and draws the brush. Returns whether the tool
    /// used the pointer (it is over the terrain, or a stroke is in progress), so a click
    /// there does not pick. `refresh` is the shortest time between two refreshes of the view
    /// ([`refresh_interval`]).
    pub fn ui(
        &mut self,
        ui: &Ui,
        response: &Response,
        painter: &Painter,
        proj: &Projector,
        state: &mut EditorState,
        refresh: Duration,
    ) -> Result<bool, CommandError> {
        let Some(target) = selected_terrain(state) else {
            self.finish(state)?;
            self.hover = None;
            return Ok(false);
        };
        let other = |i: usize| i != target.index;
        if self.stroke.as_ref().is_some_and(|s| other(s.index))
            || self.painting.as_ref().is_some_and(|p| other(p.index))
            || (self.stroke.is_some() && self.brush.kind == BrushKind::Paint)
            || (self.painting.is_some() && self.brush.kind != BrushKind::Paint)
        {
            self.finish(state)?;
        }
        let (down, invert, dt) = ui.input(|i| {
            (
                i.pointer.primary_down() && !i.pointer.secondary_down(),
                i.modifiers.ctrl || i.modifiers.command,
                i.stable_dt.clamp(0.001, 0.1),
            )
        });
        let pos = response.interact_pointer_pos().or(response.hover_pos());
        let (field, place) = match &self.stroke {
            Some(s) => (&s.work, s.place),
            None => (&*target.field, target.place),
        };
        let hit = pos.and_then(|p| {
            let (o, d) = proj.ray(p);
            ray_hit(&place, field, o, d)
        });
        self.hover = hit;
        if down && response.is_pointer_button_down_on() && self.brush.kind == BrushKind::Paint {
            self.paint(state, &target, hit, invert, refresh)?;
            ui.ctx().request_repaint();
        } else if down && response.is_pointer_button_down_on() {
            if self.stroke.is_none()
                && let Some(h) = hit
            {
                self.stroke = Some(Stroke {
                    index: target.index,
                    row: target.row.clone(),
                    terrain: target.terrain.clone(),
                    start: target.field.clone(),
                    work: (*target.field).clone(),
                    place: target.place,
                    touched: None,
                    target: h.y - target.place.origin.y,
                    refreshed: None,
                    pending: false,
                });
            }
            if let Some(s) = &mut self.stroke {
                if let Some(h) = hit {
                    let d = Dab {
                        centre: h,
                        dt,
                        invert,
                        target: s.target,
                    };
                    if let Some(r) = dab(&mut s.work, &s.place, &self.brush, &d) {
                        s.touched = Some(s.touched.map_or(r, |t| t.union(r)));
                        s.pending = true;
                    }
                }
                if s.pending && s.refreshed.is_none_or(|t| t.elapsed() >= refresh) {
                    let assets = &mut state.document.level.assets;
                    assets.insert_heightfield(&s.terrain, Arc::new(s.work.clone()));
                    // Only the probe faces that see the stroke so far are captured again.
                    match s.touched {
                        Some(r) => {
                            let (min, max) = s.place.region_bounds(r);
                            state.document.touch_region(min, max);
                        }
                        None => state.document.touch(),
                    }
                    s.refreshed = Some(Instant::now());
                    s.pending = false;
                }
                ui.ctx().request_repaint();
            }
        } else {
            self.finish(state)?;
        }
        if let Some(centre) = self.hover {
            let (field, place) = match &self.stroke {
                Some(s) => (&s.work, s.place),
                None => (&*target.field, target.place),
            };
            draw_brush(painter, proj, &place, field, centre, &self.brush, invert);
        }
        Ok(self.stroking() || self.hover.is_some())
    }

    /// One frame of a paint stroke: starts it on a hit (a terrain without a layer of its
    /// own gets one), stamps the brush at the hit, and shows what is painted at most every
    /// `refresh`.
    fn paint(
        &mut self,
        state: &mut EditorState,
        target: &TerrainTarget,
        hit: Option<Vec3>,
        erase: bool,
        refresh: Duration,
    ) -> Result<(), CommandError> {
        if self.painting.is_none()
            && hit.is_some()
            && let Some(start) = stroke_start(state, &target.terrain, &target.field)
        {
            let after = paint_backed(state, target.index, &target.row);
            let Some(path) = (after.terrain.as_ref())
                .and_then(|t| t.paint.as_ref())
                .map(|p| p.path.clone())
            else {
                return Ok(());
            };
            if after != target.row {
                // The new layer shows from the first refresh: the scene names it already.
                let mut image = (*start).clone();
                image.name = path.clone();
                state
                    .document
                    .level
                    .assets
                    .insert_texture(&path, Arc::new(image));
                let e = entity_at(state.scene(), target.index)?;
                (state.document.scene_mut().set_row(e, after.clone()))
                    .map_err(|_| CommandError(format!("entity {} vanished", target.index)))?;
            }
            self.painting = Some(Painting {
                index: target.index,
                row: target.row.clone(),
                after,
                path,
                place: PaintPlace::new(target.place.origin, target.terrain.size, &start),
                heights: target.place,
                stroke: PaintStroke::new(start, self.brush.colour, erase),
                refreshed: None,
                pending: false,
                fresh: None,
            });
        }
        let Some(p) = &mut self.painting else {
            return Ok(());
        };
        let b = &self.brush;
        if let Some(h) = hit
            && let Some(r) = p.stroke.dab(&p.place, h, b.radius, b.strength, b.falloff)
        {
            p.fresh = Some(p.fresh.map_or(r, |f| f.union(r)));
            p.pending = true;
        }
        if p.pending && p.refreshed.is_none_or(|t| t.elapsed() >= refresh) {
            let mut image = p.stroke.image().clone();
            image.name = p.path.clone();
            let assets = &mut state.document.level.assets;
            assets.insert_texture(&p.path, Arc::new(image));
            // Only the probe faces that see the pixels painted since the last refresh are
            // captured again.
            if let Some(r) = p.fresh.take() {
                let (lo, hi) = p.place.bounds(r);
                let (y0, y1) = (p.heights.origin.y, p.heights.max_height);
                state.document.touch_region(
                    Vec3::new(lo.x, y0 - 1.0, lo.y),
                    Vec3::new(hi.x, y0 + y1 + 1.0, hi.y),
                );
            }
            p.refreshed = Some(Instant::now());
            p.pending = false;
        }
        Ok(())
    }

    /// Lands the paint stroke in progress, if any, as one undo step.
    fn finish_paint(&mut self, state: &mut EditorState) -> Result<(), CommandError> {
        let Some(p) = self.painting.take() else {
            return Ok(());
        };
        // The library and the scene show the stroke; the command starts from before it.
        if p.after != p.row && state.row_at(p.index).as_ref() == Some(&p.after) {
            let e = entity_at(state.scene(), p.index)?;
            (state.document.scene_mut().set_row(e, p.row.clone()))
                .map_err(|_| CommandError(format!("entity {} vanished", p.index)))?;
        }
        if p.after == p.row {
            let assets = &mut state.document.level.assets;
            assets.insert_texture(&p.path, p.stroke.start().clone());
        }
        state.document.touch();
        // Something else changed the entity meanwhile (an undo): the stroke is dropped.
        if state.row_at(p.index).as_ref() != Some(&p.row) {
            return Ok(());
        }
        let Some(change) = p.stroke.change() else {
            return Ok(());
        };
        let cmd = Command::SetPaint {
            index: p.index,
            before: Box::new(p.row),
            after: Box::new(p.after),
            change: Arc::new(change),
        };
        state.apply(cmd, None)?;
        state.history.seal();
        Ok(())
    }

    /// Lands the stroke in progress, if any, as one undo step.
    pub fn finish(&mut self, state: &mut EditorState) -> Result<(), CommandError> {
        self.finish_paint(state)?;
        let Some(s) = self.stroke.take() else {
            return Ok(());
        };
        // The library shows the stroke; the command starts from the heights before it.
        let assets = &mut state.document.level.assets;
        assets.insert_heightfield(&s.terrain, s.start.clone());
        state.document.touch();
        let Some(region) = s.touched else {
            return Ok(());
        };
        // Something else changed the entity meanwhile (an undo): the stroke is dropped.
        if state.row_at(s.index).as_ref() != Some(&s.row) {
            return Ok(());
        }
        if copy_region(&s.start, region) == copy_region(&s.work, region) {
            return Ok(());
        }
        let after = file_backed(state, s.index, &s.row);
        let cmd = Command::SetHeights {
            index: s.index,
            before: Box::new(s.row),
            after: Box::new(after),
            change: Arc::new(HeightChange::patch(&s.start, &s.work, region)),
        };
        state.apply(cmd, None)?;
        state.history.seal();
        Ok(())
    }

    /// The tool's window over the viewport: the brushes, their size, strength (opacity for
    /// paint) and falloff, the height Set height pulls to, the paint colour; or what to
    /// select.
    pub fn panel(&mut self, ctx: &egui::Context, rect: egui::Rect, state: &mut EditorState) {
        let target = selected_terrain(state);
        let mut done = false;
        egui::Area::new(egui::Id::unique("viewport::terrain_tool"))
            .fixed_pos(rect.left_top() + egui::vec2(8.0, 8.0))
            .show(ctx, |ui| {
                egui::Frame::popup(ui.style()).show(ui, |ui| {
                    ui.set_max_width(220.0);
                    ui.label(egui::RichText::new("Terrain tool").strong());
                    let Some(target) = &target else {
                        ui.label("Select a terrain to sculpt.");
                        done = ui.button("Done (T)").clicked();
                        return;
                    };
                    ui.horizontal_wrapped(|ui| {
                        for k in BrushKind::ALL {
                            ui.selectable_value(&mut self.brush.kind, k, k.label());
                        }
                    });
                    let b = &mut self.brush;
                    let painting = b.kind == BrushKind::Paint;
                    if painting {
                        ui.horizontal(|ui| {
                            ui.label("Paint colour");
                            egui::color_picker::color_edit_button_srgb(ui, &mut b.colour)
                                .accessible_name("Paint colour");
                        });
                    }
                    slider(ui, "Brush size", &mut b.radius, 0.25..=64.0, " units");
                    let strength = if painting {
                        "Brush opacity"
                    } else {
                        "Brush strength"
                    };
                    slider(ui, strength, &mut b.strength, 0.01..=1.0, "");
                    slider(ui, "Brush falloff", &mut b.falloff, 0.0..=1.0, "");
                    if b.kind == BrushKind::SetHeight {
                        let top = target.terrain.max_height;
                        slider(ui, "Target height", &mut b.height, 0.0..=top, " units");
                    }
                    let hint = if painting {
                        "Drag on the terrain · Ctrl erases · T to finish"
                    } else {
                        "Drag on the terrain · Ctrl inverts · T to finish"
                    };
                    ui.label(egui::RichText::new(hint).small());
                    done = ui.button("Done (T)").clicked();
                });
            });
        if done {
            // A button click happens with no stroke in progress.
            self.active = false;
            self.hover = None;
        }
    }
}

fn slider(
    ui: &mut Ui,
    name: &str,
    v: &mut f32,
    range: std::ops::RangeInclusive<f32>,
    suffix: &str,
) {
    ui.horizontal(|ui| {
        ui.label(name);
        ui.add(egui::Slider::new(v, range).suffix(suffix))
            .accessible_name(name);
    });
}

/// The brush circle on the terrain's surface around `centre` (and the rim of its full-strength
/// core, fainter), with a dot at the centre.
fn draw_brush(
    painter: &Painter,
    proj: &Projector,
    place: &Placement,
    field: &Heightfield,
    centre: Vec3,
    brush: &Brush,
    invert: bool,
) {
    let colour = match (brush.kind, invert) {
        (BrushKind::Paint, false) => {
            let [r, g, b] = brush.colour;
            Color32::from_rgb(r, g, b)
        }
        (BrushKind::Paint, true) => Color32::from_gray(200),
        (BrushKind::Raise, false) | (BrushKind::Lower, true) => Color32::from_rgb(255, 200, 60),
        (BrushKind::Raise | BrushKind::Lower, _) => Color32::from_rgb(90, 170, 255),
        (BrushKind::Smooth, _) => Color32::from_rgb(240, 240, 240),
        (BrushKind::Flatten | BrushKind::SetHeight, _) => Color32::from_rgb(120, 230, 120),
        (BrushKind::Noise, _) => Color32::from_rgb(230, 120, 230),
    };
    let core = 1.0 - brush.falloff.clamp(0.0, 1.0);
    let rings = [
        (1.0, Line::new(2.0, colour)),
        (core, Line::new(1.0, colour.gamma_multiply(0.5))),
    ];
    for (scale, line) in rings {
        let r = brush.radius * scale;
        if r <= 0.0 {
            continue;
        }
        let points: Vec<_> = (0..=CIRCLE_SEGMENTS)
            .map(|k| {
                let a = k as f32 / CIRCLE_SEGMENTS as f32 * std::f32::consts::TAU;
                let p = centre + Vec3::new(a.cos(), 0.0, a.sin()) * r;
                proj.project(place.surface(field, p))
            })
            .collect();
        for w in points.windows(2) {
            if let (Some(a), Some(b)) = (w[0], w[1]) {
                painter.line_segment([a, b], line);
            }
        }
    }
    if let Some(c) = proj.project(centre) {
        painter.circle_filled(c, 3.0, colour);
    }
}
