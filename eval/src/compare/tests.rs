//! The comparison's tests: GIF panels and labels, the shared palette, overlays, and the
//! runs it refuses.

use std::path::Path;

use super::panels::{BACKGROUND, BAR, TEXT};
use super::*;

/// Decodes every frame of a GIF to RGBA.
fn decode(file: &Path) -> (u16, u16, Vec<Vec<u8>>, Vec<u16>) {
    let mut opts = gif::DecodeOptions::new();
    opts.set_color_output(gif::ColorOutput::RGBA);
    let mut d = opts
        .read_info(std::fs::File::open(file).expect("gif exists"))
        .expect("gif decodes");
    let (w, h) = (d.width(), d.height());
    let mut frames = Vec::new();
    let mut delays = Vec::new();
    while let Some(f) = d.read_next_frame().expect("frame decodes") {
        assert_eq!((f.width, f.height, f.left, f.top), (w, h, 0, 0));
        frames.push(f.buffer.to_vec());
        delays.push(f.delay);
    }
    (w, h, frames, delays)
}

fn px(frame: &[u8], w: u16, x: u32, y: u32) -> [u8; 3] {
    let i = ((y * u32::from(w) + x) * 4) as usize;
    [frame[i], frame[i + 1], frame[i + 2]]
}

#[test]
fn the_coverage_overlay_colours_each_kind_of_wrong_pixel() {
    // Four pixels: right, an object over the sky, sky over an object, another object.
    let reference = crate::metrics::Reference {
        size: UVec2::new(4, 1),
        world: vec![[0.0; 3]; 4],
        id: vec![1, 0, 2, 3],
        ..Default::default()
    };
    let frame = crate::meter::OwnedFrame {
        camera: texel_render::input::Camera::from_yaw_pitch(glam::Vec3::ZERO, 0.0, 0.0),
        reference,
        colour: [200u8, 100, 0, 255].repeat(4),
        ids: vec![1, 5, 0, 4],
        from_eye: None,
        truth: None,
    };
    let out = coverage_overlay(&frame).unwrap();
    let grey = ((200 * 3 + 100 * 6) / 20) as u8;
    assert_eq!(
        &out[0..4],
        &[grey, grey, grey, 255],
        "a right pixel is dimmed"
    );
    assert_eq!(&out[4..8], &[60, 110, 255, 255], "grown over the sky: blue");
    assert_eq!(&out[8..12], &[255, 220, 40, 255], "a hole: yellow");
    assert_eq!(&out[12..16], &[255, 40, 40, 255], "another object: red");
    let short = crate::meter::OwnedFrame {
        ids: vec![1],
        ..frame
    };
    assert!(
        coverage_overlay(&short).is_err(),
        "mismatched sizes are an error"
    );
}

/// Three methods of 4 frames of 20×10: `a` a still grey, `b` flipping between two colours,
/// `c` a still grey identical to `a` except one quadrant.
fn synthetic() -> CompareRun {
    let size = UVec2::new(20, 10);
    let n = (size.x * size.y) as usize;
    let flat = |v: [u8; 3]| [v[0], v[1], v[2], 255].repeat(n);
    let a = MethodFrames {
        method: Method::Naive,
        frames: vec![flat([90, 90, 90]); 4],
        shimmer_per_frame: vec![0.0; 3],
        shimmer: Summary::of(&[0.0; 3]),
    };
    let b = MethodFrames {
        method: Method::Snap,
        frames: (0..4)
            .map(|t| {
                flat(if t % 2 == 0 {
                    [200, 40, 40]
                } else {
                    [40, 40, 200]
                })
            })
            .collect(),
        shimmer_per_frame: vec![1.0; 3],
        shimmer: Summary::of(&[1.0; 3]),
    };
    let mut quadrant = flat([90, 90, 90]);
    for y in 0..5 {
        for x in 0..10 {
            let i = (y * 20 + x) * 4;
            quadrant[i..i + 3].copy_from_slice(&[10, 220, 10]);
        }
    }
    let c = MethodFrames {
        method: Method::Splat,
        frames: vec![quadrant; 4],
        shimmer_per_frame: vec![0.25, 0.5, 0.0],
        shimmer: Summary::of(&[0.25, 0.5, 0.0]),
    };
    CompareRun {
        level: "l.ron".into(),
        path: "p.ron".into(),
        face_res: 64,
        size,
        dt: 0.05,
        methods: vec![a, b, c],
    }
}

