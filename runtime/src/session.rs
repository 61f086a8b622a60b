//! A level being rendered: the one owner of "frame driver + renderer + scene upload +
//! warm-up + re-plan on a new viewport or level" that `texel-run render`, `texel-run play`,
//! the editor's viewport and the evaluator all use.

use std::sync::Arc;

use glam::UVec2;
use texel_render::context::GpuContext;
use texel_render::frame::{RenderError, Renderer};
use texel_render::input::{Camera, FrameInput, Schedule};
use texel_render::stats::FrameStats;
use texel_scene::PixelScale;
use texel_scene::limits::{FACE_RESOLUTIONS, face_resolution_error};

use crate::frame_plan::{DriverError, FrameDriver, PreparedLevel, RowEdit};
use crate::load::LoadedLevel;

/// Why a session could not draw.
#[derive(Debug, thiserror::Error)]
pub enum SessionError {
    /// The frame could not be planned.
    #[error(transparent)]
    Driver(#[from] DriverError),
    /// The renderer failed.
    #[error(transparent)]
    Render(#[from] RenderError),
}

/// What to draw.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameRequest {
    /// The eye.
    pub camera: Camera,
    /// Seconds since the previous frame.
    pub dt: f32,
    /// Scheduling method.
    pub schedule: Schedule,
    /// Target size in pixels (it may change between frames, e.g. a resized window).
    pub size: UVec2,
}

/// One frame drawn: what it cost and what it was asked to draw (the probes, captures).
#[derive(Debug, Clone)]
pub struct DrawnFrame {
    /// Cost and work.
    pub stats: FrameStats,
    /// The renderer's input of the frame.
    pub input: FrameInput,
}

/// A level on the GPU with its frame driver (which holds the prepared level).
pub struct Session {
    renderer: Renderer,
    driver: FrameDriver,
    /// Frames map to the level's alternate palette ([`Session::swap_palette`]).
    alternate_palette: bool,
    /// The viewport height the level's pixel scale is measured on; the output's when `None`
    /// ([`Session::set_face_height`]).
    face_height: Option<u32>,
}

/// How [`Session::update_entities`] took an edit in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EditUpdate {
    /// The edited entities were extracted alone and rewritten in place on the GPU; the
    /// probe faces that may see the change were marked for capture (how many).
    InPlace {
        /// Faces marked.
        faces_marked: u32,
    },
    /// The entities were extracted alone, but the GPU scene was uploaded again (an entity
    /// added, removed or given other geometry, another mesh, other textures, shadows turned
    /// on or off: see [`texel_render::gpu_scene::NotInPlace`]), every other object where it
    /// was; only the faces that may see the change were marked.
    Uploaded {
        /// Faces marked.
        faces_marked: u32,
    },
    /// The level was planned afresh: prepared and uploaded too ([`Session::set_level`]) when
    /// an entity is a terrain, a sprite or animated, or was added or removed in a level with
    /// sprites or animated objects; rewritten as above when a sun or a probe-grid override
    /// changed.
    Rebuilt,
}

impl Session {
    /// A session drawing `level` into views of `colour` format (a plain format is the
    /// renderer's fast path: see `Renderer::new`), planned for `size` and `fov_y` radians.
    pub fn new(
        ctx: &GpuContext,
        level: &LoadedLevel,
        colour: wgpu::TextureFormat,
        size: UVec2,
        fov_y: f32,
    ) -> Result<Self, SessionError> {
        Self::with_renderer(ctx, level, Renderer::new(ctx, colour)?, size, fov_y)
    }

    /// A session for offscreen frames ([`Session::draw_offscreen`]).
    pub fn headless(
        ctx: &GpuContext,
        level: &LoadedLevel,
        size: UVec2,
        fov_y: f32,
    ) -> Result<Self, SessionError> {
        Self::with_renderer(ctx, level, Renderer::headless(ctx)?, size, fov_y)
    }

