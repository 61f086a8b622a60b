//! Parent–child transforms in levels: round trips, refused parents, world transforms.

use std::path::Path;

use glam::Vec3;
use texel_scene::{EntityRow, ErrorKind, Level, LevelError, Name, Scene, Transform};

const STALL: &str = r#"(
    version: 3,
    entities: [
        (
            name: "lamp",
            parent: "stall",
            transform: (translation: (1.0, 2.0, 0.5), rotation: (0.0, 30.0, 0.0), scale: (0.5, 0.5, 0.5)),
            geometry: Sphere(radius: 0.25),
        ),
        (
            name: "stall",
            transform: (translation: (10.0, 0.0, -4.0), rotation: (0.0, 90.0, 0.0), scale: (2.0, 2.0, 2.0)),
        ),
        (
            name: "awning",
            parent: "stall",
            transform: (translation: (0.0, 1.5, 0.0), rotation: (10.0, 0.0, 0.0), scale: (1.0, 0.1, 1.0)),
            geometry: Box(size: (2.0, 1.0, 1.0)),
        ),
        (
            name: "cat",
            parent: "awning",
            transform: (translation: (0.3, 5.0, 0.0), rotation: (0.0, 0.0, 0.0), scale: (1.0, 1.0, 1.0)),
        ),
    ],
)"#;

fn path() -> &'static Path {
    Path::new("market.ron")
}

fn world(scene: &Scene, name: &str) -> Transform {
    let e = scene
        .entities()
        .find(|&e| scene.world().get::<&Name>(e).is_ok_and(|n| n.0 == name))
        .expect(name);
    *scene.world().get::<&Transform>(e).expect("transform")
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).abs().max_element() < 1e-4
}

/// Saved, loaded and saved again, a hierarchy gives the same bytes; the children come
/// before their parent in the file and stay so.
#[test]
fn a_hierarchy_round_trips_byte_identical() {
    let level = Level::from_ron_str(STALL, path()).expect("parses");
    assert_eq!(level.entities[0].parent, Some(Name("stall".into())));
    let scene = Scene::from_level(&level);
    assert_eq!(
        scene.to_level(),
        level,
        "the scene gives the file's rows back"
    );
    let text = scene.to_level().to_ron_string(path()).expect("saves");
    assert!(text.contains("parent: \"stall\""), "{text}");
    let again = Scene::from_level(&Level::from_ron_str(&text, path()).expect("reloads"));
    assert_eq!(again.to_level().to_ron_string(path()).expect("saves"), text);
    // On disk too.
    let dir = tempfile::tempdir().expect("tmp");
    let file = dir.path().join("market.ron");
    scene.save(&file).expect("save");
    assert_eq!(Scene::load(&file).expect("load").to_level(), level);
}

/// The scene's transforms are world transforms: a rotated, scaled parent carries its
/// children, and their children.
#[test]
fn world_transforms_compose_through_the_chain() {
    let scene = Scene::from_level(&Level::from_ron_str(STALL, path()).expect("parses"));
    let lamp = world(&scene, "lamp");
    // Parent: at (10, 0, −4), turned 90° about Y (X goes to −Z), scale 2.
    assert!(
        close(lamp.translation, Vec3::new(11.0, 4.0, -6.0)),
        "{lamp:?}"
    );
    assert!(close(lamp.rotation, Vec3::new(0.0, 120.0, 0.0)), "{lamp:?}");
    assert!(close(lamp.scale, Vec3::splat(1.0)), "{lamp:?}");
    // Every point agrees with the product of the chain's matrices.
    let t = |s: &str| {
        let l = Level::from_ron_str(STALL, path()).expect("parses");
        let row = l.entities.iter().find(|r| r.name.as_ref().unwrap().0 == s);
        row.and_then(|r| r.transform).expect("transform").matrix()
    };
    let chain = t("stall") * t("awning") * t("cat");
    let cat = world(&scene, "cat");
    for p in [Vec3::ZERO, Vec3::X, Vec3::new(0.2, -0.4, 0.9)] {
        let d = cat.matrix().transform_point3(p) - chain.transform_point3(p);
        assert!(d.length() < 1e-3, "{p}: {d}");
    }
}

