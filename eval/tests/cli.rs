//! `texel-eval run` end to end at a tiny size: writes a report with one record per method ×
//! resolution in the documented schema, the table and both charts; `texel-eval survey`
//! writes its walks, report and table; bad arguments fail with a message instead of a panic.

use std::path::Path;
use std::process::Command;

use texel_render::context::test_context;

fn assets() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets")
}

#[test]
fn run_writes_the_report_table_and_charts() {
    if test_context().is_none() {
        return;
    }
    let out = tempfile::tempdir().expect("tempdir");
    let status = Command::new(env!("CARGO_BIN_EXE_texel-eval"))
        .args([
            "run",
            "--quiet",
            "--methods",
            "splat,naive",
            "--face-res",
            "16,24",
        ])
        .args(["--size", "64x36", "--out"])
        .arg(out.path())
        .arg("--level")
        .arg(assets().join("levels/stone_circle.ron"))
        .arg("--path")
        .arg(assets().join("paths/yaw.ron"))
        .status()
        .expect("texel-eval runs");
    assert!(status.success());
    let text = std::fs::read_to_string(out.path().join("report.json")).expect("report.json");
    let json: serde_json::Value = serde_json::from_str(&text).expect("valid JSON");
    let runs = json["runs"].as_array().expect("runs");
    assert_eq!(runs.len(), 4);
    for key in [
        "level",
        "path",
        "method",
        "face_res",
        "size",
        "frames",
        "frame_ms",
        "pass_ms",
        "counters",
        "shimmer",
        "coverage_error",
        "hole_rate",
        "eye_fraction",
    ] {
        assert!(runs[0].get(key).is_some(), "missing {key}");
    }
    assert!(runs[0]["shimmer"]["p95"].is_number());
    assert_eq!(runs[0]["size"], serde_json::json!([64, 36]));
    for f in ["chart.png", "chart.svg", "table.md"] {
        assert!(out.path().join(f).exists(), "{f}");
    }
}

#[test]
fn survey_writes_its_walks_report_and_table() {
    if test_context().is_none() {
        return;
    }
    let out = tempfile::tempdir().expect("tempdir");
    let run = Command::new(env!("CARGO_BIN_EXE_texel-eval"))
        .args(["survey", "--quiet", "--count", "2", "--frames", "3"])
        .args(["--face-res", "16", "--size", "64x36", "--out"])
        .arg(out.path())
        .arg("--level")
        .arg(assets().join("levels/stone_circle.ron"))
        .output()
        .expect("texel-eval runs");
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    for walk in ["paths/survey_00.ron", "paths/survey_01.ron"] {
        let text = std::fs::read_to_string(out.path().join(walk)).expect("walk written");
        texel_runtime::path::CameraPath::from_ron_str(&text, walk).expect("a camera path");
    }
    let text = std::fs::read_to_string(out.path().join("report.json")).expect("report.json");
    let json: serde_json::Value = serde_json::from_str(&text).expect("valid JSON");
    assert_eq!(json["runs"].as_array().expect("runs").len(), 4);
    let table = std::fs::read_to_string(out.path().join("survey.md")).expect("survey.md");
    assert_eq!(
        table.lines().filter(|l| l.starts_with("| 0")).count(),
        2,
        "{table}"
    );
    assert!(
        table.contains("naive ÷ splat at faces of 16 over 2 walks"),
        "{table}"
    );
    assert!(String::from_utf8_lossy(&run.stdout).contains("| walk |"));
}

#[test]
fn bad_arguments_fail_with_a_message() {
    let out = Command::new(env!("CARGO_BIN_EXE_texel-eval"))
        .args([
            "run",
            "--methods",
            "bogus",
            "--out",
            "/tmp/never",
            "--level",
            "x",
            "--path",
        ])
        .arg(assets().join("paths/yaw.ron"))
        .output()
        .expect("texel-eval runs");
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("unknown method `bogus`"), "{err}");
    let help = Command::new(env!("CARGO_BIN_EXE_texel-eval"))
        .args(["suite", "--help"])
        .output()
        .expect("texel-eval runs");
    assert!(String::from_utf8_lossy(&help.stdout).contains("--face-res"));
    let out = Command::new(env!("CARGO_BIN_EXE_texel-eval"))
        .args(["survey", "--speed", "5,2", "--out", "/tmp/never", "--level"])
        .arg(assets().join("levels/stone_circle.ron"))
        .output()
        .expect("texel-eval runs");
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("--speed: 5 is above 2"), "{err}");
}
