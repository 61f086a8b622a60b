//! The level rendered by a `texel_runtime` session: on eframe's own wgpu device into a
//! texture egui shows ([`GpuView::render`]), or on a device of its own into pixels
//! ([`GpuView::beside`], [`GpuView::render_pixels`]: the editor's render worker). The level
//! is handed to the session again only when the document changed (the session re-plans by
//! itself when the output size changes). The session's
//! animation clock stands still at 0 outside Play, so moving objects stay put while they are
//! edited, and runs from 0 in Play.

use std::sync::Arc;
use std::time::Instant;

use egui::mutex::RwLock;
use glam::UVec2;
use texel_render::context::GpuContext;
use texel_render::frame::Renderer;
use texel_render::input::{Camera, ProbeView, Schedule};
use texel_render::passes::lines::LineVertex;
use texel_render::readback::FrameIds;
use texel_render::stats::FrameStats;
use texel_runtime::frame_plan::{RowEdit, level_palettes};
use texel_runtime::load::LoadedLevel;
use texel_runtime::session::{DrawnFrame, EditUpdate, FrameRequest, Session, SessionError};

/// The viewport texture's format: the renderer's own frame format, plain 8-bit holding its
/// sRGB-encoded colours as they are. egui samples it so: its shader takes a texture's values
/// as gamma-encoded (egui-wgpu's `egui.wgsl`, `tex_gamma`), as `texel-run play` presents
/// them. Sampled through an sRGB view, each colour was decoded once more and the view showed
/// the level darker than the game (sky 195 → 139).
pub const FORMAT: wgpu::TextureFormat = texel_render::target::FRAME_FORMAT;

/// What the last render cost.
#[derive(Debug, Clone, Default)]
pub struct RenderReport {
    /// The renderer's own stats of the last frame.
    pub stats: Option<FrameStats>,
    /// Wall time of the last `render` call, ms.
    pub frame_ms: f64,
    /// Wall time of taking in the last edit (entities rewritten in place, or the scene
    /// uploaded again), ms; `None` before the first edit. A stroke paces its refreshes by it (`sculpt::refresh_interval`).
    pub upload_ms: Option<f64>,
    /// Wall time of the renderer's start: the session with its pipelines and the first
    /// scene upload, ms. Kept apart from `upload_ms`: it is mostly compiling shaders (about
    /// a second on lavapipe), which no edit repeats, and counted as an upload it held a
    /// stroke begun right after opening a level to one refresh every three seconds.
    pub start_ms: f64,
    /// Internal resolution of the last frame.
    pub size: UVec2,
    /// Scene uploads after edits since the renderer started.
    pub uploads: u64,
    /// Palette changes taken in by mapping colours again (no upload, nothing shaded again)
    /// since the renderer started.
    pub palette_updates: u64,
    /// How the last edit of entities was taken in ([`Session::edit_rows`]; `None`
    /// before one, and after a rebuild or a terrain stroke's region update).
    pub last_edit: Option<EditUpdate>,
}

struct Target {
    /// The view the renderer draws into, and egui samples.
    draw: wgpu::TextureView,
    id: egui::TextureId,
    size: UVec2,
}

