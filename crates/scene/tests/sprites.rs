//! Sprites in level files: a round trip with every option, each bad value's message and
//! position, sheets and maps that do not fit their sprite (named with the level's line), and
//! the bundled `sprites.ron` with its images.

use std::path::{Path, PathBuf};

use glam::{UVec2, Vec2, Vec3};
use texel_scene::assets::load_assets;
use texel_scene::sprite::{
    Billboard, Refraction, Relief, Sprite, SpriteAnimation, SpriteSize, direction_index,
};
use texel_scene::{EntityRow, ErrorKind, Level, Name, Scene, Transform};

fn data(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(rel)
}

fn bundled(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../assets/levels")
        .join(name)
}

fn row(name: &str, sprite: Sprite) -> EntityRow {
    EntityRow {
        name: Some(Name(name.into())),
        transform: Some(Transform::from_translation(Vec3::new(1.0, 0.0, 2.0))),
        sprite: Some(sprite),
        ..EntityRow::default()
    }
}

/// A sprite with every field away from its default.
fn every_option() -> Sprite {
    Sprite {
        sheet: "walker.png".into(),
        frame_size: UVec2::new(24, 32),
        animations: vec![
            SpriteAnimation {
                name: "walk".into(),
                frames: vec![1, 2, 3, 4],
                fps: 8.0,
            },
            SpriteAnimation {
                name: "idle".into(),
                frames: vec![0],
                fps: 1.0,
            },
        ],
        pivot: Vec2::new(0.5, 0.5),
        size: SpriteSize::World(Vec2::new(1.44, 1.92)),
        billboard: Billboard::Spherical,
        directions: 8,
        normal_map: Some("walker_n.png".into()),
        relief: Some(Relief {
            depth_map: "d.png".into(),
            depth: 0.4,
        }),
        refraction: Some(Refraction {
            back_depth: "b.png".into(),
            index_ratio: 0.67,
        }),
        casts_shadows: true,
        outlined: false,
    }
}

#[test]
fn sprites_round_trip_with_every_option_and_write_no_defaults() {
    let path = Path::new("s.ron");
    let plain = Sprite::new("grass.png", UVec2::new(16, 16), SpriteSize::Matched);
    let fixed = Sprite {
        billboard: Billboard::Fixed,
        ..plain.clone()
    };
    let level = Level {
        entities: vec![
            row("Tuft", plain.clone()),
            row("Glass", every_option()),
            row("Sign", fixed),
        ],
        ..Level::default()
    };
    let text = level.to_ron_string(path).unwrap();
    for want in [
        "sprite: (sheet: \"grass.png\", frame_size: (16, 16), size: Matched),",
        "sprite: (sheet: \"walker.png\", frame_size: (24, 32), animations: [(name: \"walk\", \
         frames: [1, 2, 3, 4], fps: 8.0), (name: \"idle\", frames: [0], fps: 1.0)], \
         pivot: (0.5, 0.5), size: World((1.44, 1.92)), billboard: Spherical, directions: 8, \
         normal_map: \"walker_n.png\", relief: (depth_map: \"d.png\", depth: 0.4), \
         refraction: (back_depth: \"b.png\", index_ratio: 0.67), casts_shadows: true, \
         outlined: false),",
        "sprite: (sheet: \"grass.png\", frame_size: (16, 16), size: Matched, billboard: Fixed),",
    ] {
        assert!(text.contains(want), "`{want}` in {text}");
    }
    let back = Level::from_ron_str(&text, path).unwrap();
    assert_eq!(back, level);
    assert_eq!(back.to_ron_string(path).unwrap(), text);
    let scene = Scene::from_level(&back);
    assert_eq!(scene.to_level(), level);
    assert_eq!(scene.kind_counts().sprites, 3);
    // Defaults written out by hand read as the defaults and are left out again.
    let spelt = "(version: 3, entities: [(transform: (translation: (1.0, 0.0, 2.0), \
                 rotation: (0.0, 0.0, 0.0), scale: (1.0, 1.0, 1.0)), sprite: (sheet: \
                 \"grass.png\", frame_size: (16, 16), animations: [], pivot: (0.5, 1.0), \
                 size: Matched, billboard: Upright, directions: 1, normal_map: None, \
                 casts_shadows: false, outlined: true))])";
    let spelt = Level::from_ron_str(spelt, path).unwrap();
    assert_eq!(spelt.entities[0].sprite, Some(plain));
    assert!(
        spelt
            .to_ron_string(path)
            .unwrap()
            .contains("sprite: (sheet: \"grass.png\", frame_size: (16, 16), size: Matched)")
    );
}

