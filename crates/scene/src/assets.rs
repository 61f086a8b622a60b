//! Files a level refers to (glTF meshes, PNG or JPEG textures, terrain heightmaps and paint
//! layers), found relative to the level file.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use texel_geom::texture::{Filter, Image, Sampler, SurfaceMaps, TextureRef};

use crate::components::{Geometry, Material, Sampling};
use crate::gltf_import::{GltfError, load_gltf_report};
use crate::level::Level;
use crate::mesh::TriMesh;
use crate::terrain::{HeightSource, Heightfield, Terrain};
use crate::texture::{TextureError, load_heightmap, load_paint, load_texture};

/// A file a level refers to could not be loaded.
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
    /// The file's own error (which names the file).
    pub source: AssetFileError,
}

/// What was wrong with the file.
#[derive(Debug, thiserror::Error)]
pub enum AssetFileError {
    /// A glTF mesh.
    #[error(transparent)]
    Mesh(#[from] GltfError),
    /// A PNG or JPEG texture.
    #[error(transparent)]
    Texture(#[from] TextureError),
}

/// Meshes and textures loaded for a level, keyed by the path written in the level, and the
/// warnings the meshes' import raised.
#[derive(Debug, Default, Clone)]
pub struct AssetLibrary {
    meshes: BTreeMap<String, Arc<TriMesh>>,
    textures: BTreeMap<String, Arc<Image>>,
    heightfields: BTreeMap<String, Arc<Heightfield>>,
    mesh_warnings: BTreeMap<String, Vec<String>>,
}

impl AssetLibrary {
    /// The mesh for a level-relative path, if loaded.
    pub fn get(&self, rel: &str) -> Option<&Arc<TriMesh>> {
        self.meshes.get(rel)
    }

    /// The texture for a level-relative path, if loaded.
    pub fn texture(&self, rel: &str) -> Option<&Arc<Image>> {
        self.textures.get(rel)
    }

    /// What the meshes use that was not imported, as `(mesh path, message)`: each mesh's
    /// warnings once (see [`GltfImport::warnings`](crate::gltf_import::GltfImport)), meshes in
    /// path order.
    pub fn warnings(&self) -> impl Iterator<Item = (&str, &str)> {
        self.mesh_warnings
            .iter()
            .flat_map(|(path, messages)| messages.iter().map(move |m| (path.as_str(), m.as_str())))
    }

    /// Number of distinct meshes.
    pub fn len(&self) -> usize {
        self.meshes.len()
    }

    /// Whether no mesh is loaded.
    pub fn is_empty(&self) -> bool {
        self.meshes.is_empty()
    }

    /// The heights of `terrain`, if loaded (or baked).
    pub fn heightfield(&self, terrain: &Terrain) -> Option<&Arc<Heightfield>> {
        self.heightfields.get(&heightfield_key(terrain))
    }

    /// The paint layer of `terrain`, if it has one and it is loaded.
    pub fn paint(&self, terrain: &Terrain) -> Option<&Arc<Image>> {
        self.textures.get(&terrain.paint.as_ref()?.path)
    }

    /// Sets the heights of `terrain` (a sculpted or imported field).
    pub fn insert_heightfield(&mut self, terrain: &Terrain, field: Arc<Heightfield>) {
        self.heightfields.insert(heightfield_key(terrain), field);
    }

    /// Adds (or replaces) the texture a level names `rel`.
    pub fn insert_texture(&mut self, rel: &str, image: Arc<Image>) {
        self.textures.insert(rel.to_owned(), image);
    }

    /// Number of distinct textures.
    pub fn texture_count(&self) -> usize {
        self.textures.len()
    }

    /// Total triangles over the distinct meshes.
    pub fn triangle_count(&self) -> usize {
        self.meshes.values().map(|m| m.triangle_count()).sum()
    }

    /// Whether every file `material` names is loaded.
    pub fn has_textures_of(&self, material: &Material) -> bool {
        texture_paths(material).all(|p| self.textures.contains_key(p))
    }

    /// The textures `material` names, as the renderer samples them (`None` for a file not
    /// loaded). `world_uvs`: the mesh's UVs are in world units (primitives), so the UV scale
    /// also carries the texel density over the image's size.
    pub fn surface_maps(&self, material: &Material, world_uvs: bool) -> SurfaceMaps {
        let (sampler, uv_scale) = match &material.texture {
            Some(t) => (
                Sampler {
                    filter: match t.sampling {
                        Sampling::Nearest => Filter::Nearest,
                        Sampling::Linear => Filter::Linear,
                    },
                    wrap: Default::default(),
                },
                t.uv_scale,
            ),
            None => (Sampler::default(), glam::Vec2::ONE),
        };
        let texture = |p: &str| {
            self.textures.get(p).map(|image| TextureRef {
                image: image.clone(),
                sampler,
            })
        };
        let albedo = material.texture.as_ref().and_then(|t| texture(&t.path));
        let normal = material.normal_map.as_deref().and_then(texture);
        let density = material
            .texture
            .as_ref()
            .map_or(crate::components::DEFAULT_TEXEL_DENSITY, |t| t.density);
        let uv_scale = match albedo.as_ref().or(normal.as_ref()) {
            Some(t) if world_uvs => {
                let size = glam::Vec2::new(t.image.width as f32, t.image.height as f32);
                uv_scale * density / size
            }
            _ => uv_scale,
        };
        SurfaceMaps {
            albedo,
            normal,
            uv_scale,
        }
    }
}

/// What a terrain's heights are cached under: the file's path, or the noise parameters with
/// the extent and height they were baked for.
fn heightfield_key(t: &Terrain) -> String {
    match &t.heightmap {
        HeightSource::File { path } => format!("file:{path}:{}", t.max_height),
        noise => format!("{noise:?}:{:?}:{}", t.size, t.max_height),
    }
}

/// Loads (or bakes) a terrain's heights.
pub fn load_heightfield(terrain: &Terrain, level_path: &Path) -> Result<Heightfield, TextureError> {
    match &terrain.heightmap {
        HeightSource::File { path } => {
            let (w, h, samples) = load_heightmap(&resolve(level_path, path))?;
            Ok(Heightfield::from_u16(w, h, &samples, terrain.max_height))
        }
        noise => Ok(
            Heightfield::from_noise(noise, terrain.size, terrain.max_height)
                .expect("a noise source bakes"),
        ),
    }
}

/// The texture files a material names.
pub fn texture_paths(material: &Material) -> impl Iterator<Item = &str> {
    material
        .texture
        .as_ref()
        .map(|t| t.path.as_str())
        .into_iter()
        .chain(material.normal_map.as_deref())
}

/// Where a path written in a level points: relative to the level file's folder.
pub fn resolve(level_path: &Path, rel: &str) -> PathBuf {
    let dir = level_path.parent().unwrap_or(Path::new(""));
    dir.join(rel)
}

/// Loads every glTF mesh and texture `level` refers to. `level_path` is the level file (for
/// relative paths and messages); `level_text`, if given, is its text, used to point errors
/// at the line that names the file.
pub fn load_assets(
    level: &Level,
    level_path: &Path,
    level_text: Option<&str>,
) -> Result<AssetLibrary, AssetError> {
    let mut lib = AssetLibrary::default();
    for (i, row) in level.entities.iter().enumerate() {
        let error = |path: &str, source: AssetFileError| AssetError {
            level: level_path.to_owned(),
            at: level_text.and_then(|t| locate(t, &format!("{path:?}"))),
            entity: i,
            name: row
                .name
                .as_ref()
                .map_or_else(|| "unnamed".to_owned(), |n| n.0.clone()),
            source,
        };
        if let Some(Geometry::Mesh { path }) = &row.geometry
            && !lib.meshes.contains_key(path)
        {
            let import =
                load_gltf_report(&resolve(level_path, path)).map_err(|e| error(path, e.into()))?;
            if !import.warnings.is_empty() {
                lib.mesh_warnings.insert(path.clone(), import.warnings);
            }
            lib.meshes.insert(path.clone(), Arc::new(import.mesh));
        }
        if let Some(t) = &row.terrain
            && let std::collections::btree_map::Entry::Vacant(slot) =
                lib.heightfields.entry(heightfield_key(t))
        {
            let path = match &t.heightmap {
                HeightSource::File { path } => path.as_str(),
                HeightSource::Noise { .. } => "heightmap",
            };
            let field = load_heightfield(t, level_path).map_err(|e| error(path, e.into()))?;
            slot.insert(Arc::new(field));
        }
        let displacement = row.terrain.as_ref().and_then(|t| t.displacement.as_ref());
        for path in row
            .material
            .iter()
            .flat_map(texture_paths)
            .chain(displacement.map(|d| d.path.as_str()))
        {
            if !lib.textures.contains_key(path) {
                let image =
                    load_texture(&resolve(level_path, path)).map_err(|e| error(path, e.into()))?;
                lib.textures.insert(path.to_owned(), Arc::new(image));
            }
        }
        if let Some(p) = row.terrain.as_ref().and_then(|t| t.paint.as_ref())
            && !lib.textures.contains_key(&p.path)
        {
            let image =
                load_paint(&resolve(level_path, &p.path)).map_err(|e| error(&p.path, e.into()))?;
            lib.textures.insert(p.path.clone(), Arc::new(image));
        }
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
    use crate::level::EntityRow;

    #[test]
    fn paths_are_relative_to_the_level() {
        let p = resolve(Path::new("assets/levels/a.ron"), "../meshes/m.glb");
        assert_eq!(p, Path::new("assets/levels/../meshes/m.glb"));
        assert_eq!(locate("a\n  b \"x\"", "\"x\""), Some((2, 5)));
    }

    /// A one-triangle glTF with an external buffer, plus top-level JSON `members`.
    fn write_triangle(dir: &Path, name: &str, members: &str) {
        let bin: Vec<u8> = [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        std::fs::write(dir.join("tri.bin"), bin).unwrap();
        let json = format!(
            r#"{{"asset":{{"version":"2.0"}},
            "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}}}]}}],
            "accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3",
                "min":[0,0,0],"max":[1,1,0]}}],
            "bufferViews":[{{"buffer":0,"byteLength":36}}],
            "buffers":[{{"byteLength":36,"uri":"tri.bin"}}]{members}}}"#
        );
        std::fs::write(dir.join(name), json).unwrap();
    }

    #[test]
    fn mesh_warnings_are_kept_once_per_mesh() {
        let dir = tempfile::tempdir().unwrap();
        write_triangle(dir.path(), "plain.gltf", "");
        let cameras = r#","cameras":[{"type":"perspective","perspective":{"yfov":1,"znear":0.1}}]"#;
        write_triangle(
            dir.path(),
            "fancy.gltf",
            &format!(r#"{cameras},"extensionsUsed":["KHR_lights_punctual"]"#),
        );
        let row = |path: &str| EntityRow {
            geometry: Some(Geometry::Mesh {
                path: path.to_owned(),
            }),
            ..Default::default()
        };
        let level = Level {
            entities: vec![row("fancy.gltf"), row("plain.gltf"), row("fancy.gltf")],
            ..Default::default()
        };
        let lib = load_assets(&level, &dir.path().join("level.ron"), None).unwrap();
        assert_eq!(lib.len(), 2);
        let warnings: Vec<_> = lib.warnings().collect();
        assert_eq!(
            warnings,
            [
                ("fancy.gltf", "1 camera ignored"),
                (
                    "fancy.gltf",
                    "extension KHR_lights_punctual ignored: not implemented"
                )
            ]
        );
    }
}
