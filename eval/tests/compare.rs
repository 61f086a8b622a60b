//! `texel-eval compare` end to end at a tiny size on a short path: the GIF decodes with one
//! frame per path frame and three panels, and the per-frame shimmer in the JSON beside it is
//! what `run` measures for the same method, level, path and face resolution (splatting up to
//! its run-to-run noise).

use std::path::Path;
use std::process::Command;

use glam::UVec2;
use texel_eval::compare::{CompareNumbers, GAP, LABEL_HEIGHT};
use texel_eval::runner::Method;
use texel_eval::suite::{ReferenceKind, RunPlan, run_plan};
use texel_render::context::test_context;

fn assets() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets")
}

#[test]
fn compare_writes_a_gif_of_every_frame_with_runs_numbers() {
    let Some(ctx) = test_context() else {
        return;
    };
    let dir = tempfile::tempdir().expect("tempdir");
    // Five frames walking across cell boundaries into the stone circle.
    let path = dir.path().join("short.ron");
    std::fs::write(
        &path,
        "(frames: 5, dt: 0.05, keyframes: [\
         (position: (0.0, 1.6, 9.0), yaw: 0.0, pitch: -5.0),\
         (position: (0.4, 1.6, 7.5), yaw: 6.0, pitch: -5.0)])",
    )
    .expect("path written");
    let level = assets().join("levels/stone_circle.ron");
    let out = dir.path().join("out");
    let status = Command::new(env!("CARGO_BIN_EXE_texel-eval"))
        .args(["compare", "--quiet", "--methods", "naive,snap,splat"])
        .args(["--face-res", "32", "--size", "64x36", "--scale", "2"])
        .args(["--name", "cmp", "--out"])
        .arg(&out)
        .arg("--level")
        .arg(&level)
        .arg("--path")
        .arg(&path)
        .status()
        .expect("texel-eval runs");
    assert!(status.success());

    let mut opts = gif::DecodeOptions::new();
    opts.set_color_output(gif::ColorOutput::RGBA);
    let mut gif = opts
        .read_info(std::fs::File::open(out.join("cmp.gif")).expect("cmp.gif"))
        .expect("the GIF decodes");
    let (w, h) = (u32::from(gif.width()), u32::from(gif.height()));
    assert_eq!((w, h), (3 * 128 + 2 * GAP, 72 + LABEL_HEIGHT));
    let mut frames = Vec::new();
    while let Some(f) = gif.read_next_frame().expect("a frame decodes") {
        assert_eq!(f.delay, 5);
        frames.push(f.buffer.to_vec());
    }
    assert_eq!(frames.len(), 5);
    // The camera moves: the splat panel changes between the first and last frame.
    let panel = |f: &[u8], x0: u32| -> Vec<u8> {
        (0..72)
            .flat_map(|y| {
                let i = ((y * w + x0) * 4) as usize;
                f[i..i + 128 * 4].to_vec()
            })
            .collect()
    };
    let splat_x = 2 * (128 + GAP);
    assert_ne!(panel(&frames[0], splat_x), panel(&frames[4], splat_x));

    let numbers: CompareNumbers =
        serde_json::from_str(&std::fs::read_to_string(out.join("cmp.json")).expect("cmp.json"))
            .expect("the numbers parse");
    assert_eq!((numbers.frames, numbers.face_res), (5, 32));

    // The same numbers as `run`.
    let records = run_plan(
        &ctx,
        &RunPlan {
            level,
            path,
            methods: vec![Method::Naive, Method::Snap, Method::Splat],
            face_res: vec![32],
            size: UVec2::new(64, 36),
            freeze: false,
            first_frames: None,
        },
        ReferenceKind::Gpu,
        &mut |_| {},
    )
    .expect("run");
    assert_eq!(records.len(), 3);
    for (m, r) in numbers.methods.iter().zip(&records) {
        assert_eq!(m.method, r.method);
        assert_eq!(m.shimmer_per_frame.len(), 4);
        // The baselines are deterministic: equal up to the last bit JSON's decimal text may
        // round. Splatting on lavapipe is not bit-exact from run to run (a few pixels of a
        // frame differ: per-frame shimmer moved by up to 7e-5 along walk_cells at 320x180),
        // so it gets a few pixels' worth of slack at 64x36.
        let slack = if m.method == "splat" { 0.005 } else { 1e-12 };
        for (a, b) in m.shimmer_per_frame.iter().zip(&r.shimmer_per_frame) {
            assert!((a - b).abs() <= slack, "{}: {a} vs {b}", m.method);
        }
    }
}

/// `--coverage` panels: the frame in grey with the pixels the coverage error counts in one of
/// three colours, and some of them on a frame with silhouettes; `--flicker` with it is refused.
#[test]
fn compare_coverage_marks_the_pixels_coverage_counts() {
    let Some(_ctx) = test_context() else {
        return;
    };
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("still.ron");
    std::fs::write(
        &path,
        "(frames: 2, dt: 0.05, keyframes: [(position: (0.0, 1.6, 9.0), yaw: 0.0, pitch: -5.0)])",
    )
    .expect("path written");
    let level = assets().join("levels/stone_circle.ron");
    let out = dir.path().join("out");
    let run = |extra: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_texel-eval"))
            .args(["compare", "--quiet", "--methods", "naive,splat"])
            .args(["--face-res", "32", "--size", "64x36", "--scale", "1"])
            .args(extra)
            .arg("--out")
            .arg(&out)
            .arg("--level")
            .arg(&level)
            .arg("--path")
            .arg(&path)
            .output()
            .expect("texel-eval runs")
    };
    let both = run(&["--coverage", "--flicker"]);
    assert!(!both.status.success());
    assert!(
        String::from_utf8_lossy(&both.stderr).contains("--flicker"),
        "{}",
        String::from_utf8_lossy(&both.stderr)
    );
    assert!(run(&["--coverage"]).status.success());
    let mut opts = gif::DecodeOptions::new();
    opts.set_color_output(gif::ColorOutput::RGBA);
    let mut gif = opts
        .read_info(std::fs::File::open(out.join("compare.gif")).expect("compare.gif"))
        .expect("the GIF decodes");
    let w = u32::from(gif.width());
    let frame = gif.read_next_frame().expect("decodes").expect("a frame");
    let marks = [[60, 110, 255], [255, 220, 40], [255, 40, 40]];
    for x0 in [0, 64 + GAP] {
        let mut marked = 0;
        for y in 0..36 {
            for x in x0..x0 + 64 {
                let i = ((y * w + x) * 4) as usize;
                let px = [frame.buffer[i], frame.buffer[i + 1], frame.buffer[i + 2]].map(i32::from);
                // Near, not equal: past 256 colours the GIF's palette is quantized.
                let near = |c: [i32; 3]| (0..3).all(|k| (px[k] - c[k]).abs() <= 24);
                if marks.iter().any(|m| near(*m)) {
                    marked += 1;
                } else {
                    let spread = px.iter().max().unwrap() - px.iter().min().unwrap();
                    assert!(spread <= 12, "({x}, {y}) {px:?} is neither grey nor a mark");
                }
            }
        }
        assert!(marked > 0, "the panel at {x0} marks no pixel");
    }
}
