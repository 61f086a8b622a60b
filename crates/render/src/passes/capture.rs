//! Capture: rasterizes the scene into the cube faces the plan asks for (`shaders/capture.wgsl`).

use crate::context::GpuContext;
use crate::passes::LazyCompute;
use crate::passes::LazyRender;
use bytemuck::{Pod, Zeroable};
use texel_probes::cube::face_view_projection;

use super::occlusion::HeldFace;
use super::raster::{self, RasterDraw, RasterTargets};
use super::{
    FLOAT, UINT, UNIFORM_STRIDE, bind_group, entry, storage_texture, texture, uniform,
    uniform_buffer,
};
use texel_probes::visibility::TexelRect;

use crate::far_field::{FarField, FarFieldInput};
use crate::gpu_scene::{CaptureCull, GpuScene, LodFrom};
use crate::input::CaptureInput;
use crate::probe_store::{
    ALBEDO_FORMAT, GEO_FORMAT, ID_FORMAT, LayeredTexture, ProbeStore, SHADING_FORMAT, SlotTextures,
};
use crate::shader;
use texel_probes::cube::Face;
use texel_probes::probe_set::Slot;

/// The capture planes live with the input that defaults a camera's far plane to them
/// ([`crate::input::Camera::looking`]); a capture is their user.
pub use crate::input::{CAPTURE_FAR, CAPTURE_NEAR};
/// Most faces captured in one frame (three probes × six faces).
pub const MAX_CAPTURES: usize = 18;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct FaceParams {
    view_proj: [[f32; 4]; 4],
    origin: [f32; 4],
    face: u32,
    n: u32,
    mode: u32,
    /// An orthographic face's half extent, 0 for a cube face.
    half: f32,
    band_origin: [f32; 4],
    right: [f32; 4],
    down: [f32; 4],
    forward: [f32; 4],
    /// The texels drawn: columns `rect[0]..rect[2]`, rows `rect[1]..rect[3]`.
    rect: [u32; 4],
}

/// The view-projection a capture rasterizes `c` with.
fn capture_view_projection(c: &CaptureInput) -> glam::Mat4 {
    match c.ortho {
        Some(f) => f.view_projection(c.origin, CAPTURE_NEAR, CAPTURE_FAR),
        None => face_view_projection(c.origin, c.face, CAPTURE_NEAR, CAPTURE_FAR),
    }
}

/// What a capture stores as the albedo.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CaptureMode {
    /// The surface's albedo × vertex colour × texture.
    Surface,
    /// A colour for the texture's pixels per probe texel (the texel-density debug view).
    TextureDensity,
}

/// Size of `FaceParams` (WGSL `FaceParams`).
pub const FACE_PARAMS_SIZE: usize = size_of::<FaceParams>();

/// The capture pass.
pub struct CapturePass {
    /// What the captures store as the albedo ([`CaptureMode::Surface`] unless a debug view
    /// asks otherwise).
    pub mode: CaptureMode,
    /// Where the eye probe's faces measure terrain bands from: the frame's grid probe
    /// origin (stable slots measure from their own origin).
    pub eye_band_origin: glam::Vec3,
    /// What each face leaves out (everything it cannot show, unless a test asks otherwise).
    pub cull: crate::gpu_scene::CaptureCull,
    /// The eye's far field this frame (`None`: the eye draws everything every frame).
    pub far: Option<FarFieldInput>,
    /// Of the stable faces captured in part this frame, the objects the edits since their
    /// last capture rewrote ([`crate::input::PartialFace::edited`]): those faces leave out
    /// what lies behind what they hold ([`super::occlusion`]) when `occlusion` is on.
    pub edited: Vec<(Slot, Face, Vec<u32>)>,
    /// Whether a stable face captured in part leaves out what lies behind what it holds. Off:
    /// exact, but measured no faster on the town's drag step, and its read-back waits for the
    /// GPU in the middle of a frame (stability log, "The drag step's 8,000 objects").
    pub occlusion: bool,
    far_field: FarField,
    pipeline: LazyRender,
    /// Plain terrain chunks (`vs_terrain`, `fs_terrain`): the point and object alone pass
    /// to the fragments, which read the surface from the heightmap.
    terrain_raster: LazyRender,
    layout: wgpu::BindGroupLayout,
    faces: wgpu::Buffer,
    /// `colour_terrain`: the drawn face's terrain texels coloured once each.
    terrain: LazyCompute,
    drawn_layout: wgpu::BindGroupLayout,
}

