//! `texel-run` end to end: exit codes, summaries and `path:line:column:` errors.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn repo(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(rel)
}

fn texel_run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_texel-run"))
        .args(args)
        .env("RUST_BACKTRACE", "1")
        .output()
        .expect("texel-run starts")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn check_passes_every_bundled_level() {
    for name in ["stone_circle", "colonnade", "sandbox"] {
        let path = repo(&format!("assets/levels/{name}.ron"));
        let out = texel_run(&["check", path.to_str().unwrap()]);
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(out.status.success(), "{name}: {}", stderr(&out));
        assert_eq!(stdout.lines().count(), 1, "one-line summary: {stdout}");
        assert!(
            stdout.contains("entities:") && stdout.contains("player starts"),
            "{stdout}"
        );
    }
}

#[test]
fn sandbox_summary_counts_its_mesh() {
    let out = texel_run(&["check", repo("assets/levels/sandbox.ron").to_str().unwrap()]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains("1 meshes") && stdout.contains("1 probe-grid overrides"),
        "{stdout}"
    );
    assert!(stdout.contains("1 mesh files"), "{stdout}");
}

#[test]
fn check_reports_bad_levels_with_status_2_and_no_panic() {
    let dir = repo("crates/scene/tests/data/levels");
    let mut seen = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let out = texel_run(&["check", path.to_str().unwrap()]);
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(2), "{}: {err}", path.display());
        assert!(
            !err.contains("panicked") && !err.contains("backtrace"),
            "{err}"
        );
        let prefix = format!("{}:", path.display());
        assert!(err.starts_with(&prefix), "{err}");
        // `path:line:column: message` — both numbers present.
        let rest: Vec<&str> = err[prefix.len()..].splitn(3, ':').collect();
        assert!(
            rest.len() == 3 && rest[0].parse::<usize>().is_ok() && rest[1].parse::<usize>().is_ok(),
            "{err}"
        );
        assert_eq!(err.lines().count(), 1, "one line: {err}");
        seen += 1;
    }
    assert!(seen >= 15, "the catalogue has {seen} files");
}

#[test]
fn a_missing_mesh_points_at_the_line_that_names_it() {
    let path = repo("crates/scene/tests/data/levels/missing_mesh.ron");
    let out = texel_run(&["check", path.to_str().unwrap()]);
    let err = stderr(&out);
    assert!(err.starts_with(&format!("{}:20:", path.display())), "{err}");
    assert!(err.contains("no_such_mesh.glb"), "{err}");
}

#[test]
fn a_missing_level_file_is_status_2() {
    let out = texel_run(&["check", "no/such/level.ron"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).starts_with("no/such/level.ron: "),
        "{}",
        stderr(&out)
    );
}

#[test]
fn help_works() {
    for args in [&["--help"][..], &["check", "--help"], &["fmt", "--help"]] {
        let out = texel_run(args);
        assert!(out.status.success());
        assert!(String::from_utf8_lossy(&out.stdout).contains("Usage"));
    }
}

#[test]
fn fmt_check_accepts_canonical_and_fmt_rewrites_the_rest() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("l.ron");
    std::fs::copy(repo("crates/scene/tests/data/valid_base.ron"), &path).unwrap();
    let p = path.to_str().unwrap();
    assert!(texel_run(&["fmt", "--check", p]).status.success());
    let squashed = std::fs::read_to_string(&path)
        .unwrap()
        .replace("\n        ", " ");
    std::fs::write(&path, &squashed).unwrap();
    assert_eq!(texel_run(&["fmt", "--check", p]).status.code(), Some(1));
    assert_eq!(
        std::fs::read_to_string(&path).unwrap(),
        squashed,
        "--check changes nothing"
    );
    assert!(texel_run(&["fmt", p]).status.success());
    assert!(texel_run(&["fmt", "--check", p]).status.success());
}

