//! A grouped level draws exactly as the same level with its world transforms written out
//! (no parents): the renderer, its shadows and picking see world transforms only.

use glam::{UVec2, Vec3};
use texel_render::context::test_context;
use texel_render::input::Schedule;
use texel_runtime::load::LoadedLevel;
use texel_scene::hierarchy::relative;
use texel_scene::{EntityRow, Level, Name, Scene, Transform};

mod support;

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
