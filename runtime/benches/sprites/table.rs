//! The benchmark's report: our frame rates and times beside the paper's Table 1, the
//! ratios it asks for, the crowd, and where each frame's time goes.

use std::fmt::Write as _;

use super::levels::SCENES;
use super::{Measured, SIZES, median};

/// `a / b` to two decimals, a dash where either is missing.
pub(crate) fn ratio(a: f64, b: f64) -> String {
    let r = a / b;
    if r.is_finite() {
        format!("{r:.2}")
    } else {
        "—".into()
    }
}

/// `ms` to two decimals, a dash where it is missing.
pub(crate) fn ms(ms: f64) -> String {
    if ms.is_finite() {
        format!("{ms:.2}")
    } else {
        "—".into()
    }
}

/// Our measurements by scene name and size index.
pub(crate) type Results<'a> = [(&'a str, usize, Measured)];

/// Our cases: the backdrop alone, the bump sprite behind the camera, the paper's scenes;
/// each with our name, the paper's row and its frame rates.
pub(crate) fn rows() -> impl Iterator<Item = (&'static str, &'static str, Option<[f64; 2]>)> + Clone
{
    [
        ("backdrop", "(no sprites)", None),
        ("no_pixels", "(the bump sprite behind the camera)", None),
    ]
    .into_iter()
    .chain(SCENES.iter().map(|s| (s.name, s.paper, Some(s.fps))))
}

pub(crate) fn get<'a>(results: &'a Results<'_>, name: &str, size: usize) -> &'a Measured {
    (results.iter())
        .find(|(n, i, _)| *n == name && *i == size)
        .map(|(_, _, m)| m)
        .expect("measured")
}

/// The report: per scene and size our frame rate, frame and sprite-pass times beside the
/// paper's frame rate; the two ratios for both; the crowd; where each frame's time goes.
pub(crate) fn report(
    results: &Results<'_>,
    crowd: &Measured,
    n: usize,
    changed: (usize, usize),
    timestamps: bool,
) -> String {
    let mut t = String::new();
    let _ = writeln!(
        t,
        "Sprites: the paper's Table 1 on this machine (median of the measured frames; the \
         sprite pass's time from {})\n",
        if timestamps {
            "GPU timestamps"
        } else {
            "the CPU around its own submission"
        }
    );
    let _ = writeln!(
        t,
        "| scene | paper's row | size | internal | faces | ours fps | frame ms | sprite pass ms | \
         load | paper fps |"
    );
    let _ = writeln!(t, "|---|---|---|---|---:|---:|---:|---:|---:|---:|");
    // Every case captures the same backdrop (sprites never enter the probes), so the capture
    // pass's time against the quickest case's at that size tells how loaded the machine was.
    let quickest = |r: usize| {
        (results.iter())
            .filter(|(_, i, _)| *i == r)
            .map(|(_, _, m)| m.pass("capture"))
            .fold(f64::INFINITY, f64::min)
    };
    for (name, paper, fps) in rows() {
        for (r, (res, _)) in SIZES.iter().enumerate() {
            let m = get(results, name, r);
            let _ = writeln!(
                t,
                "| {name} | {paper} | {res} | {}×{} | {} | {:.1} | {:.1} | {} | {:.1}× | {} |",
                m.internal.x,
                m.internal.y,
                m.faces,
                m.fps(),
                m.frame(),
                ms(m.sprites()),
                m.pass("capture") / quickest(r),
                fps.map_or("—".into(), |f| format!("{:.0}", f[r])),
            );
        }
    }
    let _ = writeln!(
        t,
        "\n`load`: the capture pass's time (the same backdrop in every case) over the quickest \
         case's at that size; near 2× another process held one of lavapipe's cores."
    );
    ratios(&mut t, results);
    let _ = writeln!(
        t,
        "\n{n} animated sprites, 1280×720 (internal {}×{}, faces of {}): {:.2} fps, frame {:.1} \
         ms, sprite pass {} ms; {:.1}% of the sprites changed frame between consecutive frames.",
        crowd.internal.x,
        crowd.internal.y,
        crowd.faces,
        crowd.fps(),
        crowd.frame(),
        ms(crowd.sprites()),
        100.0 * changed.0 as f64 / changed.1.max(1) as f64,
    );
    passes(&mut t, results, crowd, n);
    t
}

