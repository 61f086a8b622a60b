//! Level files: canonical round trips, the broken-level catalogue, migration, saves.

use std::path::{Path, PathBuf};

use glam::Vec3;
use texel_scene::{CURRENT_VERSION, ErrorKind, Level, LevelError, Sampling, Scene, TextureMap};

fn data(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(rel)
}

fn bundled_levels() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/levels");
    let mut v: Vec<_> = std::fs::read_dir(&dir)
        .expect("assets/levels exists")
        .map(|e| e.expect("dir entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "ron"))
        .collect();
    v.sort();
    v
}

#[test]
fn every_bundled_level_saves_back_byte_identical() {
    let levels = bundled_levels();
    let names: Vec<_> = levels
        .iter()
        .filter_map(|p| p.file_name()?.to_str().map(str::to_owned))
        .collect();
    for want in [
        "colonnade.ron",
        "moving_parts.ron",
        "sandbox.ron",
        "sprites.ron",
        "stone_circle.ron",
    ] {
        assert!(names.iter().any(|n| n == want), "{want} is bundled");
    }
    for path in levels {
        let text = std::fs::read_to_string(&path).unwrap();
        let level = Level::load(&path).unwrap_or_else(|e| panic!("{e}"));
        let again = level.to_ron_string(&path).unwrap();
        assert_eq!(text, again, "{} is not canonical", path.display());
        // Through the ECS and back too.
        let via_scene = Scene::from_level(&level).to_level();
        assert_eq!(via_scene, level, "{}", path.display());
    }
}

#[test]
fn stone_circle_has_what_the_issue_asks_for() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/levels/stone_circle.ron");
    let k = Scene::load(&path).unwrap().kind_counts();
    assert!(k.primitives >= 16, "ground plus about fifteen stones: {k}");
    assert_eq!(
        (k.directional_lights, k.point_lights, k.player_starts),
        (1, 1, 1)
    );
}

/// moving_parts is stone_circle plus a windmill (hub and two crossed blade boxes turning
/// together), a sliding door and a moving platform, one of each motion.
#[test]
fn moving_parts_is_the_stone_circle_with_three_motions() {
    use texel_scene::animator::{Easing, Motion};
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/levels");
    let circle = Level::load(&dir.join("stone_circle.ron")).unwrap();
    let level = Level::load(&dir.join("moving_parts.ron")).unwrap();
    assert_eq!(
        level.entities[..circle.entities.len()],
        circle.entities[..],
        "everything of stone_circle is kept"
    );
    assert_eq!(level.settings, circle.settings);
    let animated: Vec<_> = level
        .entities
        .iter()
        .filter_map(|r| {
            Some((
                r.name.as_ref()?.0.as_str(),
                r.animator.as_ref()?,
                r.transform?,
            ))
        })
        .collect();
    let names: Vec<_> = animated.iter().map(|a| a.0).collect();
    assert_eq!(
        names,
        [
            "Windmill hub",
            "Windmill blades A",
            "Windmill blades B",
            "Sliding door",
            "Moving platform"
        ]
    );
    let (_, blades_a, at_a) = animated[1];
    let (_, blades_b, at_b) = animated[2];
    assert_eq!(
        (blades_a, at_a),
        (blades_b, at_b),
        "the blades turn together"
    );
    assert!(matches!(
        blades_a.motion,
        Motion::Rotate { speed: 40.0, .. }
    ));
    let Motion::PingPong { to, period, easing } = &animated[3].1.motion else {
        panic!("the door ping-pongs")
    };
    assert_eq!((*period, *easing), (4.0, Easing::Smooth));
    assert_eq!((to.translation - animated[3].2.translation).length(), 2.0);
    let Motion::Path { keys, period } = &animated[4].1.motion else {
        panic!("the platform follows a path")
    };
    assert_eq!((keys.len(), *period), (4, 8.0));
    let heights: Vec<f32> = keys.iter().map(|k| k.translation.y).collect();
    assert_eq!(heights, [0.2, 1.2, 1.2, 0.2]);
    // The platform starts where its path does, so the rest pose the editor shows is the
    // first key.
    let scene = Scene::from_level(&level);
    let first = scene.animated_poses(0.0);
    assert_eq!(first.len(), 5);
    assert_eq!(first[4].1, animated[4].2);
}

