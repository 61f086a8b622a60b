//! Loading a level together with every asset it refers to.

use std::path::{Path, PathBuf};

use texel_scene::assets::{AssetError, AssetLibrary, load_assets};
use texel_scene::read::{FileKind, read_bounded_string};
use texel_scene::{Level, LevelError, Scene};

/// A level with its meshes and textures, ready to play.
pub struct LoadedLevel {
    /// Where it was loaded from.
    pub path: PathBuf,
    /// The live scene.
    pub scene: Scene,
    /// The glTF meshes and textures it refers to.
    pub assets: AssetLibrary,
}

/// Why a level could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    /// The level file itself is bad.
    #[error(transparent)]
    Level(#[from] LevelError),
    /// A mesh it refers to is bad.
    #[error(transparent)]
    Asset(#[from] AssetError),
}

/// Loads `path` and every asset it refers to. What the meshes use that was not imported is
/// printed to stderr, each warning once, as `warning: <level>: <mesh>: <message>`.
pub fn load_level(path: &Path) -> Result<LoadedLevel, LoadError> {
    let level = Level::load(path)?;
    let assets = match load_assets(&level, path, None) {
        Ok(m) => m,
        // Only then is the text read again, to point the error at the line naming the mesh.
        Err(_) => {
            let text = read_bounded_string(path, FileKind::Level).ok();
            load_assets(&level, path, text.as_deref())?
        }
    };
    for (mesh, message) in assets.warnings() {
        eprintln!("warning: {}: {mesh}: {message}", path.display());
    }
    Ok(LoadedLevel {
        path: path.to_owned(),
        scene: Scene::from_level(&level),
        assets,
    })
}
