//! Unit tests of sprite sheets: frame rectangles, directions, animations, refused values.

use super::*;

/// A 4-column sheet of 16×16 frames, `rows` rows.
fn sheet(rows: u32) -> UVec2 {
    UVec2::new(64, 16 * rows)
}

fn walker() -> Sprite {
    Sprite {
        animations: vec![
            SpriteAnimation {
                name: "walk".into(),
                frames: vec![1, 2, 3],
                fps: 4.0,
            },
            SpriteAnimation {
                name: "idle".into(),
                frames: vec![0],
                fps: 1.0,
            },
        ],
        directions: 8,
        ..Sprite::new("w.png", UVec2::new(16, 16), SpriteSize::Matched)
    }
}

#[test]
fn frames_are_row_major_and_rects_clamp() {
    let s = Sprite::new("s.png", UVec2::new(16, 8), SpriteSize::Matched);
    let sheet = UVec2::new(48, 16);
    assert_eq!((s.columns(sheet), s.rows(sheet)), (3, 2));
    assert_eq!(s.frame_count(sheet), 6);
    assert_eq!(s.frame_rect(sheet, 0), (0, 0, 16, 8));
    assert_eq!(s.frame_rect(sheet, 2), (32, 0, 16, 8));
    assert_eq!(s.frame_rect(sheet, 4), (16, 8, 16, 8));
    assert_eq!(
        s.frame_rect(sheet, 99),
        (32, 8, 16, 8),
        "past the end: the last"
    );
    // A sheet smaller than a frame has no frames, and nothing panics.
    let tiny = UVec2::new(8, 8);
    assert_eq!(s.frame_count(tiny), 0);
    assert_eq!(s.frame_rect(tiny, 3), (0, 0, 16, 8));
    let zero = Sprite::new("s.png", UVec2::ZERO, SpriteSize::Matched);
    assert_eq!(zero.frame_count(sheet), 0);
    assert_eq!(zero.frame_rect(sheet, 1), (0, 0, 0, 0));
}

#[test]
fn animations_loop_at_their_fps_and_directions_move_down_rows() {
    let s = walker();
    let sheet = sheet(8);
    // 4 fps over frames 1, 2, 3: a quarter second each, looping every 0.75 s.
    for (t, want) in [
        (0.0, 1),
        (0.2, 1),
        (0.25, 2),
        (0.5, 3),
        (0.74, 3),
        (0.75, 1),
        (1.0, 2),
        (-0.1, 3),
        (3600.0, 1),
        (3600.25, 2),
        (f64::NAN, 1),
    ] {
        assert_eq!(s.frame_at(sheet, "walk", t, 0), want, "t {t}");
        assert_eq!(s.frame_at(sheet, 0, t, 0), want, "by index, t {t}");
    }
    // Direction d is d rows (4 columns each) further down.
    for d in 0..8 {
        assert_eq!(s.frame_at(sheet, "walk", 0.5, d), 3 + 4 * d);
        assert_eq!(s.frame_at(sheet, "idle", 10.0, d), 4 * d);
    }
    assert_eq!(s.frame_at(sheet, "walk", 0.5, 9), 3 + 4, "directions wrap");
    // Unknown animations, or none: frame 0 (of the direction).
    assert_eq!(s.frame_at(sheet, "run", 1.0, 2), 8);
    assert_eq!(s.frame_at(sheet, 5, 1.0, 0), 0);
    let still = Sprite {
        directions: 1,
        animations: Vec::new(),
        ..s.clone()
    };
    assert_eq!(
        still.frame_at(sheet, 0, 12.5, 3),
        0,
        "one direction ignores it"
    );
    // Fractional rates: 3 fps is a third of a second per frame.
    let thirds = Sprite {
        animations: vec![SpriteAnimation {
            name: "a".into(),
            frames: vec![5, 6, 7],
            fps: 3.0,
        }],
        directions: 1,
        ..s
    };
    assert_eq!(thirds.frame_at(sheet, 0, 1.0 / 3.0, 0), 6);
    assert_eq!(thirds.frame_at(sheet, 0, 2.0 / 3.0, 0), 7);
    assert_eq!(thirds.frame_at(sheet, 0, 1.0, 0), 5);
}

