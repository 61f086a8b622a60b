//! The viewport's picture drawn into egui's render pass by a paint callback of its own: an
//! opaque textured mesh (the re-projected grid of [`super::reproject`]), no blending, a
//! shader that only samples. On a software rasterizer egui's own image path cost about as
//! much as the rest of the window together (lavapipe at 1280×800: 35 of 71 ms of CPU a UI
//! frame), since every pixel it draws is blended through egui's general shader. Where egui
//! draws without wgpu (tests), the picture is an ordinary egui image.

use std::sync::Arc;

use egui::{ColorImage, Pos2, Rect};
use egui_wgpu::wgpu;

/// One UI frame's picture: the frame's image (uploaded when its number is new) and the
/// mesh's triangles, as screen points and texture coordinates; with more than one quad (a
/// re-projected frame) the background is drawn under them.
pub struct Picture {
    /// The frame's number and pixels.
    pub frame: (u64, Arc<ColorImage>),
    /// Triangles: three (screen point, uv) each.
    pub triangles: Vec<(Pos2, Pos2)>,
    /// Where egui paints the callback (its viewport), screen points.
    pub rect: Rect,
    /// The format of egui's render target.
    pub target: wgpu::TextureFormat,
}

/// What the callback keeps between frames, in egui's callback resources.
struct Resources {
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
    sampler: wgpu::Sampler,
    /// The texture of the frame last uploaded: its number, size and bind group.
    texture: Option<(u64, [usize; 2], wgpu::Texture, wgpu::BindGroup)>,
    vertices: wgpu::Buffer,
    count: u32,
}

/// Vertices the buffer holds: the background's quad and an 8 × 8 grid of quads.
const MAX_VERTICES: u64 = 6 * 65;
/// Bytes of one vertex: position (NDC) and uv.
const STRIDE: u64 = 16;

const SHADER: &str = r"
struct Out { @builtin(position) pos: vec4<f32>, @location(0) uv: vec2<f32> };
@vertex fn vs(@location(0) pos: vec2<f32>, @location(1) uv: vec2<f32>) -> Out {
    return Out(vec4<f32>(pos, 0.0, 1.0), uv);
}
@group(0) @binding(0) var picture: texture_2d<f32>;
@group(0) @binding(1) var nearest: sampler;
// The background where the picture leaves some: texture coordinates below 0.
const BACKGROUND: vec3<f32> = vec3<f32>(24.0, 26.0, 30.0) / 255.0;
@fragment fn fs(in: Out) -> @location(0) vec4<f32> {
    let picture = textureSample(picture, nearest, max(in.uv, vec2<f32>(0.0))).rgb;
    return vec4<f32>(select(picture, BACKGROUND, in.uv.x < 0.0), 1.0);
}
";

