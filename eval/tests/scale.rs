//! `texel-eval scale` end to end, small: two generated towns and the stone circle as the
//! reference, each measured in a process of its own (64×36, faces of 32, a frame each).

use std::process::Command;

use texel_eval::scale::ScaleReport;
use texel_render::context::test_context;

#[test]
fn scale_measures_each_town_and_the_reference_and_writes_table_and_chart() {
    // The device here names this test in the test plan's record on every driver (the
    // measurements run in processes of their own, which the second pass cannot name).
    if test_context().is_none() {
        return;
    }
    let out = tempfile::tempdir().expect("tempdir");
    // The reference's walk, short: two frames into the circle.
    let walk = out.path().join("in.ron");
    let keys = "(position: (0.0, 1.6, 6.0)), (position: (0.0, 1.6, 5.0))";
    std::fs::write(&walk, format!("(frames: 2, keyframes: [{keys}])")).expect("a path");
    let run = Command::new(env!("CARGO_BIN_EXE_texel-eval"))
        .args(["scale", "--counts", "20,80", "--size", "64x36"])
        .args(["--face-res", "32", "--frames", "1", "--assets"])
        .arg(concat!(env!("CARGO_MANIFEST_DIR"), "/../assets"))
        .arg("--reference-path")
        .arg(&walk)
        .arg("--out")
        .arg(out.path())
        .output()
        .expect("texel-eval starts");
    // Its output is kept apart: printed into the test's own, it would break the lines the
    // test plan's second pass reads from libtest.
    assert!(
        run.status.success(),
        "texel-eval scale: {}\n{}",
        run.status,
        String::from_utf8_lossy(&run.stderr)
    );
    let json = std::fs::read_to_string(out.path().join("scale.json")).expect("scale.json");
    let report: ScaleReport = serde_json::from_str(&json).expect("a report");
    let reference = report.reference.as_ref().expect("the reference row");
    assert_eq!(reference.label, "stone_circle");
    assert!(reference.frame_ms.is_some_and(|ms| ms > 0.0));
    let counts: Vec<usize> = report.towns.iter().map(|t| t.entities).collect();
    assert_eq!(counts, [20, 80], "the towns have the counts asked for");
    for t in &report.towns {
        assert!(t.error.is_none(), "{t:?}");
        assert!(
            t.frame_ms.is_some_and(|ms| ms > 0.0) && t.load_ms > 0.0,
            "{t:?}"
        );
        assert!(t.passes.contains_key("capture") && t.passes.contains_key("shade"));
        assert!(t.gpu_bytes > 0, "{t:?}");
    }
    let (small, big) = (&report.towns[0], &report.towns[1]);
    assert!(
        big.point_lights > small.point_lights && big.gpu_bytes > small.gpu_bytes,
        "a larger town has more lights and more bytes: {small:?} {big:?}"
    );
    let table = std::fs::read_to_string(out.path().join("scale.md")).expect("scale.md");
    assert_eq!(table, report.table(), "the table is the report's");
    assert!(table.contains("| stone_circle | 25 |") && table.contains("| town | 80 |"));
    let png = image::open(out.path().join("scale.png")).expect("a PNG chart");
    assert_eq!((png.width(), png.height()), (1200, 520));
    let svg = std::fs::read_to_string(out.path().join("scale.svg")).expect("an SVG chart");
    assert!(svg.contains("capture") && svg.contains("1.5× reference"));
}