/// (file, kind, line, column, words the message must contain)
const CATALOGUE: &[(&str, Option<ErrorKind>, usize, usize, &str)] = &[
    ("empty.ron", Some(ErrorKind::Syntax), 1, 1, "empty file"),
    (
        "whitespace_only.ron",
        Some(ErrorKind::Syntax),
        1,
        1,
        "empty file",
    ),
    (
        "truncated.ron",
        Some(ErrorKind::Syntax),
        23,
        19,
        "truncated",
    ),
    (
        "garbage.ron",
        Some(ErrorKind::Syntax),
        2,
        2,
        "not a text file",
    ),
    (
        "syntax_error.ron",
        Some(ErrorKind::Syntax),
        7,
        9,
        "expected comma",
    ),
    (
        "not_a_level.ron",
        Some(ErrorKind::WrongType),
        1,
        1,
        "struct `Level`",
    ),
    (
        "unknown_component.ron",
        Some(ErrorKind::UnknownComponent),
        20,
        13,
        "unknown component `sparkle`",
    ),
    (
        "unknown_field.ron",
        Some(ErrorKind::UnknownField),
        15,
        114,
        "unknown field `shiny` in Material",
    ),
    (
        "unknown_geometry.ron",
        Some(ErrorKind::UnknownField),
        20,
        23,
        "unknown kind `Cone`",
    ),
    (
        "wrong_type.ron",
        Some(ErrorKind::WrongType),
        20,
        37,
        "wrong type: expected float",
    ),
    (
        "missing_field.ron",
        Some(ErrorKind::MissingField),
        25,
        69,
        "missing field `cell_size`",
    ),
    (
        "nan.ron",
        Some(ErrorKind::InvalidValue),
        19,
        52,
        "NaN or infinite number",
    ),
    (
        "infinite.ron",
        Some(ErrorKind::InvalidValue),
        19,
        52,
        "NaN or infinite number",
    ),
    (
        "huge_overflow.ron",
        Some(ErrorKind::InvalidValue),
        19,
        53,
        "NaN or infinite number",
    ),
    (
        "huge_finite.ron",
        Some(ErrorKind::InvalidValue),
        19,
        52,
        "too large",
    ),
    (
        "zero_scale.ron",
        Some(ErrorKind::InvalidValue),
        19,
        103,
        "scale must be positive, got 0.0",
    ),
    (
        "negative_scale.ron",
        Some(ErrorKind::InvalidValue),
        19,
        104,
        "scale must be positive, got -2.0",
    ),
    (
        "negative_radius.ron",
        Some(ErrorKind::InvalidValue),
        20,
        38,
        "must be positive, got -1.0",
    ),
    (
        "unknown_version.ron",
        Some(ErrorKind::UnknownVersion),
        2,
        14,
        "unknown level version 99",
    ),
    (
        "missing_version.ron",
        Some(ErrorKind::MissingField),
        36,
        1,
        "missing field `version`",
    ),
    (
        "bad_bands.ron",
        Some(ErrorKind::InvalidValue),
        6,
        16,
        "bands must be in 2..=256",
    ),
    (
        "bad_face_resolution.ron",
        Some(ErrorKind::InvalidValue),
        25,
        91,
        "face resolution must be in 8..=2048",
    ),
    (
        "zero_direction.ron",
        Some(ErrorKind::InvalidValue),
        29,
        58,
        "direction must not be zero",
    ),
    (
        "pitch_out_of_range.ron",
        Some(ErrorKind::InvalidValue),
        34,
        45,
        "pitch must be within ±89",
    ),
    (
        "zero_speed.ron",
        Some(ErrorKind::InvalidValue),
        21,
        69,
        "speed must not be zero",
    ),
    (
        "animator_without_transform.ron",
        Some(ErrorKind::InvalidValue),
        31,
        11,
        "entity 3 (Sun): an animator moves its entity's transform, and this entity has none",
    ),
    (
        "sprite_zero_frame.ron",
        Some(ErrorKind::InvalidValue),
        25,
        71,
        "frame size must be in 1..=2048 pixels per side, got (0, 16)",
    ),
    (
        "sprite_zero_fps.ron",
        Some(ErrorKind::InvalidValue),
        25,
        124,
        "fps must be positive and at most 1000.0, got 0.0",
    ),
    (
        "sprite_four_directions.ron",
        Some(ErrorKind::InvalidValue),
        25,
        168,
        "directions must be 1 or 8, got 4",
    ),
    (
        "sprite_nan_relief_depth.ron",
        Some(ErrorKind::InvalidValue),
        25,
        207,
        "NaN or infinite number",
    ),
    (
        "sprite_index_ratio.ron",
        Some(ErrorKind::InvalidValue),
        25,
        275,
        "index ratio must be in 0.2..=5.0, got 50.0",
    ),
    (
        "sprite_refraction_without_relief.ron",
        Some(ErrorKind::InvalidValue),
        25,
        223,
        "a refraction needs a relief",
    ),
    (
        "sprite_without_transform.ron",
        Some(ErrorKind::InvalidValue),
        25,
        11,
        "entity 2 (Tuft): a sprite is placed by its entity's transform, and this entity has none",
    ),
    (
        "sprite_with_geometry.ron",
        Some(ErrorKind::InvalidValue),
        27,
        11,
        "entity 2 (Tuft): a sprite entity has no mesh",
    ),
    (
        "negative_colour.ron",
        Some(ErrorKind::InvalidValue),
        15,
        47,
        "colour channel must be in 0..=",
    ),
];

