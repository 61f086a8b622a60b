//! A grouped level draws exactly as the same level with its world transforms written out
//! (no parents): the renderer, its shadows and picking see world transforms only.

use glam::{UVec2, Vec3};
use texel_render::context::test_context;
use texel_render::input::Schedule;
use texel_runtime::load::LoadedLevel;
use texel_scene::hierarchy::relative;
use texel_scene::{EntityRow, Level, Name, Scene, Transform};

use crate::support;

fn frame(level: &LoadedLevel) -> (UVec2, Vec<u8>) {
    let ctx = test_context().expect("a device");
    let mut gpu = support::gpu_view(&ctx);
    let camera = support::camera().camera();
    let mut out = (UVec2::ZERO, Vec::new());
    for _ in 0..4 {
        out = (gpu.render_pixels(
            level,
            0,
            camera,
            UVec2::new(160, 120),
            Schedule::Ours,
            0.016,
        ))
        .expect("render");
    }
    out
}

#[test]
fn a_grouped_level_draws_as_its_flattened_twin() {
    if test_context().is_none() {
        return;
    }
    let loaded = support::stone_circle();
    let mut level: Level = loaded.scene.to_level();
    // Trilithon 1 (rows 1 to 3) into a group turned 35° and scaled 1.25 (an odd frame: the
    // stones' transforms in the file are far from their world ones), nested one deeper for
    // the lintel.
    let ring = Transform {
        translation: Vec3::new(1.0, 0.2, 4.0),
        rotation: Vec3::new(0.0, 35.0, 0.0),
        scale: Vec3::splat(1.25),
    };
    let named = |name: &str, parent: Option<&str>, t: Transform| EntityRow {
        name: Some(Name(name.into())),
        parent: parent.map(|p| Name(p.into())),
        transform: Some(t),
        ..EntityRow::default()
    };
    let inner = Transform::from_translation(Vec3::new(0.0, 1.0, 0.0));
    let inner_world = texel_scene::hierarchy::compose(&ring, &inner);
    level.entities.insert(1, named("Ring", None, ring));
    level.entities.insert(2, named("Top", Some("Ring"), inner));
    for (i, parent, frame) in [
        (3, "Ring", ring),
        (4, "Ring", ring),
        (5, "Top", inner_world),
    ] {
        let row = &mut level.entities[i];
        let world = row.transform.expect("a stone has a transform");
        row.transform = Some(relative(&frame, &world));
        row.parent = Some(Name(parent.into()));
        assert!((row.transform.expect("t").translation - world.translation).length() > 0.5);
    }
    let text = level.to_ron_string("grouped.ron".as_ref()).expect("saves");
    let grouped_level = Level::from_ron_str(&text, "grouped.ron".as_ref()).expect("loads");
    let grouped = Scene::from_level(&grouped_level);
    let flat = Level {
        entities: (grouped.entities())
            .filter_map(|e| grouped.row(e))
            .map(|r| EntityRow { parent: None, ..r })
            .collect(),
        ..grouped_level.clone()
    };
    assert_ne!(flat.entities, grouped_level.entities, "the files differ");
    let with = |scene| LoadedLevel {
        path: loaded.path.clone(),
        scene,
        assets: loaded.assets.clone(),
    };
    let a = frame(&with(grouped));
    let b = frame(&with(Scene::from_level(&flat)));
    assert_eq!(a.0, b.0);
    let first = &a.1[..4];
    assert!(
        a.1.chunks(4).any(|p| p != first),
        "the frame shows something"
    );
    let off = (a.1.chunks(4).zip(b.1.chunks(4)))
        .filter(|(p, q)| p != q)
        .count();
    assert_eq!(
        off, 0,
        "{off} pixels differ between the grouped and the flat level"
    );
}