/// The GPU side of the viewport.
pub struct GpuView {
    ctx: GpuContext,
    /// The session and the document revision it shows (made on the first render).
    session: Option<(Session, u64)>,
    /// The lines the renderer draws (kept for a session made later).
    lines: Vec<LineVertex>,
    /// Whether captures show texture density (kept for a session made later, and applied
    /// again whenever the session's level is replaced).
    density_view: bool,
    /// Whether the animation clock runs (Play; kept for a session made later).
    animating: bool,
    /// The egui renderer [`GpuView::render`] registers its texture with (`None` for a view
    /// that only renders pixels, [`GpuView::offscreen`]).
    egui: Option<Arc<RwLock<egui_wgpu::Renderer>>>,
    target: Option<Target>,
    /// A box that every change since the session's revision fell in (terrain heights during
    /// a stroke): the next render updates only the probe faces that see it.
    region: Option<(glam::Vec3, glam::Vec3)>,
    /// The entities every change since the session's revision was confined to (a gizmo
    /// drag, an inspector change): the next render takes in those alone.
    entities: Option<Vec<RowEdit>>,
    /// Whether every change since the session's revision was the palette's alone.
    palette: bool,
    /// Whether frames map to the level's alternate palette (kept for a session made later).
    night: bool,
    /// Cost of the last frame.
    pub report: RenderReport,
    /// The probes the last frame drew: eye, the camera cell's grid probe and the other stable one.
    pub probes: Option<LastProbes>,
    /// The viewport height the level's pixel scale is measured on (`None`: each frame's
    /// own); see [`GpuView::set_face_height`].
    face_height: Option<u32>,
}

/// The probes of the last frame, as its `FrameInput` named them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LastProbes {
    /// The eye probe.
    pub eye: ProbeView,
    /// The grid probe of the camera's cell.
    pub grid: ProbeView,
    /// The other stable probe drawn, if any, and what it is: the previous grid probe during
    /// a crossfade, or the next cell's probe filling behind before a crossing.
    pub other: Option<(OtherProbe, ProbeView)>,
}

/// What the second stable probe of a frame is (see [`LastProbes::other`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OtherProbe {
    /// The previous grid probe, during a crossfade.
    Previous,
    /// The next cell's probe, before the crossing.
    Next,
}

impl GpuView {
    /// Builds the renderer on eframe's device.
    pub fn new(rs: &egui_wgpu::RenderState) -> Result<Self, String> {
        // A GPU error on eframe's device becomes the viewport's message, not a panic.
        let ctx = GpuContext::from_parts(
            rs.instance.clone(),
            rs.adapter.clone(),
            rs.device.clone(),
            rs.queue.clone(),
        );
        Ok(Self::on_context(ctx, rs.renderer.clone()))
    }

    /// The renderer on `ctx`, showing its frames through `egui`'s renderer (which must draw
    /// on `ctx`'s device). Views on one context share its compiled pipelines.
    pub fn on_context(ctx: GpuContext, egui: Arc<RwLock<egui_wgpu::Renderer>>) -> Self {
        GpuView {
            ctx,
            session: None,
            lines: Vec::new(),
            density_view: false,
            animating: false,
            egui: Some(egui),
            target: None,
            region: None,
            entities: None,
            palette: false,
            night: false,
            report: RenderReport::default(),
            probes: None,
            face_height: None,
        }
    }

    /// A view rendering with a device of its own, opened on eframe's adapter: the render
    /// worker's, whose frames then queue apart from the window's (a UI frame never waits
    /// behind a viewport frame on one queue). It renders pixels ([`GpuView::render_pixels`]).
    pub fn beside(rs: &egui_wgpu::RenderState) -> Result<Self, String> {
        let (instance, adapter) = (rs.instance.clone(), rs.adapter.clone());
        let ctx = pollster::block_on(GpuContext::on_adapter(instance, adapter))
            .map_err(|e| format!("cannot open a device for the viewport: {e}"))?;
        Ok(Self::offscreen(ctx))
    }

    /// A view on `ctx` that renders pixels only ([`GpuView::render_pixels`]).
    pub fn offscreen(ctx: GpuContext) -> Self {
        GpuView {
            ctx,
            session: None,
            lines: Vec::new(),
            density_view: false,
            animating: false,
            egui: None,
            target: None,
            region: None,
            entities: None,
            palette: false,
            night: false,
            report: RenderReport::default(),
            probes: None,
            face_height: None,
        }
    }

    /// The document revision the session shows, once there is one.
    pub fn session_revision(&self) -> Option<u64> {
        self.session.as_ref().map(|s| s.1)
    }

