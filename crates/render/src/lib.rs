//! `texel_render` is Texel's renderer: it rasterizes the scene into cubemap probes, shades
//! each texel once (lights, ray-traced shadows, OKLab posterization, outlines), culls the
//! texels worth drawing and splats them as world-space quads, all on wgpu. It consumes a
//! plain [`input::FrameInput`] and never sees hecs, egui or winit, so its tests can build a
//! frame by hand and the same passes serve the runtime, the editor and the evaluator.
//!
//! Modules: [`context`] opens the GPU; [`input`] is the data it consumes; [`error`] is why
//! a frame fails; [`gpu_scene`] and
//! [`bvh`] upload the scene; [`probe_store`] holds the probe textures; [`passes`] are the
//! passes, one per WGSL file in `shaders/`, whose modules and pipelines [`pipeline_cache`]
//! makes once per device; [`frame`] orders them; [`stats`] is what a frame
//! reports; [`layouts`] lists the records Rust and WGSL share.

pub mod baselines;
pub mod bvh;
pub mod context;
pub mod error;
pub mod far_field;
pub mod frame;
pub mod gpu_scene;
pub mod gpu_sprites;
pub mod input;
pub mod layouts;
pub mod memory;
pub mod palette;
pub mod passes;
pub mod pipeline_cache;
pub mod probe_store;
pub mod readback;
pub mod shader;
pub mod shadow_region;
pub mod stats;
pub mod target;
pub mod textures;
mod timing;
pub mod validate;
pub mod view;
