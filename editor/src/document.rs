//! The document being edited: a scene, the meshes and textures it refers to, and where it is saved.

use std::path::{Path, PathBuf};

use texel_runtime::load::{LoadedLevel, load_level};
use texel_scene::Scene;
use texel_scene::assets::{AssetLibrary, load_assets};

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

    /// Reloads every mesh the scene refers to (after a mesh was added or a path changed).
    pub fn reload_assets(&mut self) -> Result<(), String> {
        let level = self.level.scene.to_level();
        let assets = load_assets(&level, &self.level.path, None).map_err(|e| e.to_string())?;
        self.level.assets = assets;
        self.revision += 1;
        Ok(())
    }
}