#[test]
fn eight_directions_by_compass_and_in_between() {
    // The viewer stands at `at` (sprite space); it looks toward the sprite at the origin.
    let from = |deg: f64| {
        let a = deg.to_radians();
        let at = Vec3::new(a.sin() as f32, 0.0, a.cos() as f32);
        direction_index(-at)
    };
    for d in 0..8 {
        assert_eq!(from(45.0 * f64::from(d)), d, "compass {d}");
        assert_eq!(from(45.0 * f64::from(d) + 20.0), d, "{d} and a bit");
        assert_eq!(from(45.0 * f64::from(d) - 20.0), d, "{d} less a bit");
        assert_eq!(
            from(45.0 * f64::from(d) + 25.0),
            (d + 1) % 8,
            "past half way"
        );
    }
    assert_eq!(
        direction_index(Vec3::new(0.0, 0.0, -1.0)),
        0,
        "from the front"
    );
    assert_eq!(direction_index(Vec3::new(-1.0, 0.0, 0.0)), 2, "from +X");
    assert_eq!(direction_index(Vec3::new(0.0, 0.0, 1.0)), 4, "from behind");
    assert_eq!(direction_index(Vec3::new(1.0, 0.0, 0.0)), 6, "from -X");
    // Height does not matter, only the bearing; straight down or garbage gives 0.
    assert_eq!(direction_index(Vec3::new(-1.0, -5.0, -1.0)), 1);
    assert_eq!(direction_index(Vec3::new(-1.0, 0.0, -1.0) * 1e-20), 1);
    assert_eq!(direction_index(Vec3::NEG_Y), 0);
    assert_eq!(direction_index(Vec3::ZERO), 0);
    assert_eq!(direction_index(Vec3::new(f32::NAN, 0.0, 1.0)), 0);
    assert_eq!(direction_index(Vec3::new(-1.0, 0.0, 1.0)), 3, "from -Z+X");
}

#[test]
fn sheets_that_do_not_fit_are_named() {
    let s = walker();
    assert_eq!(s.check_sheet(sheet(8)), Ok(()));
    let e = s.check_sheet(UVec2::new(60, 128)).unwrap_err();
    assert_eq!(e.field, "frame_size");
    assert!(
        e.message
            .contains("16×16 does not divide the sheet's 60×128"),
        "{e:?}"
    );
    let e = s.check_sheet(UVec2::new(8, 8)).unwrap_err();
    assert_eq!(e.field, "frame_size");
    let e = s.check_sheet(sheet(7)).unwrap_err();
    assert_eq!(e.field, "directions");
    assert!(
        e.message
            .contains("at least 8 rows of frames, the sheet has 7"),
        "{e:?}"
    );
    // Frame 4 is row 1: rows 1..=8 are needed, the sheet has 8.
    let mut far = walker();
    far.animations[0].frames.push(4);
    let e = far.check_sheet(sheet(8)).unwrap_err();
    assert_eq!(
        (e.field, e.animation.as_deref()),
        ("animations", Some("walk"))
    );
    assert!(e.message.contains("frame 4 is in row 1"), "{e:?}");
    assert_eq!(far.check_sheet(sheet(9)), Ok(()));
    let mut out = walker();
    out.directions = 1;
    out.animations[1].frames = vec![64];
    let e = out.check_sheet(sheet(8)).unwrap_err();
    assert_eq!(e.animation.as_deref(), Some("idle"));
    assert!(
        e.message
            .contains("frame 64 is out of range: the sheet holds 32 frames (0..=31)"),
        "{e:?}"
    );
}

#[test]
fn validation_names_the_field() {
    let bad = |f: &dyn Fn(&mut Sprite)| {
        let mut s = walker();
        f(&mut s);
        s.validate().unwrap_err()
    };
    assert!(walker().validate().is_ok());
    assert_eq!(bad(&|s| s.sheet = " ".into()).0, "sheet");
    assert_eq!(bad(&|s| s.frame_size.x = 0).0, "frame_size");
    assert_eq!(bad(&|s| s.animations[0].fps = 0.0).0, "animations");
    assert_eq!(bad(&|s| s.animations[0].fps = f32::NAN).0, "animations");
    assert_eq!(bad(&|s| s.animations[0].frames.clear()).0, "animations");
    assert_eq!(
        bad(&|s| s.animations[1].name = "walk".into()).0,
        "animations"
    );
    assert_eq!(bad(&|s| s.pivot.y = 1.5).0, "pivot");
    assert_eq!(
        bad(&|s| s.size = SpriteSize::World(Vec2::new(1.0, 0.0))).0,
        "size"
    );
    assert_eq!(bad(&|s| s.directions = 4).0, "directions");
    assert_eq!(bad(&|s| s.normal_map = Some(String::new())).0, "normal_map");
    let relief = |depth| {
        Some(Relief {
            depth_map: "d.png".into(),
            depth,
        })
    };
    assert_eq!(bad(&|s| s.relief = relief(-1.0)).0, "relief");
    assert_eq!(bad(&|s| s.relief = relief(1e5)).0, "relief");
    let e = bad(&|s| {
        s.refraction = Some(Refraction {
            back_depth: "b.png".into(),
            index_ratio: 0.67,
        })
    });
    assert_eq!(e.0, "refraction");
    assert!(e.1.contains("a refraction needs a relief"), "{e:?}");
    let e = bad(&|s| {
        s.relief = relief(1.0);
        s.refraction = Some(Refraction {
            back_depth: "b.png".into(),
            index_ratio: -0.5,
        })
    });
    assert_eq!(e.0, "refraction");
    assert!(e.1.contains("index ratio must be in 0.2..=5.0"), "{e:?}");
}
