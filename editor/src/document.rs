//! The document being edited: a scene, the meshes and textures it refers to, and where it is saved.

use std::path::{Path, PathBuf};

use texel_runtime::load::{LoadedLevel, load_level};
use texel_scene::assets::{AssetLibrary, load_assets, texture_paths};
use texel_scene::{EntityRow, Geometry, Scene};

/// A level open in the editor.
pub struct Document {
    /// The scene and its assets; `level.path` is where they are resolved from.
    pub level: LoadedLevel,
    /// Where the document is saved; `None` until the first Save As.
    pub path: Option<PathBuf>,
    /// Bumped on every change, so views know when to rebuild what they derive.
    pub revision: u64,
}

impl Document {
    /// An empty, unsaved level with default settings.
    pub fn new_empty() -> Self {
        Document {
            level: LoadedLevel {
                path: PathBuf::from("untitled.ron"),
                scene: Scene::new(),
                assets: AssetLibrary::default(),
            },
            path: None,
            revision: 0,
        }
    }

    /// Loads `path` and its meshes and textures. The error names the file, line and column.
    pub fn open(path: &Path) -> Result<Self, String> {
        let level = load_level(path).map_err(|e| e.to_string())?;
        Ok(Document {
            level,
            path: Some(path.to_owned()),
            revision: 0,
        })
    }

    /// The scene.
    pub fn scene(&self) -> &Scene {
        &self.level.scene
    }

    /// The scene, for commands.
    pub fn scene_mut(&mut self) -> &mut Scene {
        self.revision += 1;
        &mut self.level.scene
    }

    /// Saves atomically to `path` and makes it the document's path.
    pub fn save_as(&mut self, path: &Path) -> Result<(), String> {
        self.level.scene.save(path).map_err(|e| e.to_string())?;
        self.path = Some(path.to_owned());
        self.level.path = path.to_owned();
        Ok(())
    }

    /// Display name: the file name, or "untitled".
    pub fn title(&self) -> String {
        self.path
            .as_ref()
            .and_then(|p| p.file_name())
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| "untitled".to_owned())
    }

    /// Whether the scene names a mesh or texture file the library lacks (a path typed in the
    /// inspector).
    pub fn has_unloaded_assets(&self) -> bool {
        let assets = &self.level.assets;
        self.level
            .scene
            .entities()
            .filter_map(|e| self.level.scene.row(e))
            .any(|row| !unloaded_paths(&row, assets).is_empty())
    }

    /// Reloads every mesh and texture the scene refers to (after a mesh was added or a path
    /// changed). Paths still empty (a texture or mesh just added in the inspector, not yet
    /// typed) are skipped. On failure the library is left as it was.
    pub fn reload_assets(&mut self) -> Result<(), String> {
        let mut level = self.level.scene.to_level();
        for row in &mut level.entities {
            if let Some(Geometry::Mesh { path }) = &row.geometry
                && path.trim().is_empty()
            {
                row.geometry = None;
            }
            if let Some(m) = &mut row.material {
                if m.texture.as_ref().is_some_and(|t| t.path.trim().is_empty()) {
                    m.texture = None;
                }
                if m.normal_map.as_ref().is_some_and(|p| p.trim().is_empty()) {
                    m.normal_map = None;
                }
            }
        }
        let assets = load_assets(&level, &self.level.path, None).map_err(|e| e.to_string())?;
        self.level.assets = assets;
        self.revision += 1;
        Ok(())
    }
}

/// The non-empty mesh and texture paths `row` names that `assets` has not loaded.
pub fn unloaded_paths(row: &EntityRow, assets: &AssetLibrary) -> Vec<String> {
    let mut out = Vec::new();
    if let Some(Geometry::Mesh { path }) = &row.geometry
        && !path.trim().is_empty()
        && assets.get(path).is_none()
    {
        out.push(path.clone());
    }
    for p in row.material.iter().flat_map(texture_paths) {
        if !p.trim().is_empty() && assets.texture(p).is_none() {
            out.push(p.to_owned());
        }
    }
    out
}
