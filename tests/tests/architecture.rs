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

/// The crate names in every dependency table (`[dependencies]`, `[dev-dependencies]`,
/// `[build-dependencies]`, target-specific ones) of `crate_dir/Cargo.toml`.
fn all_dependencies(crate_dir: &std::path::Path) -> Vec<String> {
    let path = crate_dir.join("Cargo.toml");
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut in_deps = false;
    let mut deps = Vec::new();
    for line in text.lines().map(str::trim) {
        if line.starts_with('[') {
            in_deps = line.trim_matches(['[', ']']).ends_with("dependencies");
            continue;
        }
        if in_deps && let Some((name, _)) = line.split_once(['=', '.']) {
            deps.push(name.trim().to_owned());
        }
    }
    deps
}

/// The `name` in `dir/Cargo.toml`'s `[package]`.
fn package_name(dir: &std::path::Path) -> String {
    let text = std::fs::read_to_string(dir.join("Cargo.toml")).expect("a manifest");
    text.lines()
        .find_map(|l| l.trim().strip_prefix("name = \""))
        .and_then(|rest| rest.split('"').next())
        .unwrap_or_else(|| panic!("{}: no package name", dir.display()))
        .to_owned()
}

/// Libraries live in `crates/`; the apps (the runtime, the evaluator, the editor) and the
/// cross-crate tests are the workspace members outside it. Arrows point down: no library
/// depends on an app, not even for its tests.
#[test]
fn no_library_depends_on_an_app() {
    let root = repo_root();
    let manifest = std::fs::read_to_string(root.join("Cargo.toml")).expect("the workspace");
    let members: Vec<&str> = manifest
        .split("members = [")
        .nth(1)
        .and_then(|rest| rest.split(']').next())
        .expect("a members list")
        .split(',')
        .map(|m| m.trim().trim_matches('"'))
        .filter(|m| !m.is_empty())
        .collect();
    let apps: Vec<String> = members
        .iter()
        .filter(|m| !m.starts_with("crates/"))
        .map(|m| package_name(&root.join(m)))
        .collect();
    for must in ["texel_runtime", "texel_eval", "texel_editor"] {
        assert!(
            apps.iter().any(|a| a == must),
            "{must} not among the apps: {apps:?}"
        );
    }
    let libraries: Vec<_> = std::fs::read_dir(root.join("crates"))
        .expect("crates/")
        .map(|e| e.expect("an entry").path())
        .filter(|p| p.join("Cargo.toml").is_file())
        .collect();
    assert!(libraries.len() >= 5, "libraries: {libraries:?}");
    for lib in libraries {
        let deps = all_dependencies(&lib);
        for app in &apps {
            assert!(
                !deps.contains(app),
                "{} (a library) depends on the app {app}: move the shared part down into a library",
                lib.display()
            );
        }
    }
}
