//! Unit tests of the sprite section: frame lists, animation steps.

use super::*;

#[test]
fn frame_lists_read_and_write() {
    assert_eq!(parse_frames("1, 2,3 ,"), Ok(vec![1, 2, 3]));
    assert_eq!(parse_frames(""), Ok(vec![]));
    assert!(parse_frames("1, x").unwrap_err().contains("`x`"));
    assert!(parse_frames("-1").is_err());
    assert_eq!(frames_text(&[4, 0, 7]), "4, 0, 7");
}

#[test]
fn the_step_is_the_position_frame_at_shows() {
    let a = SpriteAnimation {
        name: "a".into(),
        frames: vec![7, 7, 3],
        fps: 4.0,
    };
    for (t, k) in [(0.0, 0), (0.25, 1), (0.5, 2), (0.75, 0), (-0.1, 2)] {
        assert_eq!(step_at(&a, t), k, "t {t}");
    }
}
