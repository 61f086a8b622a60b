//! The real frame and reference sources: texel splatting through the runtime's
//! [`FrameDriver`] and the renderer, the baselines through [`BaselineRenderer`], and the
//! reference G-buffer from the baselines' plain raster (or the CPU ray cast).

use glam::UVec2;
use texel_render::baselines::{Baseline, BaselineRenderer, BaselineView};
use texel_render::context::GpuContext;
use texel_render::input::{Camera, Display, Look, SceneInput, Schedule};
use texel_runtime::frame_plan::Animation;
use texel_runtime::load::LoadedLevel;
use texel_runtime::session::{FrameRequest, Session, set_face_resolution};

use crate::metrics::Reference;
use crate::reference::CpuScene;
use crate::runner::{EvalError, FrameSource, Method, RefFrame, ReferenceSource, RenderedFrame};

fn render_err(e: impl std::fmt::Display) -> EvalError {
    EvalError::Render(e.to_string())
}

/// Sets the level's default grid to `face_res` texels per face edge.
pub fn set_face_res(level: &mut LoadedLevel, face_res: u32) -> Result<(), EvalError> {
    set_face_resolution(level, face_res).map_err(EvalError::Render)
}

/// The level's look (sky, ambient light, bands, haze), as every method draws it.
pub fn level_look(level: &LoadedLevel) -> Look {
    texel_runtime::frame_plan::level_look(&level.scene)
}

/// Texel splatting with our schedule or the paper's, or texel marching over our schedule's
/// probes.
pub struct SplatSource<'a> {
    ctx: &'a GpuContext,
    session: Session,
    size: UVec2,
    schedule: Schedule,
}

impl<'a> SplatSource<'a> {
    /// A splat renderer for `level` (already at its face resolution) on a `size` output.
    pub fn new(
        ctx: &'a GpuContext,
        level: &LoadedLevel,
        size: UVec2,
        fov_y: f32,
        (schedule, display): (Schedule, Display),
        warm_up: &Camera,
    ) -> Result<Self, EvalError> {
        let mut session = Session::headless(ctx, level, size, fov_y).map_err(render_err)?;
        session.renderer_mut().set_display(display);
        let request = FrameRequest {
            camera: *warm_up,
            dt: 1.0 / 30.0,
            schedule,
            size,
        };
        session.warm_up(ctx, &request).map_err(render_err)?;
        Ok(SplatSource {
            ctx,
            session,
            size,
            schedule,
        })
    }

    /// Turns the sprites toward `facing` (the probes by default).
    pub fn with_sprite_facing(mut self, facing: texel_render::input::SpriteFacing) -> Self {
        self.session.renderer_mut().set_sprite_facing(facing);
        self
    }
}

impl FrameSource for SplatSource<'_> {
    fn render(&mut self, _i: u32, camera: &Camera, dt: f32) -> Result<RenderedFrame, EvalError> {
        let request = FrameRequest {
            camera: *camera,
            dt,
            schedule: self.schedule,
            size: self.size,
        };
        let (frame, pixels) = (self.session)
            .draw_offscreen(self.ctx, &request)
            .map_err(render_err)?;
        let renderer = self.session.renderer();
        let ids = renderer.read_frame_ids(self.ctx).map_err(render_err)?;
        Ok(RenderedFrame {
            stats: frame.stats,
            pixels,
            ids: ids.entity,
            from_eye: Some(ids.from_eye),
            crossfading: frame.input.previous.is_some(),
        })
    }
}

/// One of the baseline methods.
pub struct BaselineSource<'a> {
    ctx: &'a GpuContext,
    renderer: BaselineRenderer,
    method: Baseline,
    size: UVec2,
    face_res: u32,
    look: Look,
    /// The moving objects and the time of the next frame.
    animation: Animation,
    time: f64,
}

impl<'a> BaselineSource<'a> {
    /// Blooms the frames from the next one on (`None`: none).
    pub fn set_bloom(&mut self, bloom: Option<texel_render::passes::bloom::BloomInput>) {
        self.renderer.set_bloom(bloom);
    }

    /// Maps the frames to `palette` from the next one on (`None`: as shaded).
    pub fn set_palette(&mut self, palette: Option<&texel_render::palette::PaletteInput>) {
        self.renderer.set_palette(self.ctx, palette);
    }