impl CapturePass {
    /// Builds the pipeline.
    pub fn new(device: &wgpu::Device) -> Result<Self, shader::ShaderError> {
        let module = shader::module(device, "capture.wgsl")?;
        let all = wgpu::ShaderStages::VERTEX_FRAGMENT | wgpu::ShaderStages::COMPUTE;
        let scene_entries = raster::scene_layout_entries().map(|mut e| {
            e.visibility = all;
            e
        });
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("capture::layout"),
            entries: &[[entry(0, all, uniform(true))].as_slice(), &scene_entries].concat(),
        });
        let targets = [GEO_FORMAT, ID_FORMAT, ALBEDO_FORMAT, SHADING_FORMAT];
        let pipeline = raster::pipeline(device, "capture", &module, &layout, &targets);
        let spec = raster::RasterSpec {
            owner: "capture::terrain_raster",
            module: &module,
            layout: &layout,
            targets: &targets,
        };
        let terrain_raster = raster::pipeline_with(
            device,
            &spec,
            ("vs_terrain", "fs_terrain"),
            &[GpuScene::point_vertex_layout()],
        );

        let c = wgpu::ShaderStages::COMPUTE;
        let d2 = wgpu::TextureViewDimension::D2;
        let drawn_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("capture::drawn_layout"),
            entries: &[
                entry(0, c, texture(FLOAT, d2)),
                entry(1, c, texture(UINT, d2)),
                entry(
                    2,
                    c,
                    storage_texture(wgpu::StorageTextureAccess::WriteOnly, ALBEDO_FORMAT, d2),
                ),
            ],
        });
        let terrain = super::compute_pipeline(
            device,
            "capture::terrain",
            &module,
            "colour_terrain",
            &[&layout, &drawn_layout],
        );
        let faces = uniform_buffer(
            device,
            "capture::faces",
            2 * UNIFORM_STRIDE * MAX_CAPTURES as u64,
        );
        Ok(CapturePass {
            mode: CaptureMode::Surface,
            eye_band_origin: glam::Vec3::ZERO,
            cull: crate::gpu_scene::CaptureCull::default(),
            far: None,
            edited: Vec::new(),
            occlusion: false,
            far_field: FarField::default(),
            pipeline,
            terrain_raster,
            layout,
            faces,
            terrain,
            drawn_layout,
        })
    }

    /// Forgets the far faces (the scene changed).
    pub fn forget_far_field(&mut self) {
        self.far_field.forget();
    }

    /// Forgets the far faces an edit in place can have changed: those some corner of one of
    /// `boxes` (the edited objects' draw ranges before and after) lies beyond
    /// ([`FarField::forget_reaching`]).
    pub fn forget_far_faces_reaching(&mut self, boxes: &[(glam::Vec3, glam::Vec3)]) {
        self.far_field.forget_reaching(boxes);
    }

    /// GPU bytes of the far faces.
    pub fn far_field_bytes(&self) -> u64 {
        self.far_field.bytes()
    }

    /// Records one render pass per capture (at most [`MAX_CAPTURES`]). `rects[i]`, when
    /// given, limits capture `i` to those texels: the rest of an eye face is cleared to sky,
    /// the rest of a stable face (an edit changed only the rectangle: `FrameInput::partial`)
    /// keeps what it held, and only the ranges that may cover the rectangle are drawn. With
    /// a far field ([`CapturePass::far`]) a perspective eye face draws only what reaches
    /// within its distance, over its far face ([`crate::far_field`]), captured first when due.
    /// Returns what the faces draw.
    pub fn record(
        &mut self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        captures: &[CaptureInput],
        rects: &[Option<TexelRect>],
        store: &ProbeStore,
        scene: &GpuScene,
    ) -> CaptureWork {
        let mut work = CaptureWork::default();
        let device = &ctx.device;
        let captures = &captures[..captures.len().min(MAX_CAPTURES)];
        if captures.is_empty() {
            return work;
        }
        let rect_of = |i: usize| rects.get(i).copied().flatten();
        let far = self.plan_far(ctx, captures, rects, store);
        let far_of = |c: &CaptureInput| far.as_ref().filter(|_| uses_far(c));
        // Each capture's record, then (at `captures.len() + i`) its far face's.
        let mut bytes = vec![0u8; UNIFORM_STRIDE as usize * 2 * captures.len()];
        for (i, c) in captures.iter().enumerate() {
            let n = store.slot(c.slot).n;
            let mut records = vec![(i, self.params(c, n, drawn_rect(rect_of(i), n)))];
            if far_of(c).is_some() {
                records.push((captures.len() + i, self.params(c, n, [0, 0, n, n])));
            }
            for (k, p) in records {
                let at = k * UNIFORM_STRIDE as usize;
                bytes[at..at + size_of::<FaceParams>()].copy_from_slice(bytemuck::bytes_of(&p));
            }
        }
        ctx.queue.write_buffer(&self.faces, 0, &bytes);
        let face = wgpu::BindingResource::Buffer(wgpu::BufferBinding {
            buffer: &self.faces,
            offset: 0,
            size: wgpu::BufferSize::new(size_of::<FaceParams>() as u64),
        });
        let resources: Vec<_> = std::iter::once(face)
            .chain(scene.raster_resources())
            .collect();
        let bind = bind_group(device, "capture::bind", &self.layout, &resources);
        // A stable face captured in part keeps the rest: saved now, put back once drawn.
        let kept: Vec<Kept> = (captures.iter().enumerate())
            .filter_map(|(i, c)| {
                let rect = rect_of(i)?;
                let slot = store.slot(c.slot);
                (c.slot != Slot::Eye).then(|| Kept::save(device, encoder, slot, c, rect))
            })
            .collect();
        let far_textures = far.as_ref().and_then(|_| self.far_field.drawn());
        let held = self.held_faces(ctx, captures, rects, store, scene);
        work.held_faces = held.iter().flatten().count() as u32;
        for (i, c) in captures.iter().enumerate() {
            let slot = store.slot(c.slot);
            let f = c.face.index();
            // Ranges this face may see (terrain chunks, objects): of a stable face captured in
            // part, those that may cover its rectangle; of an eye face, those in its part of
            // the view (the rest is scissored away), and with a far field, those reaching
            // within its distance and overlap.
            let whole = match far_of(c) {
                Some(far) => face_view_projection(c.origin, c.face, CAPTURE_NEAR, far.near),
                None => capture_view_projection(c),
            };
            let mut d = FaceDraw {
                cull: rect_of(i).map_or(whole, |r| narrowed(whole, r, slot.n)),
                bind: &bind,
                offset: (i as u64 * UNIFORM_STRIDE) as u32,
                scissor: rect_of(i),
                beyond: None,
                held: held.get(i).and_then(Option::as_ref),
                n: slot.n,
                colour: targets(slot).map(|t| &t.layer_views[f]),
                depth: &slot.depth.layer_views[f],
                load: false,
                // With a far field an eye face's depth is kept, so wgpu never initializes a
                // discarded layer of the texture the far faces' depth is copied into (its
                // tracker asserted doing so, wgpu-core 30.0.1: `splat_gpu`'s closed room).
                keep_depth: far_of(c).is_some(),
            };
            let drawn = rect_of(i).is_none_or(|r| r.area() > 0);
            if let (Some(far), Some(ft), true) = (far_of(c), far_textures, drawn) {
                if far.due.contains(&c.face) {
                    let far_face = FaceDraw {
                        cull: capture_view_projection(c),
                        offset: ((captures.len() + i) as u64 * UNIFORM_STRIDE) as u32,
                        scissor: None,
                        beyond: Some(far.beyond),
                        held: None,
                        colour: ft.targets().map(|t| &t.layer_views[f]),
                        depth: &ft.depth.layer_views[f],
                        keep_depth: true,
                        ..d
                    };
                    self.draw(encoder, scene, c, &far_face, &mut work);
                    work.far_faces += 1;
                }
                // The eye face cleared, its part of the view and the whole depth copied from
                // the far face, then what is near drawn over it, depth-tested against it.
                let clear = FaceDraw {
                    scissor: Some(TexelRect {
                        x0: 0,
                        y0: 0,
                        x1: 0,
                        y1: 0,
                    }),
                    ..d
                };
                self.draw(encoder, scene, c, &clear, &mut work);
                copy_rect(encoder, ft, slot, f as u32, drawn_rect(rect_of(i), slot.n));
                d.load = true;
            }
            let (ranges, triangles) = self.draw(encoder, scene, c, &d, &mut work);
            if c.slot == Slot::Eye {
                work.eye_faces += 1;
                work.eye_ranges += ranges;
                work.eye_triangles += triangles;
            }
        }
        self.colour_terrain(ctx, encoder, (captures, rects), store, scene, &bind);
        for k in &kept {
            k.restore(encoder, store.slot(k.slot));
        }
        work
    }

    /// What each stable face captured in part with its edited objects known holds over its
    /// rectangle ([`HeldFace`]; `None` for the other captures, and for every one with
    /// [`CapturePass::occlusion`] off or when it cannot be read: those draw all that may
    /// cover their rectangle).
    fn held_faces(
        &self,
        ctx: &GpuContext,
        captures: &[CaptureInput],
        rects: &[Option<TexelRect>],
        store: &ProbeStore,
        scene: &GpuScene,
    ) -> Vec<Option<HeldFace>> {
        (captures.iter().enumerate())
            .map(|(i, c)| {
                let rect = rects.get(i).copied().flatten()?;
                let known = (self.edited.iter()).find(|e| e.0 == c.slot && e.1 == c.face);
                let (_, _, edited) = known.filter(|_| self.occlusion && c.ortho.is_none())?;
                if c.slot == Slot::Eye || rect.area() == 0 || self.cull == CaptureCull::Nothing {
                    return None;
                }
                let view = (c.face, c.origin, capture_view_projection(c));
                let slot = store.slot(c.slot);
                HeldFace::read(ctx, slot, view, rect, scene, edited).ok()
            })
            .collect()
    }

    /// The far field's distances and the eye faces whose far face is captured this frame
    /// (`None` without a far field or a perspective eye face, or when the faces cull
    /// nothing: that draws everything into each face, to test the culls against).
    fn plan_far(
        &mut self,
        ctx: &GpuContext,
        captures: &[CaptureInput],
        rects: &[Option<TexelRect>],
        store: &ProbeStore,
    ) -> Option<FarPlan> {
        let input = self.far.filter(|_| self.cull != CaptureCull::Nothing)?;
        let eye: Vec<(usize, &CaptureInput)> = (captures.iter().enumerate())
            .filter(|(_, c)| uses_far(c))
            .collect();
        let origin = eye.first()?.1.origin;
        let n = store.slot(Slot::Eye).n;
        let faces: Vec<Face> = (eye.iter())
            .filter(|(i, _)| {
                rects
                    .get(*i)
                    .copied()
                    .flatten()
                    .is_none_or(|r| r.area() > 0)
            })
            .map(|(_, c)| c.face)
            .collect();
        self.far_field.textures(ctx, n);
        let due = (self.far_field).plan(input, &faces, origin, (n, self.mode, self.cull));
        Some(FarPlan {
            near: input.distance(n) + input.overlap(),
            beyond: input.distance(n),
            due,
        })
    }

    /// The uniform record of capture `c` on faces of `n` texels, drawing the texels `rect`.
    fn params(&self, c: &CaptureInput, n: u32, rect: [u32; 4]) -> FaceParams {
        let axis = |f: fn(&texel_probes::ortho::OrthoFrame) -> glam::Vec3| {
            c.ortho.map_or([0.0; 4], |o| f(&o).extend(0.0).to_array())
        };
        FaceParams {
            view_proj: capture_view_projection(c).to_cols_array_2d(),
            origin: c.origin.extend(1.0).to_array(),
            face: c.face.index() as u32,
            n,
            mode: u32::from(self.mode == CaptureMode::TextureDensity),
            half: c.ortho.map_or(0.0, |o| o.half),
            band_origin: if c.slot == Slot::Eye {
                self.eye_band_origin
            } else {
                c.origin
            }
            .extend(1.0)
            .to_array(),
            right: axis(|o| o.right),
            down: axis(|o| o.down),
            forward: axis(|o| o.forward),
            rect,
        }
    }

    /// Records one face's render pass as `d` says (the ranges of the scene its `cull`
    /// matrix may see, for capture `c`); adds them to `work` and returns the ranges and
    /// triangles drawn.
    fn draw(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        scene: &GpuScene,
        c: &CaptureInput,
        d: &FaceDraw<'_>,
        work: &mut CaptureWork,
    ) -> (u64, u64) {
        let lod = match (c.ortho, c.slot) {
            (Some(o), _) => LodFrom::Texel(o.texel(d.n)),
            (None, Slot::Eye) => LodFrom::Eye(c.origin, d.n),
            (None, _) => LodFrom::Probe(c.origin, d.n),
        };
        let axis = c.face.axis();
        // Beyond `depth` along the face's axis: every corner of the range's bounds.
        let beyond = |r: &crate::gpu_scene::DrawRange| {
            d.beyond.is_none_or(|depth| {
                (0..8).all(|i| {
                    let corner = glam::Vec3::select(
                        glam::BVec3::new(i & 1 != 0, i & 2 != 0, i & 4 != 0),
                        r.max,
                        r.min,
                    );
                    (corner - c.origin).dot(axis) > depth
                })
            })
        };
        // Asked last, of the ranges every other cull keeps: those it leaves out are counted.
        let occluded = std::cell::Cell::new(0u64);
        let keep = |r: &crate::gpu_scene::DrawRange| {
            let hidden = d.held.is_some_and(|h| h.hides(&scene.ranges, r));
            occluded.set(occluded.get() + u64::from(hidden));
            beyond(r) && !hidden
        };
        let ([terrain_runs, runs], count) = match d.scissor.is_some_and(|r| r.area() == 0) {
            true => ([Vec::new(), Vec::new()], 0),
            false => {
                let ranges = &scene.ranges;
                let index = Some(scene.range_index());
                crate::gpu_scene::visible_runs_where(ranges, index, &d.cull, lod, self.cull, &keep)
            }
        };
        work.occluded += occluded.get();
        let triangles = (terrain_runs.iter().chain(&runs))
            .map(|&(_, n, _)| u64::from(n / 3))
            .sum::<u64>();
        work.ranges += count as u64;
        work.triangles += triangles;
        let clear = wgpu::Color::TRANSPARENT;
        let [geo, ids, albedo, shading] = d.colour;
        let targets = RasterTargets {
            colour: &[
                (geo, raster::SKY_CLEAR),
                (ids, clear),
                (albedo, clear),
                (shading, clear),
            ],
            depth: d.depth,
            keep_depth: d.keep_depth,
            load: d.load,
        };
        let draw = RasterDraw {
            pipeline: self.pipeline.get(),
            bind: d.bind,
            offsets: &[d.offset],
            scissor: d.scissor,
            runs: Some(&runs),
            first: Some((self.terrain_raster.get(), &terrain_runs)),
        };
        raster::record(encoder, "capture::face", &targets, scene, &draw);
        (count as u64, triangles)
    }

    /// Colours the terrain texels of the faces just drawn (`colour_terrain`), within their
    /// rectangles; nothing in the texture-density view or without terrains.
    fn colour_terrain(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        (captures, rects): (&[CaptureInput], &[Option<TexelRect>]),
        store: &ProbeStore,
        scene: &GpuScene,
        bind: &wgpu::BindGroup,
    ) {
        if self.mode == CaptureMode::TextureDensity || scene.terrain_count == 0 {
            return;
        }
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("capture::terrain"),
            timestamp_writes: None,
        });
        pass.set_pipeline(self.terrain.get());
        for (i, c) in captures.iter().enumerate() {
            let slot = store.slot(c.slot);
            let f = c.face.index();
            let drawn = bind_group(
                &ctx.device,
                "capture::drawn",
                &self.drawn_layout,
                &[
                    wgpu::BindingResource::TextureView(&slot.geo.layer_views[f]),
                    wgpu::BindingResource::TextureView(&slot.ids.layer_views[f]),
                    wgpu::BindingResource::TextureView(&slot.albedo.layer_views[f]),
                ],
            );
            let r = drawn_rect(rects.get(i).copied().flatten(), slot.n);
            let (w, h) = (r[2].saturating_sub(r[0]), r[3].saturating_sub(r[1]));
            if w == 0 || h == 0 {
                continue;
            }
            pass.set_bind_group(0, bind, &[(i as u64 * UNIFORM_STRIDE) as u32]);
            pass.set_bind_group(1, &drawn, &[]);
            pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
        }
    }
}

