//! The renderer: owns the passes and the probe store, and orders one frame
//! (capture → shade → runs → cull → splat → background (+ lines) → visible → present). This
//! is the only file that knows the pass order; what the passes work on is planned in
//! `frame/jobs.rs`.

use std::time::Instant;

use texel_probes::probe_set::Slot;

use crate::context::GpuContext;
pub use crate::error::RenderError;
use crate::gpu_scene::GpuScene;
use crate::input::{Display, FrameInput, SceneInput, Schedule};
use crate::passes::background::BackgroundPass;
use crate::passes::bloom::BloomPass;
use crate::passes::capture::CapturePass;
use crate::passes::cull::{CullPass, DrawArgs, Visit};
use crate::passes::lines::{LineVertex, LinesPass};
use crate::passes::march::{COUNTERS_BYTES, MarchCounts, MarchPass};
use crate::passes::moving::{MovingBinds, MovingPass};
use crate::passes::present::PresentPass;
use crate::passes::runs::RunsPass;
use crate::passes::shade::{ShadeInputs, ShadePass};
use crate::passes::splat::{Fade, KEY_FORMAT, SPLAT_DEPTH_FORMAT, SplatPass};
use crate::passes::sprites::{SpriteBinds, SpritePass};
use crate::passes::terrain_splat::{
    TERRAIN_COUNTS_BYTES, TerrainCounts, TerrainSplatInputs, TerrainSplatPass,
};
use crate::passes::visible::VisiblePass;
use crate::probe_store::ProbeStore;
use crate::stats::{Counters, FrameStats};
use crate::target::{FRAME_FORMAT, OffscreenTarget};
use crate::timing::{self, Stages};
use crate::view::ViewGlobals;
use texel_probes::cube::FaceMask;

mod jobs;
mod switches;
use jobs::{capture_rects, drawn_faces, runs_to_compute, settle_edges, shade_jobs};

/// Screen-sized targets besides the colour target.
pub(crate) struct Screen {
    /// Internal size.
    pub(crate) size: (u32, u32),
    /// Output size.
    pub(crate) output: (u32, u32),
    /// The internal colour target (plain unorm, sRGB-encoded bytes), when the output is
    /// larger or sRGB (else the frame is drawn straight into the caller's target).
    pub(crate) colour: Option<wgpu::TextureView>,
    pub(crate) depth: wgpu::TextureView,
    pub(crate) keys: wgpu::Texture,
    pub(crate) keys_view: wgpu::TextureView,
}