/// Moving a parent moves its children and grandchildren with it, their local transforms
/// unchanged; a new parent keeps a child's world placement; the saved file is relative.
#[test]
fn children_follow_and_reparenting_keeps_the_world_placement() {
    let mut scene = Scene::from_level(&Level::from_ron_str(STALL, path()).expect("parses"));
    let before = scene.to_level();
    let stall = scene.entities().nth(1).expect("stall");
    let mut row = scene.row(stall).expect("row");
    let cat_world = world(&scene, "cat");
    row.transform.as_mut().expect("t").translation += Vec3::new(0.0, 3.0, 0.0);
    scene.set_row(stall, row).expect("set");
    assert!(close(
        world(&scene, "cat").translation,
        cat_world.translation + Vec3::Y * 3.0
    ));
    let after = scene.to_level();
    for i in [0, 2, 3] {
        assert_eq!(after.entities[i], before.entities[i], "row {i} unchanged");
    }
    // The cat goes to the lamp: same world place, a new local transform.
    let cat = scene.entities().nth(3).expect("cat");
    let cat_world = world(&scene, "cat");
    let mut row = scene.row(cat).expect("row");
    row.parent = Some(Name("lamp".into()));
    scene.set_row(cat, row).expect("reparent");
    assert_eq!(world(&scene, "cat"), cat_world);
    assert_eq!(scene.parent(cat), scene.entities().next());
    let saved = scene.to_level();
    assert_eq!(saved.entities[3].parent, Some(Name("lamp".into())));
    let reloaded = Scene::from_level(
        &Level::from_ron_str(&saved.to_ron_string(path()).expect("save"), path()).expect("load"),
    );
    let w = world(&reloaded, "cat");
    assert!(close(w.translation, cat_world.translation), "{w:?}");
    // A row may not become its own descendant's child: it stays a root.
    let stall_row = EntityRow {
        parent: Some(Name("cat".into())),
        ..scene.row(stall).expect("row")
    };
    scene.set_row(stall, stall_row).expect("set");
    assert_eq!(scene.parent(stall), None);
}

fn error(text: &str) -> String {
    let e = Level::from_ron_str(text, path()).expect_err("refused");
    assert!(matches!(e, LevelError::Parent { .. }), "{e:?}");
    assert_eq!(e.kind(), Some(ErrorKind::InvalidValue));
    e.to_string()
}

#[test]
fn missing_shared_and_cyclic_parents_and_motion_inside_motion_are_refused_by_name() {
    let missing = STALL.replace("parent: \"awning\"", "parent: \"awnin\"");
    let m = error(&missing);
    assert_eq!(
        m,
        "market.ron: entity 3 (cat): parent: no entity is named \"awnin\""
    );
    let cycle = STALL.replace(
        "name: \"stall\",",
        "name: \"stall\",\n            parent: \"cat\",",
    );
    let m = error(&cycle);
    assert!(
        m.starts_with("market.ron: entity 0 (lamp): parent: a cycle"),
        "{m}"
    );
    let shared = STALL.replace("name: \"lamp\"", "name: \"stall\"");
    assert!(error(&shared).contains("2 entities are named \"stall\""));
    let spin = "animator: (motion: Rotate(axis: (0.0, 1.0, 0.0), speed: 30.0)),";
    let moving = STALL.replace(
        "geometry: Box(size: (2.0, 1.0, 1.0)),",
        &format!("geometry: Box(size: (2.0, 1.0, 1.0)),\n            {spin}"),
    );
    assert!(
        Level::from_ron_str(&moving, path()).is_ok(),
        "children follow"
    );
    let both = moving.replace(
        "scale: (1.0, 1.0, 1.0)),\n        ),\n    ],",
        &format!("scale: (1.0, 1.0, 1.0)),\n            {spin}\n        ),\n    ],"),
    );
    assert_ne!(both, moving);
    assert_eq!(
        error(&both),
        "market.ron: entity 3 (cat): parent: it is inside \"awning\", which moves (has an \
         animator), and has an animator (an entity moves with one animator: its own or its \
         group's)"
    );
    // Saving a scene built in code checks the same.
    let mut level = Level::from_ron_str(STALL, path()).expect("parses");
    level.entities[1].name = Some(Name("booth".into()));
    let e = level.to_ron_string(path()).expect_err("refused");
    assert!(
        e.to_string().contains("no entity is named \"stall\""),
        "{e}"
    );
    // And a scene still builds from it, the orphans at the root.
    let scene = Scene::from_level(&level);
    assert_eq!(scene.len(), 4);
    assert_eq!(scene.parent(scene.entities().next().expect("lamp")), None);
}

/// Rows given to the scene in any order link up: a child that names a parent not yet
/// there waits for it (as when a deleted group and its children come back by undo).
#[test]
fn a_child_spawned_before_its_parent_waits_for_it() {
    let level = Level::from_ron_str(STALL, path()).expect("parses");
    let scene = Scene::from_level(&level);
    let rows: Vec<EntityRow> = scene.entities().filter_map(|e| scene.row(e)).collect();
    let mut again = Scene::new();
    for r in rows.iter().rev() {
        again.spawn(r.clone());
    }
    let cat = again.entities().next().expect("cat");
    assert_eq!(
        again.row(cat).and_then(|r| r.parent),
        Some(Name("awning".into()))
    );
    assert!(again.parent(cat).is_some(), "linked when the awning came");
    let mut saved = again.to_level();
    saved.entities.reverse();
    for (a, b) in saved.entities.iter().zip(&level.entities) {
        assert_eq!(a.parent, b.parent);
        let (ta, tb) = (a.transform.expect("t"), b.transform.expect("t"));
        assert!(close(ta.translation, tb.translation), "{ta:?} {tb:?}");
        assert!(close(ta.rotation, tb.rotation), "{ta:?} {tb:?}");
    }
}