/// Whether capture `c` draws over a far face when the frame has a far field: a perspective
/// eye face.
fn uses_far(c: &CaptureInput) -> bool {
    c.slot == Slot::Eye && c.ortho.is_none()
}

/// A frame's far field ([`CapturePass::plan_far`]).
struct FarPlan {
    /// The eye faces draw the ranges reaching within this depth.
    near: f32,
    /// The far faces draw the ranges wholly beyond this depth.
    beyond: f32,
    /// The faces whose far face is captured this frame.
    due: Vec<Face>,
}

/// One face's render pass ([`CapturePass::draw`]).
#[derive(Clone, Copy)]
struct FaceDraw<'a> {
    /// What decides the ranges drawn (a face's view-projection, perhaps narrowed).
    cull: glam::Mat4,
    bind: &'a wgpu::BindGroup,
    /// Of the capture's uniform record.
    offset: u32,
    scissor: Option<TexelRect>,
    /// Only the ranges wholly beyond this depth along the face's axis (a far face).
    beyond: Option<f32>,
    /// What a stable face captured in part holds there: the ranges behind it are left out.
    held: Option<&'a HeldFace>,
    /// Texels per face edge.
    n: u32,
    /// Geo, ids, albedo and shading.
    colour: [&'a wgpu::TextureView; 4],
    depth: &'a wgpu::TextureView,
    /// The targets (colours and depth) are loaded, not cleared.
    load: bool,
    /// The depth is stored (a far face's, which its eye face copies).
    keep_depth: bool,
}

