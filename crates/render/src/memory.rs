//! What the renderer holds on the GPU, in bytes, by what it is for: the scene's geometry
//! and records, its shadow trees, its textures and sprite sheets, and the probes' faces.
//! Sizes are those of the buffers and textures created (a driver may round them up).

use serde::Serialize;

/// GPU bytes by use.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct GpuMemory {
    /// Vertices, object and surface records, lights, motions, terrain records and heights.
    pub scene: u64,
    /// Shadow-ray trees: nodes, triangles, instances, heightfield trees.
    pub bvh: u64,
    /// The texture atlas and the sprites' frames and records.
    pub textures: u64,
    /// The probe slots' faces (every layer of every slot) and draw lists.
    pub probes: u64,
}

impl GpuMemory {
    /// Everything.
    pub fn total(&self) -> u64 {
        self.scene + self.bvh + self.textures + self.probes
    }
}

/// Bytes of `texture`: every mip level of every layer, at its format's block size.
pub fn texture_bytes(texture: &wgpu::Texture) -> u64 {
    let size = texture.size();
    let format = texture.format();
    let (bw, bh) = format.block_dimensions();
    let block = u64::from(format.block_copy_size(None).unwrap_or(4));
    (0..texture.mip_level_count())
        .map(|m| {
            let w = (size.width >> m).max(1).div_ceil(bw);
            let h = (size.height >> m).max(1).div_ceil(bh);
            u64::from(w) * u64::from(h) * u64::from(size.depth_or_array_layers) * block
        })
        .sum()
}

/// Sum of the buffers' sizes.
pub fn buffer_bytes(buffers: &[&wgpu::Buffer]) -> u64 {
    buffers.iter().map(|b| b.size()).sum()
}
