//! Camera paths nobody tuned for (`texel-eval survey`): random walks through a level, made
//! from a seed, so a change to the renderer is judged on views the bundled paths do not fly.
//!
//! Each path is a walk of three keyframes at eye height over whatever floor lies under it
//! (found by casting down through the level's own geometry), at a speed drawn from a range of
//! cells per second, heading and looking roughly toward the level's content (the objects
//! other than the one with the largest footprint, usually the ground), turning and tilting a
//! little on the way. A walk is kept only if every point along it stands clear of every
//! surface ([`CLEARANCE`] cells) and outside every solid; the same seed makes the same walks.

use glam::Vec3;
use texel_probes::placement::{RayQuery, test_directions};
use texel_render::input::SceneInput;

/// How near (in cells) a surveyed camera may come to any surface along its walk.
pub const CLEARANCE: f32 = 0.25;

/// How many walks are drawn for each one kept before the survey gives up.
const TRIES: u32 = 500;

/// What walks to make.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurveySpec {
    /// How many walks.
    pub count: u32,
    /// Seed of the random walks.
    pub seed: u64,
    /// Frames of each walk.
    pub frames: u32,
    /// Seconds between frames.
    pub dt: f32,
    /// Slowest and fastest speed, cells per second.
    pub speed: (f32, f32),
    /// Lowest and highest eye height over the floor, cells.
    pub height: (f32, f32),
    /// The level's probe cell size (world units).
    pub cell_size: f32,
}

impl SurveySpec {
    /// The defaults for a level of cells of `cell_size`: eight walks of 40 frames at 30 fps,
    /// 1.5–8 cells per second (a stroll to a sprint), eyes 0.5–3 cells over the floor.
    pub fn new(cell_size: f32) -> Self {
        SurveySpec {
            count: 8,
            seed: 1,
            frames: 40,
            dt: 1.0 / 30.0,
            speed: (1.5, 8.0),
            height: (0.5, 3.0),
            cell_size,
        }
    }

    fn check(&self) -> Result<(), String> {
        let ok = |v: f32| v.is_finite() && v > 0.0;
        if self.count == 0 || self.frames < 2 {
            return Err("a survey needs at least one walk of at least two frames".into());
        }
        if !ok(self.dt) || !ok(self.cell_size) {
            return Err("dt and the cell size must be positive".into());
        }
        for (name, (lo, hi)) in [("speed", self.speed), ("height", self.height)] {
            if !ok(lo) || !ok(hi) || lo > hi {
                return Err(format!(
                    "{name} range {lo}..{hi} must be positive and ordered"
                ));
            }
        }
        Ok(())
    }
}

/// One surveyed walk: its keyframes (position, yaw and pitch in degrees, as a camera path
/// stores them) and its speed in cells per second.
#[derive(Debug, Clone, PartialEq)]
pub struct Walk {
    /// Three keyframes, spread evenly over the frames.
    pub keyframes: [(Vec3, f32, f32); 3],
    /// Cells per second.
    pub speed: f32,
}

impl Walk {
    /// The walk as a camera-path file (`texel_runtime::path`), with `comment` on top.
    pub fn to_ron(&self, spec: &SurveySpec, comment: &str) -> String {
        let mut out = String::new();
        for line in comment.lines() {
            out.push_str(&format!("// {line}\n"));
        }
        out.push_str(&format!(
            "(\n    frames: {},\n    dt: {},\n    keyframes: [\n",
            spec.frames, spec.dt
        ));
        for (p, yaw, pitch) in &self.keyframes {
            out.push_str(&format!(
                "        (position: ({:.3}, {:.3}, {:.3}), yaw: {yaw:.1}, pitch: {pitch:.1}),\n",
                p.x, p.y, p.z
            ));
        }
        out.push_str("    ],\n)\n");
        out
    }

    /// Points along the walk as the path flies it (straight between keyframes), `n` + 1 of
    /// them from the first keyframe to the last.
    pub fn points(&self, n: u32) -> Vec<Vec3> {
        let k = &self.keyframes;
        (0..=n)
            .map(|i| {
                let t = 2.0 * i as f32 / n as f32;
                if t <= 1.0 {
                    k[0].0.lerp(k[1].0, t)
                } else {
                    k[1].0.lerp(k[2].0, t - 1.0)
                }
            })
            .collect()
    }
}

