//! Cross-crate integration tests for Texel live in this package's `tests/` folder; this
//! library only holds helpers they share (paths into the repository).

use std::path::PathBuf;

/// The repository root (the folder that holds `assets/` and `shaders/`).
pub fn repo_root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .map(PathBuf::from)
        .unwrap_or_default()
}
