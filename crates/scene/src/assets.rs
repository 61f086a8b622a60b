//! Files a level refers to (glTF meshes, PNG or JPEG textures, terrain heightmaps and paint
//! layers, sprite sheets and their maps), found relative to the level file.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use texel_geom::texture::{Filter, Image, Sampler, SurfaceMaps, TextureRef};

use crate::components::{Geometry, Material, Sampling};
use crate::gltf_import::{GltfError, load_gltf_report};
use crate::level::Level;
use crate::mesh::TriMesh;
use crate::palette::{Palette, PaletteError};
use crate::sprite::Sprite;
use crate::terrain::{HeightSource, Heightfield, Terrain};
use crate::texture::{TextureError, load_heightmap, load_paint, load_texture};

/// A file a level refers to could not be loaded.
#[derive(Debug, thiserror::Error)]
#[error("{}{}: {owner}: {source}", level.display(), at.map(|(l, c)| format!(":{l}:{c}")).unwrap_or_default())]
pub struct AssetError {
    /// The level file.
    pub level: PathBuf,
    /// Line and column of the reference in the level file, when known.
    pub at: Option<(usize, usize)>,
    /// What refers to the file: `entity 3 (Crate)`, or `palette`.
    pub owner: String,
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
    /// A palette file (its error names the file and line).
    #[error(transparent)]
    Palette(#[from] PaletteError),
    /// A sprite's sheet or map that does not fit the sprite (frames that do not divide it,
    /// a map of another size, …).
    #[error("{}: {message}", file.display())]
    Sprite {
        /// The image file.
        file: PathBuf,
        /// What is wrong.
        message: String,
    },
}

/// Meshes and textures loaded for a level, keyed by the path written in the level, and the
/// warnings the meshes' import raised.
#[derive(Debug, Default, Clone)]
pub struct AssetLibrary {
    meshes: BTreeMap<String, Arc<TriMesh>>,
    textures: BTreeMap<String, Arc<Image>>,
    heightfields: BTreeMap<String, Arc<Heightfield>>,
    palettes: BTreeMap<String, Arc<Palette>>,
    mesh_warnings: BTreeMap<String, Vec<String>>,
}

impl AssetLibrary {
    /// The palette for a level-relative path, if loaded.
    pub fn palette(&self, rel: &str) -> Option<&Arc<Palette>> {
        self.palettes.get(rel)
    }

    /// Adds (or replaces) the palette a level names `rel` (a palette edited in the editor).
    pub fn insert_palette(&mut self, rel: &str, palette: Arc<Palette>) {
        self.palettes.insert(rel.to_owned(), palette);
    }

    /// Every palette loaded, by level-relative path.
    pub fn palettes(&self) -> impl Iterator<Item = (&str, &Arc<Palette>)> {
        self.palettes.iter().map(|(k, v)| (k.as_str(), v))
    }

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

    /// The sheet of `sprite`, if loaded.
    pub fn sprite_sheet(&self, sprite: &Sprite) -> Option<&Arc<Image>> {
        self.textures.get(&sprite.sheet)
    }

    /// The normal map of `sprite`, if it has one and it is loaded.
    pub fn sprite_normal_map(&self, sprite: &Sprite) -> Option<&Arc<Image>> {
        self.textures.get(sprite.normal_map.as_ref()?)
    }

    /// The relief's depth map of `sprite`, if it has one and it is loaded.
    pub fn sprite_depth_map(&self, sprite: &Sprite) -> Option<&Arc<Image>> {
        self.textures.get(&sprite.relief.as_ref()?.depth_map)
    }

