//! Hostile reports for `texel-eval chart` (issue 13): not regular files, too large, and
//! numbers no run produces (1e308 used to hang the chart). Each is refused by
//! `Report::load` with an error naming the file and the field; the 1e308 report also through
//! the binary, under a time limit.

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use texel_eval::report::Report;

/// A valid report of one run, as JSON.
fn valid() -> serde_json::Value {
    serde_json::json!({
        "adapter": "test",
        "command": "texel-eval run",
        "duration_s": 1.5,
        "runs": [{
            "level": "assets/levels/stone_circle.ron",
            "path": "assets/paths/yaw.ron",
            "method": "splat",
            "face_res": 64,
            "size": [320, 180],
            "frames": 3,
            "reference": "gpu",
            "frame_ms": {"median": 12.0, "p90": 14.0},
            "pass_ms": {"splat": 3.0},
            "counters": {"faces_captured": 1.0, "texels_shaded": 10.0,
                         "quads_splatted": 100.0, "screen_visible_texels": 50.0},
            "shimmer": {"mean": 0.01, "p95": 0.02, "max": 0.03},
            "shimmer_per_frame": [0.01, 0.02],
            "coverage_error": 0.04,
            "hole_rate": 0.001,
            "eye_fraction": 0.1,
            "eye_flicker_share": 0.2
        }]
    })
}

fn write(dir: &Path, name: &str, text: &str) -> std::path::PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// `valid()` with the value at `pointer` (a JSON pointer) replaced by raw JSON text `raw`.
fn with(pointer: &str, raw: &str) -> String {
    let mut v = valid();
    // A marker, then the raw text spliced in (so 1e308 and friends stay as written).
    *v.pointer_mut(pointer).expect(pointer) = serde_json::Value::String("__HOSTILE__".into());
    v.to_string().replace("\"__HOSTILE__\"", raw)
}

#[test]
fn hostile_reports_are_refused_with_the_field_named() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let ok = write(d, "ok.json", &valid().to_string());
    Report::load(&ok).expect("the base report is valid");

    let cases: &[(&str, &str, &str)] = &[
        ("/runs/0/frame_ms/median", "1e308", "frame_ms.median"),
        ("/runs/0/frame_ms/p90", "-1", "frame_ms.p90"),
        ("/runs/0/pass_ms/splat", "1e300", "pass_ms.splat"),
        ("/runs/0/shimmer/mean", "1e308", "shimmer.mean"),
        ("/runs/0/shimmer/max", "2.0", "shimmer.max"),
        ("/runs/0/shimmer_per_frame/1", "-0.5", "shimmer_per_frame"),
        ("/runs/0/coverage_error", "1e308", "coverage_error"),
        ("/runs/0/hole_rate", "7", "hole_rate"),
        ("/runs/0/eye_fraction", "1.5", "eye_fraction"),
        ("/runs/0/eye_flicker_share", "-1e308", "eye_flicker_share"),
        (
            "/runs/0/counters/quads_splatted",
            "1e308",
            "counters.quads_splatted",
        ),
        ("/runs/0/size", "[0, 180]", "size"),
        ("/runs/0/size", "[99999, 180]", "size"),
        ("/runs/0/frames", "4294967295", "frames"),
        ("/runs/0/face_res", "1000000", "face_res"),
        ("/duration_s", "1e308", "duration_s"),
        ("/duration_s", "1e999", "not a report"),
        ("/runs/0/frame_ms", "\"fast\"", "not a report"),
    ];
    for (i, (pointer, raw, expect)) in cases.iter().enumerate() {
        let file = write(d, &format!("case{i}.json"), &with(pointer, raw));
        let err = Report::load(&file).expect_err(pointer).to_string();
        assert!(
            err.starts_with(&file.display().to_string()) && err.contains(expect),
            "{pointer} = {raw}: {err}"
        );
    }

    // Files that are not reports at all.
    let fifo = d.join("fifo.json");
    assert!(
        Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap()
            .success()
    );
    let huge = d.join("huge.json");
    std::fs::File::create(&huge)
        .and_then(|f| f.set_len(1 << 40))
        .unwrap();
    for (file, expect) in [
        (Path::new("/dev/zero"), "a character device"),
        (fifo.as_path(), "a FIFO"),
        (d, "a directory"),
        (huge.as_path(), "too large"),
    ] {
        let err = Report::load(file).expect_err(expect).to_string();
        assert!(err.contains(expect), "{}: {err}", file.display());
    }
}

#[test]
fn chart_of_a_1e308_report_fails_fast() {
    let dir = tempfile::tempdir().unwrap();
    let report = write(
        dir.path(),
        "report.json",
        &with("/runs/0/frame_ms/median", "1e308"),
    );
    let mut child = Command::new(env!("CARGO_BIN_EXE_texel-eval"))
        .args(["chart", "--report"])
        .arg(&report)
        .arg("--out")
        .arg(dir.path().join("out"))
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let started = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if started.elapsed() > Duration::from_secs(60) {
            let _ = child.kill();
            panic!("texel-eval chart hung on a 1e308 report");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("frame_ms.median must be a number in 0..=10000000")
            && !err.contains("panicked"),
        "{err}"
    );
}
