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

/// What `level`'s terrains are given that is not applied, as `(entity, message)`: the
/// entity's name (or `entity N`, its row) and
/// [`unapplied_transform`](texel_scene::terrain::unapplied_transform)'s sentence.
pub fn terrain_warnings(level: &Level) -> Vec<(String, String)> {
    // A terrain in a group is placed by its world transform.
    let world = if level.entities.iter().any(|r| r.parent.is_some()) {
        texel_scene::hierarchy::world_transforms(&level.entities)
    } else {
        level.entities.iter().map(|r| r.transform).collect()
    };
    let rows = level.entities.iter().enumerate();
    rows.filter(|(_, row)| row.terrain.is_some())
        .filter_map(|(i, row)| {
            let message = texel_scene::terrain::unapplied_transform(world[i].as_ref()?)?;
            let name = row.name.as_ref().map(|n| n.0.clone());
            Some((name.unwrap_or_else(|| format!("entity {i}")), message))
        })
        .collect()
}

/// Loads `path` and every asset it refers to. What the meshes use that was not imported is
/// printed to stderr, each warning once, as `warning: <level>: <mesh>: <message>`, and so is
/// a terrain's rotation or scale, which are not applied (`warning: <level>: <entity>:
/// <message>`, [`terrain_warnings`]).
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
    for (entity, message) in terrain_warnings(&level) {
        eprintln!("warning: {}: {entity}: {message}", path.display());
    }
    Ok(LoadedLevel {
        path: path.to_owned(),
        scene: Scene::from_level(&level),
        assets,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_terrains_rotation_and_scale_are_named_as_not_applied() {
        let terrain = "terrain: (size: (16.0, 16.0), heightmap: Noise(seed: 1, resolution: 17, \
                       frequency: 0.1, octaves: 2, island: 0.0), max_height: 2.0, gradient: \
                       [(at: 0.0, colour: (0.3, 0.5, 0.2))], pixel_density: 4.0, \
                       band_distance: 8.0, band_transition: 0.3, casts_shadows: true, \
                       outlined: true)";
        let row = |name: &str, rotation: &str, scale: &str| {
            format!(
                "({name} transform: (translation: (1.0, 0.0, 2.0), rotation: {rotation}, scale: \
                 {scale}), {terrain}),"
            )
        };
        let text = format!(
            "(version: 3, entities: [{}{}{}(name: \"Box\", transform: (translation: (0.0, 0.0, \
             0.0), rotation: (0.0, 45.0, 0.0), scale: (2.0, 1.0, 1.0)), geometry: Box(size: \
             (1.0, 1.0, 1.0)))])",
            row("name: \"Flat\",", "(0.0, 0.0, 0.0)", "(1.0, 1.0, 1.0)"),
            row("name: \"Turned\",", "(0.0, 30.0, 0.0)", "(1.0, 1.0, 1.0)"),
            row("", "(0.0, 0.0, 0.0)", "(1.0, 3.0, 1.0)"),
        );
        let level = Level::from_ron_str(&text, Path::new("t.ron")).expect("the level parses");
        let warnings = terrain_warnings(&level);
        // The box's rotation and scale are applied: only the two terrains are named.
        assert_eq!(warnings.len(), 2, "{warnings:?}");
        assert_eq!(warnings[0].0, "Turned");
        assert!(
            warnings[0]
                .1
                .starts_with("rotation [0.0, 30.0, 0.0] not applied")
        );
        assert_eq!(warnings[1].0, "entity 2");
        assert!(
            warnings[1]
                .1
                .starts_with("scale [1.0, 3.0, 1.0] not applied")
        );
        // In the turned box, the flat terrain is turned in the world: named too.
        let grouped = text.replace("name: \"Flat\",", "name: \"Flat\", parent: \"Box\",");
        let level = Level::from_ron_str(&grouped, Path::new("t.ron")).expect("the level parses");
        let warnings = terrain_warnings(&level);
        assert_eq!(warnings.len(), 3, "{warnings:?}");
        assert_eq!(warnings[0].0, "Flat");
    }
}