#[test]
fn broken_levels_give_the_message_they_must() {
    for &(file, kind, line, column, words) in CATALOGUE {
        let path = data(&format!("levels/{file}"));
        let err = Level::load(&path).expect_err(file);
        let text = err.to_string();
        let prefix = format!("{}:{line}:{column}: ", path.display());
        assert!(
            text.starts_with(&prefix),
            "{file}: `{text}` should start with `{prefix}`"
        );
        assert!(
            text.contains(words),
            "{file}: `{text}` should say `{words}`"
        );
        assert_eq!(err.kind(), kind, "{file}: {text}");
    }
}

#[test]
fn the_catalogue_base_is_valid() {
    // Each broken file is this one with one thing wrong.
    Level::load(&data("valid_base.ron")).unwrap();
}

#[test]
fn a_missing_file_names_it() {
    let path = data("levels/does_not_exist.ron");
    let err = Level::load(&path).unwrap_err();
    assert!(matches!(err, LevelError::Io { .. }));
    assert!(err.to_string().starts_with(&path.display().to_string()));
}

#[test]
fn version_1_migrates_quaternions_to_degrees() {
    let path = data("levels_v1/quaternion_rotation.ron");
    let level = Level::load(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(level.version, texel_scene::CURRENT_VERSION);
    let close = |a: Vec3, b: Vec3| (a - b).length() < 1e-3;
    let yawed = level.entities[0].transform.unwrap();
    assert!(
        close(yawed.rotation, Vec3::new(0.0, 45.0, 0.0)),
        "{}",
        yawed.rotation
    );
    let tipped = level.entities[1].transform.unwrap();
    assert!(
        close(tipped.rotation, Vec3::new(90.0, 0.0, 0.0)),
        "{}",
        tipped.rotation
    );
    assert_eq!(tipped.scale, Vec3::new(2.0, 0.5, 1.0));
    let text = level.to_ron_string(&path).unwrap();
    assert!(text.contains(&format!("version: {CURRENT_VERSION}")));
    assert_eq!(Level::from_ron_str(&text, &path).unwrap(), level);
}

/// Version 3 added textures: a version 2 file loads unchanged but for the version, and a
/// textured material round-trips, writing only the texture fields that differ from their
/// defaults.
#[test]
fn version_2_migrates_and_textured_materials_round_trip() {
    let path = Path::new("v2.ron");
    let v2 = "(version: 2, entities: [(geometry: Plane(size: (4.0, 4.0)), \
              material: (albedo: (1.0, 1.0, 1.0)))])";
    let mut level = Level::from_ron_str(v2, path).unwrap();
    assert_eq!(level.version, CURRENT_VERSION);
    let m = level.entities[0].material.as_mut().unwrap();
    assert_eq!(m.texture, None);
    m.texture = Some(TextureMap {
        sampling: Sampling::Linear,
        ..TextureMap::new("../textures/bricks.png")
    });
    m.normal_map = Some("../textures/bricks_n.png".into());
    let text = level.to_ron_string(path).unwrap();
    assert!(
        text.contains("texture: (path: \"../textures/bricks.png\", sampling: Linear)"),
        "{text}"
    );
    assert!(
        !text.contains("density"),
        "defaults are not written: {text}"
    );
    let back = Level::from_ron_str(&text, path).unwrap();
    assert_eq!(back, level);
    assert_eq!(back.to_ron_string(path).unwrap(), text);
    let bad = text.replace("sampling: Linear", "sampling: Linear, density: 0.0");
    let e = Level::from_ron_str(&bad, path).unwrap_err().to_string();
    assert!(e.contains("v2.ron:") && e.contains("positive"), "{e}");
}

#[test]
fn older_files_without_new_optional_fields_still_load() {
    // A hand-written level that leaves out every field with a default.
    let text = r#"(
        version: 2,
        entities: [
            (geometry: Sphere(radius: 1.0), material: (albedo: (1.0, 0.0, 0.0))),
            (probe_grid_override: (size: (1.0, 1.0, 1.0), cell_size: 0.25)),
        ],
    )"#;
    let level = Level::from_ron_str(text, Path::new("old.ron")).unwrap();
    let m = level.entities[0].material.clone().unwrap();
    assert!(m.casts_shadows && m.outlined && m.emissive == Vec3::ZERO);
    assert_eq!(level.entities[1].probe_grid_override.unwrap().priority, 0);
    assert_eq!(level.settings, texel_scene::LevelSettings::default());
}

