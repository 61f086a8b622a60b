//! The viewport: the level rendered by `texel_render`, the editor camera (perspective, or
//! orthographic from the View menu or key 5), click-to-select through the renderer's id
//! buffer, the transform gizmo and the overlay; and Play (always perspective), which
//! switches to the game's walking camera from the player start without touching the document:
//! the player collides, falls and rides the moving objects ([`play::PlayPhysics`]), which
//! move only in Play.
//! Debug views of the probes ([`debug`]) paint over the render in both modes. The level is
//! drawn on a thread of its own ([`worker`]); the viewport shows its newest finished frame,
//! re-projected for the camera of the moment ([`reproject`], [`picture`]).

pub mod debug;
pub mod drag;
mod frame;
pub mod gizmo;
pub mod gpu;
pub mod handles;
pub mod overlay;
pub mod picture;
pub mod place;
pub mod play;
pub mod reproject;
pub mod select;
pub mod terrain_tool;
pub mod worker;

use std::sync::Arc;
use std::time::Instant;

use egui::{Color32, Key, PointerButton, Sense, Ui};
use glam::{Vec2, Vec3};
use texel_render::input::Schedule;
use texel_runtime::extract::Viewport as ExtractViewport;
use texel_runtime::first_person::{InputState, WalkCamera};

use crate::camera::{EditorCamera, FOV_Y_DEG, Projector};
use crate::command::CommandError;
use crate::history::MergeKey;
use crate::state::EditorState;
use debug::DebugState;
use drag::Pointer;
use gizmo::{Drag, Mode};
use gpu::{GpuView, RenderReport};
use handles::FaceDrag;
use play::PlayPhysics;
use terrain_tool::TerrainTool;
use worker::{Frame, RenderWorker, View};

/// Internal resolution relative to the panel's physical pixels while the view is still, and
/// while it moves (cheaper frames keep the camera responsive on a CPU rasterizer).
pub const SCALE_STILL: f32 = 0.5;
/// See [`SCALE_STILL`].
pub const SCALE_MOVING: f32 = 0.25;
/// Fly speed of the editor camera, units per second.
const FLY_SPEED: f32 = 6.0;
/// Internal height assumed before the viewport was first drawn (an 800-point panel at
/// [`SCALE_STILL`]).
const DEFAULT_STILL_HEIGHT: u32 = 400;

/// What the viewport is doing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ViewMode {
    /// Editing with the editor camera.
    Edit,
    /// Playing with the game camera.
    Play(WalkCamera),
}

