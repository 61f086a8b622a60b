//! The steps of one viewport frame that [`Viewport::show`] takes in turn: the keyboard
//! shortcuts, the newest frame from the render worker, the size to ask for, the request
//! handed to the worker, and painting the shown frame with what goes over it.

use egui::{Color32, Key, PointerButton};
use glam::UVec2;
use std::time::Instant;
use texel_render::input::Camera;

use super::gizmo::Mode;
use super::picture::Picture;
use super::play::PlayPhysics;
use super::worker::{LevelSnapshot, Request, View};
use super::{SCALE_MOVING, SCALE_STILL, ViewMode, Viewport, reproject};
use crate::command::CommandError;
use crate::state::EditorState;

/// The depth Play's frames are re-projected at, units: about where the walls and floor the
/// player walks past are.
const PLAY_DEPTH: f32 = 6.0;

impl Viewport {
    /// The viewport's keys outside Play (and while no text field takes the keyboard): W, E,
    /// R pick the gizmo, F focuses the selection, 5 toggles orthographic, T the terrain tool.
    pub(super) fn shortcuts(
        &mut self,
        ui: &egui::Ui,
        state: &mut EditorState,
    ) -> Result<(), CommandError> {
        ui.input(|i| {
            if i.key_pressed(Key::W) && !i.pointer.button_down(PointerButton::Secondary) {
                self.gizmo = Mode::Translate;
            }
            if i.key_pressed(Key::E) && !i.pointer.button_down(PointerButton::Secondary) {
                self.gizmo = Mode::Rotate;
            }
            if i.key_pressed(Key::R) {
                self.gizmo = Mode::Scale;
            }
            if i.key_pressed(Key::F) {
                self.focus_selection(state);
            }
            // 5 on the number row or the keypad (egui names both Num5), as numpad 5 in
            // Blender.
            if i.key_pressed(Key::Num5) && i.modifiers.is_none() {
                self.toggle_ortho();
            }
        });
        if ui.input(|i| i.key_pressed(Key::T)) {
            self.terrain.toggle(state)?;
        }
        Ok(())
    }

    /// Takes the newest frame the worker finished (and its error, and the answer to a
    /// pick); returns whether it is a new one. A frame that shows the oldest edit not yet
    /// shown times it ([`Viewport::edit_stall_ms`]).
    pub(super) fn take_frame(&mut self, ctx: &egui::Context, state: &mut EditorState) -> bool {
        let Some(worker) = &self.worker else {
            return false;
        };
        let (frame, error) = worker.newest();
        if let Some((n, answer)) = worker.picked()
            && let Some((_, how, before)) = self.picking.take_if(|p| p.0 == n)
        {
            match answer {
                // The selection changed while the answer was on its way: it is stale.
                Ok(_) if state.selected() != before => {}
                Ok(id) => {
                    // A locked entity is not picked (a hidden one is not drawn).
                    let hit = id.and_then(texel_runtime::frame_plan::entity_index);
                    state.pick(hit.filter(|i| state.pickable(*i)), how);
                }
                Err(e) => self.pick_error = Some(e),
            }
        }
        self.error = error.or_else(|| self.pick_error.clone());
        let rendered = frame.as_ref().map(|f| f.number) != self.shown.as_ref().map(|f| f.number);
        if let (Some(f), Some((edit, seen))) = (&frame, self.edit_seen)
            && f.document.0 == edit.0
            && f.document.1 >= edit.1
        {
            self.edit_stall_ms = seen.elapsed().as_secs_f64() * 1e3;
            self.edit_seen = None;
        }
        if rendered
            && self.picture_target.is_none()
            && let Some(f) = &frame
        {
            // egui uploads it before painting this UI frame.
            let options = egui::TextureOptions::NEAREST;
            match &mut self.texture {
                Some(t) => t.set(f.image.clone(), options),
                None => self.texture = Some(ctx.load_texture("viewport", f.image.clone(), options)),
            }
        }
        self.shown = frame;
        rendered
    }

    /// The size to render `rect` at: coarser while the view moves or an edit lands, that
    /// is while the shown frame is not of this camera or this revision (not in Play). The
    /// frame of the still view follows at the finer size.
    pub(super) fn render_size(
        &mut self,
        ctx: &egui::Context,
        rect: egui::Rect,
        state: &EditorState,
        camera: &Camera,
    ) -> UVec2 {
        let document = (state.document.id(), state.document.revision);
        let moving = !self.playing()
            && (self.shown.as_ref())
                .is_some_and(|f| f.view.camera != *camera || f.document != document);
        let ppp = ctx.pixels_per_point();
        let scale = if moving { SCALE_MOVING } else { SCALE_STILL };
        self.still_height = (rect.height() * ppp * SCALE_STILL).max(16.0) as u32;
        UVec2::new(
            (rect.width() * ppp * scale).max(16.0) as u32,
            (rect.height() * ppp * scale).max(16.0) as u32,
        )
    }

