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
    let apps: Vec<String> = members()
        .iter()
        .filter(|m| !m.starts_with(root.join("crates")))
        .map(|m| package_name(m))
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

/// Source files of the workspace (`.rs` under `crates/`, the apps, `xtask/`, and the WGSL
/// in `shaders/`), repository-relative, without test files (`tests/` folders, `tests.rs`).
fn source_files() -> Vec<std::path::PathBuf> {
    fn walk(dir: &std::path::Path, out: &mut Vec<std::path::PathBuf>) {
        let Ok(entries) = std::fs::read_dir(dir) else {
            return;
        };
        for entry in entries {
            let path = entry.expect("a directory entry").path();
            let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
            if path.is_dir() {
                if !matches!(name, "tests" | "target" | "fuzz" | "data") {
                    walk(&path, out);
                }
            } else if (name.ends_with(".rs") && name != "tests.rs") || name.ends_with(".wgsl") {
                out.push(path);
            }
        }
    }
    let root = repo_root();
    let mut out = Vec::new();
    for dir in ["crates", "runtime", "eval", "editor", "xtask", "shaders"] {
        walk(&root.join(dir), &mut out);
    }
    out.sort();
    out
}

/// A file's lines up to its inline test module (`#[cfg(test)]`), which is test code.
fn lines_before_tests(text: &str) -> Vec<&str> {
    text.lines()
        .take_while(|l| l.trim() != "#[cfg(test)]")
        .collect()
}

/// Each `fn` in `lines` with its length in lines, from its signature to its closing brace
/// (braces in comments, strings and character literals are not counted).
fn functions<'a>(lines: &[&'a str]) -> Vec<(&'a str, usize, usize)> {
    let mut out = Vec::new();
    for (start, line) in lines.iter().enumerate() {
        let code = line.trim_start();
        let code = ["pub ", "pub(crate) ", "pub(super) ", "const ", "async "]
            .iter()
            .fold(code, |c, p| c.strip_prefix(p).unwrap_or(c));
        let Some(rest) = code.strip_prefix("fn ") else {
            continue;
        };
        let name = rest.split(['(', '<', ' ']).next().unwrap_or("");
        let (mut depth, mut opened) = (0i64, false);
        for (i, l) in lines[start..].iter().enumerate() {
            let mut in_string = false;
            let mut chars = l.split("//").next().unwrap_or("").chars().peekable();
            while let Some(c) = chars.next() {
                match c {
                    '\\' if in_string => {
                        chars.next();
                    }
                    '"' => in_string = !in_string,
                    '\'' if !in_string => {
                        // A character literal ('{', '\'') but not a lifetime ('a).
                        let rest: String = chars.clone().take(3).collect();
                        if rest.chars().nth(1) == Some('\'') || rest.starts_with('\\') {
                            chars.nth(if rest.starts_with('\\') { 2 } else { 1 });
                        }
                    }
                    '{' if !in_string => {
                        depth += 1;
                        opened = true;
                    }
                    '}' if !in_string => depth -= 1,
                    _ => {}
                }
            }
            if opened && depth <= 0 {
                out.push((name, start + 1, i + 1));
                break;
            }
            if !opened && l.trim_end().ends_with(';') {
                break;
            }
        }
    }
    out
}

/// Rooms that fit: no source file over 800 lines (its inline tests aside) and no function
/// over 150, so a file is read in one sitting and a function in one screen or two.
#[test]
fn no_source_file_over_800_lines_and_no_function_over_150() {
    let root = repo_root();
    let mut too_big = Vec::new();
    let files = source_files();
    assert!(files.len() > 50, "{} source files found", files.len());
    for file in files {
        let text = std::fs::read_to_string(&file).expect("a source file");
        let lines = lines_before_tests(&text);
        let rel = file
            .strip_prefix(&root)
            .unwrap_or(&file)
            .display()
            .to_string();
        if lines.len() > 800 {
            too_big.push(format!("{rel}: {} lines", lines.len()));
        }
        for (name, start, length) in functions(&lines) {
            if length > 150 {
                too_big.push(format!("{rel}:{start}: fn {name}, {length} lines"));
            }
        }
    }
    assert!(too_big.is_empty(), "too big:\n{}", too_big.join("\n"));
}

#[test]
fn function_lengths_are_counted_from_signature_to_closing_brace() {
    let src = "fn a() {\n    let s = \"}\";\n    let c = '{';\n    // }\n}\npub fn b<'x>(v: &'x str) -> &'x str {\n    v\n}\nfn c();\n";
    let lines: Vec<&str> = src.lines().collect();
    assert_eq!(functions(&lines), vec![("a", 1, 5), ("b", 6, 3)]);
}

/// The workspace members' directories, from the root manifest's `members` list.
fn members() -> Vec<std::path::PathBuf> {
    let root = repo_root();
    let manifest = std::fs::read_to_string(root.join("Cargo.toml")).expect("the workspace");
    manifest
        .split("members = [")
        .nth(1)
        .and_then(|rest| rest.split(']').next())
        .expect("a members list")
        .split(',')
        .map(|m| m.trim().trim_matches('"'))
        .filter(|m| !m.is_empty())
        .map(|m| root.join(m))
        .collect()
}

/// The files of `tests/` a package's test targets reach: each `[[test]]`'s `path`, and
/// the `mod NAME;` lines of those files (as `tests/NAME.rs` or `tests/NAME/mod.rs`).
fn reached_test_files(dir: &std::path::Path, manifest: &str) -> Vec<std::path::PathBuf> {
    let targets: Vec<std::path::PathBuf> = manifest
        .lines()
        .filter_map(|l| l.trim().strip_prefix("path = \"tests/"))
        .filter_map(|rest| rest.split('"').next())
        .map(|file| dir.join("tests").join(file))
        .collect();
    let mut reached = targets.clone();
    for target in &targets {
        let text =
            std::fs::read_to_string(target).unwrap_or_else(|e| panic!("{}: {e}", target.display()));
        for name in text
            .lines()
            .filter_map(|l| l.trim().strip_prefix("mod "))
            .filter_map(|rest| rest.strip_suffix(';'))
        {
            reached.push(dir.join("tests").join(format!("{name}.rs")));
            reached.push(dir.join("tests").join(name).join("mod.rs"));
        }
    }
    reached
}

/// A package that lists its test targets itself (`autotests = false`, so its files of
/// `tests/` share one binary: `tests/integration.rs`) must reach every file there: a new
/// test file nobody added to a target would never build, and its tests never run.
#[test]
fn every_test_file_belongs_to_a_test_target() {
    let mut listed = 0;
    for dir in members() {
        let manifest = std::fs::read_to_string(dir.join("Cargo.toml")).expect("a manifest");
        if !manifest.lines().any(|l| l.trim() == "autotests = false") {
            continue;
        }
        listed += 1;
        let reached = reached_test_files(&dir, &manifest);
        let tests = dir.join("tests");
        for entry in std::fs::read_dir(&tests).expect("tests/") {
            let path = entry.expect("an entry").path();
            let file = if path.is_dir() {
                path.join("mod.rs")
            } else {
                path.clone()
            };
            if file.extension().is_some_and(|e| e == "rs") && file.is_file() {
                assert!(
                    reached.contains(&file),
                    "{} is in no test target of {}: add `mod {};` to tests/integration.rs",
                    file.display(),
                    dir.display(),
                    path.file_stem()
                        .map(|s| s.to_string_lossy())
                        .unwrap_or_default()
                );
            }
        }
    }
    assert!(listed >= 5, "packages listing their test targets: {listed}");
}
