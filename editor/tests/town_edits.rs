//! A generated town of 10,000 entities (`texel-run gen`'s generator, copies of two bundled
//! meshes among them) opened in the editor, edited the ways a user edits it (gizmo steps, a
//! material, deletes, a duplicate, an entity added), saved and opened again: the level read
//! back is the level edited. Every edit undone, the saved file is the generated one byte for
//! byte; redone, the edited level again. No GPU: the document and its history alone.

use std::path::Path;

use texel_editor::document::Document;
use texel_editor::history::MergeKey;
use texel_editor::state::EditorState;
use texel_runtime::generate::{GenOptions, generate};
use texel_scene::{EntityRow, Geometry, Level, Name, Transform};

/// The level `path` holds, as the editor opens it.
fn opened(path: &Path) -> Level {
    let doc = Document::open(path).expect("the level opens");
    EditorState::new(doc).scene().to_level()
}

#[test]
fn a_town_of_ten_thousand_edited_saved_and_undone_loses_nothing() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let file = dir.path().join("town.ron");
    let assets = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/meshes");
    let options = GenOptions {
        count: 10_000,
        meshes: ["crate.glb", "arch.glb"]
            .map(|m| texel_scene::assets::relative_path(&file, &assets.join(m)))
            .to_vec(),
        ..GenOptions::default()
    };
    let generated = generate(&options).expect("a town");
    generated.save(&file).expect("saved");
    let original = std::fs::read(&file).expect("the generated file");

    let mut s = EditorState::new(Document::open(&file).expect("the town opens"));
    let count = s.scene().len();
    assert_eq!(count, 10_000);
    // Gizmo drags over twenty entities across the town, each a gesture of five steps.
    for k in 0..20 {
        let i = 17 + k * 487;
        let row = s.row_at(i).expect("an entity");
        for step in 1..=5 {
            let mut moved = row.clone();
            let t = moved.transform.get_or_insert_with(Transform::default);
            t.translation.x += 0.25 * step as f32;
            s.set_row(i, moved, Some(MergeKey::Gizmo { index: i }))
                .expect("a drag step");
        }
        s.history.seal();
    }
    // A material changed, entities deleted from the middle and the end, one duplicated,
    // one added.
    let (i, mut row) = (4_321, s.row_at(4_321).expect("an entity"));
    if let Some(m) = &mut row.material {
        m.albedo = glam::Vec3::new(0.9, 0.1, 0.2);
    }
    s.set_row(i, row, None).expect("a material");
    s.delete(5_000).expect("a delete");
    s.delete(count - 2).expect("a delete at the end");
    s.duplicate(123).expect("a duplicate");
    s.add(EntityRow {
        name: Some(Name("Added crate".into())),
        transform: Some(Transform::default()),
        geometry: Some(Geometry::Box {
            size: glam::Vec3::ONE,
        }),
        ..EntityRow::default()
    })
    .expect("an add");
    let edited = s.scene().to_level();
    assert_eq!(edited.entities.len(), count);
    assert_ne!(edited, generated, "the edits show");

    let saved = dir.path().join("edited.ron");
    s.save_as(&saved).expect("saved");
    assert_eq!(opened(&saved), edited, "the saved edits read back");

    while s.undo().expect("an undo") {}
    let undone = dir.path().join("undone.ron");
    s.save_as(&undone).expect("saved");
    let back = std::fs::read(&undone).expect("the undone file");
    assert!(back == original, "every edit undone: the generated file");

    while s.redo().expect("a redo") {}
    assert_eq!(s.scene().to_level(), edited, "every edit redone");
}