    fn with_renderer(
        ctx: &GpuContext,
        level: &LoadedLevel,
        mut renderer: Renderer,
        size: UVec2,
        fov_y: f32,
    ) -> Result<Self, SessionError> {
        let level = Arc::new(PreparedLevel::new(level));
        renderer.set_scene(ctx, level.scene())?;
        // A fresh driver follows: whatever the palette's dithering, nothing is lit yet.
        renderer.set_palette(level.palette(false));
        renderer.set_bloom(level.bloom);
        let driver = FrameDriver::prepared(level, size, fov_y)?;
        Ok(Session {
            renderer,
            driver,
            alternate_palette: false,
            face_height: None,
        })
    }

    /// Measures the level's pixel scale on a viewport `height` pixels tall instead of each
    /// frame's output (`None`: the output's). The editor names its still view's height, so
    /// the smaller frames it draws while the view moves come from the same probes, and
    /// starting or ending a drag captures nothing anew.
    pub fn set_face_height(&mut self, height: Option<u32>) {
        self.face_height = height;
    }

    /// Replaces the level (after an edit): uploads its scene and plans afresh.
    pub fn set_level(&mut self, ctx: &GpuContext, level: &LoadedLevel) -> Result<(), SessionError> {
        let level = Arc::new(PreparedLevel::new(level));
        // Checked and uploaded first: a level the device cannot hold leaves the session as
        // it was.
        self.renderer.set_scene(ctx, level.scene())?;
        self.take_look(&level);
        let driver = self.fresh_driver(level)?;
        self.replace_driver(driver);
        Ok(())
    }

    /// A driver planned afresh for `level` on the current driver's viewport.
    fn fresh_driver(&self, level: Arc<PreparedLevel>) -> Result<FrameDriver, DriverError> {
        let d = &self.driver;
        FrameDriver::prepared_for(level, d.size(), d.face_height(), d.fov_y())
    }

    /// The level's palette (or its alternate, as swapped) and bloom, to the renderer.
    fn take_look(&mut self, level: &PreparedLevel) {
        self.take_palette(level.palette(self.alternate_palette));
        self.renderer.set_bloom(level.bloom);
    }

    /// Hands `palette` to the renderer. Where dithering turned on or off the probes are
    /// lit afresh: lit texels carry their surface's dither rank only while frames dither
    /// (`Renderer::set_palette`).
    fn take_palette(&mut self, palette: Option<texel_render::palette::PaletteInput>) {
        if self.renderer.set_palette(palette) {
            // The level it already plans for: its scheduler was made once, so this is too.
            if let Ok(driver) = self.fresh_driver(self.driver.level().clone()) {
                self.replace_driver(driver);
            }
        }
    }

    /// Swaps between the level's palette and its alternate (day and night); returns whether
    /// frames now map to the alternate, `None` when the level has no alternate.
    pub fn swap_palette(&mut self) -> Option<bool> {
        let level = self.driver.level().clone();
        if level.palettes.len() < 2 {
            return None;
        }
        self.alternate_palette = !self.alternate_palette;
        self.take_palette(level.palette(self.alternate_palette));
        Some(self.alternate_palette)
    }

    /// Replaces the level's palette and its alternate (an edit of the palette, its dither
    /// or its files): only the present pass maps frames differently from the next one on;
    /// nothing is uploaded, captured or shaded again, unless dithering turned on or off.
    pub fn set_palettes(&mut self, palettes: Vec<texel_render::palette::PaletteInput>) {
        self.driver.level_mut().palettes = palettes;
        let level = self.driver.level().clone();
        self.take_palette(level.palette(self.alternate_palette));
    }

    /// Maps frames to the level's alternate palette (`true`: night) or its own; a level
    /// without an alternate keeps its own. Nothing is shaded again, unless one dithers and
    /// the other does not.
    pub fn set_alternate_palette(&mut self, on: bool) {
        if self.alternate_palette != on {
            self.alternate_palette = on;
            let level = self.driver.level().clone();
            self.take_palette(level.palette(on));
        }
    }

    /// Takes in an edit of the entities at `indices` of `level` (which is the session's
    /// level but for them: a gizmo drag step, an inspector change, a row reloaded from
    /// disk) at the cost of what changed: [`Session::edit_rows`] with each a
    /// [`RowEdit::Set`].
    pub fn update_entities(
        &mut self,
        ctx: &GpuContext,
        level: &LoadedLevel,
        indices: &[usize],
    ) -> Result<EditUpdate, SessionError> {
        let edits: Vec<RowEdit> = indices.iter().map(|&i| RowEdit::Set(i)).collect();
        self.edit_rows(ctx, level, &edits)
    }

