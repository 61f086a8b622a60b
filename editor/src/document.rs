//! The document being edited: a scene, the meshes, textures and terrain heights it refers
//! to, and where it is saved. Terrain heights and paint layers live in the asset library,
//! where sculpting, painting and imports change them; saving writes a terrain's heightmap
//! (or paint) file when what is in memory is not what the file holds.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::sync::Arc;

use texel_runtime::frame_plan::RowEdit;
use texel_runtime::load::{LoadedLevel, load_level};
use texel_scene::assets::{AssetLibrary, load_assets, resolve, texture_paths};
use texel_scene::palette::Palette;
use texel_scene::terrain::{HeightSource, Heightfield, PaintLayer, Terrain};
use texel_scene::texture::Image;
use texel_scene::{EntityRow, Geometry, Scene};

use crate::files;

/// Most entity changes a document remembers for views to take in alone
/// ([`Document::entities_since`]).
const MAX_ENTITY_CHANGES: usize = 4096;

/// A new [`Document`] id.
fn next_id() -> u64 {
    static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);
    NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
}

/// A level open in the editor.
pub struct Document {
    /// The scene and its assets; `level.path` is where they are resolved from.
    pub level: LoadedLevel,
    /// Where the document is saved; `None` until the first Save As.
    pub path: Option<PathBuf>,
    /// Bumped on every change, so views know when to rebuild what they derive.
    pub revision: u64,
    /// Tells this document from every other one made in this process (a view keyed by
    /// revision alone would take a document just opened for the one before).
    id: u64,
    /// The heights each heightmap file (by level-relative path) held when it was last read or
    /// written: a terrain whose heights are still these is not written again on save.
    on_disk: BTreeMap<String, Arc<Heightfield>>,
    /// The layer each paint file held when it was last read or written, likewise.
    paint_on_disk: BTreeMap<String, Arc<Image>>,
    /// The last revision that changed anything but terrain heights in a known box.
    full_revision: u64,
    /// Revisions that only changed terrain heights, with the world box they changed.
    regions: Vec<(u64, glam::Vec3, glam::Vec3)>,
    /// Revisions that only changed one entity's components, added one or removed one, with
    /// its position.
    entities: Vec<(u64, RowEdit)>,
    /// The colours each palette file (by level-relative path) held when it was last read or
    /// written: a palette whose colours are still these is not written again on save.
    palettes_on_disk: BTreeMap<String, Arc<Palette>>,
    /// Revisions that only changed the palette (the views map colours again, nothing else).
    palette_changes: Vec<u64>,
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
            id: next_id(),
            on_disk: BTreeMap::new(),
            paint_on_disk: BTreeMap::new(),
            full_revision: 0,
            regions: Vec::new(),
            entities: Vec::new(),
            palettes_on_disk: BTreeMap::new(),
            palette_changes: Vec::new(),
        }
    }

    /// Loads `path` and its meshes and textures. The error names the file, line and column.
    pub fn open(path: &Path) -> Result<Self, String> {
        let level = load_level(path).map_err(|e| e.to_string())?;
        let mut doc = Document {
            level,
            path: Some(path.to_owned()),
            revision: 0,
            id: next_id(),
            on_disk: BTreeMap::new(),
            paint_on_disk: BTreeMap::new(),
            full_revision: 0,
            regions: Vec::new(),
            entities: Vec::new(),
            palettes_on_disk: BTreeMap::new(),
            palette_changes: Vec::new(),
        };
        doc.note_files_read(&AssetLibrary::default());
        Ok(doc)
    }

    /// Records the heightmap and paint files just read (the scene's terrains whose heights
    /// or paint `old` lacked) as what is on disk.
    fn note_files_read(&mut self, old: &AssetLibrary) {
        for (rel, p) in self.level.assets.palettes() {
            if old.palette(rel).is_none() {
                self.palettes_on_disk.insert(rel.to_owned(), p.clone());
            }
        }
        for t in terrains(&self.level.scene) {
            if let HeightSource::File { path } = &t.heightmap
                && old.heightfield(&t).is_none()
                && let Some(f) = self.level.assets.heightfield(&t)
            {
                self.on_disk.insert(path.clone(), f.clone());
            }
            if let Some(p) = &t.paint
                && old.paint(&t).is_none()
                && let Some(image) = self.level.assets.paint(&t)
            {
                self.paint_on_disk.insert(p.path.clone(), image.clone());
            }
        }
    }

    /// This document's id, unique in this process.
    pub fn id(&self) -> u64 {
        self.id
    }

    /// The scene.
    pub fn scene(&self) -> &Scene {
        &self.level.scene
    }

    /// The scene, for commands.
    pub fn scene_mut(&mut self) -> &mut Scene {
        self.touch();
        &mut self.level.scene
    }

    /// The scene and the asset library (where terrain heights live), for commands.
    pub fn parts_mut(&mut self) -> (&mut Scene, &mut AssetLibrary) {
        self.touch();
        (&mut self.level.scene, &mut self.level.assets)
    }

    /// The scene and the asset library, for a command that changes only the components of
    /// the entity at `index` (a gizmo drag step, an inspector change): views take in that
    /// entity alone ([`Document::entities_since`]).
    pub fn entity_parts_mut(&mut self, index: usize) -> (&mut Scene, &mut AssetLibrary) {
        self.row_parts_mut(RowEdit::Set(index))
    }

    /// The scene and the asset library, for a command that makes one change of the level's
    /// entities (`edit`: one set, added or removed): views take in that entity alone
    /// ([`Document::entities_since`]).
    pub fn row_parts_mut(&mut self, edit: RowEdit) -> (&mut Scene, &mut AssetLibrary) {
        self.revision += 1;
        // Bounded: a view older than the changes let go of rebuilds instead.
        if self.entities.len() >= MAX_ENTITY_CHANGES {
            let old: Vec<(u64, RowEdit)> = self.entities.drain(..MAX_ENTITY_CHANGES / 2).collect();
            self.full_revision = (old.last()).map_or(self.full_revision, |e| e.0);
        }
        self.entities.push((self.revision, edit));
        (&mut self.level.scene, &mut self.level.assets)
    }

    /// [`Document::row_parts_mut`] for a command that makes the changes `edits`, in order
    /// (a paste, a delete of the selection, their undo).
    pub fn rows_parts_mut(&mut self, edits: &[RowEdit]) -> (&mut Scene, &mut AssetLibrary) {
        if edits.len() >= MAX_ENTITY_CHANGES / 2 {
            return self.parts_mut();
        }
        for &e in edits {
            self.row_parts_mut(e);
        }
        (&mut self.level.scene, &mut self.level.assets)
    }

    /// [`Document::entity_parts_mut`] for a command that changes only the components of the
    /// entities at `indices` (an edit of the whole selection).
    pub fn entities_parts_mut(&mut self, indices: &[usize]) -> (&mut Scene, &mut AssetLibrary) {
        if indices.len() >= MAX_ENTITY_CHANGES / 2 {
            return self.parts_mut();
        }
        for &i in indices {
            self.entity_parts_mut(i);
        }
        (&mut self.level.scene, &mut self.level.assets)
    }

    /// Marks a change made in place, so views rebuild.
    pub fn touch(&mut self) {
        self.revision += 1;
        self.full_revision = self.revision;
        self.regions.clear();
        self.entities.clear();
        self.palette_changes.clear();
    }

    /// The scene and the asset library, for a command that changes only the level's palette
    /// (its setting and colours): views map colours again and nothing else
    /// ([`Document::palette_only_since`]).
    pub fn palette_parts_mut(&mut self) -> (&mut Scene, &mut AssetLibrary) {
        self.revision += 1;
        self.palette_changes.push(self.revision);
        (&mut self.level.scene, &mut self.level.assets)
    }

    /// Whether every change since `revision` changed only the palette (and one did).
    pub fn palette_only_since(&self, revision: u64) -> bool {
        self.full_revision <= revision
            && !self.regions.iter().any(|r| r.0 > revision)
            && !self.entities.iter().any(|e| e.0 > revision)
            && self.palette_changes.last().is_some_and(|&r| r > revision)
    }

    /// Whether a palette change came after `revision`.
    fn palette_changed_since(&self, revision: u64) -> bool {
        self.palette_changes.last().is_some_and(|&r| r > revision)
    }

    /// Marks a change of terrain heights confined to the world box `min..max` (a stroke in
    /// progress), so views update only what sees it ([`Document::region_since`]).
    pub fn touch_region(&mut self, min: glam::Vec3, max: glam::Vec3) {
        self.revision += 1;
        self.regions.push((self.revision, min, max));
    }

    /// The box every change since `revision` fell in, when they were all region changes
    /// ([`Document::touch_region`]); `None` when something else changed (rebuild the view).
    pub fn region_since(&self, revision: u64) -> Option<(glam::Vec3, glam::Vec3)> {
        if self.full_revision > revision
            || self.entities.iter().any(|e| e.0 > revision)
            || self.palette_changed_since(revision)
        {
            return None;
        }
        self.regions
            .iter()
            .filter(|r| r.0 > revision)
            .map(|r| (r.1, r.2))
            .reduce(|a, b| (a.0.min(b.0), a.1.max(b.1)))
    }

    /// The changes of entities since `revision`, when every change since was an entity's
    /// alone ([`Document::row_parts_mut`]): in order, an entity set again listed once (at
    /// its first change) while no entity was added or removed; `None` when something else
    /// changed (or nothing).
    pub fn entities_since(&self, revision: u64) -> Option<Vec<RowEdit>> {
        if self.full_revision > revision
            || self.regions.iter().any(|r| r.0 > revision)
            || self.palette_changed_since(revision)
        {
            return None;
        }
        let mut out: Vec<RowEdit> = Vec::new();
        let mut only_sets = true;
        for &(_, e) in self.entities.iter().filter(|e| e.0 > revision) {
            only_sets &= matches!(e, RowEdit::Set(_));
            if !(only_sets && out.contains(&e)) {
                out.push(e);
            }
        }
        (!out.is_empty()).then_some(out)
    }

    /// Saves atomically to `path` and makes it the document's path. The heightmaps of
    /// terrains sculpted or imported since they were last written (or missing beside `path`),
    /// and their paint layers likewise, are written first, each atomically; a failure leaves
    /// the level file untouched.
    pub fn save_as(&mut self, path: &Path) -> Result<(), String> {
        self.write_heightmaps(path)?;
        self.write_paint_layers(path)?;
        self.write_palettes(path)?;
        self.level.scene.save(path).map_err(|e| e.to_string())?;
        self.path = Some(path.to_owned());
        self.level.path = path.to_owned();
        Ok(())
    }

    /// Writes the 16-bit heightmap of every file terrain whose heights differ from what its
    /// file held, or whose file is missing, beside the level file `level` (every one when the
    /// level moves to another folder).
    fn write_heightmaps(&mut self, level: &Path) -> Result<(), String> {
        let moved = self.moves_to(level);
        let mut done = BTreeSet::new();
        for t in terrains(&self.level.scene) {
            let HeightSource::File { path: rel } = &t.heightmap else {
                continue;
            };
            if rel.trim().is_empty() || !done.insert(rel.clone()) {
                continue;
            }
            let Some(field) = self.level.assets.heightfield(&t).cloned() else {
                continue;
            };
            let file = resolve(level, rel);
            let same = self
                .on_disk
                .get(rel)
                .is_some_and(|f| Arc::ptr_eq(f, &field));
            if same && !moved && file.is_file() {
                continue;
            }
            crate::terrain::write_heightmap(&file, &field, t.max_height)?;
            self.on_disk.insert(rel.clone(), field);
        }
        Ok(())
    }

    /// Writes each palette file the level names whose colours differ from what the file held
    /// (edited), or that is missing, in its own format, atomically (every one when the level
    /// moves to another folder).
    fn write_palettes(&mut self, level: &Path) -> Result<(), String> {
        let moved = self.moves_to(level);
        let Some(setting) = self.level.scene.palette.clone() else {
            return Ok(());
        };
        for rel in std::iter::once(&setting.file).chain(&setting.alternate) {
            let Some(palette) = self.level.assets.palette(rel).cloned() else {
                continue;
            };
            let file = resolve(level, rel);
            let same = (self.palettes_on_disk.get(rel)).is_some_and(|p| Arc::ptr_eq(p, &palette));
            if same && !moved && file.is_file() {
                continue;
            }
            palette.save(&file).map_err(|e| e.to_string())?;
            self.palettes_on_disk.insert(rel.clone(), palette);
        }
        Ok(())
    }

    /// Records the palette file `rel` just read as holding `palette` (not written on save
    /// until edited).
    pub fn note_palette_read(&mut self, rel: &str, palette: Arc<Palette>) {
        self.palettes_on_disk.insert(rel.to_owned(), palette);
    }

    /// Whether the level has palette colours edited and not yet saved.
    pub fn palettes_edited(&self) -> bool {
        let Some(setting) = &self.level.scene.palette else {
            return false;
        };
        std::iter::once(&setting.file)
            .chain(&setting.alternate)
            .any(|rel| {
                let now = self.level.assets.palette(rel);
                let disk = self.palettes_on_disk.get(rel);
                !matches!((now, disk), (Some(a), Some(b)) if Arc::ptr_eq(a, b))
            })
    }

    /// Whether the level moves to `level` from another folder (or was never saved), so every
    /// file it names beside it is written.
    fn moves_to(&self, level: &Path) -> bool {
        let dir = |p: &Path| {
            let d = p.parent().unwrap_or(Path::new("")).to_owned();
            std::fs::canonicalize(&d).unwrap_or(d)
        };
        self.path.is_none() || dir(&self.level.path) != dir(level)
    }

    /// Writes the RGBA paint layer of every terrain whose layer differs from what its file
    /// held, or whose file is missing, beside the level file `level` (every one when the
    /// level moves to another folder).
    fn write_paint_layers(&mut self, level: &Path) -> Result<(), String> {
        let moved = self.moves_to(level);
        let mut done = BTreeSet::new();
        for t in terrains(&self.level.scene) {
            let Some(PaintLayer { path: rel }) = &t.paint else {
                continue;
            };
            if rel.trim().is_empty() || !done.insert(rel.clone()) {
                continue;
            }
            let Some(image) = self.level.assets.paint(&t).cloned() else {
                continue;
            };
            let file = resolve(level, rel);
            let same = (self.paint_on_disk.get(rel)).is_some_and(|i| Arc::ptr_eq(i, &image));
            if same && !moved && file.is_file() {
                continue;
            }
            crate::paint::write_paint(&file, &image)?;
            self.paint_on_disk.insert(rel.clone(), image);
        }
        Ok(())
    }

    /// An autosave of the document into `file`, taken now (the rows, and the unsaved
    /// heightmaps and paint layers, shared, not copied), to write on another thread while the
    /// editor goes on ([`AutosaveJob::write`]). A file terrain whose heights are not saved
    /// (sculpted, imported) is written beside `file` as `name.autosave.png`
    /// ([`files::autosave_heightmap`]), which the autosave names instead; so is a paint layer
    /// that is not saved, and a palette whose swatches were edited.
    pub fn autosave_job(&self, file: &Path) -> AutosaveJob {
        let mut level = self.level.scene.to_level();
        let mut images = Vec::new();
        let named = |images: &mut Vec<(PathBuf, AutosaveImage)>, path: &str, image| {
            let auto = files::autosave_heightmap(path);
            let png = resolve(file, &auto);
            if !images.iter().any(|(p, _)| *p == png) {
                images.push((png, image));
            }
            auto
        };
        for row in &mut level.entities {
            let Some(t) = &mut row.terrain else {
                continue;
            };
            if let HeightSource::File { path } = &t.heightmap
                && let Some(field) = self.level.assets.heightfield(t)
            {
                let saved = self.path.is_some()
                    && (self.on_disk.get(path)).is_some_and(|f| Arc::ptr_eq(f, field))
                    && resolve(&self.level.path, path).is_file();
                if !saved {
                    let image = AutosaveImage::Heights(Arc::clone(field), t.max_height);
                    let auto = named(&mut images, path, image);
                    t.heightmap = HeightSource::File { path: auto };
                }
            }
            let Some(image) = self.level.assets.paint(t) else {
                continue;
            };
            let Some(p) = &mut t.paint else {
                continue;
            };
            let saved = self.path.is_some()
                && (self.paint_on_disk.get(&p.path)).is_some_and(|i| Arc::ptr_eq(i, image))
                && resolve(&self.level.path, &p.path).is_file();
            if !saved {
                p.path = named(
                    &mut images,
                    &p.path,
                    AutosaveImage::Paint(Arc::clone(image)),
                );
            }
        }
        self.autosave_palettes(&mut level, file, &mut images);
        AutosaveJob {
            file: file.to_owned(),
            level,
            images,
        }
    }

    /// For [`Document::autosave_job`]: each palette the level names whose colours are not
    /// saved (a swatch edited) is written beside `file` as `name.autosave.hex` (in its own
    /// format; [`files::autosave_palette`]), which the autosaved `level` names instead.
    fn autosave_palettes(
        &self,
        level: &mut texel_scene::Level,
        file: &Path,
        images: &mut Vec<(PathBuf, AutosaveImage)>,
    ) {
        let Some(setting) = &mut level.palette else {
            return;
        };
        for rel in std::iter::once(&mut setting.file).chain(setting.alternate.as_mut()) {
            let Some(palette) = self.level.assets.palette(rel) else {
                continue;
            };
            let saved = self.path.is_some()
                && (self.palettes_on_disk.get(rel.as_str()))
                    .is_some_and(|p| Arc::ptr_eq(p, palette))
                && resolve(&self.level.path, rel).is_file();
            if saved {
                continue;
            }
            let auto = files::autosave_palette(rel);
            let path = resolve(file, &auto);
            if !images.iter().any(|(p, _)| *p == path) {
                images.push((path, AutosaveImage::Palette(Arc::clone(palette))));
            }
            *rel = auto;
        }
    }

    /// After opening an autosave: terrains reading a `name.autosave.png` name `name.png`
    /// again and keep the heights (or paint) read (written to `name.png` on the next save),
    /// and a palette read from `name.autosave.hex` is `name.hex` again, its colours kept (and
    /// written there on the next save).
    pub fn adopt_autosaved_heights(&mut self) {
        self.adopt_autosaved_palettes();
        let scene = &mut self.level.scene;
        let entities: Vec<_> = scene.entities().collect();
        for e in entities {
            let Some(mut row) = scene.row(e) else {
                continue;
            };
            let Some(t) = &mut row.terrain else {
                continue;
            };
            let mut changed = false;
            if let Some(p) = &mut t.paint
                && let Some(original) = files::autosaved_heightmap_of(&p.path)
            {
                let image = self.level.assets.texture(&p.path).cloned();
                self.paint_on_disk.remove(&p.path);
                if let Some(image) = image {
                    self.level.assets.insert_texture(&original, image);
                }
                p.path = original;
                changed = true;
            }
            if let HeightSource::File { path } = &t.heightmap
                && let Some(original) = files::autosaved_heightmap_of(path)
            {
                let field = self.level.assets.heightfield(t).cloned();
                self.on_disk.remove(path);
                t.heightmap = HeightSource::File { path: original };
                if let Some(f) = field {
                    self.level.assets.insert_heightfield(t, f);
                }
                changed = true;
            }
            if changed {
                let _ = scene.set_row(e, row);
            }
        }
        self.touch();
    }

    fn adopt_autosaved_palettes(&mut self) {
        let Some(setting) = &mut self.level.scene.palette else {
            return;
        };
        for rel in std::iter::once(&mut setting.file).chain(setting.alternate.as_mut()) {
            let Some(original) = files::autosaved_palette_of(rel) else {
                continue;
            };
            if let Some(p) = self.level.assets.palette(rel).cloned() {
                self.level.assets.insert_palette(&original, p);
            }
            self.palettes_on_disk.remove(rel.as_str());
            *rel = original;
        }
    }

    /// Whether a heightmap (or paint) file name (relative to the level) is used: named by a
    /// terrain of the scene, or a file beside the level this document did not write or read.
    pub fn heightmap_taken(&self, rel: &str) -> bool {
        let named = terrains(&self.level.scene).any(|t| {
            matches!(&t.heightmap, HeightSource::File { path } if path == rel)
                || t.paint.as_ref().is_some_and(|p| p.path == rel)
        });
        let foreign = self.path.is_some()
            && resolve(&self.level.path, rel).exists()
            && !self.on_disk.contains_key(rel)
            && !self.paint_on_disk.contains_key(rel);
        named || foreign
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
    /// typed) are skipped. Terrain heights and paint layers already in memory are kept (they
    /// may be sculpted or painted and not saved yet). On failure the library is left as it
    /// was.
    pub fn reload_assets(&mut self) -> Result<(), String> {
        self.reload_assets_keeping(&[])
    }

    /// [`Document::reload_assets`], also keeping the heights and paint in memory of `more`
    /// terrains (those the history can bring back).
    pub fn reload_assets_keeping(&mut self, more: &[Terrain]) -> Result<(), String> {
        let old = &self.level.assets;
        let mut level = self.level.scene.to_level();
        // Palettes in memory (edited, perhaps) are kept, not read again.
        level.palette = None;
        for row in &mut level.entities {
            if let Some(t) = &mut row.terrain {
                if t.displacement
                    .as_ref()
                    .is_some_and(|d| d.path.trim().is_empty())
                {
                    t.displacement = None;
                }
                if (t.paint.as_ref())
                    .is_some_and(|p| p.path.trim().is_empty() || old.texture(&p.path).is_some())
                {
                    t.paint = None;
                }
                let empty =
                    matches!(&t.heightmap, HeightSource::File { path } if path.trim().is_empty());
                if empty || old.heightfield(t).is_some() {
                    // Nothing to read: a two-sample stand-in, replaced below.
                    t.heightmap = HeightSource::Noise {
                        seed: 0,
                        resolution: 2,
                        frequency: 1.0,
                        octaves: 1,
                        island: 0.0,
                    };
                }
            }
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
        let mut assets = load_assets(&level, &self.level.path, None).map_err(|e| e.to_string())?;
        for t in terrains(&self.level.scene).chain(more.iter().cloned()) {
            if let Some(f) = old.heightfield(&t) {
                assets.insert_heightfield(&t, f.clone());
            }
            if let Some(p) = &t.paint
                && let Some(image) = old.texture(&p.path)
            {
                assets.insert_texture(&p.path, image.clone());
            }
        }
        for (rel, p) in old.palettes() {
            assets.insert_palette(rel, p.clone());
        }
        let old = std::mem::replace(&mut self.level.assets, assets);
        self.note_files_read(&old);
        self.touch();
        Ok(())
    }
}

/// The terrains of `scene`, in level order.
fn terrains(scene: &Scene) -> impl Iterator<Item = Terrain> + '_ {
    scene
        .entities()
        .filter_map(|e| scene.world().get::<&Terrain>(e).ok().map(|t| (*t).clone()))
}