/// The world-space box around an object's vertices.
fn object_bounds(o: &texel_render::input::ObjectInput) -> (Vec3, Vec3) {
    let mut lo = Vec3::splat(f32::INFINITY);
    let mut hi = Vec3::splat(f32::NEG_INFINITY);
    for &p in &o.mesh.positions {
        let w = o.transform.transform_point3(p);
        lo = lo.min(w);
        hi = hi.max(w);
    }
    (lo, hi)
}

/// The box around `boxes`.
fn union<'a>(boxes: impl Iterator<Item = &'a (Vec3, Vec3)>) -> (Vec3, Vec3) {
    let empty = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    boxes.fold(empty, |(lo, hi), b| (lo.min(b.0), hi.max(b.1)))
}

/// Where the walks start and what they look toward: the box around every still object but
/// the one with the largest footprint (the ground; with only one object, that one), and the
/// box around all of them (for the floor search's height).
fn content(scene: &SceneInput) -> Option<((Vec3, Vec3), (Vec3, Vec3))> {
    let boxes: Vec<(Vec3, Vec3)> = (scene.objects.iter().enumerate())
        .filter(|(i, o)| !scene.animated.contains(i) && !o.mesh.positions.is_empty())
        .map(|(_, o)| object_bounds(o))
        .filter(|(lo, hi)| lo.is_finite() && hi.is_finite())
        .collect();
    let footprint = |b: &(Vec3, Vec3)| (b.1.x - b.0.x) * (b.1.z - b.0.z);
    let largest =
        (0..boxes.len()).max_by(|&a, &b| footprint(&boxes[a]).total_cmp(&footprint(&boxes[b])))?;
    let all = union(boxes.iter());
    let rest = if boxes.len() > 1 {
        union((boxes.iter().enumerate()).filter_map(|(i, b)| (i != largest).then_some(b)))
    } else {
        all
    };
    Some((rest, all))
}

/// Whether a camera at `p` is clear: along none of placement's test rays (the six axes and
/// the eight diagonals) is the first surface within `reach`, or met from behind (inside a
/// solid, the first surface any ray meets is met from behind, however far it is).
fn clear(p: Vec3, reach: f32, scene: &impl RayQuery) -> bool {
    test_directions()
        .iter()
        .all(|&dir| (scene.first_hit(p, dir, FAR)).is_none_or(|h| !h.back_face && h.t > reach))
}

/// Farther than any level reaches: how far `clear`'s rays look for a solid's inside.
const FAR: f32 = 1.0e5;

/// The floor under `(x, z)` below height `top`: the first surface met from its front by a
/// ray cast straight down.
fn floor_under(x: f32, z: f32, top: f32, depth: f32, scene: &impl RayQuery) -> Option<f32> {
    let hit = scene.first_hit(Vec3::new(x, top, z), -Vec3::Y, depth)?;
    (!hit.back_face).then_some(top - hit.t)
}

/// Heading in degrees (0 looks along −Z, positive turns toward −X) of horizontal direction
/// `d`.
fn yaw_of(d: Vec3) -> f32 {
    (-d.x).atan2(-d.z).to_degrees()
}

