//! The steps of one viewport frame that [`Viewport::show`] takes in turn: the keyboard
//! shortcuts, the render's size, the render itself (while frames are left to settle), and
//! painting it with what goes over it.

use egui::{Color32, Key, PointerButton};
use glam::UVec2;
use std::time::Instant;

use super::gizmo::Mode;
use super::{SCALE_MOVING, SCALE_STILL, SETTLE_FRAMES, ViewMode, Viewport, overlay};
use crate::command::CommandError;
use crate::state::EditorState;

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

    /// The size to render `rect` at (coarser while the view moves or an edit lands), and
    /// whether the document was edited since the last frame; a new revision, camera or size
    /// (or Play) starts the frames that settle the render again.
    pub(super) fn render_size(
        &mut self,
        ctx: &egui::Context,
        rect: egui::Rect,
        state: &EditorState,
    ) -> (UVec2, bool) {
        // An edit (a gizmo or inspector drag, or a single change) renders its first frame
        // cheaply too: the scene upload and new probes then cost less, and the still
        // resolution refines it on the next frame.
        let edited = self.last.is_some_and(|l| l.0 != state.document.revision);
        if edited {
            self.moving = true;
        }
        let ppp = ctx.pixels_per_point();
        let scale = if self.moving {
            SCALE_MOVING
        } else {
            SCALE_STILL
        };
        let size = UVec2::new(
            (rect.width() * ppp * scale).max(16.0) as u32,
            (rect.height() * ppp * scale).max(16.0) as u32,
        );
        self.still_height = (rect.height() * ppp * SCALE_STILL).max(16.0) as u32;
        let key = (state.document.revision, self.camera, size);
        let changed = self.last != Some(key) || self.playing();
        if changed {
            self.settle = SETTLE_FRAMES;
            self.last = Some(key);
        }
        (size, edited)
    }

    /// Renders the level through `camera` at `size` while frames are left to settle, after
    /// bringing the ground grid (not in Play) and the texel-density view up to date; an
    /// edit's first frame is timed. Returns whether a frame was rendered.
    pub(super) fn render(
        &mut self,
        ctx: &egui::Context,
        state: &EditorState,
        camera: texel_render::input::Camera,
        size: UVec2,
        dt: f32,
        edited: bool,
    ) -> bool {
        // The ground grid is drawn by the renderer, hidden by the scene; not in Play.
        let grid = !self.playing();
        let Some(gpu) = &mut self.gpu else {
            return false;
        };
        if self.grid_lines != Some(grid) {
            let lines = if grid {
                overlay::grid_lines()
            } else {
                Vec::new()
            };
            gpu.set_lines(&lines);
            self.grid_lines = Some(grid);
            self.settle = SETTLE_FRAMES;
        }
        let density = self.debug.flags.texel_density;
        if gpu.texture_density_view() != density {
            if let Err(e) = gpu.set_texture_density_view(density) {
                self.error = Some(e);
            }
            self.settle = SETTLE_FRAMES;
        }
        let rendered = self.settle > 0;
        if rendered {
            let t = Instant::now();
            let since = gpu.session_revision();
            gpu.use_region(since.and_then(|r| state.document.region_since(r)));
            gpu.use_entities(since.and_then(|r| state.document.entities_since(r)));
            let r = gpu.render(
                &state.document.level,
                state.document.revision,
                camera,
                size,
                self.schedule,
                dt,
            );
            self.error = r.err();
            if edited {
                self.edit_stall_ms = t.elapsed().as_secs_f64() * 1e3;
            }
            self.settle -= 1;
            ctx.request_repaint();
        }
        rendered
    }

    /// Paints the last render into `rect` (and lets the debug views read this frame's
    /// counters), or says why there is none: no GPU renderer, or the render's error.
    pub(super) fn paint_render(
        &mut self,
        ctx: &egui::Context,
        painter: &egui::Painter,
        rect: egui::Rect,
        rendered: bool,
    ) {
        if let Some(gpu) = &mut self.gpu {
            if self.error.is_none()
                && let Some(id) = gpu.texture()
            {
                painter.image(
                    id,
                    rect,
                    egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0)),
                    Color32::WHITE,
                );
            }
            if self.error.is_none() {
                self.debug
                    .update(ctx, gpu, rendered, rendered && self.settle == 0);
            }
        } else {
            painter.text(
                rect.center(),
                egui::Align2::CENTER_CENTER,
                "no GPU renderer (eframe is not running on wgpu)",
                egui::FontId::proportional(14.0),
                Color32::GRAY,
            );
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