/// The non-empty mesh, texture (sprite sheets and maps among them) and heightmap paths `row`
/// names that `assets` has not loaded.
pub fn unloaded_paths(row: &EntityRow, assets: &AssetLibrary) -> Vec<String> {
    let mut out = Vec::new();
    if let Some(t) = &row.terrain {
        if let HeightSource::File { path } = &t.heightmap
            && !path.trim().is_empty()
            && assets.heightfield(t).is_none()
        {
            out.push(path.clone());
        }
        if let Some(d) = &t.displacement
            && !d.path.trim().is_empty()
            && assets.texture(&d.path).is_none()
        {
            out.push(d.path.clone());
        }
        if let Some(p) = &t.paint
            && !p.path.trim().is_empty()
            && assets.texture(&p.path).is_none()
        {
            out.push(p.path.clone());
        }
    }
    if let Some(Geometry::Mesh { path }) = &row.geometry
        && !path.trim().is_empty()
        && assets.get(path).is_none()
    {
        out.push(path.clone());
    }
    let sprite_files = row.sprite.iter().flat_map(|s| s.files().map(|(_, p)| p));
    for p in row
        .material
        .iter()
        .flat_map(texture_paths)
        .chain(sprite_files)
    {
        if !p.trim().is_empty() && assets.texture(p).is_none() {
            out.push(p.to_owned());
        }
    }
    out
}

