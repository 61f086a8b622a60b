//! Files a level refers to (glTF meshes), found relative to the level file.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::components::Geometry;
use crate::gltf_import::{GltfError, load_gltf};
use crate::level::Level;
use crate::mesh::TriMesh;

/// A mesh a level refers to could not be loaded.
#[derive(Debug, thiserror::Error)]
#[error("{}{}: entity {entity} ({name}): {source}", level.display(), at.map(|(l, c)| format!(":{l}:{c}")).unwrap_or_default())]
pub struct AssetError {
    /// The level file.
    pub level: PathBuf,
    /// Line and column of the reference in the level file, when known.
    pub at: Option<(usize, usize)>,
    /// Index of the entity row.
    pub entity: usize,
    /// The entity's name.
    pub name: String,
    /// The glTF error (which names the mesh file).
    pub source: GltfError,
}

/// Meshes loaded for a level, keyed by the path written in the level.
#[derive(Debug, Default, Clone)]
pub struct MeshLibrary {
    meshes: BTreeMap<String, Arc<TriMesh>>,
}

impl MeshLibrary {
    /// The mesh for a level-relative path, if loaded.
    pub fn get(&self, rel: &str) -> Option<&Arc<TriMesh>> {
        self.meshes.get(rel)
    }

    /// Number of distinct meshes.
    pub fn len(&self) -> usize {
        self.meshes.len()
    }

    /// Whether no mesh is loaded.
    pub fn is_empty(&self) -> bool {
        self.meshes.is_empty()
    }

    /// Total triangles over the distinct meshes.
    pub fn triangle_count(&self) -> usize {
        self.meshes.values().map(|m| m.triangle_count()).sum()
    }
}

/// Where a path written in a level points: relative to the level file's folder.
pub fn resolve(level_path: &Path, rel: &str) -> PathBuf {
    let dir = level_path.parent().unwrap_or(Path::new(""));
    dir.join(rel)
}

/// Loads every glTF mesh `level` refers to. `level_path` is the level file (for relative
/// paths and messages); `level_text`, if given, is its text, used to point errors at the
/// line that names the mesh.
pub fn load_meshes(
    level: &Level,
    level_path: &Path,
    level_text: Option<&str>,
) -> Result<MeshLibrary, AssetError> {
    let mut lib = MeshLibrary::default();
    for (i, row) in level.entities.iter().enumerate() {
        let Some(Geometry::Mesh { path }) = &row.geometry else {
            continue;
        };
        if lib.meshes.contains_key(path) {
            continue;
        }
        let mesh = load_gltf(&resolve(level_path, path)).map_err(|source| AssetError {
            level: level_path.to_owned(),
            at: level_text.and_then(|t| locate(t, &format!("{path:?}"))),
            entity: i,
            name: row
                .name
                .as_ref()
                .map_or_else(|| "unnamed".to_owned(), |n| n.0.clone()),
            source,
        })?;
        lib.meshes.insert(path.clone(), Arc::new(mesh));
    }
    Ok(lib)
}

/// 1-based line and column of the first occurrence of `needle` in `text`.
fn locate(text: &str, needle: &str) -> Option<(usize, usize)> {
    let at = text.find(needle)?;
    let before = &text[..at];
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    Some((line, col))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_are_relative_to_the_level() {
        let p = resolve(Path::new("assets/levels/a.ron"), "../meshes/m.glb");
        assert_eq!(p, Path::new("assets/levels/../meshes/m.glb"));
        assert_eq!(locate("a\n  b \"x\"", "\"x\""), Some((2, 5)));
    }
}
