//! The level's palette as the editor changes it: which files it names, its dither and its
//! colours ([`PaletteState`], what [`crate::command::Command::SetPalette`] sets and
//! restores), picking a file, and editing a swatch. A palette's colours live in the asset
//! library under the path the level names; an edited one is written back to its file when
//! the level is saved ([`crate::document::Document::save_as`]).

use std::path::Path;
use std::sync::Arc;

use texel_scene::PaletteSetting;
use texel_scene::assets::AssetLibrary;
use texel_scene::palette::Palette;

use crate::command::{Command, CommandError};
use crate::history::MergeKey;
use crate::state::EditorState;

/// The level's palette setting and the colours of each file it names.
#[derive(Debug, Clone, PartialEq)]
pub struct PaletteState {
    /// What the level names (`None`: no palette).
    pub setting: Option<PaletteSetting>,
    /// The colours of each file named, by level-relative path.
    pub palettes: Vec<(String, Arc<Palette>)>,
}

impl PaletteState {
    /// The state of the document's level: its setting and the palettes loaded for it.
    pub fn of(setting: Option<&PaletteSetting>, assets: &AssetLibrary) -> PaletteState {
        let palettes = setting
            .into_iter()
            .flat_map(|s| std::iter::once(&s.file).chain(&s.alternate))
            .filter_map(|f| assets.palette(f).map(|p| (f.clone(), p.clone())))
            .collect();
        PaletteState {
            setting: setting.cloned(),
            palettes,
        }
    }

    /// Makes this the level's palette: the setting, and its colours in `assets`.
    pub fn apply(&self, setting: &mut Option<PaletteSetting>, assets: &mut AssetLibrary) {
        for (file, p) in &self.palettes {
            assets.insert_palette(file, p.clone());
        }
        *setting = self.setting.clone();
    }

    /// The colours of `file`, if it is one the state holds.
    pub fn palette(&self, file: &str) -> Option<&Arc<Palette>> {
        self.palettes
            .iter()
            .find(|(f, _)| f == file)
            .map(|(_, p)| p)
    }
}

/// Which of the level's two palettes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Slot {
    /// The level's own palette (day).
    Main,
    /// The alternate (night).
    Alternate,
}

impl EditorState {
    /// The level's palette state now.
    pub fn palette_state(&self) -> PaletteState {
        let level = &self.document.level;
        PaletteState::of(level.scene.palette.as_ref(), &level.assets)
    }

    /// Sets the level's palette to `after` (one undo step per gesture `merge`); nothing
    /// happens when it is unchanged.
    pub fn set_palette(
        &mut self,
        after: PaletteState,
        merge: Option<MergeKey>,
    ) -> Result<(), CommandError> {
        let before = self.palette_state();
        if before == after {
            return Ok(());
        }
        let cmd = Command::SetPalette {
            before: Box::new(before),
            after: Box::new(after),
        };
        self.apply(cmd, merge)
    }

    /// Makes the palette file `file` the level's palette (`Slot::Main`) or its alternate:
    /// read now, named relative to the level (which must be saved). A file that cannot be
    /// used is an error naming it and its line, and nothing changes.
    pub fn pick_palette(&mut self, slot: Slot, file: &Path) -> Result<(), String> {
        let level = (self.document.path.clone())
            .ok_or("save the level first: palette paths are relative to the level file")?;
        let palette = Palette::load(file).map_err(|e| e.to_string())?;
        let rel = crate::assets::level_relative(&level, file);
        let mut state = self.palette_state();
        let setting = match (&mut state.setting, slot) {
            (Some(s), Slot::Main) => {
                s.file = rel.clone();
                s.clone()
            }
            (Some(s), Slot::Alternate) => {
                s.alternate = Some(rel.clone());
                s.clone()
            }
            (None, Slot::Main) => PaletteSetting {
                file: rel.clone(),
                dither: 0.0,
                alternate: None,
            },
            (None, Slot::Alternate) => {
                return Err("pick the level's palette before its alternate".into());
            }
        };
        // A file already loaded (edited, perhaps) keeps the colours in memory.
        let loaded = self.document.level.assets.palette(&rel).cloned();
        let palette = loaded.unwrap_or_else(|| {
            let read = Arc::new(palette);
            self.document.note_palette_read(&rel, read.clone());
            read
        });
        let after = PaletteState::of(Some(&setting), &self.document.level.assets);
        let mut after = after;
        after.palettes.retain(|(f, _)| *f != rel);
        after.palettes.push((rel, palette));
        self.set_palette(after, None).map_err(|e| e.to_string())
    }

    /// Takes the palette (`Slot::Main`: the palette and its alternate) or only its alternate
    /// off the level.
    pub fn clear_palette(&mut self, slot: Slot) -> Result<(), CommandError> {
        let mut state = self.palette_state();
        match slot {
            Slot::Main => state.setting = None,
            Slot::Alternate => {
                if let Some(s) = &mut state.setting {
                    s.alternate = None;
                }
            }
        }
        self.set_palette(state, None)
    }

    /// Sets colour `index` of the palette file `file` to `colour` (sRGB), one undo step per
    /// gesture `merge`.
    pub fn set_swatch(
        &mut self,
        file: &str,
        index: usize,
        colour: [u8; 3],
        merge: Option<MergeKey>,
    ) -> Result<(), CommandError> {
        let mut state = self.palette_state();
        let slot = (state.palettes.iter_mut().find(|(f, _)| f == file))
            .ok_or_else(|| CommandError(format!("the palette {file} is not loaded")))?;
        let mut palette = (*slot.1).clone();
        let c = (palette.colours.get_mut(index))
            .ok_or_else(|| CommandError(format!("the palette {file} has no colour {index}")))?;
        *c = colour;
        slot.1 = Arc::new(palette);
        self.set_palette(state, merge)
    }
}
