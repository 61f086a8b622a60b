//! The package's integration tests, one module a file, in one test binary: one link
//! instead of one a file, and on the second driver one process (and one compile of
//! each pipeline) instead of one a file (`cargo xtask test`, xtask/src/plan.rs).
//! `tests/tests/architecture.rs` checks that every file of `tests/` is reached.

mod calibration;
mod cli;
mod compare;
mod hostile_reports;
mod look;
mod reference;
mod scale;
