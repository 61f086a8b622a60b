//! The render passes, one module and one WGSL file each. Each pass owns its pipeline and
//! layouts, built once; `frame.rs` is the only place that orders them.

pub mod background;
pub mod capture;
pub mod cull;
pub mod present;
pub mod shade;
pub mod splat;
pub mod visible;

/// Stride of per-face uniform records addressed with dynamic offsets.
pub const UNIFORM_STRIDE: u64 = 256;

/// A bind group layout entry visible to `stages`.
pub(crate) fn entry(
    binding: u32,
    stages: wgpu::ShaderStages,
    ty: wgpu::BindingType,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: stages,
        ty,
        count: None,
    }
}

/// A uniform buffer binding (optionally with a dynamic offset).
pub(crate) fn uniform(dynamic: bool) -> wgpu::BindingType {
    wgpu::BindingType::Buffer {
        ty: wgpu::BufferBindingType::Uniform,
        has_dynamic_offset: dynamic,
        min_binding_size: None,
    }
}

/// A storage buffer binding.
pub(crate) fn storage(read_only: bool) -> wgpu::BindingType {
    wgpu::BindingType::Buffer {
        ty: wgpu::BufferBindingType::Storage { read_only },
        has_dynamic_offset: false,
        min_binding_size: None,
    }
}

/// A `texture_2d_array` (or `texture_2d`) binding of `sample` type, read with textureLoad.
pub(crate) fn texture(
    sample: wgpu::TextureSampleType,
    dim: wgpu::TextureViewDimension,
) -> wgpu::BindingType {
    wgpu::BindingType::Texture {
        sample_type: sample,
        view_dimension: dim,
        multisampled: false,
    }
}

/// Unfilterable float sample type (textureLoad only).
pub(crate) const FLOAT: wgpu::TextureSampleType =
    wgpu::TextureSampleType::Float { filterable: false };
/// Unsigned integer sample type.
pub(crate) const UINT: wgpu::TextureSampleType = wgpu::TextureSampleType::Uint;
/// 2D array views.
pub(crate) const ARRAY: wgpu::TextureViewDimension = wgpu::TextureViewDimension::D2Array;

/// Byte sizes of the Rust records shared with WGSL, by their WGSL struct name and the shader
/// file that declares them: a test reflects every shader with naga and compares, so a field
/// added on one side only cannot slip through.
pub fn shared_layouts() -> Vec<(&'static str, &'static str, usize)> {
    vec![
        ("capture.wgsl", "FaceParams", capture::FACE_PARAMS_SIZE),
        ("shade.wgsl", "ShadeFace", shade::SHADE_FACE_SIZE),
        (
            "shade.wgsl",
            "ShadeGlobals",
            size_of::<shade::ShadeGlobals>(),
        ),
        (
            "shade.wgsl",
            "Object",
            size_of::<crate::gpu_scene::GpuObject>(),
        ),
        (
            "shade.wgsl",
            "PointLight",
            size_of::<crate::gpu_scene::GpuPointLight>(),
        ),
        ("shade.wgsl", "BvhNode", size_of::<crate::bvh::BvhNode>()),
        (
            "shade.wgsl",
            "BvhTriangle",
            size_of::<crate::bvh::BvhTriangle>(),
        ),
        (
            "cull.wgsl",
            "ViewGlobals",
            size_of::<crate::view::ViewGlobals>(),
        ),
        ("cull.wgsl", "SlotView", size_of::<crate::view::SlotView>()),
        ("cull.wgsl", "CullWork", cull::CULL_WORK_SIZE),
        ("cull.wgsl", "DrawArgs", size_of::<cull::DrawArgs>()),
        ("cull.wgsl", "Splat", cull::SPLAT_BYTES as usize),
        ("present.wgsl", "Sizes", present::SIZES_SIZE),
    ]
}