/// `spec.count` walks through `scene`, which `rays` casts against.
pub fn survey_walks(
    scene: &SceneInput,
    rays: &impl RayQuery,
    spec: &SurveySpec,
) -> Result<Vec<Walk>, String> {
    spec.check()?;
    let ((lo, hi), (all_lo, all_hi)) =
        content(scene).ok_or("the level has no still geometry to walk over")?;
    let s = spec.cell_size;
    // Starts within the content's box and two cells around it.
    let (lo, hi) = (lo - Vec3::splat(2.0 * s), hi + Vec3::splat(2.0 * s));
    let centre = 0.5 * (lo + hi);
    let depth = all_hi.y - all_lo.y + 2.0 * s;
    let mut rng = fastrand::Rng::with_seed(spec.seed);
    let mut range = |a: f32, b: f32| a + (b - a) * rng.f32();
    let mut out = Vec::new();
    let mut tries = 0;
    while out.len() < spec.count as usize {
        tries += 1;
        if tries > TRIES * spec.count {
            return Err(format!(
                "found {} of {} clear walks in {} tries (the level leaves too little room \
                 {CLEARANCE} cells from its surfaces at eye height)",
                out.len(),
                spec.count,
                tries - 1
            ));
        }
        let speed = range(spec.speed.0, spec.speed.1);
        let length = speed * s * spec.dt * (spec.frames - 1) as f32;
        let start = Vec3::new(range(lo.x, hi.x), 0.0, range(lo.z, hi.z));
        // Head roughly toward the content's middle (within 60°), so the walk sees it.
        let toward = (centre - start) * Vec3::new(1.0, 0.0, 1.0);
        let base = if toward.length() > 1e-3 {
            yaw_of(toward)
        } else {
            0.0
        };
        let heading = base + range(-60.0, 60.0);
        let turn = range(-30.0, 30.0);
        let eye = range(spec.height.0, spec.height.1) * s;
        // A floor under the start from a random height, so walks go under roofs as well as
        // over them.
        let top = range(all_lo.y + eye, all_hi.y + s);
        let mut keys = [(Vec3::ZERO, 0.0f32, 0.0f32); 3];
        let mut at = start;
        let mut ok = true;
        for (i, key) in keys.iter_mut().enumerate() {
            let h = heading + turn * i as f32;
            if i > 0 {
                let dir = Vec3::new(-h.to_radians().sin(), 0.0, -h.to_radians().cos());
                at += dir * (0.5 * length);
            }
            let Some(floor) = floor_under(at.x, at.z, top.max(at.y + s), depth, rays) else {
                ok = false;
                break;
            };
            at.y = floor + eye;
            *key = (at, h + range(-20.0, 20.0), range(-20.0, 5.0));
        }
        if !ok {
            continue;
        }
        let walk = Walk {
            keyframes: keys,
            speed,
        };
        let reach = CLEARANCE * s;
        if walk
            .points(4 * spec.frames)
            .iter()
            .all(|&p| clear(p, reach, rays))
        {
            out.push(walk);
        }
    }
    Ok(out)
}

/// The survey's table (markdown): per walk, its start, speed and each method's mean shimmer
/// (per face resolution), splat's eye-probe share of pixels, and naive's shimmer over
/// splat's; then the least and the median of that ratio over the walks.
pub fn survey_table(report: &crate::report::Report, walks: &[Walk]) -> String {
    use std::collections::BTreeSet;
    let columns: BTreeSet<(String, u32)> = (report.runs.iter())
        .map(|r| (r.method.clone(), r.face_res))
        .collect();
    let columns: Vec<(String, u32)> = columns.into_iter().collect();
    let res: BTreeSet<u32> = columns.iter().map(|c| c.1).collect();
    let mut out = String::from("| walk | start | cells/s |");
    for (m, f) in &columns {
        out.push_str(&format!(" {m} @{f} |"));
    }
    for f in &res {
        out.push_str(&format!(" splat eye @{f} | naive ÷ splat @{f} |"));
    }
    out.push_str(&format!(
        "\n|---|---|---:|{}\n",
        "---:|".repeat(columns.len() + 2 * res.len())
    ));
    let mut ratios: Vec<Vec<f64>> = vec![Vec::new(); res.len()];
    for (i, walk) in walks.iter().enumerate() {
        let name = format!("survey_{i:02}.ron");
        let runs: Vec<_> = (report.runs.iter())
            .filter(|r| r.path.ends_with(&name))
            .collect();
        let find = |m: &str, f: u32| runs.iter().find(|r| r.method == m && r.face_res == f);
        let p = walk.keyframes[0].0;
        out.push_str(&format!(
            "| {i:02} | ({:.1}, {:.1}, {:.1}) | {:.1} |",
            p.x, p.y, p.z, walk.speed
        ));
        for (m, f) in &columns {
            match find(m, *f) {
                Some(r) => out.push_str(&format!(" {:.4} |", r.shimmer.mean)),
                None => out.push_str(" – |"),
            }
        }
        for (k, f) in res.iter().enumerate() {
            let splat = find("splat", *f);
            match splat.and_then(|r| r.eye_fraction) {
                Some(e) => out.push_str(&format!(" {:.1} % |", 100.0 * e)),
                None => out.push_str(" – |"),
            }
            match (find("naive", *f), splat) {
                (Some(n), Some(s)) => {
                    let ratio = n.shimmer.mean / s.shimmer.mean.max(1e-5);
                    ratios[k].push(ratio);
                    out.push_str(&format!(" {ratio:.1}× |"));
                }
                _ => out.push_str(" – |"),
            }
        }
        out.push('\n');
    }
    for (k, f) in res.iter().enumerate() {
        let r = &mut ratios[k];
        if r.is_empty() {
            continue;
        }
        r.sort_by(f64::total_cmp);
        out.push_str(&format!(
            "\nnaive ÷ splat at faces of {f} over {} walks: least {:.1}×, median {:.1}×\n",
            r.len(),
            r[0],
            r[r.len() / 2]
        ));
    }
    out
}

