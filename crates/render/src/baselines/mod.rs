//! The methods texel splatting is measured against, rendering the same [`SceneInput`] with
//! the same lighting, posterization and outline rule (issue "Measure ourselves"): a plain
//! full-resolution raster (the reference image), a naive low-resolution render upscaled with
//! nearest sampling, the Unity-style screen snap, and a camera-centred cubemap shaded every
//! frame. [`BaselineRenderer::reference_gbuffer`] is the evaluator's ground truth: world
//! position, entity id and depth per pixel of a plain full-resolution raster.
//!
//! Low-resolution methods draw art pixels of the splat's size ([`art_pixel_height`]), so a
//! comparison at one face resolution compares like with like.

pub mod cubemap;
pub mod gbuffer;
pub mod shade;
pub mod snap;
pub mod upscale;

use crate::passes::LazyRender;
use crate::passes::{RenderSpec, render_pipeline};
use std::time::Instant;

use glam::{UVec2, Vec2};

use crate::context::GpuContext;
use crate::error::RenderError;
use crate::gpu_scene::GpuScene;
use crate::input::{Camera, Look, SceneInput};
use crate::passes::bloom::BloomPass;
use crate::passes::capture::CapturePass;
use crate::passes::shade::ShadePass;
use crate::passes::shade::{ShadeInputs, ShadeJob};
use crate::probe_store::ProbeStore;
use crate::stats::{Counters, FrameStats, PassTime};
use crate::target::{OFFSCREEN_FORMAT, OffscreenTarget, read_texture_layer};
use crate::timing::Stages;
use cubemap::{CUBE_SLOT, CubeCamera, CubemapPass};
use gbuffer::{GBufferPass, RasterCamera, SKY_DEPTH, ScreenTargets, Target};
use shade::{Eye, ScreenShadePass};
pub use snap::{art_pixel_height, low_res_size, snap_plan};
use upscale::{Mapping, UpscalePass};

/// A baseline render method.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Baseline {
    /// Full resolution, shaded per pixel, no outlines: the reference image.
    Raster,
    /// A low-resolution render at the art-pixel size, upscaled with nearest sampling.
    Naive,
    /// Naive with the camera snapped to whole texels, a one-texel margin and the sub-texel
    /// remainder restored at full size (the Unity 3D pixel art renderer).
    Snap,
    /// A cubemap around the camera, captured and shaded every frame, sampled per pixel.
    Cubemap,
}

impl Baseline {
    /// Every method, in report order.
    pub const ALL: [Baseline; 4] = [
        Baseline::Raster,
        Baseline::Naive,
        Baseline::Snap,
        Baseline::Cubemap,
    ];

    /// Short lower-case name for reports and file names.
    pub fn name(self) -> &'static str {
        match self {
            Baseline::Raster => "raster",
            Baseline::Naive => "naive",
            Baseline::Snap => "snap",
            Baseline::Cubemap => "cubemap",
        }
    }
}

/// What a baseline frame looks at.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BaselineView {
    /// The camera (perspective or orthographic).
    pub camera: Camera,
    /// Output size in pixels.
    pub size: UVec2,
    /// Face resolution of the splat being compared: sets the art-pixel size of Naive and
    /// Snap and the cubemap's face size.
    pub face_res: u32,
    /// Level look (sky, ambient, bands).
    pub look: Look,
}

/// One rendered baseline frame, read back.
#[derive(Debug, Clone, PartialEq)]
pub struct BaselineFrame {
    /// Per-pass times (GPU timestamps when the adapter has them) and work counts.
    pub stats: FrameStats,
    /// RGBA8 sRGB pixels at the view's size, row-major.
    pub pixels: Vec<u8>,
    /// Entity id shown per output pixel (0 = sky), row-major.
    pub ids: Vec<u32>,
}