#[test]
fn saving_an_invalid_level_fails_and_keeps_the_old_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("level.ron");
    let good = Level::load(&data("valid_base.ron")).unwrap();
    good.save(&path).unwrap();
    let before = std::fs::read(&path).unwrap();

    let mut bad = good.clone();
    bad.entities[1].transform.as_mut().unwrap().translation.y = f32::NAN;
    let err = bad.save(&path).unwrap_err();
    let msg = err.to_string();
    assert!(
        msg.contains("entity 1 (Ball): transform.translation"),
        "{msg}"
    );
    assert_eq!(std::fs::read(&path).unwrap(), before);
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        1,
        "no temp file left"
    );
}

#[test]
fn saving_to_a_missing_folder_names_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("missing/level.ron");
    let err = Level::default().save(&path).unwrap_err();
    assert!(err.to_string().contains("missing/level.ron"), "{err}");
}

/// Bad terrain values are refused with the file, line and column and what is wrong.
#[test]
fn bad_terrains_are_refused_with_their_line() {
    let base = "(version: 3, entities: [\n(terrain: (size: (64.0, 64.0), \
                heightmap: Noise(seed: 1, resolution: 65, frequency: 0.05, octaves: 4), \
                max_height: 8.0, gradient: [(at: 0.0, colour: (0.2, 0.5, 0.1))], \
                pixel_density: 6.0, band_distance: 8.0, band_transition: 0.3))])";
    let path = Path::new("t.ron");
    Level::from_ron_str(base, path).expect("the base terrain is valid");
    let cases = [
        (
            "pixel_density: 6.0",
            "pixel_density: 0.0",
            "must be positive",
        ),
        (
            "pixel_density: 6.0",
            "pixel_density: -2.0",
            "must be positive",
        ),
        ("max_height: 8.0", "max_height: NaN", "NaN"),
        ("size: (64.0, 64.0)", "size: (64.0, 1e30)", "too large"),
        (
            "band_transition: 0.3",
            "band_transition: 1.5",
            "within 0..=1",
        ),
        (
            "resolution: 65",
            "resolution: 1",
            "heightmap resolution must be in 2..=",
        ),
        (
            "resolution: 65",
            "resolution: 100000",
            "heightmap resolution must be in 2..=",
        ),
        ("octaves: 4", "octaves: 0", "octaves must be in 1..=8"),
        ("at: 0.0", "at: 2.0", "within 0..=1"),
        (
            "gradient: [(at: 0.0, colour: (0.2, 0.5, 0.1))]",
            "gradient: []",
            "at least one colour stop",
        ),
        (
            "gradient: [(at: 0.0, colour: (0.2, 0.5, 0.1))]",
            "gradient: [(at: 0.5, colour: (0.2, 0.5, 0.1)), (at: 0.1, colour: (1.0, 1.0, 1.0))]",
            "ascending",
        ),
    ];
    for (from, to, words) in cases {
        let text = base.replace(from, to);
        assert_ne!(text, base, "{from}");
        let e = Level::from_ron_str(&text, path).expect_err(to).to_string();
        assert!(e.starts_with("t.ron:2:"), "{to}: {e}");
        assert!(e.contains(words), "{to}: `{e}` should say `{words}`");
    }
}

