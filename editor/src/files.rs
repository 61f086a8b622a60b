//! File chores around the document: native dialogs (with a typed-path fallback where no
//! dialog service exists), the recent-files list, and autosaves beside the level (an untitled
//! document's beside the recent-files list).

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use texel_scene::Scene;

/// How many recent files are remembered.
pub const RECENT_MAX: usize = 8;
/// How often a modified document is autosaved: a crash loses at most this much work (and
/// the write, which runs beside the editor: on a 10,000-entity level about 0.3 s).
pub const AUTOSAVE_EVERY: Duration = Duration::from_secs(5);
/// Edits after which a modified document is autosaved without waiting for the timer.
pub const AUTOSAVE_AFTER_EDITS: u32 = 20;
/// A dialog that answers faster than this found no dialog service (rfd without a portal).
const NO_SERVICE: Duration = Duration::from_millis(150);

/// What a native dialog answered.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Picked {
    /// A path was chosen.
    Path(PathBuf),
    /// The person cancelled.
    Cancelled,
    /// There is no dialog service: ask for a typed path instead.
    NoService,
}

/// Asks for a level to open.
pub fn pick_open() -> Picked {
    timed(|| {
        rfd::FileDialog::new()
            .add_filter("Texel level", &["ron"])
            .pick_file()
    })
}

/// Asks where to save a level.
pub fn pick_save(current: Option<&Path>) -> Picked {
    timed(|| {
        let mut d = rfd::FileDialog::new().add_filter("Texel level", &["ron"]);
        if let Some(name) = current.and_then(|p| p.file_name()) {
            d = d.set_file_name(name.to_string_lossy());
        }
        d.save_file()
    })
}

/// Asks for a glTF mesh.
pub fn pick_mesh() -> Picked {
    timed(|| {
        rfd::FileDialog::new()
            .add_filter("glTF", &["gltf", "glb"])
            .pick_file()
    })
}

/// Asks for a sprite sheet.
pub fn pick_sprite() -> Picked {
    timed(|| {
        rfd::FileDialog::new()
            .add_filter("Sprite sheet (PNG)", &["png"])
            .pick_file()
    })
}

/// Asks for a palette file.
pub fn pick_palette() -> Picked {
    timed(|| {
        rfd::FileDialog::new()
            .add_filter("Palette (GIMP, hex, JASC)", &["gpl", "hex", "pal"])
            .pick_file()
    })
}

/// Asks for a 16-bit heightmap PNG to import.
pub fn pick_heightmap() -> Picked {
    timed(|| {
        rfd::FileDialog::new()
            .add_filter("16-bit greyscale PNG", &["png"])
            .pick_file()
    })
}

/// Asks where to export a heightmap, suggesting `name`.
pub fn pick_heightmap_save(name: &str) -> Picked {
    timed(|| {
        rfd::FileDialog::new()
            .add_filter("16-bit greyscale PNG", &["png"])
            .set_file_name(name)
            .save_file()
    })
}

fn timed(f: impl FnOnce() -> Option<PathBuf>) -> Picked {
    if std::env::var_os("TEXEL_EDITOR_NO_DIALOGS").is_some() {
        return Picked::NoService;
    }
    let t = Instant::now();
    match f() {
        Some(p) => Picked::Path(p),
        None if t.elapsed() < NO_SERVICE => Picked::NoService,
        None => Picked::Cancelled,
    }
}

/// The autosave file beside `level`: `name.autosave.ron`.
pub fn autosave_path(level: &Path) -> PathBuf {
    let stem = level
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "untitled".into());
    level.with_file_name(format!("{stem}.autosave.ron"))
}

/// An autosave of `level` newer than the level itself, if one exists.
pub fn recoverable(level: &Path) -> Option<PathBuf> {
    let auto = autosave_path(level);
    let a = std::fs::metadata(&auto).and_then(|m| m.modified()).ok()?;
    match std::fs::metadata(level).and_then(|m| m.modified()) {
        Ok(l) if l > a => None,
        _ => Some(auto),
    }
}

/// Writes an autosave of `scene` beside `level` (atomically).
pub fn autosave(scene: &Scene, level: &Path) -> Result<PathBuf, String> {
    let path = autosave_path(level);
    write_autosave(scene, &path)?;
    Ok(path)
}