/// The evaluator's reference G-buffer: a plain full-resolution raster, read back.
#[derive(Debug, Clone, PartialEq)]
pub struct GBuffer {
    /// Width and height.
    pub size: UVec2,
    /// World position per pixel (meaningless where `id` is 0).
    pub world: Vec<[f32; 3]>,
    /// Entity id per pixel (0 = sky).
    pub id: Vec<u32>,
    /// View-space distance along the view axis; `f32::INFINITY` for sky.
    pub depth: Vec<f32>,
}

/// Entity ids of the output (0 = sky).
pub const OUTPUT_ID_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;

/// The output targets of a baseline frame: sRGB colour and entity ids at the output size.
pub struct Output {
    colour: OffscreenTarget,
    ids: Target,
    size: UVec2,
}

impl Output {
    fn new(ctx: &GpuContext, size: UVec2) -> Self {
        Output {
            colour: OffscreenTarget::new(ctx, size.x, size.y),
            ids: Target::new(
                &ctx.device,
                "baselines::output::ids",
                size,
                OUTPUT_ID_FORMAT,
            ),
            size,
        }
    }

    /// A render pass clearing both targets.
    pub fn begin<'e>(
        &self,
        encoder: &'e mut wgpu::CommandEncoder,
        label: &'static str,
    ) -> wgpu::RenderPass<'e> {
        let attach = |view| {
            Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    store: wgpu::StoreOp::Store,
                },
            })
        };
        encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(label),
            color_attachments: &[attach(&self.colour.view), attach(&self.ids.view)],
            depth_stencil_attachment: None,
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        })
    }
}

/// A fullscreen-triangle pipeline (entry points `vs`, `fs`) writing colour and ids.
pub(crate) fn fullscreen_pipeline(
    device: &wgpu::Device,
    module: &wgpu::ShaderModule,
    layout: &wgpu::BindGroupLayout,
    owner: &str,
) -> LazyRender {
    render_pipeline(
        device,
        RenderSpec {
            owner,
            module,
            vertex: "vs",
            layouts: &[layout],
            vertex_buffers: &[],
            fragment: "fs",
            targets: &[OFFSCREEN_FORMAT, OUTPUT_ID_FORMAT],
            depth: None,
        },
    )
}

/// Renders the baselines. Built once (pipelines, layouts); the scene is uploaded by
/// [`BaselineRenderer::set_scene`]; targets follow the sizes asked for.
pub struct BaselineRenderer {
    gbuffer: GBufferPass,
    shade: ScreenShadePass,
    upscale: UpscalePass,
    bloom: BloomPass,
    capture: CapturePass,
    cube_shade: ShadePass,
    cube: CubemapPass,
    store: ProbeStore,
    scene: Option<GpuScene>,
    /// Screen targets by size, most recently used last (a frame needs one; kept few).
    screens: Vec<ScreenTargets>,
    output: Option<Output>,
    queries: Option<wgpu::QuerySet>,
}

