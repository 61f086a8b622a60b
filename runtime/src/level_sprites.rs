//! Sprites from the level to the renderer: each sprite entity's [`SpriteInput`] (its sheet
//! and maps from the level's assets), and the sprites that change over time (an animation
//! of frames, an animator moving the entity) with their state at a time, the same wherever
//! a frame is drawn.

use glam::{UVec2, Vec2};
use texel_render::input::{SpriteBillboard, SpriteInput, SpriteState};
use texel_scene::Transform;
use texel_scene::assets::AssetLibrary;
use texel_scene::hierarchy::Carried;
use texel_scene::sprite::{Billboard, Sprite, SpriteSize};

/// The renderer's view of `sprite` on an entity placed by `t`, `None` when its sheet is not
/// loaded.
pub fn sprite_input(
    sprite: &Sprite,
    t: &Transform,
    assets: &AssetLibrary,
    id: u32,
) -> Option<SpriteInput> {
    let sheet = assets.sprite_sheet(sprite)?.clone();
    let size = match sprite.size {
        SpriteSize::World(s) => Some(s * Vec2::new(t.scale.x, t.scale.y)),
        SpriteSize::Matched => None,
    };
    let frame = sprite.frame_at(sheet_size(&sheet), 0usize, 0.0, 0);
    Some(SpriteInput {
        id,
        position: t.translation,
        rotation: t.quat(),
        size,
        pivot: sprite.pivot,
        billboard: match sprite.billboard {
            Billboard::Spherical => SpriteBillboard::Spherical,
            Billboard::Upright => SpriteBillboard::Upright,
            Billboard::Fixed => SpriteBillboard::Fixed,
        },
        frame_size: sprite.frame_size,
        eight_directions: sprite.directions == texel_scene::sprite::DIRECTIONS,
        normal_map: assets.sprite_normal_map(sprite).cloned(),
        relief: (sprite.relief.as_ref())
            .and_then(|r| Some((assets.sprite_depth_map(sprite)?.clone(), r.depth))),
        refraction: (sprite.refraction.as_ref())
            .and_then(|r| Some((assets.sprite_back_depth(sprite)?.clone(), r.index_ratio))),
        outlined: sprite.outlined,
        casts_shadows: sprite.casts_shadows,
        frame,
        sheet,
    })
}

fn sheet_size(sheet: &texel_render::input::Image) -> UVec2 {
    UVec2::new(sheet.width, sheet.height)
}

/// A sprite that changes over time: its frames play, or an animator moves it.
#[derive(Debug, Clone)]
pub struct SpriteClock {
    /// Index into `SceneInput::sprites`.
    pub index: usize,
    sprite: Sprite,
    sheet: UVec2,
    base: Transform,
    animator: Option<Carried>,
}

impl SpriteClock {
    /// The clock of sprite `index` (`input`, from `sprite` on an entity placed by `base`,
    /// moved by `animator`: its own or an animated ancestor's), `None` when nothing about it
    /// changes.
    pub fn new(
        index: usize,
        sprite: &Sprite,
        input: &SpriteInput,
        base: Transform,
        animator: Option<Carried>,
    ) -> Option<Self> {
        let plays = sprite
            .animations
            .first()
            .is_some_and(|a| a.frames.len() > 1);
        (plays || animator.is_some()).then(|| SpriteClock {
            index,
            sprite: sprite.clone(),
            sheet: sheet_size(&input.sheet),
            base,
            animator,
        })
    }

    /// Its state `t` seconds in: the first animation's frame (direction 0's), the animator's
    /// position.
    pub fn state(&self, t: f64) -> SpriteState {
        let position = match &self.animator {
            Some(a) => a.pose_at(t).translation,
            None => self.base.translation,
        };
        SpriteState {
            sprite: self.index,
            position,
            frame: self.sprite.frame_at(self.sheet, 0usize, t, 0),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use texel_scene::sprite::SpriteAnimation;

    fn input(sheet: UVec2) -> SpriteInput {
        SpriteInput {
            id: 1,
            position: glam::Vec3::ZERO,
            rotation: glam::Quat::IDENTITY,
            size: None,
            pivot: Vec2::new(0.5, 1.0),
            billboard: SpriteBillboard::Upright,
            sheet: std::sync::Arc::new(texel_render::input::Image::solid(
                "s", sheet.x, sheet.y, [255; 4],
            )),
            frame_size: UVec2::new(8, 8),
            eight_directions: false,
            normal_map: None,
            relief: None,
            refraction: None,
            outlined: true,
            casts_shadows: false,
            frame: 0,
        }
    }

    #[test]
    fn still_sprites_have_no_clock_and_playing_ones_follow_their_frames() {
        let mut sprite = Sprite::new("s.png", UVec2::new(8, 8), SpriteSize::Matched);
        let i = input(UVec2::new(32, 8));
        assert!(SpriteClock::new(0, &sprite, &i, Transform::default(), None).is_none());
        sprite.animations.push(SpriteAnimation {
            name: "walk".into(),
            frames: vec![1, 2, 3],
            fps: 4.0,
        });
        let clock = SpriteClock::new(0, &sprite, &i, Transform::default(), None).unwrap();
        assert_eq!(clock.state(0.0).frame, 1);
        assert_eq!(clock.state(0.26).frame, 2);
        assert_eq!(clock.state(0.76).frame, 1, "loops");
    }
}