/// Every check made while parsing, with the line it points at (and, for a number, its
/// column).
#[test]
fn bad_sprites_are_refused_with_their_line() {
    let base = "(version: 3, entities: [\n\
                (name: \"Tuft\", transform: (translation: (0.0, 0.0, 0.0), \
                rotation: (0.0, 0.0, 0.0), scale: (1.0, 1.0, 1.0)), sprite: (sheet: \"g.png\", \
                frame_size: (16, 16), animations: [(name: \"sway\", frames: [0, 1], fps: 2.0), \
                (name: \"still\", frames: [0], fps: 1.0)], size: World((0.5, 0.5)))),\n\
                (name: \"Ball\", transform: (translation: (0.0, 1.0, 0.0), \
                rotation: (0.0, 0.0, 0.0), scale: (1.0, 1.0, 1.0)), sprite: (sheet: \"b.png\", \
                frame_size: (32, 32), pivot: (0.5, 0.5), size: Matched, billboard: Spherical, \
                directions: 8, normal_map: \"n.png\", relief: (depth_map: \"f.png\", depth: 0.8), \
                refraction: (back_depth: \"k.png\", index_ratio: 0.67))),\n])";
    let path = Path::new("s.ron");
    Level::from_ron_str(base, path).expect("the base sprites are valid");
    let invalid = Some(ErrorKind::InvalidValue);
    let cases = [
        // (from, to, line, kind, words)
        (
            "frame_size: (16, 16)",
            "frame_size: (0, 16)",
            2,
            invalid,
            "frame size must be in 1..=2048 pixels per side, got (0, 16)",
        ),
        (
            "frame_size: (16, 16)",
            "frame_size: (16, 4096)",
            2,
            invalid,
            "frame size must be in 1..=2048",
        ),
        (
            "frame_size: (16, 16)",
            "frame_size: (16, -1)",
            2,
            Some(ErrorKind::WrongType),
            "wrong type",
        ),
        ("fps: 2.0", "fps: 0.0", 2, invalid, "fps must be positive"),
        ("fps: 2.0", "fps: -2.0", 2, invalid, "fps must be positive"),
        ("fps: 2.0", "fps: 5000.0", 2, invalid, "at most 1000.0"),
        ("fps: 2.0", "fps: NaN", 2, invalid, "NaN or infinite"),
        ("fps: 2.0", "fps: inf", 2, invalid, "NaN or infinite"),
        (
            "frames: [0, 1]",
            "frames: []",
            2,
            invalid,
            "an animation needs at least one frame",
        ),
        (
            "name: \"still\"",
            "name: \"sway\"",
            2,
            invalid,
            "two animations are called `sway`",
        ),
        (
            "name: \"still\"",
            "name: \" \"",
            2,
            invalid,
            "animation 1 has no name",
        ),
        (
            "size: World((0.5, 0.5))",
            "size: World((0.0, 0.5))",
            2,
            invalid,
            "size must be positive",
        ),
        (
            "size: World((0.5, 0.5))",
            "size: World((0.5, NaN))",
            2,
            invalid,
            "NaN or infinite",
        ),
        (
            "size: World((0.5, 0.5))",
            "size: Huge",
            2,
            Some(ErrorKind::UnknownField),
            "unknown kind `Huge`",
        ),
        (
            "sheet: \"g.png\"",
            "sheet: \"\"",
            2,
            invalid,
            "image path is empty",
        ),
        (
            "size: World((0.5, 0.5))",
            "size: World((0.5, 0.5)), glow: true",
            2,
            Some(ErrorKind::UnknownField),
            "unknown field `glow` in Sprite",
        ),
        (
            "pivot: (0.5, 0.5)",
            "pivot: (0.5, 1.5)",
            3,
            invalid,
            "must be within 0..=1",
        ),
        (
            "billboard: Spherical",
            "billboard: Sideways",
            3,
            Some(ErrorKind::UnknownField),
            "unknown kind `Sideways`",
        ),
        (
            "directions: 8",
            "directions: 4",
            3,
            invalid,
            "directions must be 1 or 8, got 4",
        ),
        (
            "directions: 8",
            "directions: 0",
            3,
            invalid,
            "directions must be 1 or 8, got 0",
        ),
        (
            "normal_map: \"n.png\"",
            "normal_map: \" \"",
            3,
            invalid,
            "image path is empty",
        ),
        (
            "depth: 0.8",
            "depth: 0.0",
            3,
            invalid,
            "relief depth must be positive",
        ),
        (
            "depth: 0.8",
            "depth: -1.0",
            3,
            invalid,
            "relief depth must be positive",
        ),
        ("depth: 0.8", "depth: NaN", 3, invalid, "NaN or infinite"),
        (
            "depth: 0.8",
            "depth: 1000.0",
            3,
            invalid,
            "relief depth must be at most 100.0 world units",
        ),
        (
            "index_ratio: 0.67",
            "index_ratio: 0.0",
            3,
            invalid,
            "index ratio must be in 0.2..=5.0, got 0.0",
        ),
        (
            "index_ratio: 0.67",
            "index_ratio: -1.5",
            3,
            invalid,
            "index ratio must be in 0.2..=5.0",
        ),
        (
            "index_ratio: 0.67",
            "index_ratio: NaN",
            3,
            invalid,
            "NaN or infinite",
        ),
        (
            "index_ratio: 0.67",
            "index_ratio: 50.0",
            3,
            invalid,
            "index ratio must be in 0.2..=5.0, got 50.0",
        ),
        (
            "relief: (depth_map: \"f.png\", depth: 0.8), ",
            "",
            3,
            invalid,
            "a refraction needs a relief",
        ),
    ];
    for (from, to, line, kind, words) in cases {
        let text = base.replacen(from, to, 1);
        assert_ne!(text, base, "{from}");
        let e = Level::from_ron_str(&text, path).expect_err(to);
        assert_eq!(e.kind(), kind, "{to}: {e}");
        let e = e.to_string();
        assert!(e.starts_with(&format!("s.ron:{line}:")), "{to}: {e}");
        assert!(e.contains(words), "{to}: `{e}` should say `{words}`");
    }
    // Columns: at a bad number; at the sprite's end for a refraction without relief.
    let col = |text: &str, line: usize, needle: &str| {
        let l = text.lines().nth(line - 1).unwrap();
        l.find(needle).unwrap() + needle.len() + 1
    };
    let text = base.replace("fps: 2.0", "fps: 0.0");
    let e = Level::from_ron_str(&text, path).unwrap_err().to_string();
    let at = col(&text, 2, "fps: ");
    assert!(e.starts_with(&format!("s.ron:2:{at}:")), "{e}");
    let text = base.replace("relief: (depth_map: \"f.png\", depth: 0.8), ", "");
    let e = Level::from_ron_str(&text, path).unwrap_err().to_string();
    // At the sprite's closing parenthesis.
    let at = col(&text, 3, "index_ratio: 0.67))") - 1;
    assert!(e.starts_with(&format!("s.ron:3:{at}:")), "{e}");

    // Cross-row: a sprite needs a transform, and neither geometry nor a terrain.
    let no_transform = base.replacen(
        "(name: \"Ball\", transform: (translation: (0.0, 1.0, 0.0), \
         rotation: (0.0, 0.0, 0.0), scale: (1.0, 1.0, 1.0)), ",
        "(name: \"Ball\", ",
        1,
    );
    assert_ne!(no_transform, base);
    let e = Level::from_ron_str(&no_transform, path).unwrap_err();
    assert_eq!(e.kind(), invalid);
    let e = e.to_string();
    assert!(
        e.starts_with("s.ron:3:")
            && e.contains("entity 1 (Ball): a sprite is placed by its entity's transform"),
        "{e}"
    );
    let geometry = base.replacen(
        "(name: \"Tuft\", ",
        "(name: \"Tuft\", geometry: Box(size: (1.0, 1.0, 1.0)), ",
        1,
    );
    let e = Level::from_ron_str(&geometry, path)
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("s.ron:2:") && e.contains("entity 0 (Tuft): a sprite entity has no mesh"),
        "{e}"
    );
    let terrain = base.replacen(
        "(name: \"Tuft\", ",
        "(name: \"Tuft\", terrain: (size: (64.0, 64.0), \
         heightmap: Noise(seed: 1, resolution: 9, frequency: 0.05, octaves: 1), \
         max_height: 8.0, gradient: [(at: 0.0, colour: (0.2, 0.5, 0.1))], \
         pixel_density: 6.0, band_distance: 8.0, band_transition: 0.3), ",
        1,
    );
    let e = Level::from_ron_str(&terrain, path).unwrap_err().to_string();
    assert!(
        e.starts_with("s.ron:2:")
            && e.contains("entity 0 (Tuft): an entity with a terrain cannot have a sprite"),
        "{e}"
    );
    // The same rules hold for levels built in code, before a save.
    let mut level = Level::from_ron_str(base, path).unwrap();
    level.entities[1].geometry = Some(texel_scene::Geometry::Sphere {
        radius: 1.0,
        segments: 16,
    });
    let e = level.to_ron_string(path).unwrap_err().to_string();
    assert!(
        e.contains("entity 1 (Ball): sprite.geometry: a sprite entity has no mesh"),
        "{e}"
    );
    let mut level = Level::from_ron_str(base, path).unwrap();
    level.entities[0].sprite.as_mut().unwrap().animations[0].fps = f32::NAN;
    let e = level.to_ron_string(path).unwrap_err().to_string();
    assert!(
        e.contains("entity 0 (Tuft): sprite.animations: NaN or infinite"),
        "{e}"
    );
}