    /// Hands the worker what this UI frame wants drawn, when that changed since it was last
    /// handed over (every frame in Play): the view, and a snapshot of the document when it
    /// changed and no snapshot waits (else the next UI frame sends it).
    pub(super) fn request_frame(
        &mut self,
        state: &EditorState,
        camera: Camera,
        size: UVec2,
        dt: f32,
    ) {
        let Some(worker) = &self.worker else {
            return;
        };
        let playing = self.playing();
        let flags = self.debug.flags;
        let view = View {
            camera,
            size,
            schedule: self.schedule,
            // The ground grid is drawn by the renderer, hidden by the scene; not in Play.
            grid: !playing,
            density: flags.texel_density,
            eye_pixels: flags.eye_pixels,
            cube_faces: flags.cube_faces,
            playing,
            night: self.night,
            face_height: (!playing).then_some(self.still_height),
        };
        let doc = &state.document;
        let key = (doc.id(), doc.revision);
        // Hiding or showing something sends the whole level again.
        let same_hidden = self.sent_visibility == state.visibility_revision();
        let new_level = self.sent_level.map(|s| (s.0, s.1)) != Some(key) || !same_hidden;
        if new_level && self.sent_level.is_some() && self.edit_seen.is_none() {
            self.edit_seen = Some((key, Instant::now()));
        }
        let level = (new_level && !worker.snapshot_waiting()).then(|| {
            let number = self.sent_level.map_or(0, |s| s.2) + 1;
            let before = (self.sent_level).filter(|s| s.0 == key.0 && same_hidden);
            self.sent_visibility = state.visibility_revision();
            let since = before.and_then(|s| doc.region_since(s.1).map(|r| (s.2, r)));
            let entities = before.and_then(|s| doc.entities_since(s.1).map(|e| (s.2, e)));
            let palette = (before.filter(|s| doc.palette_only_since(s.1))).map(|s| s.2);
            self.sent_level = Some((key.0, key.1, number));
            LevelSnapshot {
                number,
                document: key,
                since,
                entities,
                palette,
                path: doc.level.path.clone(),
                rows: state.render_level(),
                assets: doc.level.assets.clone(),
            }
        });
        if level.is_none() && !playing && self.sent_view == Some(view) {
            return;
        }
        let time = self.physics.as_ref().map_or(0.0, PlayPhysics::time);
        worker.submit(Request {
            view,
            dt,
            time,
            level,
        });
        self.sent_view = Some(view);
    }

    /// Paints the shown frame into `rect` (and lets the debug views take this frame's
    /// data), or says why there is none: no GPU renderer, or the render's error.
    pub(super) fn paint_render(
        &mut self,
        ctx: &egui::Context,
        painter: &egui::Painter,
        rect: egui::Rect,
        camera: &Camera,
        rendered: bool,
    ) {
        // The background only where the frame leaves some: on a software rasterizer every
        // pixel the window paints twice costs (lavapipe spends about 0.1 s of CPU on a
        // 1280×800 window's frame).
        // (The picture's own paint callback draws its background itself.)
        let covered = self.error.is_none()
            && (self.shown.as_ref())
                .is_some_and(|f| f.view.camera == *camera || self.picture_target.is_some());
        if !covered {
            painter.rect_filled(rect, 0.0, Color32::from_rgb(24, 26, 30));
        }
        if self.worker.is_none() {
            painter.text(
                rect.center(),
                egui::Align2::CENTER_CENTER,
                "no GPU renderer (eframe is not running on wgpu)",
                egui::FontId::proportional(14.0),
                Color32::GRAY,
            );
        }
        if let Some(frame) = &self.shown
            && self.error.is_none()
        {
            let depth = match self.mode {
                // The render camera of the orthographic view stands pulled back.
                ViewMode::Edit if self.camera.ortho => {
                    self.camera.distance * (1.0 + crate::camera::ORTHO_PULL_BACK)
                }
                ViewMode::Edit => self.camera.distance,
                ViewMode::Play(_) => PLAY_DEPTH,
            };
            let triangles = reproject::triangles(rect, &frame.view.camera, camera, depth);
            match (self.picture_target, &self.texture) {
                (Some(target), _) => {
                    let picture = Picture {
                        frame: (frame.number, frame.image.clone()),
                        triangles,
                        rect,
                        target,
                    };
                    painter.add(egui_wgpu::Callback::new_paint_callback(rect, picture));
                }
                (None, Some(texture)) => reproject::paint(painter, texture.id(), &triangles),
                (None, None) => {}
            }
            self.debug
                .update(ctx, &**frame, rendered, rendered && frame.settled);
        }
        if let Some(e) = &self.error {
            painter.text(
                rect.left_top() + egui::vec2(8.0, 8.0),
                egui::Align2::LEFT_TOP,
                format!("render error: {e}"),
                egui::FontId::proportional(13.0),
                Color32::from_rgb(255, 120, 120),
            );
        }
    }

    /// Play's banner at the top of `rect`: walking or flying, the keys, and the physics'
    /// note if it has one.
    pub(super) fn paint_play_banner(&self, painter: &egui::Painter, rect: egui::Rect) {
        let how = if self.grabbed {
            "mouse to look"
        } else {
            "drag to look (click to capture the mouse)"
        };
        let mode = match self.mode {
            ViewMode::Play(w) if w.fly => "flying (F to walk)",
            _ => "walking (F to fly)",
        };
        let mut banner =
            format!("PLAYING, {mode} — WASD + {how}, Shift to run, Space to jump, Esc to stop");
        if let Some(note) = self.play_note() {
            banner = format!("{banner}\n{note}");
        }
        painter.text(
            rect.center_top() + egui::vec2(0.0, 8.0),
            egui::Align2::CENTER_TOP,
            banner,
            egui::FontId::proportional(14.0),
            Color32::WHITE,
        );
    }
}