#[cfg(test)]
mod region_tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn region_changes_union_until_a_full_change() {
        let mut d = Document::new_empty();
        let r0 = d.revision;
        assert_eq!(d.region_since(r0), None, "nothing changed");
        d.touch_region(Vec3::ZERO, Vec3::ONE);
        d.touch_region(Vec3::splat(-1.0), Vec3::splat(0.5));
        assert_eq!(
            d.region_since(r0),
            Some((Vec3::splat(-1.0), Vec3::ONE)),
            "the union of both"
        );
        let r2 = d.revision;
        assert_eq!(d.region_since(r2), None);
        d.touch();
        d.touch_region(Vec3::ZERO, Vec3::ONE);
        assert_eq!(d.region_since(r2), None, "a full change since r2");
        assert_eq!(
            d.region_since(d.revision - 1),
            Some((Vec3::ZERO, Vec3::ONE))
        );
    }

    /// A palette change alone is told apart (the view maps colours again); mixed with an
    /// entity change, neither shortcut applies.
    #[test]
    fn palette_changes_alone_are_told_apart() {
        let mut d = Document::new_empty();
        let r0 = d.revision;
        assert!(!d.palette_only_since(r0), "nothing changed");
        d.palette_parts_mut();
        assert!(d.palette_only_since(r0));
        assert_eq!(d.entities_since(r0), None);
        let r1 = d.revision;
        d.entity_parts_mut(0);
        assert!(!d.palette_only_since(r1));
        assert!(!d.palette_only_since(r0));
        assert_eq!(d.entities_since(r0), None, "a palette change in between");
        assert_eq!(d.entities_since(r1), Some(vec![RowEdit::Set(0)]));
        d.touch();
        assert!(!d.palette_only_since(r0), "a full change");
    }

    /// Entity changes since a revision are listed once each, in order; a region or a full
    /// change since makes the list `None`, and an entity change makes the region `None`.
    #[test]
    fn entities_since_lists_entity_changes_alone() {
        use glam::Vec3;
        let mut d = Document::new_empty();
        let r0 = d.revision;
        assert_eq!(d.entities_since(r0), None, "nothing changed");
        d.entity_parts_mut(3);
        d.entity_parts_mut(1);
        d.entity_parts_mut(3);
        assert_eq!(
            d.entities_since(r0),
            Some(vec![RowEdit::Set(3), RowEdit::Set(1)])
        );
        // An entity added: every change since kept, in order.
        let r_add = d.revision;
        d.row_parts_mut(RowEdit::Insert(2));
        d.entity_parts_mut(2);
        d.entity_parts_mut(2);
        d.row_parts_mut(RowEdit::Remove(0));
        let (set, add, remove) = (RowEdit::Set(2), RowEdit::Insert(2), RowEdit::Remove(0));
        assert_eq!(d.entities_since(r_add), Some(vec![add, set, set, remove]));
        assert_eq!(d.region_since(r0), None, "an entity changed, not a region");
        let r1 = d.revision;
        d.touch_region(Vec3::ZERO, Vec3::ONE);
        assert_eq!(d.entities_since(r1), None, "a region changed");
        let r2 = d.revision;
        d.entity_parts_mut(0);
        d.touch();
        assert_eq!(d.entities_since(r2), None, "a full change since r2");
        let r3 = d.revision;
        for i in 0..MAX_ENTITY_CHANGES + 1 {
            d.entity_parts_mut(i % 7);
        }
        assert_eq!(d.entities_since(r3), None, "too many changes: rebuild");
        let recent = d
            .entities_since(d.revision - 3)
            .expect("recent changes kept");
        assert_eq!(recent.len(), 3);
    }
}