/// Copies the texels `rect` of face `face` of the far faces `far` into `slot`'s, and the
/// face's whole depth (a depth texture is copied whole).
fn copy_rect(
    encoder: &mut wgpu::CommandEncoder,
    far: &crate::far_field::FarTextures,
    slot: &SlotTextures,
    face: u32,
    rect: [u32; 4],
) {
    let (w, h) = (
        rect[2].saturating_sub(rect[0]),
        rect[3].saturating_sub(rect[1]),
    );
    if w == 0 || h == 0 {
        return;
    }
    for (from, to) in far.targets().iter().zip(targets(slot)) {
        encoder.copy_texture_to_texture(
            at(&from.texture, rect[0], rect[1], face),
            at(&to.texture, rect[0], rect[1], face),
            extent(w, h),
        );
    }
    encoder.copy_texture_to_texture(
        at(&far.depth.texture, 0, 0, face),
        at(&slot.depth.texture, 0, 0, face),
        extent(far.n, far.n),
    );
}

/// `view_proj` narrowed to the texels `r` of an `n`-texel face: the clip-space box of those
/// texels (rows run down the framebuffer, NDC's y up) stretched over the whole, so a range
/// outside the product's frustum covers none of them.
fn narrowed(view_proj: glam::Mat4, r: TexelRect, n: u32) -> glam::Mat4 {
    let n = n as f32;
    let (x0, x1) = (2.0 * r.x0 as f32 / n - 1.0, 2.0 * r.x1 as f32 / n - 1.0);
    let (y0, y1) = (1.0 - 2.0 * r.y1 as f32 / n, 1.0 - 2.0 * r.y0 as f32 / n);
    if x1 <= x0 || y1 <= y0 {
        return view_proj;
    }
    let (sx, sy) = (2.0 / (x1 - x0), 2.0 / (y1 - y0));
    let (cx, cy) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
    let m = glam::Mat4::from_cols(
        glam::Vec4::new(sx, 0.0, 0.0, 0.0),
        glam::Vec4::new(0.0, sy, 0.0, 0.0),
        glam::Vec4::Z,
        glam::Vec4::new(-sx * cx, -sy * cy, 0.0, 1.0),
    );
    m * view_proj
}