/// Renders `level` with its animation clock at `t` seconds.
fn frame_at(level: &LoadedLevel, t: f64) -> Vec<u8> {
    let ctx = test_context().expect("a device");
    let mut gpu = support::gpu_view(&ctx);
    let camera = support::camera().camera();
    let size = UVec2::new(160, 120);
    gpu.render_pixels(level, 0, camera, size, Schedule::Ours, 0.0)
        .expect("render");
    gpu.set_animating(true);
    let mut out = Vec::new();
    for _ in 0..4 {
        gpu.set_animation_time(t);
        out = (gpu.render_pixels(level, 0, camera, size, Schedule::Ours, 0.0))
            .expect("render")
            .1;
    }
    out
}

/// A moving group carries its children: trilithon 1 in a group sliding half a unit along X
/// draws (almost: float rounding) as the same stones each given that slide itself, and
/// unlike the stones left standing.
#[test]
fn a_moving_group_draws_as_its_children_moving_themselves() {
    if test_context().is_none() {
        return;
    }
    let loaded = support::stone_circle();
    let base: Level = loaded.scene.to_level();
    let slide = |from: Transform| {
        let to = Transform {
            translation: from.translation + Vec3::new(0.5, 0.0, 0.0),
            ..from
        };
        texel_scene::animator::Animator {
            motion: texel_scene::animator::Motion::PingPong {
                to,
                period: 4.0,
                easing: Default::default(),
            },
            phase: 0.0,
        }
    };
    let mut grouped = base.clone();
    let mover = Transform::default();
    grouped.entities.insert(
        1,
        EntityRow {
            name: Some(Name("Mover".into())),
            transform: Some(mover),
            animator: Some(slide(mover)),
            ..EntityRow::default()
        },
    );
    for row in &mut grouped.entities[2..=4] {
        row.parent = Some(Name("Mover".into()));
    }
    let mut twin = base.clone();
    twin.entities.insert(
        1,
        EntityRow {
            name: Some(Name("Mover".into())),
            transform: Some(mover),
            ..EntityRow::default()
        },
    );
    for row in &mut twin.entities[2..=4] {
        row.animator = Some(slide(row.transform.expect("a stone has a transform")));
    }
    let text = grouped
        .to_ron_string("grouped.ron".as_ref())
        .expect("saves");
    let grouped = Level::from_ron_str(&text, "grouped.ron".as_ref()).expect("loads");
    let with = |level: &Level| LoadedLevel {
        path: loaded.path.clone(),
        scene: Scene::from_level(level),
        assets: loaded.assets.clone(),
    };
    // One second in: half way out, a quarter unit along X.
    let (a, b) = (with(&grouped), with(&twin));
    // The grouped level also moves the (empty) group itself.
    let (pa, pb) = (a.scene.animated_poses(1.0), b.scene.animated_poses(1.0));
    assert_eq!((pa.len(), pb.len()), (4, 3));
    for ((ea, pa), (eb, pb)) in pa.iter().skip(1).zip(&pb) {
        assert_eq!(a.scene.index_of(*ea), b.scene.index_of(*eb));
        assert!(
            (pa.translation - pb.translation).length() < 1e-5,
            "{pa:?} {pb:?}"
        );
    }
    let moved = frame_at(&a, 1.0);
    let twins = frame_at(&b, 1.0);
    let still = frame_at(&with(&base), 1.0);
    let differ = |x: &[u8], y: &[u8]| {
        (x.chunks(4).zip(y.chunks(4)))
            .filter(|(p, q)| p != q)
            .count()
    };
    let total = moved.len() / 4;
    let off = differ(&moved, &twins);
    assert!(
        off * 200 <= total,
        "{off} of {total} pixels differ from the twin's"
    );
    let from_still = differ(&moved, &still);
    assert!(
        from_still * 20 > total,
        "the stones moved: {from_still} of {total} pixels differ"
    );
    eprintln!(
        "moving group: {off} of {total} pixels differ from the twin, {from_still} from the still level"
    );
}