/// A terrain's paint layer round-trips (written only when there is one), loads beside the
/// level as RGBA8, and a missing, undecodable or oversized file is refused naming it.
#[test]
fn terrain_paint_layers_round_trip_and_bad_files_are_named() {
    use texel_scene::assets::load_assets;
    use texel_scene::terrain::PaintLayer;
    use texel_scene::texture::{Image, encode_png};
    let dir = tempfile::tempdir().unwrap();
    let base = "(version: 3, entities: [\n(name: \"T\", terrain: (size: (64.0, 64.0), \
                heightmap: Noise(seed: 1, resolution: 9, frequency: 0.05, octaves: 1), \
                max_height: 8.0, gradient: [(at: 0.0, colour: (0.2, 0.5, 0.1))], \
                pixel_density: 6.0, band_distance: 8.0, band_transition: 0.3))])";
    let path = dir.path().join("t.ron");
    let mut level = Level::from_ron_str(base, &path).unwrap();
    let plain = level.to_ron_string(&path).unwrap();
    assert!(!plain.contains("paint"), "no paint, no field: {plain}");
    let t = level.entities[0].terrain.as_mut().unwrap();
    assert_eq!(t.paint, None);
    t.paint = Some(PaintLayer {
        path: "t_T_paint.png".into(),
    });
    let text = level.to_ron_string(&path).unwrap();
    assert!(text.contains("paint: (path: \"t_T_paint.png\")"), "{text}");
    let back = Level::from_ron_str(&text, &path).unwrap();
    assert_eq!(back, level);
    assert_eq!(back.to_ron_string(&path).unwrap(), text);
    assert_eq!(Scene::from_level(&back).to_level(), back);
    // Without the field it is the same as before.
    let mut cleared = back.clone();
    cleared.entities[0].terrain.as_mut().unwrap().paint = None;
    assert_eq!(cleared.to_ron_string(&path).unwrap(), plain);
    let empty = text.replace("t_T_paint.png", " ");
    let e = Level::from_ron_str(&empty, &path)
        .unwrap()
        .to_ron_string(&path)
        .unwrap_err()
        .to_string();
    assert!(e.contains("paint layer path is empty"), "{e}");

    // Missing: the error names the file and the line that names it.
    let e = load_assets(&back, &path, Some(&text))
        .unwrap_err()
        .to_string();
    let line = text
        .lines()
        .position(|l| l.contains("t_T_paint.png"))
        .unwrap()
        + 1;
    assert!(
        e.contains("t_T_paint.png") && e.contains(&format!("t.ron:{line}:")),
        "{e}"
    );
    // Loaded: RGBA8, any size.
    let mut img = Image::solid("p", 3, 2, [255, 0, 0, 255]);
    img.pixels[4..8].copy_from_slice(&[0, 0, 255, 64]);
    std::fs::write(dir.path().join("t_T_paint.png"), encode_png(&img)).unwrap();
    let lib = load_assets(&back, &path, Some(&text)).unwrap();
    let t = back.entities[0].terrain.as_ref().unwrap();
    let loaded = lib.paint(t).expect("paint loaded");
    assert_eq!((loaded.width, loaded.height), (3, 2));
    assert_eq!(loaded.pixels, img.pixels);
    // Undecodable and too large.
    std::fs::write(dir.path().join("t_T_paint.png"), b"not a png").unwrap();
    let e = load_assets(&back, &path, None).unwrap_err().to_string();
    assert!(e.contains("t_T_paint.png") && e.contains("PNG"), "{e}");
    let big = Image::solid("big", 4096, 1, [0; 4]);
    std::fs::write(dir.path().join("t_T_paint.png"), encode_png(&big)).unwrap();
    let e = load_assets(&back, &path, None).unwrap_err().to_string();
    assert!(
        e.contains("t_T_paint.png") && e.contains("larger than 2048"),
        "{e}"
    );
}

