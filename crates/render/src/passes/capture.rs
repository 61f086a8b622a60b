//! Capture: rasterizes the scene into the cube faces the plan asks for (`shaders/capture.wgsl`).

use crate::context::GpuContext;
use crate::passes::LazyCompute;
use crate::passes::LazyRender;
use bytemuck::{Pod, Zeroable};
use texel_probes::cube::face_view_projection;

use super::raster::{self, RasterDraw, RasterTargets};
use super::{
    FLOAT, UINT, UNIFORM_STRIDE, bind_group, entry, storage_texture, texture, uniform,
    uniform_buffer,
};
use texel_probes::visibility::TexelRect;

use crate::gpu_scene::GpuScene;
use crate::input::CaptureInput;
use crate::probe_store::{
    ALBEDO_FORMAT, GEO_FORMAT, ID_FORMAT, LayeredTexture, ProbeStore, SHADING_FORMAT, SlotTextures,
};
use crate::shader;
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
            UNIFORM_STRIDE * MAX_CAPTURES as u64,
        );
        Ok(CapturePass {
            mode: CaptureMode::Surface,
            eye_band_origin: glam::Vec3::ZERO,
            cull: crate::gpu_scene::CaptureCull::default(),
            pipeline,
            terrain_raster,
            layout,
            faces,
            terrain,
            drawn_layout,
        })
    }

    /// Records one render pass per capture (at most [`MAX_CAPTURES`]). `rects[i]`, when
    /// given, limits capture `i` to those texels: the rest of an eye face is cleared to sky,
    /// the rest of a stable face (an edit changed only the rectangle: `FrameInput::partial`)
    /// keeps what it held, and only the ranges that may cover the rectangle are drawn.
    /// Returns what the faces draw.
    pub fn record(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        captures: &[CaptureInput],
        rects: &[Option<TexelRect>],
        store: &ProbeStore,
        scene: &GpuScene,
    ) -> CaptureWork {
        let mode = self.mode;
        let mut work = CaptureWork::default();
        let (device, queue) = (&ctx.device, &ctx.queue);
        let captures = &captures[..captures.len().min(MAX_CAPTURES)];
        let mut bytes = vec![0u8; UNIFORM_STRIDE as usize * captures.len()];
        for (i, c) in captures.iter().enumerate() {
            let axis = |f: fn(&texel_probes::ortho::OrthoFrame) -> glam::Vec3| {
                c.ortho.map_or([0.0; 4], |o| f(&o).extend(0.0).to_array())
            };
            let p = FaceParams {
                view_proj: capture_view_projection(c).to_cols_array_2d(),
                origin: c.origin.extend(1.0).to_array(),
                face: c.face.index() as u32,
                n: store.slot(c.slot).n,
                mode: u32::from(mode == CaptureMode::TextureDensity),
                half: c.ortho.map_or(0.0, |o| o.half),
                band_origin: if c.slot == texel_probes::probe_set::Slot::Eye {
                    self.eye_band_origin
                } else {
                    c.origin
                }
                .extend(1.0)
                .to_array(),
                right: axis(|o| o.right),
                down: axis(|o| o.down),
                forward: axis(|o| o.forward),
                rect: drawn_rect(rects.get(i).copied().flatten(), store.slot(c.slot).n),
            };
            let at = i * UNIFORM_STRIDE as usize;
            bytes[at..at + size_of::<FaceParams>()].copy_from_slice(bytemuck::bytes_of(&p));
        }
        if bytes.is_empty() {
            return work;
        }
        queue.write_buffer(&self.faces, 0, &bytes);
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
                let rect = rects.get(i).copied().flatten()?;
                let slot = store.slot(c.slot);
                (c.slot != Slot::Eye).then(|| Kept::save(device, encoder, slot, c, rect))
            })
            .collect();
        for (i, c) in captures.iter().enumerate() {
            let slot = store.slot(c.slot);
            // Only the ranges this face may see (terrain chunks, objects); of a stable face
            // captured in part, those that may cover its rectangle.
            let view_proj = match rects.get(i).copied().flatten() {
                Some(r) if c.slot != Slot::Eye => narrowed(capture_view_projection(c), r, slot.n),
                _ => capture_view_projection(c),
            };
            let lod = match c.ortho {
                Some(o) => crate::gpu_scene::LodFrom::Texel(o.texel(slot.n)),
                None if c.slot == texel_probes::probe_set::Slot::Eye => {
                    crate::gpu_scene::LodFrom::Eye(c.origin, slot.n)
                }
                None => crate::gpu_scene::LodFrom::Probe(c.origin, slot.n),
            };
            let ([terrain_runs, runs], count) =
                crate::gpu_scene::visible_runs_by_kind(&scene.ranges, &view_proj, lod, self.cull);
            work.ranges += count as u64;
            work.triangles += (terrain_runs.iter().chain(&runs))
                .map(|&(_, n, _)| u64::from(n / 3))
                .sum::<u64>();
            let f = c.face.index();
            let clear = wgpu::Color::TRANSPARENT;
            let targets = RasterTargets {
                colour: &[
                    (&slot.geo.layer_views[f], raster::SKY_CLEAR),
                    (&slot.ids.layer_views[f], clear),
                    (&slot.albedo.layer_views[f], clear),
                    (&slot.shading.layer_views[f], clear),
                ],
                depth: &slot.depth.layer_views[f],
                keep_depth: false,
            };
            let draw = RasterDraw {
                pipeline: self.pipeline.get(),
                bind: &bind,
                offsets: &[(i as u64 * UNIFORM_STRIDE) as u32],
                scissor: rects.get(i).copied().flatten(),
                runs: Some(&runs),
                first: Some((self.terrain_raster.get(), &terrain_runs)),
            };
            raster::record(encoder, "capture::face", &targets, scene, &draw);
        }
        if mode == CaptureMode::TextureDensity || scene.terrain_count == 0 {
            for k in &kept {
                k.restore(encoder, store.slot(k.slot));
            }
            return work;
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
                device,
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
            pass.set_bind_group(0, &bind, &[(i as u64 * UNIFORM_STRIDE) as u32]);
            pass.set_bind_group(1, &drawn, &[]);
            pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
        }
        drop(pass);
        for k in &kept {
            k.restore(encoder, store.slot(k.slot));
        }
        work
    }
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
}

/// The texels a capture draws, `[x0, y0, x1, y1]`: its rectangle, or the whole face.
fn drawn_rect(rect: Option<TexelRect>, n: u32) -> [u32; 4] {
    rect.map_or([0, 0, n, n], |r| [r.x0, r.y0, r.x1.min(n), r.y1.min(n)])
}