/// Writes `scene` to the autosave file `path` (atomically), creating its folder.
pub fn write_autosave(scene: &Scene, path: &Path) -> Result<(), String> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    scene.save(path).map_err(|e| e.to_string())
}

/// Removes the autosave beside `level` (after a save or a discard), with the heightmaps it
/// kept.
pub fn remove_autosave(level: &Path) {
    remove_autosave_file(&autosave_path(level));
}

/// Removes the autosave file `auto` and the heightmaps it kept ([`autosave_heightmaps`]).
pub fn remove_autosave_file(auto: &Path) {
    for png in autosave_heightmaps(auto) {
        let _ = std::fs::remove_file(png);
    }
    let _ = std::fs::remove_file(auto);
}

/// The heightmap an autosave keeps a terrain's unsaved heights in: `a/name.png` →
/// `a/name.autosave.png` (relative to the autosave, which sits where the level does).
pub fn autosave_heightmap(rel: &str) -> String {
    let stem = rel
        .len()
        .checked_sub(4)
        .filter(|&n| rel.is_char_boundary(n) && rel[n..].eq_ignore_ascii_case(".png"))
        .map_or(rel, |n| &rel[..n]);
    format!("{stem}{AUTOSAVE_HEIGHTMAP}")
}

/// The heightmap an autosave's heightmap stands for (`name.autosave.png` → `name.png`);
/// `None` for any other path.
pub fn autosaved_heightmap_of(rel: &str) -> Option<String> {
    rel.strip_suffix(AUTOSAVE_HEIGHTMAP)
        .filter(|s| !s.is_empty())
        .map(|s| format!("{s}.png"))
}

/// What autosaved heightmap names end with.
pub const AUTOSAVE_HEIGHTMAP: &str = ".autosave.png";

/// The palette file an autosave keeps a palette's unsaved colours in (swatch edits):
/// `a/name.hex` → `a/name.autosave.hex`, in the palette's own format.
pub fn autosave_palette(rel: &str) -> String {
    let (stem, ext) = split_extension(rel);
    format!("{stem}.autosave{ext}")
}

/// The palette an autosave's palette stands for (`name.autosave.hex` → `name.hex`); `None`
/// for any other path.
pub fn autosaved_palette_of(rel: &str) -> Option<String> {
    let (stem, ext) = split_extension(rel);
    let original = stem.strip_suffix(".autosave")?;
    (!original.is_empty() && !original.ends_with('/')).then(|| format!("{original}{ext}"))
}

/// `rel` before and from the dot of its file name's extension ("" without one).
fn split_extension(rel: &str) -> (&str, &str) {
    let name_at = rel.rfind('/').map_or(0, |i| i + 1);
    match rel[name_at..].rfind('.') {
        Some(i) if i > 0 => rel.split_at(name_at + i),
        _ => (rel, ""),
    }
}

/// The heightmap, paint and palette files the autosave `auto` names and keeps
/// ([`autosave_heightmap`], [`autosave_palette`]); none when it is missing or unreadable.
pub fn autosave_heightmaps(auto: &Path) -> Vec<PathBuf> {
    let Ok(level) = texel_scene::Level::load(auto) else {
        return Vec::new();
    };
    let palettes = (level.palette.iter())
        .flat_map(|s| std::iter::once(&s.file).chain(&s.alternate))
        .filter(|path| autosaved_palette_of(path).is_some())
        .map(|path| texel_scene::assets::resolve(auto, path));
    let images: Vec<PathBuf> = level
        .entities
        .iter()
        .filter_map(|r| r.terrain.as_ref())
        .flat_map(|t| {
            let heights = match &t.heightmap {
                texel_scene::terrain::HeightSource::File { path } => Some(path),
                texel_scene::terrain::HeightSource::Noise { .. } => None,
            };
            heights.into_iter().chain(t.paint.as_ref().map(|p| &p.path))
        })
        .filter(|path| autosaved_heightmap_of(path).is_some())
        .map(|path| texel_scene::assets::resolve(auto, path))
        .collect();
    images.into_iter().chain(palettes).collect()
}

/// The recent-files list, most recent first, kept in the user's config directory.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Recent {
    /// The files.
    pub files: Vec<PathBuf>,
    store: Option<PathBuf>,
}