/// A level with the three motions round-trips byte-identically, through the ECS too;
/// defaults (no phase, linear easing, unrotated path keys) are not written.
#[test]
fn animators_round_trip_and_write_no_defaults() {
    use texel_scene::animator::{Animator, Easing, Motion, PathKey};
    use texel_scene::{EntityRow, Transform};
    let path = Path::new("a.ron");
    let at = |x: f32, y: f32, z: f32| Transform::from_translation(Vec3::new(x, y, z));
    let key = |time, y| PathKey {
        time,
        translation: Vec3::new(0.0, y, 0.0),
        rotation: Vec3::ZERO,
    };
    let row = |name: &str, motion, phase| EntityRow {
        name: Some(texel_scene::Name(name.into())),
        transform: Some(at(0.0, 1.0, 0.0)),
        animator: Some(Animator { motion, phase }),
        ..EntityRow::default()
    };
    let level = Level {
        entities: vec![
            row(
                "Spinner",
                Motion::Rotate {
                    axis: Vec3::Z,
                    speed: 40.0,
                },
                0.0,
            ),
            row(
                "Door",
                Motion::PingPong {
                    to: at(2.0, 1.0, 0.0),
                    period: 4.0,
                    easing: Easing::Linear,
                },
                0.5,
            ),
            row(
                "Lift",
                Motion::Path {
                    keys: vec![key(0.0, 0.2), key(2.0, 1.2)],
                    period: 8.0,
                },
                0.0,
            ),
        ],
        ..Level::default()
    };
    let text = level.to_ron_string(path).unwrap();
    for want in [
        "animator: (motion: Rotate(axis: (0.0, 0.0, 1.0), speed: 40.0))",
        "animator: (motion: PingPong(to: (translation: (2.0, 1.0, 0.0), rotation: (0.0, 0.0, 0.0), \
         scale: (1.0, 1.0, 1.0)), period: 4.0), phase: 0.5)",
        "animator: (motion: Path(keys: [(time: 0.0, translation: (0.0, 0.2, 0.0)), \
         (time: 2.0, translation: (0.0, 1.2, 0.0))], period: 8.0))",
    ] {
        assert!(text.contains(want), "`{want}` in {text}");
    }
    let back = Level::from_ron_str(&text, path).unwrap();
    assert_eq!(back, level);
    assert_eq!(back.to_ron_string(path).unwrap(), text);
    let scene = Scene::from_level(&back);
    assert_eq!(scene.to_level(), level);
    // Written when not the default.
    let mut eased = level.clone();
    let Some(Animator {
        motion: Motion::PingPong { easing, .. },
        ..
    }) = &mut eased.entities[1].animator
    else {
        unreachable!()
    };
    *easing = Easing::Smooth;
    let Some(Animator {
        motion: Motion::Path { keys, .. },
        ..
    }) = &mut eased.entities[2].animator
    else {
        unreachable!()
    };
    keys[1].rotation = Vec3::new(0.0, 90.0, 0.0);
    let text = eased.to_ron_string(path).unwrap();
    assert!(text.contains("period: 4.0, easing: Smooth)"), "{text}");
    assert!(text.contains("rotation: (0.0, 90.0, 0.0))"), "{text}");
    assert_eq!(Level::from_ron_str(&text, path).unwrap(), eased);
    // Every animated entity, in level order, at its pose.
    let p = scene.animated_poses(1.0);
    let names: Vec<_> = p
        .iter()
        .map(|(e, _)| scene.row(*e).unwrap().name.unwrap().0)
        .collect();
    assert_eq!(names, ["Spinner", "Door", "Lift"]);
    // The door's phase of 0.5 s puts it 1.5 s in: three quarters of the way there.
    assert!((p[1].1.translation.x - 1.5).abs() < 1e-6, "{:?}", p[1].1);
    assert!((p[2].1.translation.y - 0.7).abs() < 1e-6, "{:?}", p[2].1);
}