/// The viewport panel's own state.
pub struct Viewport {
    /// The editor camera.
    pub camera: EditorCamera,
    /// Edit or Play.
    pub mode: ViewMode,
    /// Which schedule the renderer uses.
    pub schedule: Schedule,
    /// Gizmo mode.
    pub gizmo: Mode,
    /// Grid, angle and surface snapping, for the session.
    pub snap: crate::snap::Snap,
    /// The thread drawing the level, when eframe runs on wgpu ([`worker`]).
    pub worker: Option<RenderWorker>,
    /// The last render or GPU error.
    pub error: Option<String>,
    /// The frame shown: the newest the worker finished, and its texture.
    pub shown: Option<Arc<Frame>>,
    texture: Option<egui::TextureHandle>,
    /// The format of egui's render target when the picture is drawn by its own paint
    /// callback ([`picture`]; under eframe), else `None` (an egui image: tests).
    pub picture_target: Option<wgpu::TextureFormat>,
    /// Wall time between the last two UI frames, ms (what the person feels while the
    /// window repaints; the viewport's frames are drawn elsewhere, so it no longer holds
    /// one).
    pub ui_frame_ms: f32,
    /// Time the UI thread worked on its last frame, ms: eframe's measure (the UI and its
    /// painting, not waiting for the display), or the UI's own update where there is none.
    pub ui_busy_ms: f32,
    /// UI frames in the last whole second.
    pub ui_fps: u32,
    /// Debug views and what they read back.
    pub debug: DebugState,
    /// Whether the pointer is grabbed (hidden and held) for Play.
    pub grabbed: bool,
    /// Where the viewport was drawn last (screen points).
    pub rect: Option<egui::Rect>,
    /// Wall time from the UI frame that first saw the last edit to the UI frame that first
    /// showed a frame with it (its snapshot, upload and frame on the worker included), ms.
    pub edit_stall_ms: f64,
    /// The terrain tool.
    pub terrain: TerrainTool,
    /// Frames show the level's alternate palette (night: key N, in edit and in Play).
    pub night: bool,
    /// An asset dropped on the viewport this frame, and the point under the pointer where
    /// it lands ([`Viewport::point_under`]); the app places it.
    pub dropped_asset: Option<(crate::assets::AssetDrag, Vec3)>,
    /// The colliders and the player while playing.
    physics: Option<PlayPhysics>,
    /// Internal height of a still frame at the last draw: the face resolution a level's
    /// pixel size gives follows it.
    still_height: u32,
    drag: Option<Drag>,
    /// The selected rows when a gizmo drag of several began.
    drag_rows: Vec<(usize, texel_scene::EntityRow)>,
    /// A box select in progress.
    box_drag: Option<select::BoxDrag>,
    face_drag: Option<FaceDrag>,
    /// Whether the renderer was last given the grid (`None`: never told).
    grab_lost: bool,
    /// What the worker was last handed, and the last level snapshot: document id,
    /// revision and snapshot number.
    sent_view: Option<View>,
    sent_level: Option<(u64, u64, u64)>,
    /// The visibility revision of the last snapshot ([`EditorState::visibility_revision`]).
    sent_visibility: u64,
    /// The oldest edit no frame shows yet: document (id, revision), and when it was seen.
    edit_seen: Option<((u64, u64), Instant)>,
    /// The pick asked of the worker, if one is on its way (and what it does to the
    /// selection), and the last pick's error.
    /// The pick asked, how it selects, and the selection when it was asked (an answer that
    /// comes after the selection changed otherwise, by Ctrl+A say, is dropped).
    picking: Option<(u64, crate::selection::Pick, Vec<usize>)>,
    pick_error: Option<String>,
    /// UI frames counted in the current second, and when it began.
    fps_count: (u32, Option<Instant>),
    /// When the last UI frame began.
    clock: Option<Instant>,
}

impl Default for Viewport {
    fn default() -> Self {
        Viewport {
            camera: EditorCamera::default(),
            mode: ViewMode::Edit,
            schedule: Schedule::Ours,
            gizmo: Mode::Translate,
            snap: crate::snap::Snap::default(),
            worker: None,
            error: None,
            shown: None,
            texture: None,
            picture_target: None,
            ui_frame_ms: 0.0,
            ui_busy_ms: 0.0,
            ui_fps: 0,
            debug: DebugState::default(),
            grabbed: false,
            rect: None,
            edit_stall_ms: 0.0,
            terrain: TerrainTool::default(),
            night: false,
            dropped_asset: None,
            physics: None,
            still_height: DEFAULT_STILL_HEIGHT,
            drag: None,
            drag_rows: Vec::new(),
            box_drag: None,
            face_drag: None,
            grab_lost: false,
            sent_view: None,
            sent_level: None,
            sent_visibility: 0,
            edit_seen: None,
            picking: None,
            pick_error: None,
            fps_count: (0, None),
            clock: None,
        }
    }
}

impl Viewport {
    /// Starts Play from the level's player start: builds the colliders and the player,
    /// and starts the moving objects from time 0.
    pub fn play(&mut self, state: &EditorState) {
        let mut camera = WalkCamera::from_scene(state.scene());
        self.physics = Some(PlayPhysics::new(&state.document, &mut camera));
        self.mode = ViewMode::Play(camera);
        self.grab_lost = false;
    }