impl BaselineRenderer {
    /// Builds every pipeline. A shader or pipeline the device rejects is an error.
    pub fn new(ctx: &GpuContext) -> Result<Self, RenderError> {
        let _cache = crate::pipeline_cache::building(&ctx.pipelines);
        let scope = ctx.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let d = &ctx.device;
        let built = (|| {
            Ok::<_, RenderError>(BaselineRenderer {
                gbuffer: GBufferPass::new(d)?,
                shade: ScreenShadePass::new(d)?,
                upscale: UpscalePass::new(d)?,
                bloom: BloomPass::new(d, gbuffer::LIT_FORMAT, false)?,
                capture: CapturePass::new(d)?,
                cube_shade: ShadePass::new(d)?,
                cube: CubemapPass::new(d)?,
                store: ProbeStore::new(ctx, 8),
                scene: None,
                screens: Vec::new(),
                output: None,
                queries: crate::timing::query_set(ctx, "baselines::timestamps"),
            })
        })();
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(RenderError::Pipeline(e.to_string()));
        }
        built
    }

    /// Uploads the scene (meshes, materials, textures, lights, shadow BVH), after checking
    /// that the device can hold it (else the scene in use stays).
    pub fn set_scene(&mut self, ctx: &GpuContext, scene: &SceneInput) -> Result<(), RenderError> {
        crate::validate::scene(&ctx.device.limits(), scene)?;
        let uploaded =
            GpuScene::upload(ctx, scene).map_err(|e| RenderError::SceneTooLarge(e.to_string()))?;
        self.scene = Some(uploaded);
        Ok(())
    }

    /// The bloom of the raster, naive and snap frames from the next one on (`None`: none),
    /// on each method's art pixels. The cubemap baseline draws without it.
    pub fn set_bloom(&mut self, bloom: Option<crate::passes::bloom::BloomInput>) {
        self.bloom.set(bloom);
    }

    /// The palette the raster, naive and snap frames are mapped to from the next one on
    /// (`None`: as shaded), dithered by each method's own art pixel. The cubemap baseline
    /// draws without it.
    pub fn set_palette(&self, ctx: &GpuContext, palette: Option<&crate::palette::PaletteInput>) {
        self.upscale.set_palette(&ctx.queue, palette);
    }

    /// Screen targets of `size`, taken out of the cache (give them back with `keep`).
    fn take_screen(&mut self, ctx: &GpuContext, size: UVec2) -> ScreenTargets {
        match self.screens.iter().position(|s| s.size == size) {
            Some(i) => self.screens.remove(i),
            None => ScreenTargets::new(&ctx.device, size),
        }
    }

    fn keep_screen(&mut self, screen: ScreenTargets) {
        self.screens.push(screen);
        if self.screens.len() > 3 {
            self.screens.remove(0);
        }
    }

    /// Applies a frame's sprite changes (moves, animation frames).
    pub fn set_sprites(&mut self, ctx: &GpuContext, states: &[crate::input::SpriteState]) {
        if let Some(sprites) = self.scene.as_mut().and_then(|s| s.sprites.as_mut()) {
            sprites.update(ctx, states);
        }
    }

    /// Moves the scene's animated objects to `poses` for the following renders and
    /// reference G-buffers (the others stay at their base transforms).
    pub fn set_poses(&self, ctx: &GpuContext, poses: &[crate::input::Pose]) {
        if let Some(scene) = &self.scene {
            scene.set_poses(&ctx.queue, poses);
        }
    }

    /// Renders `view` with `method` and reads the image and the per-pixel ids back.
    pub fn render(
        &mut self,
        ctx: &GpuContext,
        method: Baseline,
        view: &BaselineView,
    ) -> Result<BaselineFrame, RenderError> {
        let started = Instant::now();
        validate(ctx, view)?;
        if self.scene.is_none() {
            return Err(RenderError::NoScene);
        }
        if self.output.as_ref().is_none_or(|o| o.size != view.size) {
            self.output = Some(Output::new(ctx, view.size));
        }
        let (passes, gpu_timestamps, mut counters) = match method {
            Baseline::Cubemap => self.record_cubemap(ctx, view)?,
            _ => self.record_screen(ctx, method, view)?,
        };
        let frame_ms = started.elapsed().as_secs_f64() * 1e3;
        counters.texture_bytes = self.scene.as_ref().map_or(0, |s| s.memory().textures);
        let out = self.output.as_ref().ok_or(RenderError::NoScene)?;
        let pixels = out.colour.read_rgba(ctx)?;
        let ids = read_texture_layer(ctx, &out.ids.texture, 0, 4)?;
        ctx.check()?;
        Ok(BaselineFrame {
            stats: FrameStats {
                passes,
                gpu_timestamps,
                frame_ms,
                counters,
            },
            pixels,
            ids: bytemuck::cast_slice::<u8, u32>(&ids).to_vec(),
        })
    }

    /// Raster, Naive and Snap: G-buffer, per-pixel shading, upscale.
    fn record_screen(
        &mut self,
        ctx: &GpuContext,
        method: Baseline,
        view: &BaselineView,
    ) -> Result<(Vec<PassTime>, bool, Counters), RenderError> {
        let cam = &view.camera;
        let size = view.size;
        let low = match method {
            Baseline::Raster => size,
            _ => low_res_size(size, art_pixel_height(view.face_res, cam.fov_y)?),
        };
        let scale = low.as_vec2() / size.as_vec2();
        let (target, view_proj, drawn, offset) = match method {
            Baseline::Snap => {
                let plan = snap_plan(cam, low);
                (plan.target, plan.view_proj, plan.snapped, plan.origin)
            }
            _ => {
                let vp = cam.projection(low.x as f32 / low.y as f32) * cam.view();
                (low, vp, *cam, Vec2::ZERO)
            }
        };
        let screen = self.take_screen(ctx, target);
        let scene = self.scene.as_ref().ok_or(RenderError::NoScene)?;
        let out = self.output.as_ref().ok_or(RenderError::NoScene)?;
        let eye = Eye {
            position: drawn.position,
            axis: drawn.forward.normalize(),
            ortho: drawn.ortho_height.is_some(),
            outlines: method != Baseline::Raster,
        };
        let camera = RasterCamera {
            view_proj,
            eye: eye.position,
            axis: eye.axis,
            ortho: eye.ortho,
            // Screen-space methods turn sprites toward their camera.
            sprite_eye: (eye.position, view.face_res),
        };
        let mut stages = Stages::new(ctx, self.queries.as_ref());
        stages.run("gbuffer", |enc| {
            self.gbuffer.record(ctx, enc, &screen, scene, &camera);
        });
        let shaded = stages.run("shade", |enc| {
            self.shade.record(ctx, enc, &screen, scene, &view.look, eye)
        });
        // Bloom on the method's art pixels: its shaded screen, or the raster's full one
        // with the radius grown to the art pixel's size.
        let mut bloomed = false;
        if self.bloom.on() {
            let art = match method {
                Baseline::Raster => {
                    let a = low_res_size(size, art_pixel_height(view.face_res, cam.fov_y)?);
                    size.y as f32 / a.y.max(1) as f32
                }
                _ => 1.0,
            };
            let (lit, at) = (&screen.lit.view, (target.x, target.y));
            stages.run("bloom", |enc| {
                bloomed = self.bloom.record(ctx, enc, lit, at, art).is_some();
            });
        }
        stages.run("upscale", |enc| {
            let mapping = Mapping { scale, offset };
            let lit = (self.bloom.output().filter(|_| bloomed)).unwrap_or(&screen.lit.view);
            self.upscale
                .record(ctx, enc, &screen, lit, scene, mapping, out);
        });
        let result = stages.finish(&[]);
        self.keep_screen(screen);
        let timed = result?;
        let counters = Counters {
            texels_shaded: shaded,
            ..Default::default()
        };
        Ok((timed.passes, timed.gpu_timestamps, counters))
    }

    /// Cubemap: capture and shade six faces around the camera, then draw them.
    fn record_cubemap(
        &mut self,
        ctx: &GpuContext,
        view: &BaselineView,
    ) -> Result<(Vec<PassTime>, bool, Counters), RenderError> {
        let n = view.face_res;
        self.store.ensure(ctx, CUBE_SLOT, n);
        let cam = &view.camera;
        let caps = cubemap::captures(cam.position, n);
        let vp = cam.projection(view.size.x as f32 / view.size.y as f32) * cam.view();
        let scene = self.scene.as_ref().ok_or(RenderError::NoScene)?;
        let out = self.output.as_ref().ok_or(RenderError::NoScene)?;
        let store = &self.store;
        let mut stages = Stages::new(ctx, self.queries.as_ref());
        stages.run("capture", |enc| {
            self.capture.eye_band_origin = view.camera.position;
            self.capture.record(ctx, enc, &caps, &[], store, scene);
        });
        stages.run("shade", |enc| {
            let jobs: Vec<ShadeJob> = caps
                .iter()
                .map(|c| ShadeJob {
                    slot: c.slot,
                    face: c.face,
                    origin: c.origin,
                    valid: texel_probes::cube::FaceMask::ALL,
                    border: false,
                    view_cull: false,
                    rect: None,
                    filter: None,
                })
                .collect();
            let inputs = ShadeInputs {
                store,
                scene,
                look: &view.look,
                view: None,
                edges: false,
            };
            self.cube_shade.record(ctx, enc, &jobs, &inputs);
        });
        stages.run("cubemap", |enc| {
            let camera = CubeCamera {
                view_proj: vp,
                eye: cam.position,
                look: view.look,
            };
            let slot = store.slot(CUBE_SLOT);
            self.cube.record(ctx, enc, slot, scene, &camera, out);
        });
        let timed = stages.finish(&[])?;
        let (passes, gpu) = (timed.passes, timed.gpu_timestamps);
        let counters = Counters {
            faces_captured: caps.len() as u32,
            texels_shaded: caps.len() as u64 * u64::from(n) * u64::from(n),
            ..Default::default()
        };
        Ok((passes, gpu, counters))
    }

    /// The reference G-buffer of `camera` at `size`: a plain full-resolution raster of world
    /// position, entity id and view-axis depth, read back; sprites turned toward
    /// `sprite_eye` (a point and the face resolution of matched sizes: the frame's grid
    /// probe, where texel splatting turns them).
    pub fn reference_gbuffer(
        &mut self,
        ctx: &GpuContext,
        camera: &Camera,
        size: UVec2,
        sprite_eye: (glam::Vec3, u32),
    ) -> Result<GBuffer, RenderError> {
        crate::validate::view(camera, size)?;
        crate::validate::device_texture(&ctx.device.limits(), size)?;
        let screen = self.take_screen(ctx, size);
        let scene = self.scene.as_ref().ok_or(RenderError::NoScene)?;
        let vp = camera.projection(size.x as f32 / size.y as f32) * camera.view();
        let mut enc = ctx.device.create_command_encoder(&Default::default());
        let camera = RasterCamera {
            view_proj: vp,
            eye: camera.position,
            axis: camera.forward.normalize(),
            ortho: camera.ortho_height.is_some(),
            sprite_eye,
        };
        self.gbuffer.record(ctx, &mut enc, &screen, scene, &camera);
        ctx.queue.submit([enc.finish()]);
        let world = read_texture_layer(ctx, &screen.world.texture, 0, 16);
        let ids = read_texture_layer(ctx, &screen.ids.texture, 0, 8);
        self.keep_screen(screen);
        let (world, ids) = (world?, ids?);
        ctx.check()?;
        let world: &[[f32; 4]] = bytemuck::cast_slice(&world);
        let object_ids = &self.scene.as_ref().ok_or(RenderError::NoScene)?.object_ids;
        let id: Vec<u32> = bytemuck::cast_slice::<u8, [u32; 2]>(&ids)
            .iter()
            .map(|&[o, _]| {
                o.checked_sub(1)
                    .and_then(|i| object_ids.get(i as usize).copied())
                    .unwrap_or(0)
            })
            .collect();
        let depth = world
            .iter()
            .zip(&id)
            .map(|(w, &i)| {
                if i == 0 || w[3] >= SKY_DEPTH {
                    f32::INFINITY
                } else {
                    w[3]
                }
            })
            .collect();
        Ok(GBuffer {
            size,
            world: world.iter().map(|w| [w[0], w[1], w[2]]).collect(),
            id,
            depth,
        })
    }
}

/// A baseline frame's view, face resolution, and output (read back) within the device's
/// limits, before any target of its size is created.
fn validate(ctx: &GpuContext, view: &BaselineView) -> Result<(), RenderError> {
    crate::validate::view(&view.camera, view.size)?;
    crate::validate::device_output(&ctx.device.limits(), view.size)?;
    crate::validate::face_resolution(view.face_res)
}
