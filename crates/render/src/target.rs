//! Offscreen colour targets and reading textures back to the CPU.

use crate::context::{GpuContext, GpuError};

/// The colour format the baselines write offscreen (sRGB, so PNGs look as on screen).
pub const OFFSCREEN_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;

/// The format the texel renderer draws offscreen: sRGB-encoded bytes in a plain unorm
/// texture (the renderer encodes in its shaders; see `Renderer::new`).
pub const FRAME_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

/// A texture to render into and read back.
pub struct OffscreenTarget {
    /// The texture.
    pub texture: wgpu::Texture,
    /// Its view.
    pub view: wgpu::TextureView,
    /// Width and height.
    pub size: (u32, u32),
}

impl OffscreenTarget {
    /// A new `width × height` target of [`OFFSCREEN_FORMAT`].
    pub fn new(ctx: &GpuContext, width: u32, height: u32) -> Self {
        Self::with_format(ctx, width, height, OFFSCREEN_FORMAT)
    }

    /// A new `width × height` target of an RGBA8 `format`.
    pub fn with_format(
        ctx: &GpuContext,
        width: u32,
        height: u32,
        format: wgpu::TextureFormat,
    ) -> Self {
        let texture = ctx.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("target::offscreen"),
            size: wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let view = texture.create_view(&Default::default());
        OffscreenTarget {
            texture,
            view,
            size: (width, height),
        }
    }

    /// Reads the target back as tightly packed RGBA8 rows.
    pub fn read_rgba(&self, ctx: &GpuContext) -> Result<Vec<u8>, GpuError> {
        read_texture_layer(ctx, &self.texture, 0, 4)
    }
}

/// Reads one array layer of a 2D texture with `bytes_per_texel` bytes per texel, tightly
/// packed (row padding removed).
pub fn read_texture_layer(
    ctx: &GpuContext,
    texture: &wgpu::Texture,
    layer: u32,
    bytes_per_texel: u32,
) -> Result<Vec<u8>, GpuError> {
    let size = glam::UVec2::new(texture.width(), texture.height());
    read_texture_region(
        ctx,
        texture,
        layer,
        glam::UVec2::ZERO,
        size,
        bytes_per_texel,
    )
}

/// Reads the `size` texels from `origin` of one array layer of a 2D texture with
/// `bytes_per_texel` bytes per texel, tightly packed (row padding removed): the one texture
/// read-back (whole layers, the editor's picked texel).
pub fn read_texture_region(
    ctx: &GpuContext,
    texture: &wgpu::Texture,
    layer: u32,
    origin: glam::UVec2,
    size: glam::UVec2,
    bytes_per_texel: u32,
) -> Result<Vec<u8>, GpuError> {
    let (w, h) = (size.x, size.y);
    let row = w * bytes_per_texel;
    let padded =
        row.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let buffer = ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("target::readback"),
        size: u64::from(padded) * u64::from(h),
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut enc = ctx.device.create_command_encoder(&Default::default());
    enc.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: 0,
            origin: wgpu::Origin3d {
                x: origin.x,
                y: origin.y,
                z: layer,
            },
            aspect: wgpu::TextureAspect::All,
        },
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded),
                rows_per_image: Some(h),
            },
        },
        wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
    );
    ctx.queue.submit([enc.finish()]);
    let data = read_buffer(ctx, &buffer)?;
    let mut out = Vec::with_capacity((row * h) as usize);
    for y in 0..h as usize {
        let start = y * padded as usize;
        out.extend_from_slice(&data[start..start + row as usize]);
    }
    Ok(out)
}

/// Maps a `MAP_READ` buffer and copies it out (waits for the GPU).
pub fn read_buffer(ctx: &GpuContext, buffer: &wgpu::Buffer) -> Result<Vec<u8>, GpuError> {
    let slice = buffer.slice(..);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    ctx.wait_idle()?;
    rx.recv()
        .map_err(|e| GpuError::Readback(e.to_string()))?
        .map_err(|e| GpuError::Readback(e.to_string()))?;
    let bytes = slice
        .get_mapped_range()
        .map_err(|e| GpuError::Readback(e.to_string()))?
        .to_vec();
    buffer.unmap();
    Ok(bytes)
}