    /// Stops Play: drops the colliders and puts the moving objects back at time 0.
    pub fn stop(&mut self) {
        self.mode = ViewMode::Edit;
        self.physics = None;
    }

    /// Why some (or every) object has no collider in Play, when that is so.
    pub fn play_note(&self) -> Option<&str> {
        self.physics.as_ref().and_then(|p| p.note.as_deref())
    }

    /// Switches the render method (the view renders again).
    pub fn set_schedule(&mut self, schedule: Schedule) {
        self.schedule = schedule;
    }

    /// Switches the editor camera between perspective and orthographic (Play's walking
    /// camera is always perspective).
    pub fn toggle_ortho(&mut self) {
        self.camera.ortho = !self.camera.ortho;
    }

    /// Whether Play is on.
    pub fn playing(&self) -> bool {
        matches!(self.mode, ViewMode::Play(_))
    }

    /// The camera the viewport renders from: the editor camera (perspective or orthographic)
    /// while editing, the walking camera (always perspective) in Play.
    pub fn render_camera(&self) -> texel_render::input::Camera {
        match self.mode {
            ViewMode::Edit => self.camera.camera(),
            ViewMode::Play(w) => w.camera(FOV_Y_DEG.to_radians()),
        }
    }

    /// Looks at the selection: the selected entity, or the centre of several from far
    /// enough to take them in.
    pub fn focus_selection(&mut self, state: &EditorState) {
        let rows = state.selected_rows();
        let Some(c) = select::centre(&rows) else {
            return;
        };
        let size = (rows.iter().filter_map(|(_, r)| r.transform))
            .map(|t| t.scale.max_element().max(1.0) * 4.0 + 2.0 * (t.translation - c).length())
            .fold(4.0, f32::max);
        self.camera.focus(c, size);
    }

    /// Where something added "at the view's focus" goes: where the view's centre line meets
    /// the ground (y = 0) within 500 units, else the point the camera orbits.
    pub fn ground_focus(&self) -> Vec3 {
        let (eye, forward) = (self.camera.eye, self.camera.forward());
        if forward.y < -1e-3 {
            let t = -eye.y / forward.y;
            if (0.0..=500.0).contains(&t) {
                return eye + forward * t;
            }
        }
        eye + forward * self.camera.distance
    }

    /// The viewport as the level's face resolution sees it: the internal height of a still
    /// frame and the editor camera's field of view.
    pub fn extract_viewport(&self) -> ExtractViewport {
        ExtractViewport {
            height: self.still_height,
            fov_y: FOV_Y_DEG.to_radians(),
        }
    }

    /// Moves the editor camera to see the selected entity's texture 1:1: perpendicular to
    /// its face that most faces the camera, from the 1:1 distance with the level's face
    /// resolution on this viewport ([`crate::pixel::frame_one_to_one`]). An error says why
    /// it cannot (nothing selected, no loaded texture).
    pub fn frame_one_to_one(&mut self, state: &EditorState) -> Result<(), String> {
        let (_, row) = state.selected_row().ok_or("nothing is selected")?;
        let level = &state.document.level;
        let view = self.extract_viewport();
        let settings = level.scene.settings;
        crate::pixel::frame_one_to_one(&mut self.camera, &row, &settings, &level.assets, view)?;
        Ok(())
    }

