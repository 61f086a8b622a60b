//! `texel_probes` holds the CPU side of texel splatting: cube-face conventions, grid
//! snapping of probe origins (with probe-grid override volumes), the probe lifecycle and
//! crossfade, and per-frame update plans. It exists so that all of this math can be tested
//! without a GPU and without the scene ECS: it depends on `glam` alone.
//!
//! Modules, in the order a frame uses them:
//! - [`grid`]: snap the camera to the probe grid, honouring override volumes;
//! - [`probe_set`]: eye / grid / previous probes, their storage slots and the crossfade;
//! - [`visibility`]: which faces of a probe can reach the camera frustum;
//! - [`schedule`]: which faces to capture and shade this frame, within a budget;
//! - [`cube`]: the cube-face convention, texel directions, splat quads, face matrices;
//! - [`ortho`]: the one orthographic face that serves an orthographic camera;
//! - [`bayer`]: the 4×4 dither that splits pixels between previous and grid;
//! - [`resolution`]: face resolution from an on-screen pixel size.
//!
//! A frame:
//! `grid::resolve_grid` → `ProbeSet::begin_frame` → `Scheduler::plan` → (GPU work) →
//! `Scheduler::commit` → `ProbeSet::advance_fade(plan.readiness())` → draw at the
//! `fade_t` it leaves (the plan's captures come before the splats).

pub mod bayer;
pub mod cube;
pub mod grid;
pub mod ortho;
pub mod placement;
pub mod probe_set;
pub mod resolution;
pub mod schedule;
pub mod visibility;