/// The walks of the level `level` (loaded: `loaded`) made with `spec`, written to `dir` as
/// `{prefix}NN.ron`, and the plans that fly each with `methods` at `face_res` and `size`.
pub fn walk_plans(
    (level, loaded): (&std::path::Path, &texel_runtime::load::LoadedLevel),
    spec: &SurveySpec,
    (dir, prefix): (&std::path::Path, &str),
    (methods, face_res, size): (&[crate::runner::Method], &[u32], glam::UVec2),
) -> Result<(Vec<crate::suite::RunPlan>, Vec<Walk>), crate::runner::EvalError> {
    use crate::runner::EvalError;
    let rays =
        texel_runtime::occluders::SceneRays::new(texel_runtime::frame_plan::scene_input(loaded));
    let walks = survey_walks(rays.scene(), &rays, spec)
        .map_err(|e| EvalError::Input(format!("{}: {e}", level.display())))?;
    std::fs::create_dir_all(dir)
        .map_err(|e| EvalError::Input(format!("creating {}: {e}", dir.display())))?;
    let mut plans = Vec::new();
    for (i, walk) in walks.iter().enumerate() {
        let file = dir.join(format!("{prefix}{i:02}.ron"));
        let comment = format!(
            "texel-eval survey of {}, seed {}, walk {i}: {:.1} cells per second",
            level.display(),
            spec.seed,
            walk.speed
        );
        std::fs::write(&file, walk.to_ron(spec, &comment))
            .map_err(|e| EvalError::Input(format!("writing {}: {e}", file.display())))?;
        plans.push(crate::suite::RunPlan {
            level: level.to_owned(),
            path: file,
            methods: methods.to_vec(),
            face_res: face_res.to_vec(),
            size,
            freeze: false,
            first_frames: None,
        });
    }
    Ok((plans, walks))
}

