//! Sprites in the document: what Add → Sprite makes of a sheet. The sheet is read once to
//! learn its size (and refused with the decoder's message if it is not an image), its path is
//! stored relative to the level like a glTF mesh's, and the decoded image goes straight into
//! the document's asset library, so nothing is read twice. The inspector's sprite section
//! and preview are [`crate::ui::sprite_section`].

use std::path::Path;
use std::sync::Arc;

use glam::{UVec2, Vec2, Vec3};
use texel_scene::sprite::{MAX_ANIMATION_FRAMES, Sprite, SpriteAnimation, SpriteSize};
use texel_scene::texture::load_texture;
use texel_scene::{EntityRow, Name, Transform};

use crate::state::EditorState;

/// Frames per second of the animation Add → Sprite makes for a strip of frames.
pub const DEFAULT_FPS: f32 = 8.0;

/// The sprite Add → Sprite makes of the sheet `rel`, `sheet` pixels large: a strip of square
/// frames (a sheet whose width is a multiple of its height, or the other way round) is cut
/// into them and played as one animation, "play", at [`DEFAULT_FPS`]; any other sheet is one
/// frame. The quad is 1 world unit high, as wide as the frame's proportions say; it stands
/// upright on its bottom centre.
pub fn default_sprite(rel: &str, sheet: UVec2) -> Sprite {
    let (w, h) = (sheet.x.max(1), sheet.y.max(1));
    let frame = if w > h && w.is_multiple_of(h) {
        UVec2::splat(h)
    } else if h > w && h.is_multiple_of(w) {
        UVec2::splat(w)
    } else {
        UVec2::new(w, h)
    };
    let size = SpriteSize::World(Vec2::new(frame.x as f32 / frame.y as f32, 1.0));
    let mut sprite = Sprite::new(rel, frame, size);
    let count = sprite.frame_count(sheet).min(MAX_ANIMATION_FRAMES as u32);
    if count > 1 {
        sprite.animations.push(SpriteAnimation {
            name: "play".into(),
            frames: (0..count).collect(),
            fps: DEFAULT_FPS,
        });
    }
    sprite
}

/// An entity named `name` with the [`default_sprite`] of `rel` standing at `at`.
pub fn sprite_row(name: &str, rel: &str, sheet: UVec2, at: Vec3) -> EntityRow {
    EntityRow {
        name: Some(Name(name.to_owned())),
        transform: Some(Transform::from_translation(at)),
        sprite: Some(default_sprite(rel, sheet)),
        ..EntityRow::default()
    }
}

/// Adds a sprite of the sheet `file` standing at `at`, as one undo step, and selects it. The
/// level must be saved (the sheet's path is stored relative to it); a file that cannot be
/// read or decoded is refused with the reason, and nothing is added.
pub fn add_sprite(state: &mut EditorState, file: &Path, at: Vec3) -> Result<(), String> {
    let Some(level) = state.document.path.clone() else {
        return Err(
            "save the level first: sprite sheet paths are relative to the level file".into(),
        );
    };
    let image = load_texture(file).map_err(|e| e.to_string())?;
    let rel = crate::assets::level_relative(&level, file);
    let name = file
        .file_stem()
        .map_or_else(|| "Sprite".to_owned(), |s| s.to_string_lossy().into_owned());
    let row = sprite_row(&name, &rel, UVec2::new(image.width, image.height), at);
    row.validate().map_err(|(component, (field, message))| {
        format!("{}: {component}.{field}: {message}", file.display())
    })?;
    // The library keys images by the path the level writes, as the loader would.
    let assets = &mut state.document.level.assets;
    assets.insert_texture(&rel, Arc::new(image));
    state.add(row).map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;
    use texel_scene::Validate;

    #[test]
    fn strips_are_cut_into_square_frames_and_played() {
        let strip = default_sprite("g.png", UVec2::new(32, 16));
        assert_eq!(strip.frame_size, UVec2::new(16, 16));
        assert_eq!(strip.animations.len(), 1);
        assert_eq!(strip.animations[0].frames, vec![0, 1]);
        assert_eq!(strip.size, SpriteSize::World(Vec2::new(1.0, 1.0)));
        let column = default_sprite("c.png", UVec2::new(8, 32));
        assert_eq!(column.frame_size, UVec2::new(8, 8));
        assert_eq!(column.animations[0].frames, vec![0, 1, 2, 3]);
        // Anything else is one frame, as wide as it is.
        let one = default_sprite("w.png", UVec2::new(120, 256));
        assert_eq!(one.frame_size, UVec2::new(120, 256));
        assert!(one.animations.is_empty());
        assert_eq!(one.size, SpriteSize::World(Vec2::new(120.0 / 256.0, 1.0)));
        for s in [strip, column, one] {
            assert!(s.validate().is_ok(), "{s:?}");
        }
        let square = default_sprite("s.png", UVec2::new(32, 32));
        assert_eq!(square.check_sheet(UVec2::new(32, 32)), Ok(()));
        assert!(square.animations.is_empty());
    }
}