/// A stable face captured in part: what its four capture targets held, to put back around
/// the rectangle drawn (the capture clears the whole face).
struct Kept {
    slot: Slot,
    face: u32,
    n: u32,
    rect: TexelRect,
    /// Copies of the face of geo, ids, albedo and shading, in that order.
    saved: [wgpu::Texture; 4],
}

impl Kept {
    /// Copies the face `c` of `slot` aside before it is captured within `rect`.
    fn save(
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        slot: &SlotTextures,
        c: &CaptureInput,
        rect: TexelRect,
    ) -> Self {
        let (n, face) = (slot.n, c.face.index() as u32);
        let saved = targets(slot).map(|t| {
            let copy = device.create_texture(&wgpu::TextureDescriptor {
                label: Some("capture::kept"),
                size: extent(n, n),
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: t.texture.format(),
                usage: wgpu::TextureUsages::COPY_DST | wgpu::TextureUsages::COPY_SRC,
                view_formats: &[],
            });
            encoder.copy_texture_to_texture(
                at(&t.texture, 0, 0, face),
                at(&copy, 0, 0, 0),
                extent(n, n),
            );
            copy
        });
        Kept {
            slot: c.slot,
            face,
            n,
            rect,
            saved,
        }
    }

    /// Puts the saved texels outside the rectangle back into `slot`'s face.
    fn restore(&self, encoder: &mut wgpu::CommandEncoder, slot: &SlotTextures) {
        let (n, r) = (self.n, self.rect);
        let (x0, y0, x1, y1) = (r.x0.min(n), r.y0.min(n), r.x1.min(n), r.y1.min(n));
        // Above, below, left of and right of the rectangle: (x, y, width, height).
        let bands = [
            (0, 0, n, y0),
            (0, y1, n, n.saturating_sub(y1)),
            (0, y0, x0, y1.saturating_sub(y0)),
            (x1, y0, n.saturating_sub(x1), y1.saturating_sub(y0)),
        ];
        for (t, saved) in targets(slot).iter().zip(&self.saved) {
            for &(x, y, w, h) in bands.iter().filter(|b| b.2 > 0 && b.3 > 0) {
                encoder.copy_texture_to_texture(
                    at(saved, x, y, 0),
                    at(&t.texture, x, y, self.face),
                    extent(w, h),
                );
            }
        }
    }
}