    /// Tells the next render that every change since [`GpuView::session_revision`] fell in
    /// `region` (or not: `None`), so it can update the probes that see it instead of
    /// rebuilding the session.
    pub fn use_region(&mut self, region: Option<(glam::Vec3, glam::Vec3)>) {
        self.region = region;
    }

    /// Tells the next render that every change since [`GpuView::session_revision`] changed
    /// only the entities at these positions (or not: `None`), so it can take in those alone
    /// ([`Session::update_entities`]) instead of rebuilding the session.
    pub fn use_entities(&mut self, entities: Option<Vec<usize>>) {
        self.entities = entities.map(|e| e.into_iter().map(RowEdit::Set).collect());
    }

    /// Tells the next render that every change since [`GpuView::session_revision`] was
    /// these changes of entities, in order (set, added, removed; or not: `None`), so it can
    /// take in those alone ([`Session::edit_rows`]) instead of rebuilding the session.
    pub fn use_rows(&mut self, edits: Option<Vec<RowEdit>>) {
        self.entities = edits;
    }

    /// Tells the next render whether every change since [`GpuView::session_revision`] was
    /// the level's palette alone, so it maps colours again ([`Session::set_palettes`])
    /// instead of taking the level in.
    pub fn use_palette(&mut self, only: bool) {
        self.palette = only;
    }

    /// Maps frames to the level's alternate palette (`true`) or its own, from the next frame
    /// on (nothing is shaded again); the setting holds for a session made later.
    pub fn set_night(&mut self, on: bool) {
        self.night = on;
        if let Some((session, _)) = &mut self.session {
            session.set_alternate_palette(on);
        }
    }

    /// Renders `level` (at document `revision`) from `camera` at `size` into a texture
    /// registered with egui, and returns it.
    pub fn render(
        &mut self,
        level: &LoadedLevel,
        revision: u64,
        camera: Camera,
        size: UVec2,
        schedule: Schedule,
        dt: f32,
    ) -> Result<egui::TextureId, String> {
        let size = size.max(UVec2::splat(16));
        self.prepare(level, revision, camera, size)?;
        let id = self.ensure_target(size)?;
        let target = self.target.as_ref().ok_or("no target")?.draw.clone();
        let request = FrameRequest {
            camera,
            dt,
            schedule,
            size,
        };
        let t = Instant::now();
        let (session, _) = self.session.as_mut().ok_or("no session")?;
        let frame = (session.draw(&self.ctx, &request, &target)).map_err(|e| e.to_string())?;
        self.finish(&frame, t, size);
        Ok(id)
    }

    /// [`GpuView::render`] offscreen: the frame read back as RGBA8 rows, its colours
    /// sRGB-encoded as the game presents them ([`RenderReport::frame_ms`] counts the read).
    pub fn render_pixels(
        &mut self,
        level: &LoadedLevel,
        revision: u64,
        camera: Camera,
        size: UVec2,
        schedule: Schedule,
        dt: f32,
    ) -> Result<(UVec2, Vec<u8>), String> {
        let size = size.max(UVec2::splat(16));
        self.prepare(level, revision, camera, size)?;
        let request = FrameRequest {
            camera,
            dt,
            schedule,
            size,
        };
        let t = Instant::now();
        let (session, _) = self.session.as_mut().ok_or("no session")?;
        let (frame, pixels) =
            (session.draw_offscreen(&self.ctx, &request)).map_err(|e| e.to_string())?;
        self.finish(&frame, t, size);
        Ok((size, pixels))
    }

