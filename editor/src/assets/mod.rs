//! The asset panel (View → Asset panel): the open level's project assets with thumbnails,
//! to drag into the viewport or add at the view's centre. `scan` finds the files (the walk
//! runs on a thread of its own: a frame waits for it [`WALK_WAIT`] at most, then the panel
//! says it is looking and the frames go on), `thumbs` makes their thumbnails off the UI
//! thread, `panel` draws them; the app places what is dropped or asked for
//! (`app::asset_chores`).

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{Receiver, RecvTimeoutError};
use std::time::Duration;

pub mod mesh_thumb;
pub mod panel;
pub mod scan;
pub mod thumbs;

pub use scan::{AssetFile, AssetKind, Scan};

/// How long a frame waits for a walk of the project folder before it goes on without it
/// (the usual walk, a few hundred files on a local disk, takes a few milliseconds).
pub const WALK_WAIT: Duration = Duration::from_millis(100);

/// What a tile dragged from the panel carries (egui's drag-and-drop payload).
#[derive(Debug, Clone, PartialEq)]
pub struct AssetDrag {
    /// The file.
    pub path: PathBuf,
    /// What it is.
    pub kind: AssetKind,
}

/// The panel between frames.
#[derive(Default)]
pub struct AssetPanel {
    /// Whether it is shown.
    pub open: bool,
    /// The last walk of the project folder (made when the panel opens on a level, and by
    /// Rescan).
    pub scan: Option<Scan>,
    /// The level the scan was made for.
    scanned_for: Option<PathBuf>,
    /// Thumbnails.
    pub thumbs: thumbs::Thumbnails,
    /// The kinds shown (all when empty).
    pub only: Option<AssetKind>,
    /// The tile last clicked.
    pub selected: Option<AssetDrag>,
    /// Walk the folder again on the next frame (the Rescan button).
    pub rescan: bool,
    /// Whether a walk answered for `scanned_for`.
    walked: bool,
    /// The walk under way, if one is: the level it is for, and where its answer comes.
    walking: Option<(Option<PathBuf>, Receiver<Option<Scan>>)>,
    /// While set, a walk waits before it starts (tests hold it to see the frames go on).
    held: Arc<AtomicBool>,
}

/// `file` relative to the folder of `level`, with `/` separators, as the level stores it: the
/// path as given when it leads there (so a file reached through a linked folder keeps the
/// link, `../meshes/a.glb`), else [`texel_scene::assets::relative_path`] (through the real
/// folders).
pub fn level_relative(level: &Path, file: &Path) -> String {
    let abs = |p: &Path| std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf());
    let (base, to) = (abs(level.parent().unwrap_or(Path::new("."))), abs(file));
    let shared = (base.components().zip(to.components()))
        .take_while(|(a, b)| a == b)
        .count();
    let mut parts: Vec<String> = (base.components().skip(shared))
        .map(|_| "..".to_owned())
        .collect();
    let rest = to.components().skip(shared);
    parts.extend(rest.map(|c| c.as_os_str().to_string_lossy().into_owned()));
    let lexical = parts.join("/");
    let same = |a: &Path, b: &Path| match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    };
    if shared > 1 && same(&base.join(&lexical), file) {
        lexical
    } else {
        texel_scene::assets::relative_path(level, file)
    }
}

impl AssetPanel {
    /// Walks the project folder of `level` again if the level changed since the last walk (or
    /// `force`), on a thread of its own: waits for it [`WALK_WAIT`] at most, and takes its
    /// answer on a later call when it is longer (asking `ctx` for a frame then). An untitled
    /// level has no project folder.
    pub fn refresh(&mut self, ctx: &egui::Context, level: Option<&Path>, force: bool) {
        let level = level.map(Path::to_path_buf);
        let walking_for = self.walking.as_ref().map(|w| &w.0);
        let current = match walking_for {
            Some(l) => *l == level,
            None => self.walked && self.scanned_for == level,
        };
        if force || !current {
            self.walking = Some((level.clone(), self.walk(ctx, level.as_deref())));
            self.selected = None;
            if self.scanned_for != level {
                self.scan = None;
            }
        }
        let Some((for_level, answer)) = &self.walking else {
            return;
        };
        let wait = if force || !current {
            WALK_WAIT
        } else {
            Duration::ZERO
        };
        match answer.recv_timeout(wait) {
            Ok(scan) => {
                self.scan = scan;
                self.scanned_for = for_level.clone();
                self.walked = true;
                self.walking = None;
            }
            Err(RecvTimeoutError::Timeout) => {}
            // The walk's thread is gone (it panicked): no list, and no walk under way.
            Err(RecvTimeoutError::Disconnected) => {
                self.scan = None;
                self.scanned_for = for_level.clone();
                self.walked = true;
                self.walking = None;
            }
        }
    }

    /// Whether a walk of the project folder is under way.
    pub fn walking(&self) -> bool {
        self.walking.is_some()
    }

    /// Holds the walks (a walk started waits before it begins) or lets them go on.
    pub fn hold_walks(&self, held: bool) {
        self.held.store(held, Ordering::SeqCst);
    }

    /// Starts a walk of `level`'s project folder on its own thread.
    fn walk(&self, ctx: &egui::Context, level: Option<&Path>) -> Receiver<Option<Scan>> {
        let (tx, rx) = std::sync::mpsc::channel();
        let root = level.and_then(scan::project_root);
        let (ctx, held) = (ctx.clone(), self.held.clone());
        let spawned = std::thread::Builder::new()
            .name("asset folder walk".into())
            .spawn(move || {
                while held.load(Ordering::SeqCst) {
                    std::thread::sleep(Duration::from_millis(5));
                }
                let _ = tx.send(root.map(|root| scan::scan(&root)));
                ctx.request_repaint();
            });
        if let Err(e) = spawned {
            eprintln!("texel-editor: no thread for the asset folder walk: {e}");
        }
        rx
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_linked_folder_stays_in_the_relative_path() {
        let dir = tempfile::tempdir().unwrap();
        let real = dir.path().join("real");
        std::fs::create_dir_all(&real).unwrap();
        std::fs::write(real.join("m.glb"), b"x").unwrap();
        std::fs::create_dir_all(dir.path().join("p/levels")).unwrap();
        std::os::unix::fs::symlink(&real, dir.path().join("p/meshes")).unwrap();
        let level = dir.path().join("p/levels/a.ron");
        let file = dir.path().join("p/meshes/m.glb");
        assert_eq!(level_relative(&level, &file), "../meshes/m.glb");
        // The scene's own function goes through the link's target.
        assert_eq!(
            texel_scene::assets::relative_path(&level, &file),
            "../../real/m.glb"
        );
    }
}
