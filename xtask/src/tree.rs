//! Tests write into temporary directories, never into the source tree: the files git does
//! not track (untracked or ignored, `target/` aside) are listed before the run and after
//! each test step, and a new one fails the step by name. An autosave a test left beside a
//! bundled level, for one, was offered back to every later editor test that opened it.

use std::collections::BTreeSet;
use std::process::Command;

use crate::{Failure, workspace_root};

/// The files and folders git does not track, as `git status` names them; `None` outside a
/// git checkout (then nothing is checked, which the run says).
pub(crate) fn untracked() -> Option<BTreeSet<String>> {
    let out = Command::new("git")
        .args([
            "status",
            "--porcelain=v1",
            "--ignored",
            "--untracked-files=normal",
        ])
        .current_dir(workspace_root())
        .output()
        .ok()
        .filter(|o| o.status.success())?;
    Some(parse_status(&String::from_utf8_lossy(&out.stdout)))
}

/// The untracked (`??`) and ignored (`!!`) paths of `git status --porcelain` output, but
/// the build's own `target/`.
fn parse_status(text: &str) -> BTreeSet<String> {
    text.lines()
        .filter_map(|l| l.strip_prefix("?? ").or_else(|| l.strip_prefix("!! ")))
        .filter(|p| *p != "target/" && !p.starts_with("target/"))
        .map(str::to_owned)
        .collect()
}

/// Fails naming what `step` left in the tree that was not there `before`.
pub(crate) fn check(before: Option<&BTreeSet<String>>, step: &str) -> Result<(), Failure> {
    let (Some(before), Some(after)) = (before, untracked()) else {
        return Ok(());
    };
    let new: Vec<&String> = after.difference(before).collect();
    if new.is_empty() {
        return Ok(());
    }
    let list: Vec<&str> = new.iter().map(|s| s.as_str()).collect();
    Err(Failure::new(format!(
        "{step} wrote into the source tree: {}. Tests write into temporary directories \
         (tempfile); remove these files and fix the test that made them.",
        list.join(", ")
    )))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn untracked_and_ignored_paths_are_read_and_target_is_left_out() {
        let text = " M README.md\n?? new.txt\n!! target/\n!! assets/levels/a.autosave.ron\n";
        let got = parse_status(text);
        let want: BTreeSet<String> = ["new.txt", "assets/levels/a.autosave.ron"]
            .into_iter()
            .map(str::to_owned)
            .collect();
        assert_eq!(got, want);
    }
}