/// Bad animators are refused with the file, line and column and what is wrong; an animator
/// on an entity without a transform, or on a terrain, names the entity at its row's end.
#[test]
fn bad_animators_are_refused_with_their_line() {
    let base = "(version: 3, entities: [\n(name: \"Mill\", transform: (translation: (0.0, 1.0, 0.0), \
                rotation: (0.0, 0.0, 0.0), scale: (1.0, 1.0, 1.0)), \
                animator: (motion: Rotate(axis: (0.0, 0.0, 1.0), speed: 40.0))),\n\
                (name: \"Door\", transform: (translation: (0.0, 1.0, 0.0), \
                rotation: (0.0, 0.0, 0.0), scale: (1.0, 1.0, 1.0)), \
                animator: (motion: PingPong(to: (translation: (2.0, 1.0, 0.0), \
                rotation: (0.0, 0.0, 0.0), scale: (1.0, 1.0, 1.0)), period: 4.0, easing: Smooth))),\n\
                (name: \"Lift\", transform: (translation: (0.0, 1.0, 0.0), \
                rotation: (0.0, 0.0, 0.0), scale: (1.0, 1.0, 1.0)), \
                animator: (motion: Path(keys: [(time: 0.0, translation: (0.0, 0.2, 0.0)), \
                (time: 2.0, translation: (0.0, 1.2, 0.0))], period: 8.0), phase: 1.0)),\n])";
    let path = Path::new("a.ron");
    Level::from_ron_str(base, path).expect("the base animators are valid");
    let col = |line: &str, needle: &str| line.find(needle).unwrap() + needle.len() + 1;
    let lines: Vec<&str> = base.lines().collect();
    let cases = [
        // (from, to, line, words)
        ("speed: 40.0", "speed: 0.0", 2, "speed must not be zero"),
        ("speed: 40.0", "speed: NaN", 2, "NaN or infinite"),
        ("speed: 40.0", "speed: inf", 2, "NaN or infinite"),
        (
            "axis: (0.0, 0.0, 1.0)",
            "axis: (0.0, 0.0, 0.0)",
            2,
            "axis must not be zero",
        ),
        ("period: 4.0", "period: 0.0", 3, "period must be positive"),
        ("period: 4.0", "period: -4.0", 3, "period must be positive"),
        ("period: 4.0", "period: inf", 3, "NaN or infinite"),
        (
            "easing: Smooth",
            "easing: Bouncy",
            3,
            "unknown kind `Bouncy`",
        ),
        ("phase: 1.0", "phase: NaN", 4, "NaN or infinite"),
        (
            "[(time: 0.0, translation: (0.0, 0.2, 0.0)), ",
            "[",
            4,
            "a path needs at least 2 keys, got 1",
        ),
        (
            "(time: 2.0, translation",
            "(time: 0.0, translation",
            4,
            "path key times must increase: key 1 at 0.0 s does not come after key 0 at 0.0 s",
        ),
        (
            "(time: 0.0, translation: (0.0, 0.2",
            "(time: 0.5, translation: (0.0, 0.2",
            4,
            "the first path key must be at time 0, got 0.5",
        ),
        (
            "period: 8.0",
            "period: 2.0",
            4,
            "the path's period (2.0 s) must be longer than its last key's time (2.0 s)",
        ),
        (
            "period: 8.0",
            "period: 1.5",
            4,
            "must be longer than its last key's time",
        ),
    ];
    for (from, to, line, words) in cases {
        let text = base.replacen(from, to, 1);
        assert_ne!(text, base, "{from}");
        let e = Level::from_ron_str(&text, path).expect_err(to);
        let kind = if to.contains("Bouncy") {
            ErrorKind::UnknownField
        } else {
            ErrorKind::InvalidValue
        };
        assert_eq!(e.kind(), Some(kind), "{to}: {e}");
        let e = e.to_string();
        assert!(e.starts_with(&format!("a.ron:{line}:")), "{to}: {e}");
        assert!(e.contains(words), "{to}: `{e}` should say `{words}`");
    }
    // Columns: at the bad value for a single number, at the motion's end for the period
    // against the keys.
    let e = Level::from_ron_str(&base.replace("speed: 40.0", "speed: 0.0"), path)
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with(&format!("a.ron:2:{}:", col(lines[1], "speed: "))),
        "{e}"
    );
    let short = base.replace("period: 8.0", "period: 2.0");
    let e = Level::from_ron_str(&short, path).unwrap_err().to_string();
    let line4 = short.lines().nth(3).unwrap();
    // At the motion's closing parenthesis.
    let end = col(line4, "period: 2.0)") - 1;
    assert!(e.starts_with(&format!("a.ron:4:{end}:")), "{e}");

    // Cross-row: no transform, or a terrain.
    let no_transform = base.replacen(
        "(name: \"Door\", transform: (translation: (0.0, 1.0, 0.0), \
         rotation: (0.0, 0.0, 0.0), scale: (1.0, 1.0, 1.0)), ",
        "(name: \"Door\", ",
        1,
    );
    assert_ne!(no_transform, base);
    let e = Level::from_ron_str(&no_transform, path).unwrap_err();
    assert_eq!(e.kind(), Some(ErrorKind::InvalidValue));
    let e = e.to_string();
    assert!(
        e.starts_with("a.ron:3:")
            && e.contains("entity 1 (Door): an animator moves its entity's transform"),
        "{e}"
    );
    let terrain = base.replacen(
        "(name: \"Mill\", ",
        "(name: \"Mill\", terrain: (size: (64.0, 64.0), \
         heightmap: Noise(seed: 1, resolution: 9, frequency: 0.05, octaves: 1), \
         max_height: 8.0, gradient: [(at: 0.0, colour: (0.2, 0.5, 0.1))], \
         pixel_density: 6.0, band_distance: 8.0, band_transition: 0.3), ",
        1,
    );
    let e = Level::from_ron_str(&terrain, path).unwrap_err().to_string();
    assert!(
        e.starts_with("a.ron:2:") && e.contains("entity 0 (Mill): terrains do not move"),
        "{e}"
    );
    // The same rules hold for levels built in code, before a save.
    let mut level = Level::from_ron_str(base, path).unwrap();
    level.entities[1].transform = None;
    let e = level.to_ron_string(path).unwrap_err().to_string();
    assert!(
        e.contains("entity 1 (Door): animator.transform: an animator moves"),
        "{e}"
    );
}

/// palette_night is the stone circle drawn in a palette, with a night palette to swap to
/// (`texel-run play`'s N, the editor's Night): both files load, and they differ.
#[test]
fn palette_night_is_the_stone_circle_with_a_day_and_a_night_palette() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/levels");
    let circle = Level::load(&dir.join("stone_circle.ron")).unwrap();
    let level = Level::load(&dir.join("palette_night.ron")).unwrap();
    assert_eq!(
        level.entities, circle.entities,
        "the stone circle's entities"
    );
    let setting = level.palette.as_ref().expect("a palette");
    let alternate = setting.alternate.as_ref().expect("a night palette");
    assert!(setting.dither > 0.0 && setting.dither <= 1.0);
    let load = |file: &str| texel_scene::palette::Palette::load(&dir.join(file)).unwrap();
    let (day, night) = (load(&setting.file), load(alternate));
    assert!(day.colours.len() >= 8 && night.colours.len() >= 8);
    assert_ne!(day.colours, night.colours, "night is another palette");
}
