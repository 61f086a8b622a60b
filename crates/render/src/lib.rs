//! `texel_render` is Texel's renderer: it rasterizes the scene into cubemap probes, shades
//! each texel once (lights, ray-traced shadows, OKLab posterization, outlines), culls the
//! texels worth drawing and splats them as world-space quads, all on wgpu. It consumes a
//! plain `FrameInput` and never sees hecs, egui or winit, so its tests can build a frame by
//! hand and the same passes serve the runtime, the editor and the evaluator.
//!
//! The passes arrive with the core-renderer issue; the crate is thin until then.