/// The textures a capture writes (its depth aside, which nothing reads after it).
fn targets(slot: &SlotTextures) -> [&LayeredTexture; 4] {
    [&slot.geo, &slot.ids, &slot.albedo, &slot.shading]
}

/// Texel `(x, y)` of layer `layer` of `texture`.
fn at(texture: &wgpu::Texture, x: u32, y: u32, layer: u32) -> wgpu::TexelCopyTextureInfo<'_> {
    wgpu::TexelCopyTextureInfo {
        texture,
        mip_level: 0,
        origin: wgpu::Origin3d { x, y, z: layer },
        aspect: wgpu::TextureAspect::All,
    }
}

/// `w × h` texels of one layer.
fn extent(w: u32, h: u32) -> wgpu::Extent3d {
    wgpu::Extent3d {
        width: w,
        height: h,
        depth_or_array_layers: 1,
    }
}

/// What a frame's captures drew, summed over its faces.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct CaptureWork {
    /// Draw ranges (objects, terrain chunks) drawn.
    pub ranges: u64,
    /// Their triangles.
    pub triangles: u64,
    /// Far faces captured ([`crate::far_field`]; their ranges and triangles are counted
    /// above, not in the eye's).
    pub far_faces: u32,
    /// Of those, the eye probe's faces, ranges and triangles.
    pub eye_faces: u32,
    /// See `eye_faces`.
    pub eye_ranges: u64,
    /// See `eye_faces`.
    pub eye_triangles: u64,
    /// Stable faces captured in part whose held depths and ids were read back to leave out
    /// what lies behind them ([`super::occlusion`]).
    pub held_faces: u32,
    /// Ranges those faces left out, lying behind what they held (not counted in `ranges`).
    pub occluded: u64,
}

/// The texels a capture draws, `[x0, y0, x1, y1]`: its rectangle, or the whole face.
fn drawn_rect(rect: Option<TexelRect>, n: u32) -> [u32; 4] {
    rect.map_or([0, 0, n, n], |r| [r.x0, r.y0, r.x1.min(n), r.y1.min(n)])
}
