//! Cubemap (`shaders/cubemap.wgsl`): the camera-centred cubemap baseline. Every frame the six
//! faces around the camera are captured and shaded by the texel renderer's own capture and
//! shade passes (into a probe store of the baseline's own), then each output pixel shows the
//! lit texel in its view direction, nearest-sampled.

use crate::context::GpuContext;
use crate::passes::LazyRender;
use crate::passes::bind_group;
use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3};
use texel_probes::cube::Face;
use texel_probes::probe_set::Slot;

use super::{Output, fullscreen_pipeline};
use crate::gpu_scene::GpuScene;
use crate::input::{CaptureInput, Look};
use crate::passes::{ARRAY, FLOAT, UINT, entry, storage, texture, uniform, uniform_buffer};
use crate::probe_store::SlotTextures;
use crate::shader;

/// The slot of the baseline's probe store the cubemap lives in.
pub const CUBE_SLOT: Slot = Slot::Eye;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct CubeView {
    inv_view_proj: [[f32; 4]; 4],
    eye: [f32; 4],
    sky: [f32; 4],
    n: u32,
    haze: f32,
    _pad: [u32; 2],
}

/// The six captures of a camera-centred cubemap of `n` texels per face edge.
pub fn captures(eye: Vec3, n: u32) -> Vec<CaptureInput> {
    Face::ALL
        .iter()
        .map(|&face| CaptureInput {
            slot: CUBE_SLOT,
            face,
            origin: eye,
            face_resolution: n,
            ortho: None,
        })
        .collect()
}

/// What the cubemap is drawn for: the camera's `view_proj` and position, and the look.
#[derive(Debug, Clone, Copy)]
pub struct CubeCamera {
    /// World → clip of the output camera.
    pub view_proj: Mat4,
    /// The camera position (the cubemap's centre).
    pub eye: Vec3,
    /// Sky and haze.
    pub look: Look,
}

/// The pass drawing the cubemap at the output size.
pub struct CubemapPass {
    pipeline: LazyRender,
    layout: wgpu::BindGroupLayout,
    uniform: wgpu::Buffer,
}

impl CubemapPass {
    /// Builds the pipeline.
    pub fn new(device: &wgpu::Device) -> Result<Self, shader::ShaderError> {
        let module = shader::module(device, "cubemap.wgsl")?;
        let f = wgpu::ShaderStages::FRAGMENT;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("baselines::cubemap::layout"),
            entries: &[
                entry(0, f, uniform(false)),
                entry(1, f, texture(FLOAT, ARRAY)),
                entry(2, f, texture(UINT, ARRAY)),
                entry(3, f, storage(true)),
                entry(4, f, texture(FLOAT, ARRAY)),
            ],
        });
        let pipeline = fullscreen_pipeline(device, &module, &layout, "baselines::cubemap");
        let uniform = uniform_buffer(
            device,
            "baselines::cubemap::uniform",
            size_of::<CubeView>() as u64,
        );
        Ok(CubemapPass {
            pipeline,
            layout,
            uniform,
        })
    }

    /// Records drawing the lit cubemap in `slot`, centred at `eye`, into `out`, hazed by
    /// `look.haze` as the draw passes are.
    pub fn record(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        slot: &SlotTextures,
        scene: &GpuScene,
        camera: &CubeCamera,
        out: &Output,
    ) {
        let (device, queue) = (&ctx.device, &ctx.queue);
        let CubeCamera {
            view_proj,
            eye,
            look,
        } = *camera;
        let u = CubeView {
            inv_view_proj: view_proj.inverse().to_cols_array_2d(),
            eye: eye.extend(1.0).to_array(),
            sky: look.sky.extend(1.0).to_array(),
            n: slot.n,
            haze: look.haze.max(0.0),
            _pad: [0; 2],
        };
        queue.write_buffer(&self.uniform, 0, bytemuck::bytes_of(&u));
        let bind = bind_group(
            device,
            "baselines::cubemap::bind",
            &self.layout,
            &[
                self.uniform.as_entire_binding(),
                wgpu::BindingResource::TextureView(&slot.lit.array_view),
                wgpu::BindingResource::TextureView(&slot.ids.array_view),
                scene.objects.as_entire_binding(),
                wgpu::BindingResource::TextureView(&slot.geo.array_view),
            ],
        );
        let mut pass = out.begin(encoder, "baselines::cubemap::pass");
        pass.set_pipeline(self.pipeline.get());
        pass.set_bind_group(0, &bind, &[]);
        pass.draw(0..3, 0..1);
    }
}