/// (fixture, line, column, words): levels that parse but whose sprite images are missing,
/// undecodable or do not fit the sprite. The error names the level's line and the image.
const IMAGE_CATALOGUE: &[(&str, usize, usize, &str)] = &[
    (
        "sprite_missing_sheet.ron",
        25,
        29,
        "sprites/no_such_sheet.png: cannot read image",
    ),
    (
        "sprite_broken_sheet.ron",
        25,
        29,
        "sprites/broken.png: not a PNG or JPEG image",
    ),
    (
        "sprite_frame_not_dividing.ron",
        25,
        53,
        "sprites/sheet.png: frame size 20×16 does not divide the sheet's 48×32 pixels",
    ),
    (
        "sprite_frame_out_of_range.ron",
        25,
        95,
        "sprites/sheet.png: animation `sway`: frame 6 is out of range: the sheet holds 6 \
         frames (0..=5)",
    ),
    (
        "sprite_too_few_rows.ron",
        25,
        156,
        "sprites/sheet.png: 8 directions need at least 8 rows of frames, the sheet has 2",
    ),
    (
        "sprite_map_size.ron",
        25,
        168,
        "sprites/normal_small.png: the normal map is 16×16 pixels, but the sheet \
         \"../sprites/sheet.png\" is 48×32",
    ),
];