    /// Draws the viewport into the remaining space of `ui`. A command of the gizmo or the
    /// face handles that fails is returned, for the caller to show.
    pub fn show(&mut self, ui: &mut Ui, state: &mut EditorState) -> Result<(), CommandError> {
        self.count_frame();
        // egui's frame time: the wall clock's under eframe, the harness's fixed step in tests,
        // so Play's physics and moving objects run alike in both.
        let dt = ui.input(|i| i.unstable_dt);
        let playing = self.playing();
        ui.add_enabled_ui(!playing, |ui| {
            ui.horizontal(|ui| crate::snap::bar(ui, &mut self.snap))
        });
        let (rect, response) = ui.allocate_exact_size(ui.available_size(), Sense::click_and_drag());
        self.rect = Some(rect);
        self.asset_drop(ui, &response, rect, state);
        let typing = ui.ctx().egui_wants_keyboard_input();
        self.handle_camera(ui, &response, dt, typing, state);
        self.update_grab(ui.ctx(), &response);
        if !typing && !self.playing() {
            self.shortcuts(ui, state)?;
        }
        let camera = self.render_camera();
        let painter = ui.painter_at(rect);
        let rendered = self.take_frame(ui.ctx(), state);
        let size = self.render_size(ui.ctx(), rect, state, &camera);
        self.request_frame(state, camera, size, dt);
        self.paint_render(ui.ctx(), &painter, rect, &camera, rendered);
        let proj = Projector::new(&camera, rect);
        let extract_view = ExtractViewport {
            height: size.y,
            fov_y: camera.fov_y,
        };
        let probes = self.shown.as_ref().and_then(|f| f.probes);
        self.debug.paint(
            &painter,
            &proj,
            probes.as_ref(),
            state.scene(),
            camera.position,
            extract_view,
        );
        self.debug.faces_window(ui.ctx(), rect);
        self.debug.density_legend(ui.ctx(), rect);
        if self.playing() {
            self.paint_play_banner(&painter, rect);
            return Ok(());
        }
        if self.camera.ortho {
            painter.text(
                rect.right_top() + egui::vec2(-8.0, 8.0),
                egui::Align2::RIGHT_TOP,
                "ortho (5)",
                egui::FontId::proportional(14.0),
                Color32::WHITE,
            );
        }
        let flags = state.hidden_and_locked();
        let shown = |i: usize| flags.get(i).is_none_or(|f| !f.0);
        overlay::markers(&painter, &proj, state.scene(), &state.selected(), shown);
        select::paint_selected(&painter, &proj, state);
        // The terrain tool on a selected terrain takes the primary button (no gizmo).
        let sculpting =
            self.terrain.active && crate::terrain_edits::selected_terrain(state).is_some();
        let used = if sculpting {
            self.drag = None;
            self.face_drag = None;
            let upload_ms = self.report().and_then(|r| r.upload_ms);
            let refresh = terrain_tool::refresh_interval(upload_ms);
            self.terrain
                .ui(ui, &response, &painter, &proj, state, refresh)?
        } else {
            self.terrain.finish(state)?;
            let on_face = self.face_handles_ui(ui, &response, &painter, &proj, state)?;
            // A face handle in use takes the drag from the gizmo.
            let on_gizmo = !on_face
                && if state.also_selected.is_empty() {
                    self.gizmo_ui(ui, &response, &painter, &proj, state)?
                } else {
                    self.gizmo_many(ui, &response, &painter, &proj, state)?
                };
            let used = on_face || on_gizmo;
            self.box_select(ui, &response, &painter, &proj, state, used);
            used
        };
        if self.terrain.active {
            self.terrain.panel(ui.ctx(), rect, state);
        }
        if response.clicked() && !used {
            let how = crate::selection::Pick::from_modifiers(
                ui.input(|i| i.modifiers),
                crate::selection::Pick::Add,
            );
            self.select_at(&response, rect, how, state.selected());
        }
        Ok(())
    }

