//! The bundled sprites level through the runtime: every sprite reaches the renderer with its
//! sheet and maps, and the animation clock plays their frames the same way for every caller.

use std::path::Path;

use texel_runtime::frame_plan::{Animation, scene_input};
use texel_runtime::load::load_level;

#[test]
fn sprites_reach_the_renderer_and_their_frames_play() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/levels/sprites.ron");
    let level = load_level(&path).expect("sprites level");
    let scene = scene_input(&level);
    assert!(scene.sprites.len() >= 10, "{} sprites", scene.sprites.len());
    let walker = scene
        .sprites
        .iter()
        .position(|s| s.eight_directions && s.normal_map.is_some())
        .expect("the 8-direction walker");
    assert!(scene.sprites.iter().any(|s| s.relief.is_some()));
    assert!(scene.sprites.iter().any(|s| s.refraction.is_some()));
    assert!(scene.sprites.iter().any(|s| s.casts_shadows));
    let animation = Animation::new(&level, &scene);
    let frame_at = |t: f64| {
        (animation.sprite_states(t).iter())
            .find(|s| s.sprite == walker)
            .map(|s| s.frame)
    };
    // "walk" is frames 1–4 at 8 fps.
    assert_eq!(frame_at(0.0), Some(1));
    assert_eq!(frame_at(0.13), Some(2));
    assert_eq!(frame_at(0.5), Some(1), "loops");
    assert_eq!(animation.sprite_states(0.3), animation.sprite_states(0.3));
}
