//! `texel-run`: see `texel-run --help`.

use clap::Parser;

fn main() -> std::process::ExitCode {
    texel_runtime::cli::run(texel_runtime::cli::Cli::parse())
}
