//! Finding a project's assets: the folder an open level belongs to, walked with bounds (a
//! depth, a number of entries, hidden and build folders skipped), symlinks followed but each
//! folder walked once (a link back up the tree ends there), each file sorted by its extension
//! into meshes, textures, sprite sheets and palettes.

use std::collections::HashSet;
use std::path::{Path, PathBuf};

/// How deep below the project folder the walk looks.
pub const MAX_DEPTH: usize = 8;
/// How many directory entries the walk reads at most; past them it stops and says so.
pub const MAX_ENTRIES: usize = 4000;

/// What an asset file is to the editor.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum AssetKind {
    /// A glTF mesh (`.gltf`, `.glb`).
    Mesh,
    /// A PNG or JPEG image outside a `sprites` folder.
    Texture,
    /// A PNG or JPEG image inside a `sprites` folder.
    Sprite,
    /// A palette file (`.gpl`, `.hex`, `.pal`).
    Palette,
}

impl AssetKind {
    /// Every kind, in the panel's order.
    pub const ALL: [AssetKind; 4] = [
        AssetKind::Mesh,
        AssetKind::Texture,
        AssetKind::Sprite,
        AssetKind::Palette,
    ];

    /// The kind's name in the panel, plural.
    pub fn label(self) -> &'static str {
        match self {
            AssetKind::Mesh => "Meshes",
            AssetKind::Texture => "Textures",
            AssetKind::Sprite => "Sprites",
            AssetKind::Palette => "Palettes",
        }
    }

    /// Whether the file is an image (its thumbnail is the image itself).
    pub fn is_image(self) -> bool {
        matches!(self, AssetKind::Texture | AssetKind::Sprite)
    }
}

/// One asset file found.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AssetFile {
    /// Where it is.
    pub path: PathBuf,
    /// Its path below the project folder, with `/` separators (what the panel shows).
    pub shown: String,
    /// What it is.
    pub kind: AssetKind,
}

/// What a walk of a project folder found.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Scan {
    /// The folder walked.
    pub root: PathBuf,
    /// The assets, by kind, then by path.
    pub files: Vec<AssetFile>,
    /// Whether the walk stopped at [`MAX_ENTRIES`] (more may be there).
    pub truncated: bool,
}

/// The project folder of the level at `level`: the folder holding its `levels` folder when
/// it lies in one (`project/levels/x.ron` → `project`, beside `meshes/`, `textures/`, …),
/// else the level's own folder.
pub fn project_root(level: &Path) -> Option<PathBuf> {
    let folder = level.parent()?;
    let folder = if folder.as_os_str().is_empty() {
        Path::new(".")
    } else {
        folder
    };
    match (folder.file_name(), folder.parent()) {
        (Some(name), Some(up)) if name == "levels" && !up.as_os_str().is_empty() => {
            Some(up.to_path_buf())
        }
        _ => Some(folder.to_path_buf()),
    }
}

/// What `path`'s extension makes of it (`in_sprites`: it lies in a `sprites` folder).
pub fn kind_of(path: &Path, in_sprites: bool) -> Option<AssetKind> {
    let ext = path.extension()?.to_string_lossy().to_lowercase();
    match ext.as_str() {
        "gltf" | "glb" => Some(AssetKind::Mesh),
        "png" | "jpg" | "jpeg" if in_sprites => Some(AssetKind::Sprite),
        "png" | "jpg" | "jpeg" => Some(AssetKind::Texture),
        "gpl" | "hex" | "pal" => Some(AssetKind::Palette),
        _ => None,
    }
}

/// Walks `root` for assets (see the module's description).
pub fn scan(root: &Path) -> Scan {
    let mut out = Scan {
        root: root.to_path_buf(),
        ..Scan::default()
    };
    let mut seen = HashSet::new();
    let mut entries = 0usize;
    // (folder, depth, shown prefix, inside a sprites folder)
    let mut stack = vec![(root.to_path_buf(), 0usize, String::new(), false)];
    while let Some((dir, depth, prefix, in_sprites)) = stack.pop() {
        let Ok(real) = dir.canonicalize() else {
            continue;
        };
        if !seen.insert(real) {
            continue;
        }
        let Ok(read) = std::fs::read_dir(&dir) else {
            continue;
        };
        for entry in read.flatten() {
            entries += 1;
            if entries > MAX_ENTRIES {
                out.truncated = true;
                stack.clear();
                break;
            }
            let name = entry.file_name().to_string_lossy().into_owned();
            if name.starts_with('.') || name == "target" || name == "node_modules" {
                continue;
            }
            let path = entry.path();
            let shown = format!("{prefix}{name}");
            // `metadata` follows links: a linked folder is walked (once, by its real path).
            let Ok(meta) = std::fs::metadata(&path) else {
                continue;
            };
            if meta.is_dir() {
                if depth < MAX_DEPTH {
                    let sprites = in_sprites || name.eq_ignore_ascii_case("sprites");
                    stack.push((path, depth + 1, format!("{shown}/"), sprites));
                }
            } else if let Some(kind) = kind_of(&path, in_sprites) {
                out.files.push(AssetFile { path, shown, kind });
            }
        }
    }
    out.files
        .sort_by(|a, b| (a.kind, &a.shown).cmp(&(b.kind, &b.shown)));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_project_is_the_folder_above_levels() {
        assert_eq!(
            project_root(Path::new("/p/levels/a.ron")),
            Some(PathBuf::from("/p"))
        );
        assert_eq!(
            project_root(Path::new("/p/maps/a.ron")),
            Some(PathBuf::from("/p/maps"))
        );
        assert_eq!(project_root(Path::new("a.ron")), Some(PathBuf::from(".")));
    }

    #[test]
    fn kinds_follow_extensions_and_the_sprites_folder() {
        assert_eq!(kind_of(Path::new("a.GLB"), false), Some(AssetKind::Mesh));
        assert_eq!(kind_of(Path::new("a.png"), false), Some(AssetKind::Texture));
        assert_eq!(kind_of(Path::new("a.png"), true), Some(AssetKind::Sprite));
        assert_eq!(kind_of(Path::new("a.hex"), true), Some(AssetKind::Palette));
        assert_eq!(kind_of(Path::new("a.ron"), false), None);
        assert_eq!(kind_of(Path::new("README"), false), None);
    }

    #[test]
    fn a_link_loop_is_walked_once_and_entries_are_bounded() {
        let dir = tempfile::tempdir().unwrap();
        let sprites = dir.path().join("sprites");
        std::fs::create_dir_all(&sprites).unwrap();
        std::fs::write(sprites.join("a.png"), b"x").unwrap();
        std::fs::write(dir.path().join("m.glb"), b"x").unwrap();
        // A link back to the root: without the seen set this would loop to MAX_DEPTH.
        std::os::unix::fs::symlink(dir.path(), sprites.join("up")).unwrap();
        let found = scan(dir.path());
        let shown: Vec<_> = found
            .files
            .iter()
            .map(|f| (f.kind, f.shown.as_str()))
            .collect();
        assert_eq!(
            shown,
            vec![
                (AssetKind::Mesh, "m.glb"),
                (AssetKind::Sprite, "sprites/a.png")
            ]
        );
        assert!(!found.truncated);
        let many = dir.path().join("many");
        std::fs::create_dir_all(&many).unwrap();
        for i in 0..MAX_ENTRIES {
            std::fs::write(many.join(format!("{i}.txt")), b"").unwrap();
        }
        assert!(scan(dir.path()).truncated);
    }
}