    /// Makes the session, or hands it `level` when `revision` is not the one it shows.
    fn prepare(
        &mut self,
        level: &LoadedLevel,
        revision: u64,
        camera: Camera,
        size: UVec2,
    ) -> Result<(), String> {
        let err = |e: SessionError| e.to_string();
        let t = Instant::now();
        match &mut self.session {
            Some((_, r)) if *r == revision => {}
            Some((session, r)) if std::mem::take(&mut self.palette) => {
                session.set_palettes(level_palettes(level));
                *r = revision;
                self.report.palette_updates += 1;
            }
            Some((session, r)) => {
                let edit = match (self.entities.take(), self.region.take()) {
                    (Some(edits), _) => (session.edit_rows(&self.ctx, level, &edits))
                        .map(Some)
                        .map_err(err)?,
                    (None, Some((min, max))) => {
                        session
                            .update_level_region(&self.ctx, level, min, max)
                            .map_err(err)?;
                        None
                    }
                    (None, None) => {
                        session.set_level(&self.ctx, level).map_err(err)?;
                        Some(EditUpdate::Rebuilt)
                    }
                };
                let rebuilt = edit == Some(EditUpdate::Rebuilt);
                self.report.last_edit = edit.filter(|_| !rebuilt);
                // A session planned afresh captures as it did when the view was made.
                if self.density_view && rebuilt {
                    session.set_texture_density_view(true).map_err(err)?;
                }
                *r = revision;
                self.report.upload_ms = Some(t.elapsed().as_secs_f64() * 1e3);
                self.report.uploads += 1;
            }
            None => {
                let fov_y = camera.fov_y;
                let mut session =
                    Session::new(&self.ctx, level, FORMAT, size, fov_y).map_err(err)?;
                session.set_face_height(self.face_height);
                session.renderer_mut().set_lines(&self.ctx, &self.lines);
                session.set_animation_paused(!self.animating);
                session.set_alternate_palette(self.night);
                if self.density_view {
                    session.set_texture_density_view(true).map_err(err)?;
                }
                self.session = Some((session, revision));
                self.report.start_ms = t.elapsed().as_secs_f64() * 1e3;
                self.report.upload_ms = None;
            }
        }
        Ok(())
    }

    /// Records what the frame `frame`, begun at `started`, cost and drew.
    fn finish(&mut self, frame: &DrawnFrame, started: Instant, size: UVec2) {
        self.report.frame_ms = started.elapsed().as_secs_f64() * 1e3;
        let input = &frame.input;
        let other = match (input.filling_ahead, input.previous) {
            (true, _) => Some((OtherProbe::Next, input.grid)),
            (false, p) => p.map(|p| (OtherProbe::Previous, p)),
        };
        self.probes = Some(LastProbes {
            eye: input.eye,
            grid: *input.cell_probe(),
            other,
        });
        self.report.stats = Some(frame.stats.clone());
        self.report.size = size;
    }

    /// The entity id under `pixel` of the last frame (`texel_runtime::frame_plan::entity_id`).
    pub fn pick(&self, pixel: UVec2) -> Result<Option<u32>, String> {
        let Some((session, _)) = &self.session else {
            return Ok(None);
        };
        (session.renderer())
            .pick(&self.ctx, pixel)
            .map_err(|e| e.to_string())
    }

    /// Per pixel of the last frame: entity id and whether the eye probe drew it.
    pub fn frame_ids(&self) -> Result<FrameIds, String> {
        self.renderer()?
            .read_frame_ids(&self.ctx)
            .map_err(|e| e.to_string())
    }

    /// The six lit faces of `view`'s slot, read back and converted to sRGB8 RGBA
    /// (`n × n` texels each, rows top to bottom), with `n`.
    pub fn probe_faces(&self, view: &ProbeView) -> Result<(u32, Vec<Vec<u8>>), String> {
        (self.renderer()?.read_lit_faces(&self.ctx, view.slot)).map_err(|e| e.to_string())
    }