    /// The refraction's back depth map of `sprite`, if it has one and it is loaded.
    pub fn sprite_back_depth(&self, sprite: &Sprite) -> Option<&Arc<Image>> {
        self.textures.get(&sprite.refraction.as_ref()?.back_depth)
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

/// `file` relative to the directory of `level`, with `/` separators: what [`resolve`]
/// undoes (absolute when it cannot be made relative).
pub fn relative_path(level: &Path, file: &Path) -> String {
    let base = level
        .parent()
        .map(|p| std::fs::canonicalize(p).unwrap_or_else(|_| p.to_owned()))
        .unwrap_or_default();
    let file = std::fs::canonicalize(file).unwrap_or_else(|_| file.to_owned());
    let mut b = base.components().peekable();
    let mut f = file.components().peekable();
    while let (Some(x), Some(y)) = (b.peek(), f.peek()) {
        if x != y {
            break;
        }
        b.next();
        f.next();
    }
    let mut parts: Vec<String> = b.map(|_| "..".to_owned()).collect();
    parts.extend(f.map(|c| c.as_os_str().to_string_lossy().into_owned()));
    parts.join("/")
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
        let error_at = |needles: &[String], source: AssetFileError| AssetError {
            level: level_path.to_owned(),
            at: level_text.and_then(|t| locate_in_row(t, i, needles)),
            owner: format!(
                "entity {i} ({})",
                (row.name.as_ref()).map_or("unnamed", |n| n.0.as_str())
            ),
            source,
        };
        let error = |path: &str, source: AssetFileError| error_at(&[format!("{path:?}")], source);
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
        if let Some(sprite) = &row.sprite {
            load_sprite(&mut lib, sprite, level_path).map_err(|(at, e)| error_at(&at, e))?;
        }
    }
    load_palettes(&mut lib, level, level_path, level_text)?;
    Ok(lib)
}

/// Loads the level's palette and its alternate into `lib`.
fn load_palettes(
    lib: &mut AssetLibrary,
    level: &Level,
    level_path: &Path,
    level_text: Option<&str>,
) -> Result<(), AssetError> {
    let Some(setting) = &level.palette else {
        return Ok(());
    };
    for file in std::iter::once(&setting.file).chain(&setting.alternate) {
        if lib.palettes.contains_key(file) {
            continue;
        }
        let palette = Palette::load(&resolve(level_path, file)).map_err(|e| AssetError {
            level: level_path.to_owned(),
            at: level_text.and_then(|t| locate(t, &format!("{file:?}"))),
            owner: "palette".into(),
            source: e.into(),
        })?;
        lib.palettes.insert(file.clone(), Arc::new(palette));
    }
    Ok(())
}

/// Loads a sprite's sheet and maps into `lib` and checks them against the sprite: the
/// frames fit the sheet and every map is the sheet's size. The error comes with what to
/// look for in the sprite's row to point at the line (the file, or the field at fault).
fn load_sprite(
    lib: &mut AssetLibrary,
    sprite: &Sprite,
    level_path: &Path,
) -> Result<(), (Vec<String>, AssetFileError)> {
    for (_, path) in sprite.files() {
        if !lib.textures.contains_key(path) {
            let image = load_texture(&resolve(level_path, path))
                .map_err(|e| (vec![format!("{path:?}")], e.into()))?;
            lib.textures.insert(path.to_owned(), Arc::new(image));
        }
    }
    let Some(sheet) = lib.textures.get(&sprite.sheet) else {
        return Ok(());
    };
    sprite
        .check_sheet(glam::UVec2::new(sheet.width, sheet.height))
        .map_err(|e| {
            let at = match e.animation {
                Some(name) => vec!["animations".to_owned(), format!("{name:?}")],
                None => vec![e.field.to_owned()],
            };
            let file = resolve(level_path, &sprite.sheet);
            (
                at,
                AssetFileError::Sprite {
                    file,
                    message: e.message,
                },
            )
        })?;
    let size_of = |p: &str| (lib.textures.get(p)).map(|m| glam::UVec2::new(m.width, m.height));
    sprite
        .check_map_sizes(glam::UVec2::new(sheet.width, sheet.height), size_of)
        .map_err(|(path, message)| {
            let file = resolve(level_path, &path);
            (
                vec![format!("{path:?}")],
                AssetFileError::Sprite { file, message },
            )
        })
}

/// 1-based line and column of `needles` found one after the other inside entity row `row`
/// of a level's text (see [`entity_rows`]): of the last needle, or of the row itself if
/// they are not all there; without the row, of the first occurrence of the last needle in
/// the whole text.
fn locate_in_row(text: &str, row: usize, needles: &[String]) -> Option<(usize, usize)> {
    let Some(span) = entity_rows(text).into_iter().nth(row) else {
        return locate(text, needles.last()?);
    };
    let mut at = span.start;
    for needle in needles {
        match text[at..span.end].find(needle.as_str()) {
            Some(offset) => at += offset,
            None => return Some(line_col_at(text, span.start)),
        }
    }
    Some(line_col_at(text, at))
}

/// Byte ranges of a level text's entity rows, in order: each from its `(` to its `)`. A
/// small scanner over the text (strings, raw strings and comments skipped, brackets
/// counted), for pointing errors found after parsing at the right row; a text it cannot
/// follow gives fewer rows.
fn entity_rows(text: &str) -> Vec<std::ops::Range<usize>> {
    let b = text.as_bytes();
    let ident = |c: Option<&u8>| c.is_some_and(|c| c.is_ascii_alphanumeric() || *c == b'_');
    let mut rows = Vec::new();
    let (mut depth, mut i) = (0usize, 0usize);
    let (mut want_list, mut list, mut start) = (false, None, None);
    while i < b.len() {
        let c = b[i];
        let next = b.get(i + 1).copied();
        match c {
            b'"' => {
                i = skip_string(b, i + 1);
                continue;
            }
            b'r' if matches!(next, Some(b'"' | b'#'))
                && !ident(i.checked_sub(1).and_then(|p| b.get(p))) =>
            {
                i = skip_raw_string(b, i + 1);
                continue;
            }
            b'/' if next == Some(b'/') => {
                i = text[i..].find('\n').map_or(b.len(), |n| i + n);
                continue;
            }
            b'/' if next == Some(b'*') => {
                i = skip_block_comment(b, i + 2);
                continue;
            }
            b'(' | b'[' | b'{' => {
                if c == b'[' && want_list && list.is_none() {
                    list = Some(depth + 1);
                    want_list = false;
                } else if c == b'(' && list == Some(depth) {
                    start = Some(i);
                }
                depth += 1;
            }
            b')' | b']' | b'}' => {
                depth = depth.saturating_sub(1);
                if c == b')' && list == Some(depth) {
                    rows.extend(start.take().map(|s| s..i + 1));
                } else if list == Some(depth + 1) {
                    return rows;
                }
            }
            b'e' if depth == 1
                && text[i..].starts_with("entities")
                && !ident(i.checked_sub(1).and_then(|p| b.get(p)))
                && !ident(b.get(i + 8)) =>
            {
                want_list = true;
                i += 8;
                continue;
            }
            _ => {}
        }
        i += 1;
    }
    rows
}

/// The index just after the string whose body starts at `i`.
fn skip_string(b: &[u8], mut i: usize) -> usize {
    while i < b.len() {
        match b[i] {
            b'\\' => i += 2,
            b'"' => return i + 1,
            _ => i += 1,
        }
    }
    b.len()
}

/// The index just after the raw string whose `#`s (or opening quote) start at `i`.
fn skip_raw_string(b: &[u8], mut i: usize) -> usize {
    let hashes = b[i..].iter().take_while(|&&c| c == b'#').count();
    i += hashes + 1;
    while i < b.len() {
        if b[i] == b'"'
            && b[i + 1..]
                .iter()
                .take(hashes)
                .filter(|&&c| c == b'#')
                .count()
                == hashes
        {
            return i + 1 + hashes;
        }
        i += 1;
    }
    b.len()
}

/// The index just after the (nested) block comment whose body starts at `i`.
fn skip_block_comment(b: &[u8], mut i: usize) -> usize {
    let mut open = 1;
    while i < b.len() {
        match (b[i], b.get(i + 1)) {
            (b'*', Some(b'/')) => {
                open -= 1;
                i += 2;
                if open == 0 {
                    return i;
                }
            }
            (b'/', Some(b'*')) => {
                open += 1;
                i += 2;
            }
            _ => i += 1,
        }
    }
    b.len()
}

/// 1-based line and column of the first occurrence of `needle` in `text`.
fn locate(text: &str, needle: &str) -> Option<(usize, usize)> {
    Some(line_col_at(text, text.find(needle)?))
}

/// 1-based line and column of byte `at` of `text`.
fn line_col_at(text: &str, at: usize) -> (usize, usize) {
    let before = &text[..at];
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, col)
}

#[cfg(test)]
mod tests;