/// The two ratios of frame rates, ours (whole frame; the sprite pass; the sprite
/// pass less its cost without pixels, `no_pixels`) and the paper's.
pub(crate) fn ratios(t: &mut String, results: &Results<'_>) {
    let net = |m: &Measured, r: usize| m.sprites() - get(results, "no_pixels", r).sprites();
    let _ = writeln!(
        t,
        "\nRelief box ÷ bump sprite (ratio of frame rates; for the sprite pass, of its times):\n"
    );
    let _ = writeln!(
        t,
        "| size | ours, frame | ours, sprite pass | ours, sprite pass less no-pixel cost | paper |"
    );
    let _ = writeln!(t, "|---|---:|---:|---:|---:|");
    for (r, (res, _)) in SIZES.iter().enumerate() {
        let (b, x) = (get(results, "bump", r), get(results, "relief_box", r));
        let _ = writeln!(
            t,
            "| {res} | {} | {} | {} | {} |",
            ratio(x.fps(), b.fps()),
            ratio(b.sprites(), x.sprites()),
            ratio(net(b, r), net(x, r)),
            ratio(SCENES[1].fps[r], SCENES[0].fps[r]),
        );
    }
    let _ = writeln!(
        t,
        "\n1920×1080 ÷ 800×600 (ratio of frame rates, likewise):\n"
    );
    let _ = writeln!(
        t,
        "| scene | ours, frame | ours, sprite pass | ours, sprite pass less no-pixel cost | paper |"
    );
    let _ = writeln!(t, "|---|---:|---:|---:|---:|");
    for (name, _, fps) in rows() {
        let (hd, sd) = (get(results, name, 0), get(results, name, 1));
        let _ = writeln!(
            t,
            "| {name} | {} | {} | {} | {} |",
            ratio(hd.fps(), sd.fps()),
            ratio(sd.sprites(), hd.sprites()),
            if name == "no_pixels" {
                "—".into()
            } else {
                ratio(net(sd, 1), net(hd, 0))
            },
            fps.map_or("—".into(), |f| ratio(f[0], f[1])),
        );
    }
}

/// Median milliseconds of every pass, and the faces captured per frame, per case.
pub(crate) fn passes(t: &mut String, results: &Results<'_>, crowd: &Measured, n: usize) {
    let crowd_name = format!("animated_{n}");
    let cases: Vec<(String, &Measured)> = (results.iter())
        .map(|(name, r, m)| (format!("{name} {}", SIZES[*r].0), m))
        .chain([(format!("{crowd_name} 1280x720"), crowd)])
        .collect();
    // Frame order (`texel_render::frame`).
    let order = [
        "capture",
        "shade",
        "sprite shade",
        "runs",
        "cull",
        "splat",
        "moving",
        "sprites",
        "background",
        "march",
        "visible",
        "present",
    ];
    let mut names: Vec<&str> = Vec::new();
    for (_, m) in &cases {
        for (p, _) in &m.passes {
            if !names.contains(p) {
                names.push(p);
            }
        }
    }
    names.sort_by_key(|p| order.iter().position(|o| o == p).unwrap_or(order.len()));
    let _ = writeln!(
        t,
        "\nWhere a frame goes (median ms per pass; faces captured per frame):\n"
    );
    let _ = writeln!(t, "| case | faces | {} |", names.join(" | "));
    let _ = writeln!(t, "|---|---:|{}", "---:|".repeat(names.len()));
    for (case, m) in &cases {
        let cells: Vec<String> = names.iter().map(|p| ms(m.pass(p))).collect();
        let _ = writeln!(
            t,
            "| {case} | {:.0} | {} |",
            median(&m.captured),
            cells.join(" | ")
        );
    }
}