/// Random trees (rows shuffled, parents before or after their children, uniform and
/// uneven scales): a scene gives the file's rows back exactly, and with uniform scales each
/// world transform is the product of its chain's matrices.
#[test]
fn random_trees_round_trip_and_compose() {
    let mut seed = 0x2545_f491_4f6c_dd1d_u64;
    let mut next = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f32 / (1u64 << 53) as f32
    };
    for case in 0..40 {
        let uneven = case % 2 == 1;
        let n = 2 + (next() * 12.0) as usize;
        let mut rows: Vec<EntityRow> = Vec::new();
        for i in 0..n {
            let parent = (i > 0 && next() < 0.8).then(|| (next() * i as f32) as usize);
            let s = 0.5 + next() * 1.5;
            let scale = if uneven {
                Vec3::new(s, 0.5 + next(), 0.5 + next())
            } else {
                Vec3::splat(s)
            };
            let round = |v: f32| (v * 100.0).round() / 100.0;
            rows.push(EntityRow {
                name: Some(Name(format!("n{i}"))),
                parent: parent.map(|p| Name(format!("n{p}"))),
                transform: Some(Transform {
                    translation: Vec3::new(next(), next(), next()).map(|v| round(v * 20.0 - 10.0)),
                    rotation: Vec3::new(next(), next(), next()).map(|v| round(v * 360.0 - 180.0)),
                    scale: scale.map(round),
                }),
                ..EntityRow::default()
            });
        }
        let chain_matrix = |rows: &[EntityRow], mut i: usize| {
            let mut m = glam::Mat4::IDENTITY;
            loop {
                m = rows[i].transform.expect("t").matrix() * m;
                match &rows[i].parent {
                    Some(p) => {
                        i = rows
                            .iter()
                            .position(|r| r.name.as_ref() == Some(p))
                            .expect("p")
                    }
                    None => return m,
                }
            }
        };
        let expected: Vec<glam::Mat4> = (0..n).map(|i| chain_matrix(&rows, i)).collect();
        // Shuffle the rows: children may come first.
        let mut order: Vec<usize> = (0..n).collect();
        for i in (1..n).rev() {
            order.swap(i, (next() * (i + 1) as f32) as usize % (i + 1));
        }
        let level = Level {
            entities: order.iter().map(|&i| rows[i].clone()).collect(),
            ..Level::default()
        };
        let text = level.to_ron_string(path()).expect("valid");
        let level = Level::from_ron_str(&text, path()).expect("loads");
        let scene = Scene::from_level(&level);
        assert_eq!(scene.to_level(), level, "case {case}");
        if uneven {
            continue;
        }
        for (k, &i) in order.iter().enumerate() {
            let e = scene.entities().nth(k).expect("entity");
            let w = scene.world().get::<&Transform>(e).expect("t").matrix();
            for p in [Vec3::ZERO, Vec3::X, Vec3::new(0.5, -1.0, 2.0)] {
                let d = w.transform_point3(p) - expected[i].transform_point3(p);
                assert!(d.length() < 1e-2, "case {case} row {i}: {d}");
            }
        }
    }
}

/// A moving parent carries its children: their poses are the parent's pose composed with
/// their place relative to it at rest.
#[test]
fn children_follow_a_moving_parent() {
    let spin = "animator: (motion: Rotate(axis: (0.0, 1.0, 0.0), speed: 90.0)),";
    let text = STALL.replace(
        "geometry: Box(size: (2.0, 1.0, 1.0)),",
        &format!("geometry: Box(size: (2.0, 1.0, 1.0)),\n            {spin}"),
    );
    let scene = Scene::from_level(&Level::from_ron_str(&text, path()).expect("loads"));
    let at = |t: f64| -> Vec<(String, Transform)> {
        (scene.animated_poses(t).into_iter())
            .map(|(e, p)| (scene.world().get::<&Name>(e).expect("name").0.clone(), p))
            .collect()
    };
    let names: Vec<String> = at(0.0).into_iter().map(|(n, _)| n).collect();
    assert_eq!(
        names,
        ["awning", "cat"],
        "the awning moves, and the cat with it"
    );
    let rest = world(&scene, "cat");
    let cat0 = at(0.0)[1].1;
    assert!(close(cat0.translation, rest.translation), "at rest at 0 s");
    // A second later the awning has turned 90° about the world's Y through its origin:
    // the cat has swung around it.
    let awning = world(&scene, "awning").translation;
    let cat1 = at(1.0)[1].1;
    let before = rest.translation - awning;
    let turned = glam::Quat::from_rotation_y(90f32.to_radians()) * before;
    assert!(close(cat1.translation, awning + turned), "{cat1:?}");
}
