//! `texel_render`: wgpu passes.
