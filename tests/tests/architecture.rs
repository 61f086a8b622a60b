//! The dependency rules `ARCHITECTURE.md` states: the renderer and what it builds on see
//! plain data only (no hecs, RON or glTF), so the scene format can change without touching
//! the GPU code.

use texel_tests::repo_root;

/// The crate names in the `[dependencies]` table of `crate_dir/Cargo.toml`.
fn normal_dependencies(crate_dir: &str) -> Vec<String> {
    let path = repo_root().join(crate_dir).join("Cargo.toml");
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut in_deps = false;
    let mut deps = Vec::new();
    for line in text.lines().map(str::trim) {
        if line.starts_with('[') {
            in_deps = line == "[dependencies]";
            continue;
        }
        if in_deps && let Some((name, _)) = line.split_once(['=', '.']) {
            deps.push(name.trim().to_owned());
        }
    }
    deps
}

#[test]
fn the_renderer_and_its_inputs_depend_on_no_scene_format() {
    for dir in ["crates/render", "crates/probes", "crates/geom"] {
        let deps = normal_dependencies(dir);
        assert!(
            !deps.is_empty() || dir == "crates/geom",
            "{dir}: no dependencies read"
        );
        for banned in ["texel_scene", "hecs", "ron", "gltf", "egui", "winit"] {
            assert!(
                !deps.iter().any(|d| d == banned),
                "{dir} depends on {banned}: {deps:?}"
            );
        }
    }
    assert!(normal_dependencies("crates/render").contains(&"texel_geom".to_owned()));
}
