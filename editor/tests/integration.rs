//! The package's integration tests, one module a file, in one test binary: one link
//! instead of one a file, and on the second driver one process (and one compile of
//! each pipeline) instead of one a file (`cargo xtask test`, xtask/src/plan.rs).
//! `tests/tests/architecture.rs` checks that every file of `tests/` is reached.

mod flat_terrain;
mod support;

mod animator;
mod assets;
mod debug_views_gpu;
mod flows;
mod groups;
mod groups_gpu;
mod kill_recovery;
mod many;
mod paint;
mod palette;
mod palette_gpu;
mod play_physics;
mod render_worker;
mod snap_and_outliner;
mod sprite;
mod sprite_gpu;
mod terrain;
mod textures;
mod town_edits;
mod viewport_gpu;
mod views_and_handles;
