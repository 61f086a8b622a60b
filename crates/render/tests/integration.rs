//! The package's integration tests, one module a file, in one test binary: one link
//! instead of one a file, and on the second driver one process (and one compile of
//! each pipeline) instead of one a file (`cargo xtask test`, xtask/src/plan.rs).
//! `tests/tests/architecture.rs` checks that every file of `tests/` is reached.

mod common;

mod baselines;
mod bvh_gpu;
mod convention;
mod culling;
mod edge_roots;
mod editor_support;
mod far_field;
mod first_light;
mod gpu_errors;
mod instancing;
mod light_grid;
mod moving;
mod outline_strips;
mod sprites;
mod terrain_fields;