/// The worst of the suite's surveyed walks (`runs`, flown by naive and splat): per level,
/// walk and face resolution, splat's mean and worst-frame shimmer, naive's, and naive's over
/// splat's; the `shown` walks where that ratio is least, then the least and the median over
/// every walk. Empty without a walk both methods flew.
pub fn worst_walks_table(runs: &[crate::report::RunRecord], shown: usize) -> String {
    let mut rows: Vec<(&crate::report::RunRecord, &crate::report::RunRecord, f64)> = (runs.iter())
        .filter(|s| s.method == "splat")
        .filter_map(|s| {
            let n = runs.iter().find(|n| {
                n.method == "naive"
                    && (&n.level, &n.path, n.face_res) == (&s.level, &s.path, s.face_res)
            })?;
            Some((s, n, n.shimmer.mean / s.shimmer.mean.max(1e-5)))
        })
        .collect();
    if rows.is_empty() {
        return String::new();
    }
    rows.sort_by(|a, b| a.2.total_cmp(&b.2));
    let stem = |p: &str| {
        std::path::Path::new(p)
            .file_stem()
            .map_or(p.to_owned(), |s| s.to_string_lossy().into_owned())
    };
    let mut out = format!(
        "\n### The worst of {} surveyed walks (naive ÷ splat least first)\n\n\
         | walk | faces | splat | splat's worst frame | naive | naive ÷ splat |\n\
         |---|---:|---:|---:|---:|---:|\n",
        rows.len()
    );
    for (s, n, ratio) in rows.iter().take(shown) {
        out.push_str(&format!(
            "| {} | {} | {:.4} | {:.4} | {:.4} | {ratio:.1}× |\n",
            stem(&s.path),
            s.face_res,
            s.shimmer.mean,
            s.shimmer.max,
            n.shimmer.mean
        ));
    }
    let ratios: Vec<f64> = rows.iter().map(|r| r.2).collect();
    out.push_str(&format!(
        "\nnaive ÷ splat over {} walks: least {:.1}×, median {:.1}×\n",
        ratios.len(),
        ratios[0],
        ratios[ratios.len() / 2]
    ));
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3Swizzles;
    use std::path::Path;
    use texel_runtime::frame_plan::scene_input;
    use texel_runtime::load::load_level;
    use texel_runtime::occluders::SceneRays;

    fn level(name: &str) -> (SceneRays, f32) {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../assets/levels")
            .join(name);
        let level = load_level(&path).expect("bundled level loads");
        let rays = SceneRays::new(scene_input(&level));
        (rays, level.scene.settings.cell_size)
    }

    #[test]
    fn walks_are_made_from_the_seed_alone() {
        let (rays, s) = level("stone_circle.ron");
        let spec = SurveySpec {
            count: 4,
            ..SurveySpec::new(s)
        };
        let a = survey_walks(rays.scene(), &rays, &spec).expect("walks");
        let b = survey_walks(rays.scene(), &rays, &spec).expect("walks");
        assert_eq!(a, b);
        assert_eq!(a.len(), 4);
        let c = survey_walks(rays.scene(), &rays, &SurveySpec { seed: 2, ..spec }).expect("walks");
        assert_ne!(a, c);
    }

    /// Judged by a finer test than the survey's own: 26 directions, every frame's point.
    #[test]
    fn walks_stand_clear_over_a_floor_at_eye_height_and_at_their_speed() {
        for name in ["stone_circle.ron", "colonnade.ron", "terrain_hills.ron"] {
            let (rays, s) = level(name);
            let spec = SurveySpec {
                count: 6,
                seed: 7,
                ..SurveySpec::new(s)
            };
            for walk in survey_walks(rays.scene(), &rays, &spec).expect("walks") {
                let mut dirs = Vec::new();
                for x in -1..=1 {
                    for y in -1..=1 {
                        for z in -1..=1 {
                            if (x, y, z) != (0, 0, 0) {
                                dirs.push(Vec3::new(x as f32, y as f32, z as f32).normalize());
                            }
                        }
                    }
                }
                for p in walk.points(spec.frames) {
                    for &d in &dirs {
                        assert!(
                            rays.first_hit(p, d, 0.9 * CLEARANCE * s).is_none(),
                            "{name}: {p} is within {CLEARANCE} cells of a surface along {d}"
                        );
                    }
                    let floor = rays
                        .first_hit(p, -Vec3::Y, 10.0 * s)
                        .expect("a floor under it");
                    assert!(!floor.back_face, "{name}: {p} is inside a solid");
                }
                for (p, _, pitch) in walk.keyframes {
                    let floor = rays.first_hit(p, -Vec3::Y, 10.0 * s).expect("floor");
                    assert!(
                        floor.t >= spec.height.0 * s - 1e-3 && floor.t <= spec.height.1 * s + 1e-3,
                        "{name}: eye {} over the floor",
                        floor.t
                    );
                    assert!((-20.0..=5.0).contains(&pitch));
                }
                let k = &walk.keyframes;
                let length = k[0].0.xz().distance(k[1].0.xz()) + k[1].0.xz().distance(k[2].0.xz());
                let want = walk.speed * s * spec.dt * (spec.frames - 1) as f32;
                assert!(
                    (length - want).abs() < 1e-3 * want.max(1.0),
                    "{length} vs {want}"
                );
                assert!((spec.speed.0..=spec.speed.1).contains(&walk.speed));
            }
        }
    }

    #[test]
    fn a_walk_is_a_camera_path() {
        let (rays, s) = level("stone_circle.ron");
        let spec = SurveySpec {
            count: 1,
            ..SurveySpec::new(s)
        };
        let walk = &survey_walks(rays.scene(), &rays, &spec).expect("walk")[0];
        let text = walk.to_ron(&spec, "a comment\non two lines");
        let path = texel_runtime::path::CameraPath::from_ron_str(&text, "walk").expect("parses");
        assert_eq!((path.frames, path.keyframes.len()), (spec.frames, 3));
        let first = path.keyframes[0].position;
        assert!(Vec3::from(first).distance(walk.keyframes[0].0) < 1e-3);
    }

    #[test]
    fn bad_specs_and_levels_without_room_are_refused() {
        let (rays, s) = level("stone_circle.ron");
        for spec in [
            SurveySpec {
                count: 0,
                ..SurveySpec::new(s)
            },
            SurveySpec {
                frames: 1,
                ..SurveySpec::new(s)
            },
            SurveySpec {
                speed: (3.0, 1.0),
                ..SurveySpec::new(s)
            },
            SurveySpec {
                height: (f32::NAN, 1.0),
                ..SurveySpec::new(s)
            },
            SurveySpec::new(0.0),
        ] {
            assert!(
                survey_walks(rays.scene(), &rays, &spec).is_err(),
                "{spec:?} accepted"
            );
        }
        // Eyes too near the floor for the clearance: a clear refusal, not a hang.
        let spec = SurveySpec {
            count: 1,
            height: (0.01, 0.02),
            ..SurveySpec::new(s)
        };
        let err = survey_walks(rays.scene(), &rays, &spec).expect_err("no room");
        assert!(err.contains("clear walks"), "{err}");
        let empty = SceneInput::default();
        assert!(survey_walks(&empty, &rays, &SurveySpec::new(s)).is_err());
    }

    #[test]
    fn the_worst_walks_are_those_where_splat_gains_least() {
        use crate::metrics::Summary;
        use crate::report::RunRecord;
        let run = |method: &str, path: &str, mean: f64| RunRecord {
            level: "l.ron".into(),
            path: path.into(),
            method: method.into(),
            face_res: 128,
            shimmer: Summary {
                mean,
                p95: mean,
                max: 2.0 * mean,
            },
            ..RunRecord::default()
        };
        let runs = [
            run("splat", "d/paths/a_survey_00.ron", 0.001),
            run("naive", "d/paths/a_survey_00.ron", 0.05),
            run("splat", "d/paths/b_survey_00.ron", 0.01),
            run("naive", "d/paths/b_survey_00.ron", 0.03),
            run("splat", "d/paths/b_survey_01.ron", 0.002),
            run("naive", "d/paths/b_survey_01.ron", 0.04),
            // A walk naive did not fly is not ranked.
            run("splat", "d/paths/c_survey_00.ron", 0.5),
        ];
        let table = worst_walks_table(&runs, 2);
        assert!(table.contains("worst of 3 surveyed walks"), "{table}");
        let rows: Vec<&str> = table
            .lines()
            .filter(|l| l.starts_with("| b_") || l.starts_with("| a_"))
            .collect();
        assert_eq!(rows.len(), 2, "{table}");
        assert!(
            rows[0].starts_with("| b_survey_00 | 128 | 0.0100 | 0.0200 | 0.0300 | 3.0× |"),
            "{table}"
        );
        assert!(rows[1].starts_with("| b_survey_01 |"), "{table}");
        assert!(
            table.contains("over 3 walks: least 3.0×, median 20.0×"),
            "{table}"
        );
        assert_eq!(worst_walks_table(&runs[6..], 5), "");
    }
}