    /// The texture of `slot`, made (or made again) at `size`; a size the device cannot hold
    /// is an error, before wgpu would raise one.
    fn ensure_target(&mut self, size: UVec2) -> Result<egui::TextureId, String> {
        if let Some(t) = &self.target
            && t.size == size
        {
            return Ok(t.id);
        }
        let egui = self
            .egui
            .clone()
            .ok_or("this view renders offscreen only")?;
        let max = self.ctx.device.limits().max_texture_dimension_2d;
        if size.x > max || size.y > max {
            return Err(format!(
                "a {}×{} viewport is larger than the device's textures ({max} pixels)",
                size.x, size.y
            ));
        }
        let texture = self.ctx.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("editor::viewport"),
            size: wgpu::Extent3d {
                width: size.x,
                height: size.y,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        });
        let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
        let mut egui = egui.write();
        let id = match self.target.take() {
            Some(old) => {
                egui.update_egui_texture_from_wgpu_texture(
                    &self.ctx.device,
                    &view,
                    wgpu::FilterMode::Nearest,
                    old.id,
                );
                old.id
            }
            None => {
                egui.register_native_texture(&self.ctx.device, &view, wgpu::FilterMode::Nearest)
            }
        };
        self.target = Some(Target {
            draw: view,
            id,
            size,
        });
        Ok(id)
    }
}

impl GpuView {
    /// The renderer, once a frame was rendered.
    fn renderer(&self) -> Result<&Renderer, String> {
        let (session, _) = self.session.as_ref().ok_or("nothing rendered yet")?;
        Ok(session.renderer())
    }

    /// Sets the world-space lines drawn, depth-tested, into the following frames (the
    /// ground grid); an empty list draws none.
    pub fn set_lines(&mut self, lines: &[LineVertex]) {
        self.lines = lines.to_vec();
        if let Some((session, _)) = &mut self.session {
            session.renderer_mut().set_lines(&self.ctx, lines);
        }
    }

    /// Turns the texel-density debug view on or off: captures then store green where one
    /// texture pixel is one probe texel, blue where textures are magnified, red where
    /// minified, grey untextured. Every probe is captured again; the setting holds for a
    /// session made later and across level edits.
    pub fn set_texture_density_view(&mut self, on: bool) -> Result<(), String> {
        self.density_view = on;
        if let Some((session, _)) = &mut self.session {
            session
                .set_texture_density_view(on)
                .map_err(|e| e.to_string())?;
        }
        Ok(())
    }

    /// Measures the level's pixel scale on a viewport `height` pixels tall (`None`: each
    /// frame's own), for this session and any made later (`Session::set_face_height`).
    pub fn set_face_height(&mut self, height: Option<u32>) {
        self.face_height = height;
        if let Some((session, _)) = &mut self.session {
            session.set_face_height(height);
        }
    }

    /// Starts the animation clock from 0 (`true`, entering Play) or stops it at 0 (leaving
    /// Play: the moving objects stand at their start while edited).
    pub fn set_animating(&mut self, on: bool) {
        self.animating = on;
        if let Some((session, _)) = &mut self.session {
            session.set_animation_time(0.0);
            session.set_animation_paused(!on);
        }
    }

    /// The animation time the next frame poses the moving objects at, once there is a
    /// session (Play's physics moves their colliders to the same poses).
    pub fn animation_time(&self) -> Option<f64> {
        self.session.as_ref().map(|(s, _)| s.animation_time())
    }

    /// Whether the texel-density debug view is on.
    pub fn texture_density_view(&self) -> bool {
        self.density_view
    }

    /// The texture of the last frame, if one was rendered.
    pub fn texture(&self) -> Option<egui::TextureId> {
        self.target.as_ref().map(|t| t.id)
    }

    /// Draws the next frame's moving objects at `t` seconds (Play's physics clock, which the
    /// worker follows so the player rides what is drawn).
    pub fn set_animation_time(&mut self, t: f64) {
        if let Some((session, _)) = &mut self.session {
            session.set_animation_time(t);
        }
    }

    /// Drops the session (after a panic left it in doubt): the next render makes a new one.
    pub fn reset(&mut self) {
        self.session = None;
        self.probes = None;
    }
}