impl Resources {
    fn new(device: &wgpu::Device, target: wgpu::TextureFormat) -> Resources {
        let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("editor::picture"),
            source: wgpu::ShaderSource::Wgsl(SHADER.into()),
        });
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("editor::picture"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: true },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                    count: None,
                },
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("editor::picture"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("editor::picture"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &shader,
                entry_point: Some("vs"),
                compilation_options: Default::default(),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: STRIDE,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &wgpu::vertex_attr_array![0 => Float32x2, 1 => Float32x2],
                })],
            },
            fragment: Some(wgpu::FragmentState {
                module: &shader,
                entry_point: Some("fs"),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format: target,
                    blend: None,
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: None,
            multisample: wgpu::MultisampleState::default(),
            multiview_mask: None,
            cache: None,
        });
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("editor::picture"),
            mag_filter: wgpu::FilterMode::Nearest,
            min_filter: wgpu::FilterMode::Nearest,
            ..Default::default()
        });
        let vertices = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("editor::picture"),
            size: MAX_VERTICES * STRIDE,
            usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Resources {
            pipeline,
            layout,
            sampler,
            texture: None,
            vertices,
            count: 0,
        }
    }

    /// Uploads `image` (frame `number`) unless it is the one uploaded last; the texture is
    /// made again when the size changes. Its bytes are sRGB-encoded: viewed as sRGB when
    /// the target is, so what lands is the bytes either way.
    fn upload(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        target: wgpu::TextureFormat,
        number: u64,
        image: &ColorImage,
    ) {
        if self.texture.as_ref().is_some_and(|t| t.0 == number) {
            return;
        }
        let [w, h] = image.size;
        let size = wgpu::Extent3d {
            width: w as u32,
            height: h as u32,
            depth_or_array_layers: 1,
        };
        let texture = match self.texture.take() {
            Some((_, s, texture, group)) if s == image.size => (texture, group),
            _ => {
                let texture = device.create_texture(&wgpu::TextureDescriptor {
                    label: Some("editor::picture"),
                    size,
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: wgpu::TextureDimension::D2,
                    format: wgpu::TextureFormat::Rgba8Unorm,
                    usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
                    view_formats: &[wgpu::TextureFormat::Rgba8UnormSrgb],
                });
                let format = if target.is_srgb() {
                    wgpu::TextureFormat::Rgba8UnormSrgb
                } else {
                    wgpu::TextureFormat::Rgba8Unorm
                };
                let view = texture.create_view(&wgpu::TextureViewDescriptor {
                    format: Some(format),
                    ..Default::default()
                });
                let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("editor::picture"),
                    layout: &self.layout,
                    entries: &[
                        wgpu::BindGroupEntry {
                            binding: 0,
                            resource: wgpu::BindingResource::TextureView(&view),
                        },
                        wgpu::BindGroupEntry {
                            binding: 1,
                            resource: wgpu::BindingResource::Sampler(&self.sampler),
                        },
                    ],
                });
                (texture, group)
            }
        };
        let bytes: Vec<u8> = image.pixels.iter().flat_map(|c| c.to_array()).collect();
        queue.write_texture(
            texture.0.as_image_copy(),
            &bytes,
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(4 * w as u32),
                rows_per_image: Some(h as u32),
            },
            size,
        );
        self.texture = Some((number, image.size, texture.0, texture.1));
    }
}

impl egui_wgpu::CallbackTrait for Picture {
    fn prepare(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        _screen: &egui_wgpu::ScreenDescriptor,
        _encoder: &mut wgpu::CommandEncoder,
        resources: &mut egui_wgpu::CallbackResources,
    ) -> Vec<wgpu::CommandBuffer> {
        if !resources.contains::<Resources>() {
            resources.insert(Resources::new(device, self.target));
        }
        let Some(r) = resources.get_mut::<Resources>() else {
            return Vec::new();
        };
        r.upload(device, queue, self.target, self.frame.0, &self.frame.1);
        let (min, size) = (self.rect.min, self.rect.size());
        // A re-projected picture leaves an edge uncovered: the background first, drawn by
        // the same opaque pipeline (egui's fill under it was blended, pixel by pixel).
        let (area, held) = (self.rect, self.triangles.len() <= 6);
        let below = Pos2::new(-1.0, -1.0);
        let background = [
            (area.left_top(), below),
            (area.right_top(), below),
            (area.right_bottom(), below),
            (area.left_top(), below),
            (area.right_bottom(), below),
            (area.left_bottom(), below),
        ];
        let background = if held { &[][..] } else { &background[..] };
        let all = background.iter().chain(&self.triangles);
        let mut bytes = Vec::with_capacity((6 + self.triangles.len()) * STRIDE as usize);
        for (p, uv) in all.take(MAX_VERTICES as usize) {
            let x = (p.x - min.x) / size.x * 2.0 - 1.0;
            let y = 1.0 - (p.y - min.y) / size.y * 2.0;
            for v in [x, y, uv.x, uv.y] {
                bytes.extend_from_slice(&v.to_le_bytes());
            }
        }
        queue.write_buffer(&r.vertices, 0, &bytes);
        r.count = (bytes.len() as u64 / STRIDE) as u32;
        Vec::new()
    }

    fn paint(
        &self,
        _info: egui::PaintCallbackInfo,
        pass: &mut wgpu::RenderPass<'static>,
        resources: &egui_wgpu::CallbackResources,
    ) {
        let Some(r) = resources.get::<Resources>() else {
            return;
        };
        let Some((_, _, _, group)) = &r.texture else {
            return;
        };
        pass.set_pipeline(&r.pipeline);
        pass.set_bind_group(0, group, &[]);
        pass.set_vertex_buffer(0, r.vertices.slice(..));
        pass.draw(0..r.count, 0..1);
    }
}
