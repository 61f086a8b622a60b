//! `texel-editor [level.ron]`: the egui level editor. The binary only reads its argument and
//! hands over to [`texel_editor::run`], so tests drive the same code.

fn main() -> anyhow::Result<()> {
    let path = std::env::args_os().nth(1).map(std::path::PathBuf::from);
    texel_editor::run(path)
}