impl Screen {
    fn new(
        ctx: &GpuContext,
        size: (u32, u32),
        output: (u32, u32),
        format: wgpu::TextureFormat,
        palette: bool,
    ) -> Self {
        let tex = |label, format, usage| {
            ctx.device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d {
                    width: size.0,
                    height: size.1,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        use wgpu::TextureUsages as U;
        let depth = tex("frame::depth", SPLAT_DEPTH_FORMAT, U::RENDER_ATTACHMENT);
        let keys = tex(
            "frame::keys",
            KEY_FORMAT,
            U::RENDER_ATTACHMENT | U::TEXTURE_BINDING | U::COPY_SRC,
        );
        // The frame is drawn sRGB-encoded into a plain unorm target (the splats' colours are
        // stored so, and an sRGB target would encode every fragment): into the caller's
        // target when it is plain, of the output size and not mapped to a palette, else into
        // this texture.
        let colour = (size != output || format.is_srgb() || palette).then(|| {
            tex(
                "frame::internal_colour",
                format.remove_srgb_suffix(),
                U::RENDER_ATTACHMENT | U::TEXTURE_BINDING,
            )
            .create_view(&Default::default())
        });
        Screen {
            size,
            output,
            colour,
            depth: depth.create_view(&Default::default()),
            keys_view: keys.create_view(&Default::default()),
            keys,
        }
    }
}

/// Everything long-lived on the GPU side.
pub struct Renderer {
    capture: CapturePass,
    /// What the last frame's captures drew (its counters).
    captured: crate::passes::capture::CaptureWork,
    shade: ShadePass,
    runs: RunsPass,
    /// Stable faces lit in the paper schedule, whose runs are not yet recomputed.
    runs_stale: [FaceMask; 3],
    /// Stable faces lit without the silhouette edges' search (by the paper schedule, or while
    /// marching): our splats light them again before drawing them.
    edges_owed: [FaceMask; 3],
    pub(crate) cull: CullPass,
    splat: SplatPass,
    terrain_splat: TerrainSplatPass,
    /// Whether every splat pipeline has been drawn with once (`SplatPass::warm_up`).
    splat_warm: bool,
    background: BackgroundPass,
    moving: MovingPass,
    sprites: SpritePass,
    /// Built on the first marched frame: splatting never pays for its pipeline.
    march: Option<MarchPass>,
    lines: LinesPass,
    visible: VisiblePass,
    bloom: BloomPass,
    present: PresentPass,
    colour: wgpu::TextureFormat,
    pub(crate) store: ProbeStore,
    pub(crate) scene: Option<GpuScene>,
    view: wgpu::Buffer,
    pub(crate) screen: Option<Screen>,
    offscreen: Option<OffscreenTarget>,
    queries: Option<wgpu::QuerySet>,
    runs_on: bool,
    /// An edit in place forgets only the far faces it reaches (else all of them).
    far_kept: bool,
    /// Whether scenes grid their point lights ([`Renderer::set_light_grid`]).
    light_grid: bool,
    /// Whether the eye draws over far faces when a frame asks for them
    /// ([`FrameInput::far_field`]; off with `TEXEL_NO_FAR_FIELD`, to compare).
    far_field: bool,
    display: Display,
}

impl Renderer {
    /// Builds every pass for views of `colour` format to draw into. A plain format (say
    /// `Rgba8Unorm`) is the fast path: it receives sRGB-encoded bytes, as a PNG or a window
    /// shows them; an sRGB format costs a decode per output pixel (the frame is drawn into
    /// an internal plain texture first). A shader the device rejects is an error here; a
    /// pipeline compiles on its first use (`passes::LazyCompute`), so one the device rejects
    /// fails the first frame that draws with it (`GpuContext::check`). Neither panics.
    pub fn new(ctx: &GpuContext, colour: wgpu::TextureFormat) -> Result<Self, RenderError> {
        let _cache = crate::pipeline_cache::building(&ctx.pipelines);
        let scope = ctx.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let built = Self::build(ctx, colour);
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(RenderError::Pipeline(e.to_string()));
        }
        built
    }

    fn build(ctx: &GpuContext, colour: wgpu::TextureFormat) -> Result<Self, RenderError> {
        let d = &ctx.device;
        let queries = timing::query_set(ctx, "frame::timestamps");
        Ok(Renderer {
            capture: CapturePass::new(d)?,
            captured: Default::default(),
            shade: ShadePass::new(d)?,
            runs: RunsPass::new(d)?,
            runs_stale: [FaceMask::EMPTY; 3],
            edges_owed: [FaceMask::EMPTY; 3],
            cull: CullPass::new(d)?,
            splat: SplatPass::new(d, colour.remove_srgb_suffix())?,
            terrain_splat: TerrainSplatPass::new(d)?,
            splat_warm: false,
            background: BackgroundPass::new(d, colour.remove_srgb_suffix())?,
            moving: MovingPass::new(d, colour.remove_srgb_suffix())?,
            sprites: SpritePass::new(d, colour.remove_srgb_suffix())?,
            march: None,
            lines: LinesPass::new(d, colour.remove_srgb_suffix())?,
            visible: VisiblePass::new(d)?,
            bloom: BloomPass::new(d, colour.remove_srgb_suffix(), true)?,
            present: PresentPass::new(d, colour)?,
            colour,
            store: ProbeStore::new(ctx, 16),
            scene: None,
            view: d.create_buffer(&wgpu::BufferDescriptor {
                label: Some("frame::view"),
                size: size_of::<ViewGlobals>() as u64,
                usage: wgpu::BufferUsages::UNIFORM
                    | wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            screen: None,
            offscreen: None,
            queries,
            runs_on: true,
            far_kept: true,
            light_grid: std::env::var_os("TEXEL_NO_LIGHT_GRID").is_none(),
            far_field: std::env::var_os("TEXEL_NO_FAR_FIELD").is_none(),
            display: Display::Splat,
        })
    }

    /// A renderer for offscreen frames ([`Renderer::render_offscreen`]).
    pub fn headless(ctx: &GpuContext) -> Result<Self, RenderError> {
        Self::new(ctx, FRAME_FORMAT)
    }

    /// Uploads the scene (meshes, materials, textures, lights, shadow BVH), after checking
    /// that the device can hold it (else the scene in use stays). Shared meshes are
    /// instanced unless `TEXEL_NO_INSTANCING` is set, and the point lights are gridded
    /// unless `TEXEL_NO_LIGHT_GRID` is (to measure against).
    pub fn set_scene(&mut self, ctx: &GpuContext, scene: &SceneInput) -> Result<(), RenderError> {
        let instancing = std::env::var_os("TEXEL_NO_INSTANCING").is_none();
        self.set_scene_with(ctx, scene, instancing)
    }

    /// [`Renderer::set_scene`], meshes several objects share instanced, and still casters
    /// of one shape casting through its one tree (`gpu_scene::shapes`), only if
    /// `instancing` (else every copy written out and every caster in the flat tree, to
    /// compare against).
    pub fn set_scene_with(
        &mut self,
        ctx: &GpuContext,
        scene: &SceneInput,
        instancing: bool,
    ) -> Result<(), RenderError> {
        let shapes = crate::gpu_scene::shapes::ShadowShapes::new(scene, instancing);
        crate::validate::scene_shaped(&ctx.device.limits(), scene, &shapes)?;
        let light_grid = self.light_grid;
        let choices = crate::gpu_scene::Upload {
            instancing,
            light_grid,
        };
        let uploaded = GpuScene::upload_shaped(ctx, scene, choices, shapes)
            .map_err(|e| RenderError::SceneTooLarge(e.to_string()))?;
        self.scene = Some(uploaded);
        self.terrain_splat.forget();
        self.capture.forget_far_field();
        Ok(())
    }

    /// The uploaded scene's objects drawn from shared meshes, and the meshes they share.
    pub fn instanced(&self) -> (usize, usize) {
        self.scene.as_ref().map_or((0, 0), |s| s.instanced)
    }

    /// Brings the scene up to `scene` after an edit of the objects `changed` (their
    /// transforms or materials) and of the lights: in place when it can be
    /// ([`GpuScene::update_objects`], returning what it wrote), else by uploading `scene`
    /// again ([`Renderer::set_scene`], returning `None`). The terrain splats' cache is
    /// forgotten, as a new scene's is: an object moved may shadow terrain pixels; of the
    /// eye's far faces, those the edited objects reach into, before or after
    /// ([`crate::far_field`]: a far face draws only what lies wholly beyond its distance).
    pub fn update_scene(
        &mut self,
        ctx: &GpuContext,
        scene: &SceneInput,
        changed: &[usize],
    ) -> Result<Option<crate::gpu_scene::InPlaceEdit>, RenderError> {
        let Some(uploaded) = self.scene.as_mut() else {
            return self.set_scene(ctx, scene).map(|()| None);
        };
        let drawn = |s: &GpuScene| changed.iter().filter_map(|&i| s.drawn_bounds(i)).collect();
        let mut boxes: Vec<_> = drawn(uploaded);
        match uploaded.update_objects(&ctx.queue, scene, changed) {
            Ok(edit) => {
                self.terrain_splat.forget();
                boxes.extend(drawn(uploaded));
                match self.far_kept {
                    true => self.capture.forget_far_faces_reaching(&boxes),
                    false => self.capture.forget_far_field(),
                }
                Ok(Some(edit))
            }
            Err(_) => self.set_scene(ctx, scene).map(|()| None),
        }
    }

    /// GPU bytes the renderer holds for its scene and probes.
    pub fn memory(&self) -> crate::memory::GpuMemory {
        let mut m = (self.scene.as_ref()).map_or_else(Default::default, |s| s.memory());
        m.probes = self.store.bytes() + self.capture.far_field_bytes() + self.background.bytes();
        m
    }

    /// Sets the world-space line segments drawn over every following frame (consecutive
    /// pairs of `lines`), depth-tested against the scene; an empty list draws nothing.
    pub fn set_lines(&mut self, ctx: &GpuContext, lines: &[LineVertex]) {
        self.lines.set(ctx, lines);
    }

    /// How texels reach the pixels: splatted (the default) or marched.
    pub fn set_display(&mut self, display: Display) {
        self.display = display;
    }

    /// The bloom of the frames from the next one on (`None`: none).
    pub fn set_bloom(&mut self, bloom: Option<crate::passes::bloom::BloomInput>) {
        self.bloom.set(bloom);
    }

    /// The palette frames are mapped to from the next one on (`None`: as drawn). Returns
    /// whether dithering turned on or off: texels lit from then on carry (or drop) their
    /// surface's dither rank, so the caller lights the probes afresh.
    pub fn set_palette(&mut self, palette: Option<crate::palette::PaletteInput>) -> bool {
        let dither = palette
            .as_ref()
            .is_some_and(|p| p.dither > 0.0 && !p.colours.is_empty());
        self.present.set_palette(palette);
        std::mem::replace(&mut self.shade.dither, dither) != dither
    }

    /// The probe textures (for tests and debug views).
    pub fn probes(&self) -> &ProbeStore {
        &self.store
    }

    /// The per-pixel texel keys of the last frame (for tests and picking).
    pub fn keys_texture(&self) -> Option<&wgpu::Texture> {
        self.screen.as_ref().map(|s| &s.keys)
    }

    /// Renders `input` into a texture of the renderer's own and reads it back as RGBA8.
    pub fn render_offscreen(
        &mut self,
        ctx: &GpuContext,
        input: &FrameInput,
    ) -> Result<(FrameStats, Vec<u8>), RenderError> {
        let size = (input.size.x, input.size.y);
        // Before the target and its read-back buffer are created.
        crate::validate::frame(input)?;
        crate::validate::device_output(&ctx.device.limits(), input.size)?;
        if self.offscreen.as_ref().is_none_or(|t| t.size != size) {
            let format = self.colour;
            self.offscreen = Some(OffscreenTarget::with_format(ctx, size.0, size.1, format));
        }
        let target = self.offscreen.take().ok_or(RenderError::NoScene)?;
        let result = self.draw(ctx, input, &target.view);
        let pixels = target.read_rgba(ctx);
        self.offscreen = Some(target);
        Ok((result?, pixels?))
    }

    /// Renders one frame into `target` (a view of `input.size`) and returns its cost and work.
    pub fn render(
        &mut self,
        ctx: &GpuContext,
        input: &FrameInput,
        target: &wgpu::TextureView,
    ) -> Result<FrameStats, RenderError> {
        crate::validate::frame(input)?;
        crate::validate::device_texture(&ctx.device.limits(), input.size)?;
        self.draw(ctx, input, target)
    }

    /// [`Renderer::render`] of a validated `input`: the frame's targets and globals, its
    /// probes captured and lit, the texels shown by the display in use ([`Display`]), then
    /// the visible texels, the output and the frame's counts.
    fn draw(
        &mut self,
        ctx: &GpuContext,
        input: &FrameInput,
        target: &wgpu::TextureView,
    ) -> Result<FrameStats, RenderError> {
        let started = Instant::now();
        let globals = self.prepare(ctx, input)?;
        let queries = self.queries.clone();
        let mut stages = Stages::new(ctx, queries.as_ref());
        let lit = self.light(ctx, input, &globals, &mut stages)?;
        let shown = match self.display {
            Display::Splat => {
                self.draw_splatted(ctx, input, target, &globals, &lit, &mut stages)?
            }
            Display::March => self.draw_marched(ctx, input, target, &lit, &mut stages)?,
        };
        let shown = Shown {
            max_n: globals.max_n,
            ..shown
        };
        self.finish(ctx, input, target, started, stages, shown)
    }

    /// Readies the frame: the sprites' state, the probe slots it uses, the animated objects'
    /// poses, the view globals (returned), the passes' capacities, the screen targets and,
    /// for the first marched frame, the march pass.
    fn prepare(
        &mut self,
        ctx: &GpuContext,
        input: &FrameInput,
    ) -> Result<ViewGlobals, RenderError> {
        if let Some(sprites) = self.scene.as_mut().and_then(|s| s.sprites.as_mut()) {
            sprites.update(ctx, &input.sprites);
        }
        let scene = self.scene.as_ref().ok_or(RenderError::NoScene)?;
        for p in [Some(&input.eye), Some(&input.grid), input.previous.as_ref()]
            .into_iter()
            .flatten()
        {
            self.store.ensure(ctx, p.slot, p.face_resolution);
        }
        for c in &input.captures {
            self.store.ensure(ctx, c.slot, c.face_resolution);
        }
        scene.set_poses(&ctx.queue, &input.poses);
        let slot_n = Slot::ALL.map(|s| self.store.slot(s).n);
        let globals = ViewGlobals::new(input, slot_n);
        ctx.queue
            .write_buffer(&self.view, 0, bytemuck::bytes_of(&globals));
        self.cull.ensure_capacity(&ctx.device, globals.max_n);
        self.visible.ensure_capacity(&ctx.device, globals.max_n);
        let output = (input.size.x, input.size.y);
        let size = (input.internal_size.x, input.internal_size.y);
        let palette = self.present.has_palette() || self.bloom.on();
        if (self.screen.as_ref())
            .is_none_or(|s| s.size != size || s.output != output || (palette && s.colour.is_none()))
        {
            self.screen = Some(Screen::new(ctx, size, output, self.colour, palette));
        }
        if self.display == Display::March && self.march.is_none() {
            let colour = self.colour.remove_srgb_suffix();
            self.march = Some(MarchPass::new(&ctx.device, colour)?);
        }
        Ok(globals)
    }

    /// Captures the frame's faces and lights them (then the sprites' texels); returns what
    /// the display draws with besides the probes.
    fn light(
        &mut self,
        ctx: &GpuContext,
        input: &FrameInput,
        globals: &ViewGlobals,
        stages: &mut Stages<'_>,
    ) -> Result<Lit, RenderError> {
        let scene = self.scene.as_ref().ok_or(RenderError::NoScene)?;
        let store = &self.store;
        let moving = (self.moving).prepare(ctx, &self.view, scene, &input.look);
        let fading = input.previous.is_some() && input.fade_t < 1.0;
        let sprites = (self.sprites).prepare(ctx, &self.view, scene, store, &input.look, fading);
        let rects = capture_rects(input, globals, store);
        let mut captured = crate::passes::capture::CaptureWork::default();
        stages.run("capture", |enc| {
            self.capture.eye_band_origin = input.cell_probe().origin;
            self.capture.far = input.far_field.filter(|_| self.far_field);
            self.capture.edited = (input.partial.iter())
                .filter_map(|p| Some((p.slot, p.face, p.edited.clone()?)))
                .collect();
            captured = (self.capture).record(ctx, enc, &input.captures, &rects, store, scene);
        });
        self.captured = captured;
        let mut jobs = shade_jobs(input, &rects);
        // Only splat quads end at edges (texel marching meets the texel planes).
        let edges = input.schedule == Schedule::Ours && self.display == Display::Splat;
        settle_edges(&mut jobs, input, &mut self.edges_owed, edges);
        let inputs = ShadeInputs {
            store,
            scene,
            look: &input.look,
            view: Some(&self.view),
            edges,
        };
        let shaded = stages.run("shade", |enc| self.shade.record(ctx, enc, &jobs, &inputs));
        // Sprite texels after the probes' (refraction reads their lit faces).
        if let Some(binds) = &sprites {
            stages.run("sprite shade", |enc| self.sprites.shade(enc, binds));
        }
        let runs_faces = runs_to_compute(&mut self.runs_stale, input.schedule, shaded);
        Ok(Lit {
            moving,
            sprites,
            runs_faces,
        })
    }

    /// [`Display::Splat`]: the runs, the cull, the terrain splats, then the splats, the
    /// animated objects, the sprites, the background and the lines into `target` (or the
    /// internal colour target).
    fn draw_splatted(
        &mut self,
        ctx: &GpuContext,
        input: &FrameInput,
        target: &wgpu::TextureView,
        globals: &ViewGlobals,
        lit: &Lit,
        stages: &mut Stages<'_>,
    ) -> Result<Shown, RenderError> {
        let scene = self.scene.as_ref().ok_or(RenderError::NoScene)?;
        let screen = self.screen.as_ref().ok_or(RenderError::NoScene)?;
        let draw_target = screen.colour.as_ref().unwrap_or(target);
        let store = &self.store;
        stages.run("runs", |enc| {
            (self.runs).record(ctx, enc, store, lit.runs_faces)
        });
        let drawn = drawn_faces(input, self.runs_on);
        let list = stages.run("cull", |enc| {
            (self.cull).record(ctx, enc, &self.view, store, globals.max_n, &drawn)
        });
        if scene.terrain_count > 0 {
            stages.run("terrain splats", |enc| {
                let inputs = TerrainSplatInputs {
                    view: &self.view,
                    scene,
                    shade_globals: self.shade.globals(),
                    globals_key: self.shade.globals_key(),
                    list,
                    max_n: globals.max_n,
                    haze: input.look.haze > 0.0,
                };
                (self.terrain_splat).record(ctx, enc, &inputs);
            });
        }
        let terrain = self.terrain_splat.records();
        let splat_bind = (self.splat).bind_group(ctx, &self.view, list, terrain);
        let bg_bind = (self.background).bind_group(ctx, &self.view, store.slot(Slot::Eye));
        let fade = match input.previous {
            Some(_) if input.fade_t >= 1.0 => Fade::None,
            Some(_) if !input.grid_complete => Fade::DitherPartial,
            Some(_) => Fade::Dither,
            None => Fade::None,
        };
        let runs =
            (drawn.iter()).any(|(slot, _, visit)| *slot != Slot::Eye && *visit == Visit::List);
        stages.run("splat", |enc| {
            let mut pass = begin_draw(enc, draw_target, screen, true);
            if !self.splat_warm {
                self.splat.warm_up(&mut pass, &splat_bind);
                self.splat_warm = true;
            }
            self.splat.draw(&mut pass, &splat_bind, list, runs, fade);
        });
        if let Some(binds) = &lit.moving {
            stages.run("moving", |enc| {
                let mut pass = begin_draw(enc, draw_target, screen, false);
                self.moving.draw(&mut pass, binds, scene);
            });
        }
        if let Some(binds) = &lit.sprites {
            stages.run("sprites", |enc| {
                let mut pass = begin_draw(enc, draw_target, screen, false);
                self.sprites.draw(&mut pass, binds);
            });
        }
        stages.run("background", |enc| {
            (self.background).strip_ends(enc, &bg_bind, input.eye.draw.bits().count_ones());
            let mut pass = begin_draw(enc, draw_target, screen, false);
            self.background.draw(&mut pass, &bg_bind);
            self.lines.draw(ctx, &mut pass, &self.view);
        });
        let mut copies = vec![(list.args.clone(), size_of::<DrawArgs>() as u64)];
        let terrain_drawn = scene.terrain_count > 0;
        if terrain_drawn {
            copies.push((self.terrain_splat.counts().clone(), TERRAIN_COUNTS_BYTES));
        }
        Ok(Shown {
            copies,
            terrain_drawn,
            pixels_marched: 0,
            max_n: 0,
        })
    }

    /// [`Display::March`]: every pixel marched through the probes, then the animated
    /// objects, the sprites and the lines, in one pass into `target` (or the internal colour
    /// target).
    fn draw_marched(
        &mut self,
        ctx: &GpuContext,
        input: &FrameInput,
        target: &wgpu::TextureView,
        lit: &Lit,
        stages: &mut Stages<'_>,
    ) -> Result<Shown, RenderError> {
        let scene = self.scene.as_ref().ok_or(RenderError::NoScene)?;
        let screen = self.screen.as_ref().ok_or(RenderError::NoScene)?;
        let draw_target = screen.colour.as_ref().unwrap_or(target);
        // The runs are not drawn, but stay owed to the faces just lit.
        for (stale, lit) in self.runs_stale.iter_mut().zip(lit.runs_faces) {
            *stale = stale.union(lit);
        }
        let march = (self.march.as_ref())
            .ok_or_else(|| RenderError::Pipeline("the march pass was not built".into()))?;
        let binds = march.bind_groups(ctx, &self.view, &self.store);
        stages.run("march", |enc| {
            march.clear(enc);
            let mut pass = begin_draw(enc, draw_target, screen, true);
            march.draw(&mut pass, &binds);
            if let Some(binds) = &lit.moving {
                self.moving.draw(&mut pass, binds, scene);
            }
            if let Some(binds) = &lit.sprites {
                self.sprites.draw(&mut pass, binds);
            }
            self.lines.draw(ctx, &mut pass, &self.view);
        });
        let size = (input.internal_size.x, input.internal_size.y);
        Ok(Shown {
            copies: vec![(march.counters.clone(), COUNTERS_BYTES)],
            terrain_drawn: false,
            pixels_marched: u64::from(size.0) * u64::from(size.1),
            max_n: 0,
        })
    }

    /// Ends the frame: the visible texels, the output into `target`, then the frame's work
    /// read back and counted.
    fn finish(
        &mut self,
        ctx: &GpuContext,
        input: &FrameInput,
        target: &wgpu::TextureView,
        started: Instant,
        mut stages: Stages<'_>,
        shown: Shown,
    ) -> Result<FrameStats, RenderError> {
        let screen = self.screen.as_ref().ok_or(RenderError::NoScene)?;
        let output = (input.size.x, input.size.y);
        let size = (input.internal_size.x, input.internal_size.y);
        stages.run("visible", |enc| {
            self.visible.record(ctx, enc, &screen.keys_view, size);
        });
        let mut bloomed = false;
        if let (Some(frame), true) = (&screen.colour, self.bloom.on()) {
            stages.run("bloom", |enc| {
                bloomed = self.bloom.record(ctx, enc, frame, size, 1.0).is_some();
            });
        }
        stages.run("present", |enc| {
            if let Some(frame) = &screen.colour {
                let frame = (self.bloom.output().filter(|_| bloomed)).unwrap_or(frame);
                let (sources, n) = ((frame, &screen.keys_view), shown.max_n);
                self.present
                    .record(ctx, enc, sources, target, size, output, n);
            }
        });
        let mut copies: Vec<(&wgpu::Buffer, u64)> =
            (shown.copies.iter()).map(|(b, n)| (b, *n)).collect();
        // The texels lit, then each slot's queue (the eye's first).
        copies.push((self.shade.texels_lit(), 8));
        copies.push((&self.visible.bits, self.visible.bytes()));
        let timed = stages.finish(&copies)?;
        let (head, mut rest) = timed.readback.split_at(copies[0].1 as usize);
        let (quads_splatted, cull_entries, march) = match self.display {
            Display::Splat => {
                let args: DrawArgs = bytemuck::pod_read_unaligned(head);
                let quads = u64::from(args.instance_count);
                (quads, u64::from(args.entries), MarchCounts::default())
            }
            Display::March => (0, 0, MarchCounts::from_bytes(head)),
        };
        let mut terrain = TerrainCounts::default();
        if shown.terrain_drawn {
            let (counts, after) = rest.split_at(TERRAIN_COUNTS_BYTES as usize);
            terrain = TerrainCounts::from_bytes(counts);
            rest = after;
        }
        let (shaded, bits) = rest.split_at(8);
        let word =
            |i: usize| u64::from(u32::from_le_bytes([0, 1, 2, 3].map(|k| shaded[4 * i + k])));
        let (texels_shaded, eye_texels_shaded) = (word(0), word(1));
        let screen_visible_texels = (bits.chunks_exact(4))
            .map(|w| u64::from(u32::from_le_bytes([w[0], w[1], w[2], w[3]]).count_ones()))
            .sum();
        // A validation error or a lost device anywhere in this frame's work (or in an upload
        // since the last frame) fails the frame with the device's message.
        ctx.check()?;
        let memory = self.memory();
        Ok(FrameStats {
            passes: timed.passes,
            gpu_timestamps: timed.gpu_timestamps,
            frame_ms: started.elapsed().as_secs_f64() * 1e3,
            counters: Counters {
                faces_captured: input.captures.len() as u32,
                objects_captured: self.captured.ranges,
                triangles_captured: self.captured.triangles,
                eye_faces_captured: self.captured.eye_faces,
                far_faces_captured: self.captured.far_faces,
                eye_objects_captured: self.captured.eye_ranges,
                eye_triangles_captured: self.captured.eye_triangles,
                objects_occluded: self.captured.occluded,
                texels_shaded,
                eye_texels_shaded,
                quads_splatted,
                cull_entries,
                screen_visible_texels,
                pixels_marched: shown.pixels_marched,
                march_steps: march.steps,
                march_fallbacks: march.fallbacks,
                texture_bytes: memory.textures,
                gpu_scene_bytes: memory.scene,
                gpu_bvh_bytes: memory.bvh,
                gpu_probe_bytes: memory.probes,
                terrain_records_made: u64::from(terrain.records_made),
                terrain_pixels_cast: u64::from(terrain.pixels_cast),
                terrain_records_shared: u64::from(terrain.records_shared),
            },
        })
    }
}

/// What the lighting leaves the display: the animated objects' and the sprites' bindings
/// (when the scene has them) and the stable faces whose runs to recompute.
struct Lit {
    /// The moving pass's bindings.
    moving: Option<MovingBinds>,
    /// The sprite passes' bindings.
    sprites: Option<SpriteBinds>,
    /// Per slot, the stable faces whose runs to recompute ([`runs_to_compute`]).
    runs_faces: [FaceMask; 3],
}

/// What a display drew: the buffers of its counts to read back (first the splat list's
/// draw arguments or the march counters, then the terrain splats' counts when
/// `terrain_drawn`), and how many pixels it marched.
struct Shown {
    /// Buffers and byte counts to copy back.
    copies: Vec<(wgpu::Buffer, u64)>,
    /// The terrain splats ran (their counts follow the first copy).
    terrain_drawn: bool,
    /// Pixels marched (0 when splatting).
    pixels_marched: u64,
    /// The faces' side the frame's texel keys are dense over.
    max_n: u32,
}

/// The on-screen render pass: colour and key targets, splat depth. The first pass of a frame
/// (`first`) clears them; later ones load.
fn begin_draw<'e>(
    enc: &'e mut wgpu::CommandEncoder,
    target: &wgpu::TextureView,
    screen: &Screen,
    first: bool,
) -> wgpu::RenderPass<'e> {
    let attach = |view| {
        Some(wgpu::RenderPassColorAttachment {
            view,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: if first {
                    wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT)
                } else {
                    wgpu::LoadOp::Load
                },
                store: wgpu::StoreOp::Store,
            },
        })
    };
    enc.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("frame::draw"),
        color_attachments: &[attach(target), attach(&screen.keys_view)],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: &screen.depth,
            depth_ops: Some(wgpu::Operations {
                // Reversed depth: 0 is the far plane.
                load: if first {
                    wgpu::LoadOp::Clear(0.0)
                } else {
                    wgpu::LoadOp::Load
                },
                store: wgpu::StoreOp::Store,
            }),
            stencil_ops: None,
        }),
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}