    fn handle_camera(
        &mut self,
        ui: &Ui,
        response: &egui::Response,
        dt: f32,
        typing: bool,
        state: &EditorState,
    ) {
        let (delta, keys, wheel, esc, raw, fly) = ui.input(|i| {
            let keys = InputState {
                forward: i.key_down(Key::W),
                back: i.key_down(Key::S),
                left: i.key_down(Key::A),
                right: i.key_down(Key::D),
                up: i.key_down(Key::E) || i.key_down(Key::Space),
                down: i.key_down(Key::Q),
                run: i.modifiers.shift,
            };
            (
                i.pointer.delta(),
                keys,
                i.smooth_scroll_delta.y,
                i.key_pressed(Key::Escape),
                play::raw_motion(i),
                !typing && i.key_pressed(Key::F),
            )
        });
        let keys = if typing { InputState::default() } else { keys };
        match &mut self.mode {
            ViewMode::Play(walk) => {
                let drag = Vec2::new(delta.x, delta.y);
                let look = play::look(self.grabbed, raw, response.dragged(), drag);
                // The physics keeps the animation clock; the frame asked of the worker
                // poses the moving objects at the time the player rode them.
                match &mut self.physics {
                    Some(p) => {
                        if fly {
                            p.toggle_fly(walk);
                        }
                        p.frame(&state.document, walk, &keys, look, dt);
                    }
                    None => walk.update(&keys, look, dt),
                }
                if esc {
                    self.stop();
                }
                ui.ctx().request_repaint();
            }
            ViewMode::Edit => {
                let looking = response.dragged_by(PointerButton::Secondary);
                if looking {
                    self.camera.look(Vec2::new(delta.x, delta.y));
                    let axis = |p: bool, n: bool| f32::from(u8::from(p)) - f32::from(u8::from(n));
                    let run = if keys.run { 3.0 } else { 1.0 };
                    let local = Vec3::new(
                        axis(keys.right, keys.left),
                        axis(keys.up, keys.down),
                        axis(keys.forward, keys.back),
                    ) * FLY_SPEED
                        * run
                        * dt.min(0.1);
                    self.camera.fly(local);
                    ui.ctx().request_repaint();
                }
                if response.hovered() && wheel != 0.0 {
                    self.camera.zoom(wheel / 50.0);
                }
            }
        }
    }

    /// Takes the pointer while playing, gives it back when Play stops or the window loses
    /// focus (a click in the viewport takes it again).
    fn update_grab(&mut self, ctx: &egui::Context, response: &egui::Response) {
        let focused = ctx.input(|i| i.focused);
        if self.playing() && !focused {
            self.grab_lost = true;
        }
        if self.playing() && self.grab_lost && focused && response.clicked() {
            self.grab_lost = false;
        }
        let want = self.playing() && !self.grab_lost;
        if want != self.grabbed {
            for c in play::grab_commands(want) {
                ctx.send_viewport_cmd(c);
            }
            self.grabbed = want;
        }
    }

    /// The face handles of a selected probe-grid override (alone in the selection); true
    /// when the pointer is on one or a face drag is in progress.
    fn face_handles_ui(
        &mut self,
        ui: &Ui,
        response: &egui::Response,
        painter: &egui::Painter,
        proj: &Projector,
        state: &mut EditorState,
    ) -> Result<bool, CommandError> {
        let alone = state.also_selected.is_empty();
        let Some((index, row)) = state.selected_row().filter(|_| alone) else {
            self.face_drag = None;
            return Ok(false);
        };
        let Some(volume) = row.probe_grid_override.filter(|_| state.pickable(index)) else {
            self.face_drag = None;
            return Ok(false);
        };
        let t = row.transform.unwrap_or_default();
        let hs = handles::handles(proj, &t, &volume);
        let pointer = Pointer::read(ui, response);
        let hit = |p| handles::hit(&hs, p);
        let frame = drag::update(&mut self.face_drag, &pointer, hit, (t, volume));
        handles::draw(painter, &hs, frame.highlight);
        if let Some(d) = frame.dragged {
            let ctrl = ui.input(|i| i.modifiers.ctrl || i.modifiers.command);
            let snap = self.snap.now(ctrl).grid;
            let (start, start_volume) = &d.start;
            let moved = handles::outward(proj, &d);
            let (t2, o2) = handles::resize(start, start_volume, d.handle, moved, snap);
            let mut row = row;
            row.transform = Some(t2);
            row.probe_grid_override = Some(o2);
            state.set_row(index, row, Some(MergeKey::Resize { index }))?;
        }
        Ok(frame.used)
    }