    /// A baseline renderer for `scene` (its moving objects posed by `animation`), comparing
    /// against splats of `face_res`.
    pub fn new(
        ctx: &'a GpuContext,
        (scene, animation): (&SceneInput, &Animation),
        method: Baseline,
        size: UVec2,
        face_res: u32,
        look: Look,
        warm_up: &Camera,
    ) -> Result<Self, EvalError> {
        let mut renderer = BaselineRenderer::new(ctx).map_err(render_err)?;
        renderer.set_scene(ctx, scene).map_err(render_err)?;
        let mut me = BaselineSource {
            ctx,
            renderer,
            method,
            size,
            face_res,
            look,
            animation: animation.clone(),
            time: 0.0,
        };
        me.render(0, warm_up, 0.0)?;
        me.time = 0.0;
        Ok(me)
    }
}

impl FrameSource for BaselineSource<'_> {
    fn render(&mut self, _i: u32, camera: &Camera, dt: f32) -> Result<RenderedFrame, EvalError> {
        let poses = self.animation.poses(self.time);
        self.renderer.set_poses(self.ctx, &poses);
        let sprites = self.animation.sprite_states(self.time);
        self.renderer.set_sprites(self.ctx, &sprites);
        self.time = Animation::next_time(self.time, dt);
        let view = BaselineView {
            camera: *camera,
            size: self.size,
            face_res: self.face_res,
            look: self.look,
        };
        let f = self
            .renderer
            .render(self.ctx, self.method, &view)
            .map_err(render_err)?;
        Ok(RenderedFrame {
            stats: f.stats,
            pixels: f.pixels,
            ids: f.ids,
            from_eye: None,
            crossfading: false,
        })
    }
}

/// The baseline of `method`, or `None` for the splat methods.
pub fn baseline_of(method: Method) -> Option<Baseline> {
    match method {
        Method::Raster => Some(Baseline::Raster),
        Method::Naive => Some(Baseline::Naive),
        Method::Snap => Some(Baseline::Snap),
        Method::Cubemap => Some(Baseline::Cubemap),
        Method::SplatPaper | Method::Splat | Method::March | Method::SplatFacing => None,
    }
}

/// Reference G-buffers from the baselines' plain full-resolution raster.
pub struct GpuReference<'a> {
    ctx: &'a GpuContext,
    renderer: BaselineRenderer,
}

impl<'a> GpuReference<'a> {
    /// A reference renderer for `scene`.
    pub fn new(ctx: &'a GpuContext, scene: &SceneInput) -> Result<Self, EvalError> {
        let mut renderer = BaselineRenderer::new(ctx).map_err(render_err)?;
        renderer.set_scene(ctx, scene).map_err(render_err)?;
        Ok(GpuReference { ctx, renderer })
    }
}

impl ReferenceSource for GpuReference<'_> {
    fn reference(
        &mut self,
        camera: &Camera,
        size: UVec2,
        frame: &RefFrame<'_>,
    ) -> Result<Reference, EvalError> {
        self.renderer.set_poses(self.ctx, frame.poses);
        self.renderer.set_sprites(self.ctx, frame.sprites);
        let g = self
            .renderer
            .reference_gbuffer(self.ctx, camera, size, frame.sprite_eye)
            .map_err(render_err)?;
        Ok(Reference {
            size: g.size,
            world: g.world,
            id: g.id,
            poses: Vec::new(),
            sprites: Vec::new(),
        })
    }
}

impl ReferenceSource for CpuScene {
    fn reference(
        &mut self,
        camera: &Camera,
        size: UVec2,
        frame: &RefFrame<'_>,
    ) -> Result<Reference, EvalError> {
        if self.has_sprites() {
            return Err(EvalError::Input(
                "the CPU reference draws no sprites; this level has sprites (use --reference gpu)"
                    .into(),
            ));
        }
        if !frame.poses.is_empty() {
            return Err(EvalError::Input(
                "the CPU reference draws still scenes only; this level has moving objects \
                 (use --reference gpu)"
                    .into(),
            ));
        }
        Ok(self.gbuffer(camera, size))
    }
}
