//! Unit tests of the asset library: paths, loading, what it refuses.

#[test]
fn relative_paths_climb_and_descend_and_resolve_back() {
    let p = Path::new;
    let level = p("/nowhere/levels/gen/town.ron");
    let mesh = p("/nowhere/assets/meshes/crate.glb");
    let rel = super::relative_path(level, mesh);
    assert_eq!(rel, "../../assets/meshes/crate.glb");
    assert_eq!(
        super::resolve(level, &rel),
        p("/nowhere/levels/gen/../../assets/meshes/crate.glb")
    );
    assert_eq!(
        super::relative_path(p("/nowhere/a.ron"), p("/nowhere/b.glb")),
        "b.glb"
    );
}

use super::*;
use crate::level::EntityRow;

#[test]
fn entity_rows_skip_strings_comments_and_nested_brackets() {
    let text = "// entities: [(x)]\n(version: 3, settings: (bands: 32),\n entities: [\n\
                (name: \"a ) ] \\\" (\", geometry: Box(size: (1.0, 1.0, 1.0))),\n\
                /* (not a row) /* nested ) */ */ (name: r#\"raw \" )\"#),\n\
                Entity(sprite: (sheet: \"s.png\", animations: [(name: \"w\")])),\n])";
    let rows = entity_rows(text);
    let rows: Vec<&str> = rows.iter().map(|r| &text[r.clone()]).collect();
    assert_eq!(rows.len(), 3, "{rows:?}");
    assert!(rows[0].starts_with("(name: \"a ) ]") && rows[0].ends_with("1.0)))"));
    assert_eq!(rows[1], "(name: r#\"raw \" )\"#)");
    assert!(rows[2].starts_with("(sprite:") && rows[2].ends_with("]))"));
    // The third row's "w", not the first mention of it anywhere.
    let at = locate_in_row(text, 2, &["animations".into(), "\"w\"".into()]);
    assert_eq!(at, Some((6, 53)));
    // A needle the row lacks: the row itself; a row past the end: the whole text.
    assert_eq!(locate_in_row(text, 1, &["nothing".into()]), Some((5, 34)));
    assert_eq!(locate_in_row(text, 9, &["\"s.png\"".into()]), Some((6, 24)));
    assert!(entity_rows("(version: 3)").is_empty());
    assert!(entity_rows("(entities: [(a: \"unterminated").is_empty());
}

#[test]
fn paths_are_relative_to_the_level() {
    let p = resolve(Path::new("assets/levels/a.ron"), "../meshes/m.glb");
    assert_eq!(p, Path::new("assets/levels/../meshes/m.glb"));
    assert_eq!(locate("a\n  b \"x\"", "\"x\""), Some((2, 5)));
}

/// A one-triangle glTF with an external buffer, plus top-level JSON `members`.
fn write_triangle(dir: &Path, name: &str, members: &str) {
    let bin: Vec<u8> = [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    std::fs::write(dir.join("tri.bin"), bin).unwrap();
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}}}]}}],
        "accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3",
            "min":[0,0,0],"max":[1,1,0]}}],
        "bufferViews":[{{"buffer":0,"byteLength":36}}],
        "buffers":[{{"byteLength":36,"uri":"tri.bin"}}]{members}}}"#
    );
    std::fs::write(dir.join(name), json).unwrap();
}

#[test]
fn mesh_warnings_are_kept_once_per_mesh() {
    let dir = tempfile::tempdir().unwrap();
    write_triangle(dir.path(), "plain.gltf", "");
    let cameras = r#","cameras":[{"type":"perspective","perspective":{"yfov":1,"znear":0.1}}]"#;
    write_triangle(
        dir.path(),
        "fancy.gltf",
        &format!(r#"{cameras},"extensionsUsed":["KHR_lights_punctual"]"#),
    );
    let row = |path: &str| EntityRow {
        geometry: Some(Geometry::Mesh {
            path: path.to_owned(),
        }),
        ..Default::default()
    };
    let level = Level {
        entities: vec![row("fancy.gltf"), row("plain.gltf"), row("fancy.gltf")],
        ..Default::default()
    };
    let lib = load_assets(&level, &dir.path().join("level.ron"), None).unwrap();
    assert_eq!(lib.len(), 2);
    let warnings: Vec<_> = lib.warnings().collect();
    assert_eq!(
        warnings,
        [
            ("fancy.gltf", "1 camera ignored"),
            (
                "fancy.gltf",
                "extension KHR_lights_punctual ignored: not implemented"
            )
        ]
    );
}

/// A level's palette loads with its assets; a bad one stops the load naming the level's
/// line, the palette file and its line.
#[test]
fn a_levels_palette_loads_and_a_bad_one_is_named() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("day.hex"), "102030\nffeedd\n").unwrap();
    std::fs::write(dir.path().join("night.gpl"), "GIMP Palette\n0 0 0\n1 2 x\n").unwrap();
    let text =
        "(\n    version: 3,\n    palette: (file: \"day.hex\", alternate: \"night.gpl\"),\n)\n";
    let level = Level::from_ron_str(text, Path::new("level.ron")).unwrap();
    let setting = level.palette.clone().unwrap();
    assert_eq!((setting.file.as_str(), setting.dither), ("day.hex", 0.0));
    let path = dir.path().join("level.ron");
    let e = load_assets(&level, &path, Some(text))
        .unwrap_err()
        .to_string();
    assert!(e.contains(":3:"), "the level's line: {e}");
    assert!(e.contains("palette") && e.contains("night.gpl:3:"), "{e}");
    assert!(e.contains("blue `x`"), "{e}");

    std::fs::write(dir.path().join("night.gpl"), "GIMP Palette\n0 0 0\n").unwrap();
    let lib = load_assets(&level, &path, None).unwrap();
    assert_eq!(
        lib.palette("day.hex").unwrap().colours,
        [[16, 32, 48], [255, 238, 221]]
    );
    assert_eq!(lib.palette("night.gpl").unwrap().colours.len(), 1);
}
