//! The package's integration tests, one module a file, in one test binary: one link
//! instead of one a file, and on the second driver one process (and one compile of
//! each pipeline) instead of one a file (`cargo xtask test`, xtask/src/plan.rs).
//! `tests/tests/architecture.rs` checks that every file of `tests/` is reached.

mod cli;
mod edit_gpu;
mod hostile;
mod look_gpu;
mod occlusion_gpu;
mod play_window;
mod sculpt_gpu;
mod sprites;