/// `texel-run soak` end to end on a short run: it samples resident memory, reports the
/// growth, and passes when the renderer holds no per-frame allocation (measured: +0.5 MiB
/// over 1,200 frames of orbit at 160×90, faces of 32; 10,000 frames in the README).
#[test]
fn soak_reports_resident_memory_and_holds_it_flat() {
    if texel_render::context::test_context().is_none() {
        return;
    }
    let out = texel_run(&[
        "soak",
        repo("assets/levels/stone_circle.ron").to_str().unwrap(),
        "--path",
        repo("assets/paths/orbit.ron").to_str().unwrap(),
        "--frames",
        "300",
        "--sample-every",
        "100",
        "--size",
        "64x36",
        "--face-res",
        "16",
    ]);
    let (stdout, err) = (String::from_utf8_lossy(&out.stdout), stderr(&out));
    assert!(out.status.success(), "{stdout}{err}");
    assert!(
        stdout.contains("300 frames") && stdout.contains("MiB"),
        "{stdout}"
    );
    // One sample at the start and one every 100 frames.
    assert_eq!(err.matches("resident").count(), 4, "{err}");
    // Out-of-range arguments fail before any work.
    let bad = texel_run(&["soak", "x.ron", "--path", "y.ron", "--frames", "0"]);
    assert_eq!(bad.status.code(), Some(1));
    assert!(stderr(&bad).contains("--frames"), "{}", stderr(&bad));
}

#[test]
fn check_density_lists_the_entities_far_from_one_to_one() {
    let out = texel_run(&[
        "check",
        "--density",
        repo("assets/levels/textured.ron").to_str().unwrap(),
    ]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("texture density at the reference distance 4"),
        "{text}"
    );
    assert!(
        text.contains("(Meadow): ../textures/grass.png at 8.0 px/unit"),
        "{text}"
    );
    assert!(
        text.contains("of 11 textured entities are far from 1:1"),
        "{text}"
    );
    // A bad number is refused before the level is read.
    let bad = texel_run(&[
        "check",
        "--density",
        "--size",
        "0x0",
        repo("assets/levels/textured.ron").to_str().unwrap(),
    ]);
    assert!(!bad.status.success());
    assert!(String::from_utf8_lossy(&bad.stderr).contains("--size"));
}

#[test]
fn gen_writes_a_level_that_loads_with_its_meshes_and_refuses_bad_options() {
    let dir = tempfile::tempdir().unwrap();
    let sub = dir.path().join("levels");
    std::fs::create_dir(&sub).unwrap();
    let out = sub.join("town.ron");
    let out = out.to_str().unwrap();
    let crate_glb = repo("assets/meshes/crate.glb");
    let args = [
        "gen",
        "--count",
        "500",
        "--terrain",
        "--mesh",
        crate_glb.to_str().unwrap(),
        "--out",
        out,
    ];
    let made = texel_run(&args);
    assert!(made.status.success(), "{}", stderr(&made));
    let first = std::fs::read_to_string(out).unwrap();
    // The mesh is named relative to the level, and every copy refers to the one file.
    assert!(first.contains("Mesh(path: \""), "no mesh copies");
    let checked = texel_run(&["check", out]);
    let summary = String::from_utf8_lossy(&checked.stdout);
    assert!(checked.status.success(), "{}", stderr(&checked));
    assert!(summary.contains("1 mesh files"), "{summary}");
    // The same options write the same file.
    assert!(texel_run(&args).status.success());
    assert_eq!(std::fs::read_to_string(out).unwrap(), first);
    for (bad, phrase) in [
        (vec!["gen", "--count", "2", "--out", out], "count"),
        (
            vec!["gen", "--mesh", "nowhere.glb", "--out", out],
            "nowhere.glb",
        ),
        (vec!["gen", "--out", "/no/such/folder/x.ron"], "no folder"),
    ] {
        let o = texel_run(&bad);
        assert_eq!(o.status.code(), Some(2), "{bad:?}");
        assert!(stderr(&o).contains(phrase), "{bad:?}: {}", stderr(&o));
    }
    // A refused run left the good file alone.
    assert_eq!(std::fs::read_to_string(out).unwrap(), first);
}