#[test]
fn the_gif_shows_each_method_in_its_panel_with_its_labels() {
    let dir = tempfile::tempdir().expect("temp dir");
    let run = synthetic();
    let files = write_compare(&run, dir.path(), "cmp", 6, None).expect("writes");
    let (w, h, frames, delays) = decode(&files.gif);
    // 3 panels of 120×60 with 2 gaps, and the label strip.
    assert_eq!(
        (u32::from(w), u32::from(h)),
        (3 * 120 + 2 * GAP, 60 + LABEL_HEIGHT)
    );
    assert_eq!(files.size, UVec2::new(u32::from(w), u32::from(h)));
    assert_eq!((frames.len(), files.frames), (4, 4));
    // dt 0.05 s: 20 fps, 5 hundredths per frame.
    assert!(delays.iter().all(|d| *d == 5), "{delays:?}");
    let (a, b, c) = (0, 120 + GAP, 2 * (120 + GAP));
    for (t, f) in frames.iter().enumerate() {
        // Panel a is still grey everywhere; panel c differs from it only in its quadrant.
        assert_eq!(px(f, w, a + 90, 50), [90, 90, 90]);
        assert_eq!(px(f, w, a + 10, 10), [90, 90, 90]);
        assert_eq!(px(f, w, c + 90, 50), [90, 90, 90]);
        assert_eq!(px(f, w, c + 10, 10), [10, 220, 10]);
        assert_eq!(px(f, w, c + 59, 29), [10, 220, 10]);
        assert_eq!(px(f, w, c + 60, 29), [90, 90, 90]);
        // Panel b flips every frame.
        let want = if t % 2 == 0 {
            [200, 40, 40]
        } else {
            [40, 40, 200]
        };
        assert_eq!(px(f, w, b + 60, 30), want, "frame {t}");
        // The gaps are background.
        assert_eq!(px(f, w, 120 + 1, 30), BACKGROUND);
    }
    // Labels: text pixels in each label strip, and the shimmer line changes with the
    // value (frame 1 and 2 of c differ: 0.2500 and 0.5000; a's stay the same).
    let strip = |f: &[u8], x0: u32| -> Vec<[u8; 3]> {
        (60..60 + LABEL_HEIGHT)
            .flat_map(|y| (x0..x0 + 120).map(move |x| (x, y)))
            .map(|(x, y)| px(f, w, x, y))
            .collect()
    };
    for x0 in [a, b, c] {
        assert!(
            strip(&frames[1], x0).contains(&TEXT),
            "no label text in the strip at {x0}"
        );
    }
    assert_ne!(strip(&frames[1], c), strip(&frames[2], c));
    assert_eq!(strip(&frames[1], a), strip(&frames[2], a));
    // b's bar is the full panel width (the largest shimmer), c's at frame 1 a quarter.
    let bar_y = 60 + LABEL_HEIGHT - 4;
    assert_eq!(px(&frames[1], w, b + 119, bar_y), BAR);
    assert_eq!(px(&frames[1], w, c + 25, bar_y), BAR);
    assert_ne!(px(&frames[1], w, c + 35, bar_y), BAR);
    assert_ne!(px(&frames[0], w, b + 10, bar_y), BAR);

    let numbers: CompareNumbers =
        serde_json::from_str(&std::fs::read_to_string(&files.json).expect("json written"))
            .expect("json parses");
    assert_eq!(numbers.frames, 4);
    assert_eq!(numbers.fps, 20.0);
    assert_eq!(numbers.methods[2].method, "splat");
    assert_eq!(numbers.methods[2].shimmer_per_frame, vec![0.25, 0.5, 0.0]);
}

#[test]
fn more_than_256_colours_share_one_palette_across_frames() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut run = synthetic();
    // A gradient of 400 colours, the same in every frame.
    let n = (run.size.x * run.size.y) as usize;
    let g: Vec<u8> = (0..n)
        .flat_map(|i| {
            [
                (i % 256) as u8,
                (i / 2 % 256) as u8,
                255 - (i % 200) as u8,
                255,
            ]
        })
        .collect();
    run.methods[0].frames = vec![g; 4];
    let files = write_compare(&run, dir.path(), "grad", 1, Some(10.0)).expect("writes");
    let (w, _, frames, delays) = decode(&files.gif);
    assert_eq!(delays[0], 10);
    // Quantised, yet a still panel is the same in every frame.
    let panel = |f: &[u8]| -> Vec<[u8; 3]> {
        (0..10)
            .flat_map(|y| (0..20).map(move |x| (x, y)))
            .map(|(x, y)| px(f, w, x, y))
            .collect()
    };
    for f in &frames[1..] {
        assert_eq!(panel(f), panel(&frames[0]));
    }
}

#[test]
fn unusable_runs_are_errors() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut run = synthetic();
    run.methods[1].frames.pop();
    let e = write_compare(&run, dir.path(), "x", 1, None).unwrap_err();
    assert!(e.to_string().contains("snap"), "{e}");
    let e = write_compare(&CompareRun::default(), dir.path(), "x", 1, None).unwrap_err();
    assert!(matches!(e, CompareError::Layout(_)), "{e}");
    assert!(Layout::new(3, UVec2::new(4096, 100), 8).is_err());
    assert!(write_compare(&synthetic(), dir.path(), "x", 0, None).is_err());
    assert_eq!(
        (gif_delay(30.0), gif_delay(100.0), gif_delay(10.0)),
        (3, 2, 10)
    );
}
