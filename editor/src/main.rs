//! `texel-editor [level.ron]`: the egui level editor. The binary only reads its argument and
//! hands over to [`texel_editor::run`], so tests drive the same code.

use std::process::ExitCode;

fn main() -> ExitCode {
    let arg = std::env::args_os().nth(1);
    if arg.as_deref().is_some_and(|a| a == "--help" || a == "-h") {
        println!(
            "texel-editor [LEVEL.ron]\n\nOpens the level editor on LEVEL (default: \
             assets/levels/stone_circle.ron). Needs a display; to render a level without one, \
             use `texel-run render LEVEL --out DIR`."
        );
        return ExitCode::SUCCESS;
    }
    match texel_editor::run(arg.map(std::path::PathBuf::from)) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("texel-editor: {e:#}");
            if std::env::var_os("DISPLAY").is_none()
                && std::env::var_os("WAYLAND_DISPLAY").is_none()
            {
                eprintln!(
                    "texel-editor: no display; to render a level without one, use \
                     `cargo run -p texel_runtime --bin texel-run -- render LEVEL --out DIR`"
                );
            }
            ExitCode::FAILURE
        }
    }
}
