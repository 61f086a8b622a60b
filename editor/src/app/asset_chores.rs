//! The asset panel's chores: drawing it (when shown, walking the level's project folder
//! again when the level changed) and placing an asset dropped on the viewport or added at
//! the view's centre. A mesh becomes an entity with the mesh, a texture a textured box, a
//! sprite sheet a sprite (Add → Sprite's defaults), a palette the level's palette; each is
//! one undo step, and a file that cannot be used is shown in the error dialog and changes
//! nothing.

use std::path::Path;
use std::sync::Arc;

use glam::Vec3;
use texel_scene::texture::load_texture;
use texel_scene::{Material, TextureMap};

use super::EditorApp;
use crate::assets::{AssetDrag, AssetKind};
use crate::ui::menu::Action;

impl EditorApp {
    /// Draws the asset panel at the bottom of the window when it is shown; returns what it
    /// asked for.
    pub(super) fn asset_panel(&mut self, ui: &mut egui::Ui, playing: bool) -> Option<Action> {
        if !self.assets.open {
            return None;
        }
        let rescan = std::mem::take(&mut self.assets.rescan);
        let ctx = ui.ctx().clone();
        (self.assets).refresh(&ctx, self.state.document.path.as_deref(), rescan);
        egui::Panel::bottom("assets")
            .resizable(true)
            .default_size(140.0)
            .show(ui, |ui| {
                crate::assets::panel::show(ui, &mut self.assets, playing)
            })
            .inner
    }

    /// Places the asset `drag` at `at` (a drop), or where Add places things (`None`).
    pub fn place_asset(&mut self, drag: &AssetDrag, at: Option<Vec3>) {
        self.viewport.stop();
        let at = at.unwrap_or_else(|| self.viewport.place_point(&self.state));
        let file = drag.path.as_path();
        match drag.kind {
            AssetKind::Mesh => self.add_mesh_at(file, at),
            AssetKind::Sprite => {
                if let Err(e) = crate::add_sprite::add_sprite(&mut self.state, file, at) {
                    self.dialogs.error = Some(format!("cannot add the sprite: {e}"));
                }
            }
            AssetKind::Texture => {
                if let Err(e) = self.add_textured_box(file, at) {
                    self.dialogs.error = Some(format!("cannot add the texture: {e}"));
                }
            }
            AssetKind::Palette => {
                self.pick_palette(crate::palette_edits::Slot::Main, file);
            }
        }
    }

    /// Adds a unit box standing on `at` with the texture `file` (read and decoded first, so a
    /// bad file adds nothing), as one undo step.
    fn add_textured_box(&mut self, file: &Path, at: Vec3) -> Result<(), String> {
        let level = (self.state.document.path.clone())
            .ok_or("save the level first: texture paths are relative to the level file")?;
        let image = load_texture(file).map_err(|e| e.to_string())?;
        let rel = crate::assets::level_relative(&level, file);
        let (_, mut row) = (crate::ui::menu::presets().into_iter())
            .find(|(label, _)| *label == "Box")
            .ok_or("no box preset")?;
        let name = file
            .file_stem()
            .map_or_else(|| "Box".to_owned(), |s| s.to_string_lossy().into_owned());
        row.name = Some(texel_scene::Name(name));
        row.material = Some(Material {
            texture: Some(TextureMap::new(&rel)),
            ..Material::default()
        });
        let row = crate::viewport::place::placed_at(row, at);
        // The library keys images by the path the level writes, as the loader would.
        (self.state.document.level.assets).insert_texture(&rel, Arc::new(image));
        self.state.add(row).map_err(|e| e.to_string())
    }
}