impl Recent {
    /// Reads the list from `store` (missing or unreadable means empty).
    pub fn load(store: Option<PathBuf>) -> Self {
        let files = store
            .as_ref()
            .and_then(|s| std::fs::read_to_string(s).ok())
            .map(|t| {
                t.lines()
                    .filter(|l| !l.is_empty())
                    .map(PathBuf::from)
                    .collect()
            })
            .unwrap_or_default();
        Recent { files, store }
    }

    /// The default store: `$XDG_CONFIG_HOME/texel/recent.txt` or `~/.config/texel/recent.txt`.
    pub fn default_store() -> Option<PathBuf> {
        let base = std::env::var_os("XDG_CONFIG_HOME")
            .map(PathBuf::from)
            .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".config")))?;
        Some(base.join("texel").join("recent.txt"))
    }

    /// Where an untitled document is autosaved: beside the list, `untitled.autosave.ron`
    /// (none without a store).
    pub fn untitled_autosave(&self) -> Option<PathBuf> {
        Some(self.store.as_ref()?.parent()?.join("untitled.autosave.ron"))
    }

    /// Puts `path` first and writes the list back (best effort: a read-only home is fine).
    pub fn touch(&mut self, path: &Path) {
        let path = std::fs::canonicalize(path).unwrap_or_else(|_| path.to_owned());
        self.files.retain(|p| *p != path);
        self.files.insert(0, path);
        self.files.truncate(RECENT_MAX);
        if let Some(store) = &self.store {
            if let Some(dir) = store.parent() {
                let _ = std::fs::create_dir_all(dir);
            }
            let text: Vec<String> = self
                .files
                .iter()
                .map(|p| p.to_string_lossy().into_owned())
                .collect();
            let _ = std::fs::write(store, text.join("\n"));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn autosaved_heightmaps_name_their_heightmap() {
        assert_eq!(
            autosave_heightmap("a/hills_T.png"),
            "a/hills_T.autosave.png"
        );
        assert_eq!(autosave_heightmap("x.PNG"), "x.autosave.png");
        assert_eq!(autosave_heightmap("odd"), "odd.autosave.png");
        assert_eq!(
            autosaved_heightmap_of("a/hills_T.autosave.png").as_deref(),
            Some("a/hills_T.png")
        );
        assert_eq!(autosaved_heightmap_of("hills_T.png"), None);
    }

    #[test]
    fn autosaved_palettes_name_their_palette_in_its_format() {
        let rel = "../palettes/texel-night.gpl";
        assert_eq!(
            autosave_palette(rel),
            "../palettes/texel-night.autosave.gpl"
        );
        assert_eq!(autosave_palette("a.b/odd"), "a.b/odd.autosave");
        let back = autosaved_palette_of(&autosave_palette(rel));
        assert_eq!(back.as_deref(), Some(rel));
        assert_eq!(autosaved_palette_of(rel), None);
        assert_eq!(autosaved_palette_of("a/.autosave.hex"), None);
    }

    #[test]
    fn autosave_sits_beside_the_level() {
        assert_eq!(
            autosave_path(Path::new("a/b/level.ron")),
            PathBuf::from("a/b/level.autosave.ron")
        );
    }

    #[test]
    fn recent_list_is_most_recent_first_and_bounded() {
        let dir = tempfile::tempdir().expect("tempdir");
        let store = dir.path().join("recent.txt");
        let mut r = Recent::load(Some(store.clone()));
        for i in 0..10 {
            r.touch(Path::new(&format!("/nowhere/{i}.ron")));
        }
        r.touch(Path::new("/nowhere/5.ron"));
        assert_eq!(r.files.len(), RECENT_MAX);
        assert_eq!(r.files[0], PathBuf::from("/nowhere/5.ron"));
        assert_eq!(Recent::load(Some(store)).files, r.files);
    }

    #[test]
    fn autosave_is_offered_only_when_newer() {
        let dir = tempfile::tempdir().expect("tempdir");
        let level = dir.path().join("l.ron");
        Scene::new().save(&level).expect("save");
        assert_eq!(recoverable(&level), None);
        std::thread::sleep(Duration::from_millis(20));
        autosave(&Scene::new(), &level).expect("autosave");
        assert_eq!(recoverable(&level), Some(autosave_path(&level)));
        remove_autosave(&level);
        assert_eq!(recoverable(&level), None);
    }
}
