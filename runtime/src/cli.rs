//! The `texel-run` command line.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use texel_scene::Level;

use crate::load::load_level;

/// Plays, renders and checks Texel levels.
#[derive(Debug, Parser)]
#[command(name = "texel-run", version, about)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Load a level and every asset it refers to; print a summary. Exits 2 on a bad level.
    Check {
        /// The level file (.ron).
        level: PathBuf,
    },
    /// Rewrite a level in canonical form (atomically), as the editor would save it.
    Fmt {
        /// The level files (.ron).
        #[arg(required = true)]
        levels: Vec<PathBuf>,
        /// Only report files that are not canonical; change nothing (exit 1 if any).
        #[arg(long)]
        check: bool,
    },
}

/// Exit status for a bad level or asset.
pub const EXIT_BAD_INPUT: u8 = 2;

/// Runs a parsed command line; errors are printed to stderr as `path:line:column: message`.
pub fn run(cli: Cli) -> ExitCode {
    match cli.command {
        Command::Check { level } => check(&level),
        Command::Fmt { levels, check } => fmt(&levels, check),
    }
}

fn check(path: &std::path::Path) -> ExitCode {
    match load_level(path) {
        Ok(loaded) => {
            println!(
                "{}: ok: {}; {} mesh files ({} triangles)",
                path.display(),
                loaded.scene.kind_counts(),
                loaded.meshes.len(),
                loaded.meshes.triangle_count()
            );
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("{e}");
            ExitCode::from(EXIT_BAD_INPUT)
        }
    }
}

fn fmt(paths: &[PathBuf], check_only: bool) -> ExitCode {
    let mut status = ExitCode::SUCCESS;
    for path in paths {
        let result = (|| {
            let level = Level::load(path)?;
            let canonical = level.to_ron_string(path)?;
            let current = std::fs::read_to_string(path).unwrap_or_default();
            if canonical == current {
                return Ok(false);
            }
            if !check_only {
                level.save(path)?;
            }
            Ok::<bool, texel_scene::LevelError>(true)
        })();
        match result {
            Ok(true) if check_only => {
                println!("{}: not canonical", path.display());
                status = ExitCode::FAILURE;
            }
            Ok(true) => println!("{}: rewritten", path.display()),
            Ok(false) => {}
            Err(e) => {
                eprintln!("{e}");
                return ExitCode::from(EXIT_BAD_INPUT);
            }
        }
    }
    status
}
