//! What the terrain and paint tool tests share: an editor under egui_kittest and a level
//! holding one flat terrain.

use std::path::{Path, PathBuf};

use egui_kittest::Harness;
use glam::Vec2;
use texel_editor::app::EditorApp;
use texel_editor::terrain::default_terrain;
use texel_scene::terrain::{HeightSource, Terrain};
use texel_scene::texture::encode_heightmap;
use texel_scene::{EntityRow, Name, Scene, Transform};

/// Height of the flat terrain (about: it is read from 16 bits), and its max height.
pub const FLAT: f32 = 2.0;
pub const TOP: f32 = 8.0;

/// The editor `app` in a 1200 × 800 harness, one frame run.
pub fn harness(app: EditorApp) -> Harness<'static, EditorApp> {
    let mut h = Harness::builder()
        .with_size([1200.0, 800.0])
        .build_ui_state(|ui, app: &mut EditorApp| app.ui(ui), app);
    h.run();
    h
}

/// A level in `dir` with one terrain "Flat" 32 units across centred on the origin: 33 × 33
/// samples (one per unit) all at [`FLAT`], from `flat.png`; no paint.
pub fn flat_level(dir: &Path) -> PathBuf {
    let sample = (FLAT / TOP * 65535.0).round() as u16;
    let png = encode_heightmap(33, 33, &vec![sample; 33 * 33]);
    std::fs::write(dir.join("flat.png"), png).expect("write heightmap");
    let mut scene = Scene::new();
    scene.spawn(EntityRow {
        name: Some(Name("Flat".into())),
        transform: Some(Transform::default()),
        terrain: Some(Terrain {
            size: Vec2::splat(32.0),
            heightmap: HeightSource::File {
                path: "flat.png".into(),
            },
            max_height: TOP,
            ..default_terrain()
        }),
        ..EntityRow::default()
    });
    let path = dir.join("flat.ron");
    scene.save(&path).expect("save level");
    path
}