/// A heightmap, paint layer or palette an autosave keeps beside it.
#[derive(Debug, Clone)]
pub enum AutosaveImage {
    /// A terrain's heights and the height its white stands for.
    Heights(Arc<Heightfield>, f32),
    /// A terrain's paint layer.
    Paint(Arc<Image>),
    /// A palette's colours (edited swatches).
    Palette(Arc<Palette>),
}

/// An autosave taken from the document ([`Document::autosave_job`]), to be written.
#[derive(Debug, Clone)]
pub struct AutosaveJob {
    /// The autosave file.
    pub file: PathBuf,
    level: texel_scene::Level,
    images: Vec<(PathBuf, AutosaveImage)>,
}

impl AutosaveJob {
    /// Writes the images, then the level, each atomically (creating the folder); returns
    /// the images written.
    pub fn write(self) -> Result<Vec<PathBuf>, String> {
        if let Some(dir) = self.file.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        }
        let mut written = Vec::new();
        for (png, image) in self.images {
            match &image {
                AutosaveImage::Heights(field, max) => {
                    crate::terrain::write_heightmap(&png, field, *max)?
                }
                AutosaveImage::Paint(image) => crate::paint::write_paint(&png, image)?,
                AutosaveImage::Palette(p) => p.save(&png).map_err(|e| e.to_string())?,
            }
            written.push(png);
        }
        self.level.save(&self.file).map_err(|e| e.to_string())?;
        Ok(written)
    }
}
