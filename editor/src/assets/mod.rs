//! The asset panel (View → Asset panel): the open level's project assets with thumbnails,
//! to drag into the viewport or add at the view's centre. `scan` finds the files, `thumbs`
//! makes their thumbnails off the UI thread, `panel` draws them; the app places what is
//! dropped or asked for (`app::asset_chores`).

use std::path::{Path, PathBuf};

pub mod mesh_thumb;
pub mod panel;
pub mod scan;
pub mod thumbs;

pub use scan::{AssetFile, AssetKind, Scan};

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
    /// `force`). An untitled level has no project folder.
    pub fn refresh(&mut self, level: Option<&Path>, force: bool) {
        let level = level.map(Path::to_path_buf);
        if !force && self.scan.is_some() && self.scanned_for == level {
            return;
        }
        self.scan = (level.as_deref())
            .and_then(scan::project_root)
            .map(|root| scan::scan(&root));
        self.scanned_for = level;
        self.selected = None;
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