#[test]
fn sprite_images_that_do_not_fit_are_named_with_the_levels_line() {
    for &(file, line, column, words) in IMAGE_CATALOGUE {
        let path = data(&format!("levels/{file}"));
        let text = std::fs::read_to_string(&path).unwrap();
        let level = Level::load(&path).unwrap_or_else(|e| panic!("{file} parses: {e}"));
        let e = load_assets(&level, &path, Some(&text))
            .expect_err(file)
            .to_string();
        let prefix = format!("{}:{line}:{column}: entity 2 (Tuft): ", path.display());
        assert!(
            e.starts_with(&prefix),
            "{file}: `{e}` should start with `{prefix}`"
        );
        assert!(e.contains(words), "{file}: `{e}` should say `{words}`");
        // Without the text, the same error without a position.
        let e = load_assets(&level, &path, None).unwrap_err().to_string();
        assert!(e.contains(words) && !e.contains(":25:"), "{file}: {e}");
    }
}

/// Two sprites share a sheet; the second's frames do not fit it: the error points at the
/// second's row, not at the first mention of the sheet.
#[test]
fn a_shared_sheets_error_points_at_the_row_at_fault() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(data("sprites/sheet.png"), dir.path().join("sheet.png")).unwrap();
    std::fs::copy(
        data("sprites/normal_small.png"),
        dir.path().join("small.png"),
    )
    .unwrap();
    let good = Sprite::new("sheet.png", UVec2::new(16, 16), SpriteSize::Matched);
    let path = dir.path().join("l.ron");
    let mut level = Level {
        entities: vec![row("A", good.clone()), row("B", good.clone())],
        ..Level::default()
    };
    let text = level.to_ron_string(&path).unwrap();
    let lib = load_assets(&level, &path, Some(&text)).unwrap();
    let sheet = lib.sprite_sheet(&good).expect("the sheet is loaded");
    assert_eq!((sheet.width, sheet.height), (48, 32));
    assert_eq!(lib.texture_count(), 1, "shared");
    assert!(lib.sprite_normal_map(&good).is_none());

    level.entities[1].sprite.as_mut().unwrap().frame_size = UVec2::new(16, 20);
    let text = level.to_ron_string(&path).unwrap();
    let e = load_assets(&level, &path, Some(&text))
        .unwrap_err()
        .to_string();
    let (line, l) = text
        .lines()
        .enumerate()
        .find(|(_, l)| l.contains("frame_size: (16, 20)"))
        .unwrap();
    let column = l.find("frame_size").unwrap() + 1;
    let at = format!("l.ron:{}:{column}: entity 1 (B): ", line + 1);
    assert!(e.contains(&at) && e.contains("does not divide"), "{e}");

    // Every map is loaded and available; one of another size is refused.
    let mut maps = good.clone();
    maps.normal_map = Some("sheet.png".into());
    maps.relief = Some(Relief {
        depth_map: "sheet.png".into(),
        depth: 0.5,
    });
    maps.refraction = Some(Refraction {
        back_depth: "small.png".into(),
        index_ratio: 0.67,
    });
    let level = Level {
        entities: vec![row("Comment (with) \"quotes\"", maps.clone())],
        ..Level::default()
    };
    let text = level.to_ron_string(&path).unwrap();
    let e = load_assets(&level, &path, Some(&text))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("small.png: the back depth map is 16×16 pixels"),
        "{e}"
    );
    let back_line = text
        .lines()
        .position(|l| l.contains("\"small.png\""))
        .unwrap()
        + 1;
    assert!(e.contains(&format!("l.ron:{back_line}:")), "{e}");
    maps.refraction.as_mut().unwrap().back_depth = "sheet.png".into();
    let level = Level {
        entities: vec![row("M", maps.clone())],
        ..Level::default()
    };
    let lib = load_assets(&level, &path, None).unwrap();
    for image in [
        lib.sprite_normal_map(&maps),
        lib.sprite_depth_map(&maps),
        lib.sprite_back_depth(&maps),
    ] {
        assert_eq!(image.map(|i| (i.width, i.height)), Some((48, 32)));
    }
}