    /// Takes in `edits` of the session's level, in order, whose result is `level` (entities
    /// edited, added, removed: an editor command, a level file reloaded) at the cost of what
    /// changed: each entity touched is extracted alone ([`PreparedLevel::edit_rows`]); one
    /// edited in place has its vertices, record and shadow triangles rewritten on the GPU
    /// with the lights, one removed has its objects blanked in place (nothing drawn or cast,
    /// the later rows' ids rewritten), while one added or given more objects has the scene
    /// uploaded again with every other object where it was; either way only the probe faces
    /// that may see its old or new bounds, their shadows or a changed light's reach are
    /// captured again ([`EditUpdate`] says how it went). What cannot be taken so (a terrain,
    /// a sprite or an animated entity, or one added or removed in a level that has sprites
    /// or animated objects) falls back to [`Session::set_level`]; a sun or a probe-grid
    /// override changed plans afresh.
    ///
    /// Should the scene fail to upload, the session keeps drawing the scene it had while
    /// planning for the new one; call [`Session::set_level`] to recover.
    pub fn edit_rows(
        &mut self,
        ctx: &GpuContext,
        level: &LoadedLevel,
        edits: &[RowEdit],
    ) -> Result<EditUpdate, SessionError> {
        let edit = match self.driver.level_mut().edit_rows(level, edits) {
            Ok(edit) => edit,
            Err(_) => {
                self.set_level(ctx, level)?;
                return Ok(EditUpdate::Rebuilt);
            }
        };
        let scene = self.driver.level().scene();
        let changed = [edit.objects, edit.blanked].concat();
        let in_place = self.renderer.update_scene(ctx, scene, &changed)?.is_some();
        let faces_marked = match edit.area {
            _ if edit.grid_changed => None,
            None => Some(self.driver.level_edited(None)),
            Some(a) if a.region.0.is_finite() && a.region.1.is_finite() => {
                Some(self.driver.level_edited(Some(a)))
            }
            Some(_) => None,
        };
        // A sun changed (it lights everything) or the probe grid did: planned afresh.
        let Some(faces_marked) = faces_marked else {
            self.replan()?;
            return Ok(EditUpdate::Rebuilt);
        };
        Ok(match in_place {
            true => EditUpdate::InPlace { faces_marked },
            false => EditUpdate::Uploaded { faces_marked },
        })
    }

    /// Plans afresh for the same level and viewport (every probe captured again), keeping
    /// the animation clock.
    fn replan(&mut self) -> Result<(), SessionError> {
        let driver = self.fresh_driver(self.driver.level().clone())?;
        self.replace_driver(driver);
        Ok(())
    }

    /// Replaces the level after an edit confined to the box `min..max` (a terrain brush dab,
    /// an object moved): the scene is uploaded again (vertices, textures, shadow BVH), but
    /// only the probe faces that may see the box — or the ground its shadows may fall on,
    /// along each sun — are captured and shaded again; the rest of the probe cache stays.
    /// Returns the number of faces marked for capture.
    pub fn update_level_region(
        &mut self,
        ctx: &GpuContext,
        level: &LoadedLevel,
        min: glam::Vec3,
        max: glam::Vec3,
    ) -> Result<u32, SessionError> {
        let level = Arc::new(PreparedLevel::new(level));
        self.renderer.set_scene(ctx, level.scene())?;
        self.take_look(&level);
        let (lo, hi) = level.shadow_region(min, max);
        Ok(self.driver.replace_level(level, lo, hi))
    }

    /// Turns the texel-density debug view on or off (see
    /// [`Renderer::set_texture_density_view`]) and plans afresh, so every probe is captured
    /// again in the new mode.
    pub fn set_texture_density_view(&mut self, on: bool) -> Result<(), SessionError> {
        self.renderer.set_texture_density_view(on);
        self.replan()
    }