    /// The transform gizmo of the selected entity; true when the pointer is on a handle or
    /// a gizmo drag is in progress.
    fn gizmo_ui(
        &mut self,
        ui: &Ui,
        response: &egui::Response,
        painter: &egui::Painter,
        proj: &Projector,
        state: &mut EditorState,
    ) -> Result<bool, CommandError> {
        let Some((index, row)) = state.selected_row().filter(|(i, _)| state.pickable(*i)) else {
            self.drag = None;
            return Ok(false);
        };
        let Some(t) = row.transform else {
            return Ok(false);
        };
        let Some((o, ends)) = gizmo::handles(proj, t.translation) else {
            return Ok(false);
        };
        let mode = gizmo::mode_for(self.gizmo, &row);
        let pointer = Pointer::read(ui, response);
        let hit = |p| gizmo::hit(o, ends, p);
        let frame = drag::update(&mut self.drag, &pointer, hit, t);
        gizmo::draw(painter, o, ends, mode, frame.highlight);
        if let Some(d) = frame.dragged {
            let world_len = gizmo::world_len(proj, d.start.translation);
            let ctrl = ui.input(|i| i.modifiers.ctrl || i.modifiers.command);
            let snap = self.snap.now(ctrl);
            let (o0, ends0) = gizmo::handles(proj, d.start.translation).unwrap_or((o, ends));
            let next = gizmo::apply(&d, mode, o0, ends0[d.handle], world_len, snap);
            let mut row = row;
            row.transform = Some(next);
            state.set_row(index, row, Some(MergeKey::Gizmo { index }))?;
        }
        Ok(frame.used)
    }

    /// Asks the worker for the entity under the click; the selection follows when the
    /// answer comes ([`Viewport::take_frame`]), from the frame it drew last.
    fn select_at(
        &mut self,
        response: &egui::Response,
        rect: egui::Rect,
        how: crate::selection::Pick,
        selected: Vec<usize>,
    ) {
        let (Some(worker), Some(pos)) = (&self.worker, response.interact_pointer_pos()) else {
            return;
        };
        let uv = (pos - rect.min) / rect.size();
        self.picking = Some((worker.pick(Vec2::new(uv.x, uv.y)), how, selected));
    }

    /// Starts the render worker drawing with `gpu` (`ctx` repaints when a frame is done); a
    /// worker that cannot start becomes the viewport's message.
    pub fn attach(&mut self, gpu: GpuView, ctx: egui::Context) {
        self.shown = None;
        self.sent_view = None;
        self.sent_level = None;
        match RenderWorker::start(gpu, ctx) {
            Ok(w) => self.worker = Some(w),
            Err(e) => self.error = Some(e),
        }
    }

    /// What the shown frame cost, and the renderer's totals.
    pub fn report(&self) -> Option<&RenderReport> {
        self.shown.as_ref().map(|f| &f.report)
    }

    /// Times this UI frame ([`Viewport::ui_frame_ms`]) and counts it into
    /// [`Viewport::ui_fps`].
    fn count_frame(&mut self) {
        let now = Instant::now();
        if let Some(t) = self.clock {
            self.ui_frame_ms = now.duration_since(t).as_secs_f32() * 1e3;
        }
        self.clock = Some(now);
        let (count, since) = &mut self.fps_count;
        *count += 1;
        match since {
            Some(t) if now.duration_since(*t).as_secs_f32() >= 1.0 => {
                let secs = now.duration_since(*t).as_secs_f32();
                self.ui_fps = (*count as f32 / secs).round() as u32;
                (*count, *since) = (0, Some(now));
            }
            Some(_) => {}
            None => *since = Some(now),
        }
    }
}