/// The bundled sprites level: stone_circle plus the walker (animated, 8 directions,
/// upright), the bump-mapped tablet, the relief pyramid, the glass sphere and a dozen
/// foliage sprites on the ground, every image loaded and fitting its sprite.
#[test]
fn the_sprites_level_is_the_stone_circle_with_sprites_and_loads_its_images() {
    let circle = Level::load(&bundled("stone_circle.ron")).unwrap();
    let path = bundled("sprites.ron");
    let level = Level::load(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(level.entities[..circle.entities.len()], circle.entities[..]);
    assert_eq!(level.settings, circle.settings);
    let lib = load_assets(&level, &path, None).unwrap_or_else(|e| panic!("{e}"));
    let sprites: Vec<(&str, &Sprite, Transform)> = level
        .entities
        .iter()
        .filter_map(|r| {
            Some((
                r.name.as_ref()?.0.as_str(),
                r.sprite.as_ref()?,
                r.transform?,
            ))
        })
        .collect();
    for (name, s, _) in &sprites {
        let sheet = lib
            .sprite_sheet(s)
            .unwrap_or_else(|| panic!("{name}'s sheet"));
        let size = UVec2::new(sheet.width, sheet.height);
        s.check_sheet(size)
            .unwrap_or_else(|e| panic!("{name}: {e:?}"));
        // Every frame holds something.
        for i in 0..s.frame_count(size) {
            let (x0, y0, w, h) = s.frame_rect(size, i);
            let opaque = (y0..y0 + h)
                .flat_map(|y| (x0..x0 + w).map(move |x| (x, y)))
                .filter(|&(x, y)| sheet.pixel(x, y)[3] > 0)
                .count();
            assert!(opaque > 0, "{name}: frame {i} is empty");
        }
    }
    let find = |name: &str| {
        sprites
            .iter()
            .find(|s| s.0 == name)
            .unwrap_or_else(|| panic!("{name}"))
            .1
    };
    let walker = find("Walker");
    assert_eq!(
        (walker.directions, walker.billboard),
        (8, Billboard::Upright)
    );
    let walk = walker.animation("walk").expect("a walk");
    assert!(walk.frames.len() >= 4);
    let sheet = lib.sprite_sheet(walker).unwrap();
    let size = UVec2::new(sheet.width, sheet.height);
    assert!((16..=32).contains(&walker.frame_size.x) && (16..=32).contains(&walker.frame_size.y));
    assert_eq!(walker.rows(size), 8);
    let normal = lib
        .sprite_normal_map(walker)
        .expect("the walker's normal map");
    assert_eq!((normal.width, normal.height), (sheet.width, sheet.height));
    // The walk at 8 fps: 0.125 s is its second frame; seen from +X (direction 2) two rows
    // down; the front and the side are different pictures.
    let side = walker.frame_at(size, "walk", 0.125, 2);
    assert_eq!(side, walk.frames[1] + 2 * walker.columns(size));
    let front = walker.frame_at(size, "walk", 0.125, direction_index(Vec3::NEG_Z));
    let pixels = |i| {
        let (x0, y0, w, h) = walker.frame_rect(size, i);
        (y0..y0 + h)
            .flat_map(|y| (x0..x0 + w).map(move |x| (x, y)))
            .map(|(x, y)| sheet.pixel(x, y))
            .collect::<Vec<_>>()
    };
    assert_ne!(pixels(front), pixels(side));

    let tablet = find("Carved tablet");
    assert!(tablet.normal_map.is_some() && tablet.relief.is_none());
    let pyramid = find("Stepped pyramid");
    assert!(pyramid.relief.is_some() && lib.sprite_depth_map(pyramid).is_some());
    let glass = find("Glass sphere");
    assert!(lib.sprite_depth_map(glass).is_some() && lib.sprite_back_depth(glass).is_some());
    let foliage: Vec<_> = sprites
        .iter()
        .filter(|s| s.0.starts_with("Grass") || s.0.starts_with("Bush"))
        .collect();
    assert!(foliage.len() >= 12, "{} foliage sprites", foliage.len());
    assert!(
        foliage.iter().all(|s| s.2.translation.y == 0.0),
        "on the ground"
    );
    assert_eq!(
        Scene::from_level(&level).kind_counts().sprites,
        sprites.len()
    );
}
