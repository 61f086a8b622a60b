//! `texel-editor [--stats FILE] [LEVEL.ron]`: the egui level editor. The binary only reads
//! its arguments and hands over to [`texel_editor::run`], so tests drive the same code.

use std::path::PathBuf;
use std::process::ExitCode;

const USAGE: &str = "texel-editor [--stats FILE] [LEVEL.ron]\n\n\
Opens the level editor on LEVEL (default: assets/levels/stone_circle.ron). Needs a display; \
to render a level without one, use `texel-run render LEVEL --out DIR`.\n\n\
Options:\n  --stats FILE  append the status bar's figures to FILE as JSON lines, one a second \
(UI frame, viewport render, edit to frame, uploads, entities)\n  -h, --help    print this";

/// The level and the stats file of the command line, or why it is wrong.
fn parse(args: &[String]) -> Result<(Option<PathBuf>, Option<PathBuf>), String> {
    let (mut level, mut stats) = (None, None);
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "--stats" => {
                let f = it.next().ok_or("--stats needs a FILE")?;
                stats = Some(PathBuf::from(f));
            }
            flag if flag.starts_with('-') => return Err(format!("unknown option {flag}")),
            _ if level.is_some() => return Err(format!("one level only, not also {a}")),
            _ => level = Some(PathBuf::from(a)),
        }
    }
    Ok((level, stats))
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.iter().any(|a| a == "--help" || a == "-h") {
        println!("{USAGE}");
        return ExitCode::SUCCESS;
    }
    let (level, stats) = match parse(&args) {
        Ok(v) => v,
        Err(e) => {
            eprintln!("texel-editor: {e}\n\n{USAGE}");
            return ExitCode::from(2);
        }
    };
    match texel_editor::run(level, stats) {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arguments_are_a_level_and_a_stats_file() {
        let s = |v: &[&str]| v.iter().map(|a| (*a).to_owned()).collect::<Vec<_>>();
        assert_eq!(parse(&s(&[])), Ok((None, None)));
        assert_eq!(
            parse(&s(&["--stats", "s.jsonl", "a.ron"])),
            Ok((Some("a.ron".into()), Some("s.jsonl".into())))
        );
        assert!(parse(&s(&["--stats"])).unwrap_err().contains("FILE"));
        assert!(parse(&s(&["--frob"])).unwrap_err().contains("--frob"));
        assert!(
            parse(&s(&["a.ron", "b.ron"]))
                .unwrap_err()
                .contains("b.ron")
        );
    }
}