    /// Renders `request` once offscreen with a throwaway driver, so shaders are compiled and
    /// targets allocated before the first measured frame, and the session's own driver still
    /// starts from nothing.
    pub fn warm_up(
        &mut self,
        ctx: &GpuContext,
        request: &FrameRequest,
    ) -> Result<(), SessionError> {
        let fov_y = request.camera.fov_y;
        let level = self.driver.level().clone();
        let mut warm = FrameDriver::prepared(level, request.size, fov_y)?;
        let input = warm.frame(request.camera, request.dt, request.schedule)?;
        self.renderer.render_offscreen(ctx, &input)?;
        Ok(())
    }

    /// Plans `request`. A new size keeps the probes where the face resolution and grid stay
    /// as planned ([`FrameDriver::resize`]); a new field of view, or a size that changes the
    /// face resolution, plans afresh.
    fn plan(&mut self, request: &FrameRequest) -> Result<FrameInput, SessionError> {
        let fov_y = request.camera.fov_y;
        let face_height = self.face_height.unwrap_or(request.size.y);
        let d = &self.driver;
        if (request.size, face_height, fov_y) != (d.size(), d.face_height(), d.fov_y()) {
            let kept = fov_y == d.fov_y() && self.driver.resize(request.size, face_height);
            if !kept {
                let level = self.driver.level().clone();
                let driver = FrameDriver::prepared_for(level, request.size, face_height, fov_y)?;
                self.replace_driver(driver);
            }
        }
        Ok((self.driver).frame(request.camera, request.dt, request.schedule)?)
    }

    /// Draws `request` into `target`, a view of `request.size` pixels.
    pub fn draw(
        &mut self,
        ctx: &GpuContext,
        request: &FrameRequest,
        target: &wgpu::TextureView,
    ) -> Result<DrawnFrame, SessionError> {
        let input = self.plan(request)?;
        let stats = self.renderer.render(ctx, &input, target)?;
        Ok(DrawnFrame { stats, input })
    }

    /// Draws `request` offscreen and reads it back as RGBA8 (sRGB-encoded bytes).
    pub fn draw_offscreen(
        &mut self,
        ctx: &GpuContext,
        request: &FrameRequest,
    ) -> Result<(DrawnFrame, Vec<u8>), SessionError> {
        let input = self.plan(request)?;
        let (stats, pixels) = self.renderer.render_offscreen(ctx, &input)?;
        Ok((DrawnFrame { stats, input }, pixels))
    }

    /// Takes `driver` in place of the current one, keeping the animation clock.
    fn replace_driver(&mut self, mut driver: FrameDriver) {
        driver.keep_clock(&self.driver);
        self.driver = driver;
    }

    /// Animation time of the next frame, seconds: where the animated objects will be drawn
    /// (physics moves their colliders to the same poses).
    pub fn animation_time(&self) -> f64 {
        self.driver.time()
    }

    /// Sets the animation time of the next frame (see [`FrameDriver::set_time`]).
    pub fn set_animation_time(&mut self, t: f64) {
        self.driver.set_time(t);
    }

    /// Stops or restarts the animation clock (the editor keeps it stopped outside Play, so
    /// objects stand at their transforms while being edited).
    pub fn set_animation_paused(&mut self, paused: bool) {
        self.driver.set_paused(paused);
    }

    /// The camera at the level's player start, with the session's field of view.
    pub fn start_camera(&self) -> Camera {
        self.driver.start_camera()
    }

    /// The scene the renderer holds.
    pub fn scene(&self) -> &texel_render::input::SceneInput {
        self.driver.scene_input()
    }

    /// The renderer (picking, read-backs, debug data of the last frame).
    pub fn renderer(&self) -> &Renderer {
        &self.renderer
    }

    /// The renderer, to change its options.
    pub fn renderer_mut(&mut self) -> &mut Renderer {
        &mut self.renderer
    }
}

pub use crate::frame_plan::shadow_extended;

/// Makes `level` use faces of `n` texels (a command line's `--face-res`), checked against
/// the engine's range.
pub fn set_face_resolution(level: &mut LoadedLevel, n: u32) -> Result<(), String> {
    if !FACE_RESOLUTIONS.contains(&n) {
        return Err(face_resolution_error("face resolution", n));
    }
    level.scene.settings.pixel_scale = PixelScale::FaceResolution(n);
    Ok(())
}
