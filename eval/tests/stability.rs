//! Where methods fail, measured (GPU, lavapipe-sized): each test flies one bundled camera path
//! with one or two methods at 160×90 and checks the shimmer, coverage or provenance numbers
//! the design promises. Bounds come from measured values with margin; each says why.

use std::path::{Path, PathBuf};

use glam::UVec2;
use texel_eval::report::RunRecord;
use texel_eval::runner::Method;
use texel_eval::suite::{ReferenceKind, RunPlan, run_plan, short_form_frames};
use texel_render::context::test_context;

const SIZE: UVec2 = UVec2::new(160, 90);

fn assets() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets")
}

/// Runs `methods` at `face_res` along `path` on `level`; `None` without a GPU.
fn run(level: &str, path: &str, methods: &[Method], face_res: u32) -> Option<Vec<RunRecord>> {
    run_frozen(level, path, methods, face_res, false)
}

/// [`run`], with the level's animators taken off when `freeze`.
fn run_frozen(
    level: &str,
    path: &str,
    methods: &[Method],
    face_res: u32,
    freeze: bool,
) -> Option<Vec<RunRecord>> {
    run_sized(level, path, methods, (face_res, SIZE), freeze)
}

fn run_sized(
    level: &str,
    path: &str,
    methods: &[Method],
    sized: (u32, UVec2),
    freeze: bool,
) -> Option<Vec<RunRecord>> {
    let level = assets().join("levels").join(format!("{level}.ron"));
    let path = assets().join("paths").join(format!("{path}.ron"));
    run_files(level, path, methods, sized, freeze)
}

/// [`run_sized`] on a level and a path given as files.
fn run_files(
    level: PathBuf,
    path: PathBuf,
    methods: &[Method],
    (face_res, size): (u32, UVec2),
    freeze: bool,
) -> Option<Vec<RunRecord>> {
    let ctx = test_context()?;
    let name = path.file_stem().map(|s| s.to_string_lossy().into_owned());
    let plan = RunPlan {
        level,
        first_frames: short_form_frames(&path),
        path,
        methods: methods.to_vec(),
        face_res: vec![face_res],
        size,
        freeze,
    };
    let records = run_plan(&ctx, &plan, ReferenceKind::Gpu, &mut |_| {}).expect("run");
    for r in &records {
        eprintln!(
            "{name:?} {} @{face_res}: shimmer {:?} coverage {:.4} holes {:.4} eye {:?} eye share {:?}",
            r.method, r.shimmer, r.coverage_error, r.hole_rate, r.eye_fraction, r.eye_flicker_share
        );
    }
    Some(records)
}

/// [`run`] with splat and naive at `face_res`: their records, in that order.
fn splat_and_naive(level: &str, path: &str, face_res: u32) -> Option<(RunRecord, RunRecord)> {
    splat_and_naive_sized(level, path, (face_res, SIZE))
}

/// [`splat_and_naive`] at output size `size` instead of [`SIZE`].
fn splat_and_naive_sized(
    level: &str,
    path: &str,
    sized: (u32, UVec2),
) -> Option<(RunRecord, RunRecord)> {
    let level = assets().join("levels").join(format!("{level}.ron"));
    let path = assets().join("paths").join(format!("{path}.ron"));
    splat_and_naive_files(level, path, sized)
}

/// [`splat_and_naive_sized`] on a level and a path given as files.
fn splat_and_naive_files(
    level: PathBuf,
    path: PathBuf,
    sized: (u32, UVec2),
) -> Option<(RunRecord, RunRecord)> {
    let methods = [Method::Splat, Method::Naive];
    let r = run_files(level, path, &methods, sized, false)?;
    Some((
        find(&r, Method::Splat).clone(),
        find(&r, Method::Naive).clone(),
    ))
}

/// Asserts that splat's coverage error is below `factor` times naive's.
fn assert_coverage_below(splat: &RunRecord, naive: &RunRecord, factor: f64) {
    assert!(
        splat.coverage_error < factor * naive.coverage_error,
        "splat {} against naive {} (bound {factor}x)",
        splat.coverage_error,
        naive.coverage_error
    );
}

fn find(records: &[RunRecord], m: Method) -> &RunRecord {
    records
        .iter()
        .find(|r| r.method == m.name())
        .expect("the method ran")
}

/// Bounds below were measured at 160×90, face resolution 32, on lavapipe; the measured value
/// is quoted in each test. The metric's own floor, for a perfectly world-stable image, is
/// about 0.01 (checker corners and sub-pixel detail; see `calibration.rs`).
#[test]
fn splat_under_pure_yaw_does_not_shimmer() {
    let Some((splat, naive)) = splat_and_naive("stone_circle", "yaw", 32) else {
        return;
    };
    // Measured: splat max 0.004 (resampling residue at texel corners, none of it from the
    // eye probe), naive mean 0.14. Nothing in the world moves relative to the probes, so
    // anything above the metric's floor would be a real pop.
    assert!(splat.shimmer.max < 0.01, "{:?}", splat.shimmer);
    assert!(splat.shimmer.mean * 20.0 < naive.shimmer.mean);
}

/// Also the colours: against the full-resolution raster's frames, both reduced to art
/// pixels (`texel_eval::colour`), splat's colour error is at most naive's.
#[test]
fn splat_strafing_inside_a_cell_is_far_below_naive() {
    let methods = [Method::Raster, Method::Splat, Method::Naive];
    let Some(records) = run("stone_circle", "strafe_in_cell", &methods, 32) else {
        return;
    };
    let (splat, naive) = (find(&records, Method::Splat), find(&records, Method::Naive));
    let colour = |r: &RunRecord| r.colour_error.expect("the raster ran first");
    eprintln!(
        "colour error: splat {:?}, naive {:?}",
        colour(splat),
        colour(naive)
    );
    assert_eq!(colour(find(&records, Method::Raster)).mean, 0.0);
    assert!(colour(naive).mean > 0.0);
    assert!(
        colour(splat).mean <= colour(naive).mean,
        "splat {:?} naive {:?}",
        colour(splat),
        colour(naive)
    );
    // Measured: splat mean 0.0021, naive 0.030 (14×) over every pixel; leaving out what the
    // raster changed too (2026-12-07), splat 0.00088, naive 0.030 (34×). The probes stay put
    // inside a cell, so only the eye probe and raster resampling can flicker; ask for at
    // least 5×.
    assert!(
        splat.shimmer.mean * 5.0 < naive.shimmer.mean,
        "splat {:?} naive {:?}",
        splat.shimmer,
        naive.shimmer
    );
    assert!(splat.shimmer.max < 0.015, "{:?}", splat.shimmer);
}

#[test]
fn snap_is_stable_under_an_orthographic_pan_and_not_under_a_perspective_strafe() {
    let Some(ortho) = run("stone_circle", "ortho_pan", &[Method::Snap], 32) else {
        return;
    };
    let Some(persp) = run("stone_circle", "strafe_in_cell", &[Method::Snap], 32) else {
        return;
    };
    let (o, p) = (find(&ortho, Method::Snap), find(&persp, Method::Snap));
    // Measured: ortho max 0.0 (whole-texel snapping keeps every art pixel on the geometry);
    // perspective max 0.28 (depths drift at different rates, the snap cannot hold them).
    assert!(o.shimmer.max < 0.005, "{:?}", o.shimmer);
    assert!(p.shimmer.max > 0.1, "{:?}", p.shimmer);
}

#[test]
fn splat_across_cells_stays_bounded_per_frame() {
    let Some((splat, naive)) = splat_and_naive("stone_circle", "sprint_cells", 32) else {
        return;
    };
    // A cell every four frames. Measured: splat mean 0.043, worst frame 0.21, eye pixels
    // 4.0%; naive mean 0.18. With fades that took a whole cell of travel (the reference's
    // rate) each fade was still running when the next crossing came: mean 0.054, worst
    // frame 0.30, eye pixels 7.2%, so the bounds below fail for them.
    assert!(splat.shimmer.max < 0.25, "{:?}", splat.shimmer_per_frame);
    let eye = splat.eye_fraction.expect("splat reports eye pixels");
    assert!(eye < 0.05, "eye probe draws {eye} of the pixels");
    assert!(splat.shimmer.mean < 0.08, "{:?}", splat.shimmer);
    assert!(splat.shimmer.mean * 2.0 < naive.shimmer.mean);
}

#[test]
fn behind_an_occluder_the_flicker_concentrates_in_eye_pixels() {
    let Some(r) = run("colonnade", "occluder_pass", &[Method::Splat], 48) else {
        return;
    };
    let splat = find(&r, Method::Splat);
    let eye = splat.eye_fraction.expect("splat reports eye pixels");
    let share = splat.eye_flicker_share.expect("something flickered");
    // Inside one cell the grid probe is fixed, so what flickers is what it cannot see: the
    // disoccluded regions the eye probe fills. Measured: eye pixels are 14% of the frame
    // and hold 84% of the flicker (66% at faces of 32, 72% at 64). Bound: a majority.
    assert!(share > 0.5, "eye share {share} of flicker, {eye} of pixels");
    assert!(
        share > 3.0 * eye,
        "eye share {share} of flicker, {eye} of pixels"
    );
}

/// Close behind a pillar, the grid probe a cell away sees the pillar's side from its
/// neighbour face at a grazing angle, as quads standing across it like the slats of a blind;
/// from the camera, off the probe's origin, the floor and wall behind showed between them in
/// stripes. The eye's fill now takes every pixel whose splat lies far behind what the eye
/// sees (`shaders/background.wgsl`).
#[test]
fn no_farther_surface_shows_through_a_near_pillar() {
    let Some(r) = run("colonnade", "occluder_pass", &[Method::Splat], 32) else {
        return;
    };
    let splat = find(&r, Method::Splat);
    // Measured: coverage error 0.046 (0.057 while the eye filled only where no quad landed;
    // naive 0.059), shimmer 0.0094 (0.0107). Bound between the two.
    assert!(splat.coverage_error < 0.052, "{}", splat.coverage_error);
    assert!(splat.hole_rate < 0.002, "{}", splat.hole_rate);
}

#[test]
fn along_the_wall_the_hole_rate_stays_low() {
    let Some((splat, naive)) = splat_and_naive("colonnade", "wall_graze", 32) else {
        return;
    };
    // Measured: splat 0.0006 of pixels, naive 0.0087 (thin geometry lost at low
    // resolution). 0.0029 (SwiftShader 0.0027) while silhouettes ended half a texel out
    // (today they end where the shade pass finds the edge: the edge search), 0.0013 while flat
    // surfaces' silhouettes against the sky also grew by their angle. At faces of 128 (the
    // suite's) 0.0003.
    assert!(splat.hole_rate < 0.002, "{}", splat.hole_rate);
    assert!(splat.hole_rate * 4.0 < naive.hole_rate);
}

/// Along the wall at faces of 64 (a texel spans about five pixels), splat's silhouettes had
/// been a pixel out wherever the eye filled beside them: the background pass drew each eye
/// texel whole, half a texel past the edge the shade pass had found, and the eye's quads grew
/// like a stable probe's, though the eye sits at the camera. Both now end at the found edges
/// (background.wgsl `past_edge`, cull.wgsl's `exact` for the eye). The floor's quads along
/// its junction with the wall had a corner inside the wall, drawn in front of the wall's
/// quads as a sawtooth of wedges (now clipped to the wall's plane: cull.wgsl
/// `clip_behind`), and slanting silhouettes erred outward at every texel's corner (now cut:
/// `CORNER_CUT_LEFT`).
#[test]
fn along_the_wall_at_faces_of_64_silhouettes_are_as_tight_as_naive() {
    let Some((splat, naive)) =
        splat_and_naive_sized("colonnade", "wall_graze", (64, UVec2::new(320, 180)))
    else {
        return;
    };
    // Measured: coverage error 0.0210 against naive's 0.0213 on lavapipe (0.0208 and 0.0213
    // on SwiftShader); 0.0222 with the junction's corners clipped but no corner cut, 0.0228
    // with neither, 0.0238 with the eye's quads grown, 0.0255 with the eye's texels drawn
    // whole too. Holes 0.0006 (0.0003 with every corner whole).
    assert_coverage_below(&splat, &naive, 1.0);
    assert!(splat.hole_rate < 0.001, "{}", splat.hole_rate);
}

/// A silhouette that slants across the probe's texel grid crosses a texel's two sides near a
/// corner, and a quad is a rectangle: its corner there lay outside the surface on every texel
/// along the edge, so slanting silhouettes erred outward. A ray toward each such corner tells
/// a slanting edge (the corner is cut onto the line through the two sides' edges) from a
/// box's corner (kept). Boxes rolled to many angles against the sky (a level made for this
/// test, `tests/data/slanted_edges.ron`), strafing across a cell face, at faces of 64.
#[test]
fn slanting_silhouettes_are_as_tight_as_low_resolution_rendering() {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data");
    let Some((splat, naive)) = splat_and_naive_files(
        data.join("slanted_edges.ron"),
        data.join("slanted_strafe.ron"),
        (64, UVec2::new(320, 180)),
    ) else {
        return;
    };
    // Measured on lavapipe: coverage error 0.0158 against naive's 0.0186 (0.0202 with every
    // corner whole), holes 0.0012 against 0.0047 (0.0007 whole; 0.0015 with cut corners on
    // the line itself rather than 0.6 of the way out).
    assert_coverage_below(&splat, &naive, 0.95);
    assert!(splat.hole_rate < 0.002, "{}", splat.hole_rate);
    assert!(splat.hole_rate * 2.0 < naive.hole_rate);
}

/// Silhouettes end where the shade pass found the surface's edge between a texel and its
/// neighbour (shade.wgsl's edge search), not half a texel out: a straight silhouette (a stone's
/// top, the horizon) is no longer rounded one way for as long as a probe stays, so splat's
/// silhouettes are as tight as low-resolution rendering's.
#[test]
fn silhouettes_are_tighter_than_low_resolution_rendering() {
    let Some((splat, naive)) = splat_and_naive("stone_circle", "walk_cells", 32) else {
        return;
    };
    // Measured: coverage error 0.0517 against naive's 0.0642 (0.0691 with every silhouette
    // half a texel out); holes 0.0028 against 0.0121.
    assert_coverage_below(&splat, &naive, 0.9);
    assert!(splat.hole_rate * 2.0 < naive.hole_rate);
}

/// Where a floor meets a wall, or an architrave's underside ends in front of one, the edge
/// lies on the nearer surface's plane: the shade pass finds a junction as where nothing in the
/// BVH hides that plane (the floor casts no shadow, the wall does), and the cull pass puts the
/// quad's corners on that side onto the plane, so an off-probe camera sees the edge where it
/// is. Strafing behind the pillar (320×180, faces of 128, where a texel spans two pixels), the
/// floor's junction with the long wall and the architrave's far edge had each been a whole
/// row off across the frame. Where no stable quad covers a pixel, the eye's fill ends at the
/// same edges (it had drawn the eye's silhouette texels whole, half a texel out).
#[test]
fn junctions_and_edges_against_farther_walls_are_as_tight_as_low_resolution_rendering() {
    let Some((splat, naive)) =
        splat_and_naive_sized("colonnade", "occluder_pass", (128, UVec2::new(320, 180)))
    else {
        return;
    };
    // Measured: coverage error 0.0024 against naive's 0.0090 on lavapipe, 0.0026 on
    // SwiftShader (0.0026 on lavapipe before the floor's corners were clipped to the wall's
    // plane and slanting silhouettes' corners cut), since the eye's fill (background.wgsl
    // `past_edge`) ends where the shade pass found each silhouette's edge, as its quads do;
    // 0.0059 (SwiftShader 0.0076) while
    // it drew every eye texel whole, 0.0108 with quads ending at the texel's depth and
    // junctions unsearched, 0.0099 with the junctions searched alone.
    assert_coverage_below(&splat, &naive, 0.5);
    assert!(splat.hole_rate < 0.001, "{}", splat.hole_rate);
}

/// A camera 0.35 above the ground puts its cell centre on the ground plane: a probe there
/// sees the ground edge-on, so the eye probe filled most of the frame. Placement moves the
/// grid probe up to the top of the cell (`texel_probes::placement::CLEARANCE`), where it
/// sees the ground with short texels.
#[test]
fn a_low_camera_is_served_by_the_grid_probe() {
    let Some((splat, naive)) = splat_and_naive("stone_circle", "low_orbit", 32) else {
        return;
    };
    let eye = splat.eye_fraction.expect("splat reports eye pixels");
    // Measured: the eye probe draws 5.0% of the pixels (SwiftShader 5.2%; 14% with the
    // probe a quarter cell up, 57% at the cell centre); splat mean shimmer 0.0146
    // (SwiftShader 0.0191; 0.040 a quarter cell up, 0.061 at the centre), naive 0.109 (0.163).
    assert!(eye < 0.1, "eye probe draws {eye} of the pixels");
    assert!(splat.shimmer.mean < 0.03, "{:?}", splat.shimmer);
    assert!(splat.shimmer.mean * 5.0 < naive.shimmer.mean);
}

/// Walking past a standing stone's edge puts the cell centre 0.15 from its face: the first
/// clear point of the cell stands in front of the face, and sees the stone where a camera by
/// its edge sees past it, which the eye probe then drew. Placement takes the earliest point
/// that sees nearly as much of what the cell's cameras see as the best one
/// (`texel_probes::placement::SEES_TIE`).
#[test]
fn a_camera_by_a_stones_edge_is_served_by_the_grid_probe() {
    let Some((splat, naive)) = splat_and_naive("stone_circle", "stone_edge", 32) else {
        return;
    };
    let eye = splat.eye_fraction.expect("splat reports eye pixels");
    // Measured: the eye probe draws 6.6 % of the pixels (SwiftShader 6.7 %; 13.4 % with the
    // probe in front of the face); splat mean shimmer 0.0346 (SwiftShader 0.0360; 0.0443 in
    // front of the face), naive 0.0712 (0.0843).
    assert!(eye < 0.1, "eye probe draws {eye} of the pixels");
    assert!(
        splat.shimmer.mean < 0.7 * naive.shimmer.mean,
        "{:?}",
        splat.shimmer
    );
}

/// Walking 0.6 from a wall puts the cell centre 0.2 from it; placement keeps the probe
/// 0.45 of a cell from every surface, so the grid probe still sees along the wall.
#[test]
fn a_camera_brushing_a_wall_is_served_by_the_grid_probe() {
    let Some((splat, naive)) = splat_and_naive("colonnade", "wall_brush", 32) else {
        return;
    };
    let eye = splat.eye_fraction.expect("splat reports eye pixels");
    // Measured: eye pixels 2.7% (SwiftShader 2.5%; 6.6% with the probe a quarter cell
    // from the wall, 40% at the cell centre), mean shimmer 0.0092 (0.011, 0.027).
    assert!(eye < 0.1, "eye probe draws {eye} of the pixels");
    // Holes 0.0013 on both drivers (0.0020 and 0.0023 with the probe a quarter cell from
    // the wall), naive's 0.015 and 0.014: at faces of 32 the far colonnade's pillars are
    // narrower than a texel and alias, a texel off between probes.
    assert!(splat.hole_rate < 0.0025, "{}", splat.hole_rate);
    assert!(splat.hole_rate * 4.0 < naive.hole_rate);
}

/// An orthographic camera is served by orthographic probes (`texel_probes::ortho`): one face
/// whose texel rays run along the view, its origin on a lattice of whole texels, so a pan
/// never resamples a texel: as stable as snapping to the screen's art-pixel grid, with a
/// like coverage error. Turning, the grid probe holds its direction in 5° steps and the eye
/// probe fills what it misses: well below both screen-space methods.
#[test]
fn splat_under_an_orthographic_camera_is_as_stable_as_screen_snapping() {
    let methods = [Method::Splat, Method::Snap, Method::Naive];
    let Some(pan) = run("stone_circle", "ortho_pan", &methods, 32) else {
        return;
    };
    let Some(orbit) = run("stone_circle", "iso_orbit", &methods, 32) else {
        return;
    };
    let (splat, snap) = (find(&pan, Method::Splat), find(&pan, Method::Snap));
    // Measured: splat mean and worst frame 0.0000 (0.019 and 0.031 with the far cube probe
    // this replaced), coverage error 0.0666 against snap's 0.0636 and naive's 0.0657 (at
    // faces of 128 on 320x180: 0.0179 against 0.0189); eye pixels 0.00% (0.35% while the
    // back-face test used the camera's position).
    assert!(splat.shimmer.max <= 0.002, "{:?}", splat.shimmer_per_frame);
    assert!(
        splat.coverage_error < 1.1 * snap.coverage_error,
        "splat {} snap {}",
        splat.coverage_error,
        snap.coverage_error
    );
    let eye = splat.eye_fraction.expect("splat reports eye pixels");
    assert!(eye < 0.001, "eye probe draws {eye} of the pixels");
    let (splat, snap, naive) = (
        find(&orbit, Method::Splat),
        find(&orbit, Method::Snap),
        find(&orbit, Method::Naive),
    );
    // Measured: splat 0.0136 (worst frame 0.031), snap 0.0217, naive 0.0218; coverage error
    // 0.0445 against 0.0594 for both. (Splat was 0.0127 while each crossing's fade moved a
    // frame late, after the frame was drawn: the handovers' frames fall differently on this
    // 30-frame path; at faces of 128 on 320x180 0.0038 -> 0.0040.)
    assert!(
        splat.shimmer.mean * 1.5 < snap.shimmer.mean.min(naive.shimmer.mean),
        "splat {:?} snap {:?} naive {:?}",
        splat.shimmer,
        snap.shimmer,
        naive.shimmer
    );
    assert!(splat.coverage_error < 1.15 * snap.coverage_error);
}

#[test]
fn march_is_exact_under_yaw_and_calm_inside_a_cell() {
    let Some(yaw) = run("stone_circle", "yaw", &[Method::March, Method::Naive], 32) else {
        return;
    };
    let Some(strafe) = run(
        "stone_circle",
        "strafe_in_cell",
        &[Method::March, Method::Naive],
        32,
    ) else {
        return;
    };
    let (m, naive) = (find(&yaw, Method::March), find(&yaw, Method::Naive));
    // Measured: march max 0.0001 under yaw (a ray meets the same world-fixed texel planes
    // whichever way the camera turns), naive mean 0.14.
    assert!(m.shimmer.max < 0.003, "{:?}", m.shimmer);
    assert!(m.shimmer.mean * 50.0 < naive.shimmer.mean);
    let (m, naive) = (find(&strafe, Method::March), find(&strafe, Method::Naive));
    // Measured: march mean 0.0011, max 0.0061; naive mean 0.030. Inside a cell the probes stay
    // put, so only the eye fallback and resampling can flicker.
    assert!(m.shimmer.mean * 5.0 < naive.shimmer.mean, "{:?}", m.shimmer);
    assert!(m.shimmer.max < 0.015, "{:?}", m.shimmer);
    // Measured: 40 texels crossed per pixel, 2.4% of pixels fall back. The counters are real
    // (a march takes at least one step) and bounded by the march's own limit.
    let steps = m.steps_per_pixel.expect("march counts its steps");
    assert!((1.0..512.0).contains(&steps), "{steps}");
    let fallback = m.fallback_fraction.expect("march counts its fallbacks");
    assert!(fallback < 0.1, "{fallback}");
    assert!(naive.steps_per_pixel.is_none() && naive.fallback_fraction.is_none());
    // Measured: coverage error 0.069 (splat 0.086, naive 0.070): the marched texels show the
    // objects the reference raster shows, not just stable colours.
    assert!(m.coverage_error < 0.1, "{}", m.coverage_error);
}

/// Textured surfaces: inside a cell the probes' texels keep their colours, so texture
/// detail adds no flicker of its own (naive rendering resamples the textures every frame
/// and shimmers far more than on flat colours); and the runs still merge enough texels
/// that no more quads are drawn than texels are seen.
#[test]
fn textured_strafing_inside_a_cell_stays_calm_with_fewer_quads_than_seen_texels() {
    let Some((splat, naive)) = splat_and_naive("textured", "textured_strafe", 64) else {
        return;
    };
    let quads = splat.counters.quads_splatted / splat.counters.screen_visible_texels;
    eprintln!("quads per screen-visible texel {quads:.3}");
    assert!(
        splat.shimmer.mean * 10.0 < naive.shimmer.mean,
        "splat {:?} naive {:?}",
        splat.shimmer,
        naive.shimmer
    );
    // An outlined quad is drawn as a body and a strip per outlined side (cull.wgsl
    // `emit_outlined`): measured 1.069 with strips (2026-12-02), at most 1.0 before them;
    // 1.116 since the next cell's probe fills behind the grid probe near the cell's edge
    // (its quads where something hides a corner from the grid probe, most of them drawn
    // behind the grid probe's: runtime `FrameDriver::frame`, 2026-12-05); 1.143 (SwiftShader
    // 1.138) since the eye's outlined texels that no stable probe shows are drawn as body
    // and strips too (2026-12-07; 1.263 with strips on every outlined eye texel).
    assert!(quads <= 1.18, "{quads} quads per screen-visible texel");
}

/// Terrain: a walk over the island's hills. Terrain pixels are coloured per world cell with
/// bands measured from the grid probe, so inside a cell nothing changes colour; what flickers
/// is the hills' occlusion (eye pixels) and crossings. Bounded against naive rendering.
#[test]
fn terrain_walk_stays_well_below_naive() {
    let Some((splat, naive)) = splat_and_naive("terrain_hills", "terrain_walk", 48) else {
        return;
    };
    // Measured at 48 on 160x90: splat 0.0176 (max 0.034; 0.029 and 0.066 before terrain
    // pixels were drawn pixel by pixel), naive 0.126; splat's holes 0.0007 (2026-12-01 on
    // lavapipe). Earlier: holes 0.0025 on both
    // drivers (naive's 0.0050: at this size a texel is big, and where a hill's crest falls
    // short of its texel's square against the sky, the sky shows; 0.0022 while flat
    // surfaces' silhouettes against the sky grew too, 0.0037 with the crests' exact).
    // Ask for 3x. (The issue asks for 10x: not met yet, see the closing note.)
    assert!(
        splat.shimmer.mean * 3.0 < naive.shimmer.mean,
        "splat {:?} naive {:?}",
        splat.shimmer,
        naive.shimmer
    );
    assert!(splat.hole_rate < 0.003, "{}", splat.hole_rate);
}

/// Moving objects keep their pixels: followed with their objects, the windmill's, the door's
/// and the platform's pixels barely change while the camera walks, and the still world is no
/// less stable with them moving than with them frozen into the probes.
#[test]
fn moving_objects_stay_locked_and_leave_the_world_as_stable() {
    let methods = [Method::Splat, Method::Naive];
    let Some(r) = run("moving_parts", "moving_walk", &methods, 32) else {
        return;
    };
    let Some(frozen) = run_frozen("moving_parts", "moving_walk", &[Method::Splat], 32, true) else {
        return;
    };
    let (splat, naive) = (find(&r, Method::Splat), find(&r, Method::Naive));
    let frozen = find(&frozen, Method::Splat);
    let moving = splat.moving_shimmer.expect("moving objects in view");
    let still = splat.still_shimmer.expect("moving objects in view");
    let naive_moving = naive.moving_shimmer.expect("moving objects in view");
    // Measured: moving pixels 0.014 (most of it their own light changing as they turn), the
    // still world 0.027 (0.031 frozen: frozen objects are captured into the probes and
    // shimmer like the rest), naive's moving pixels 0.095.
    assert!(moving <= 2.0 * still, "moving {moving}, still {still}");
    assert!(
        still <= 1.1 * frozen.shimmer.mean,
        "still world {still} with motion, {} frozen",
        frozen.shimmer.mean
    );
    assert!(
        moving * 4.0 < naive_moving,
        "{moving} vs naive {naive_moving}"
    );
    assert!(frozen.moving_shimmer.is_none(), "nothing moves when frozen");
}

/// Sprites keep the texel world's rules: with their frames held (`--freeze`; a playing
/// animation changes its pixels on purpose), sprite pixels shimmer at most twice as much as
/// the whole image while the camera turns or strafes inside a cell, and turning them toward
/// the camera (screen-space sprites) shimmers clearly more. At 320×180 with 64-texel faces
/// (measured: yaw 0.00004 against 0.00006, camera-facing 0.045; strafe 0.0017 against
/// 0.0019, camera-facing 0.0039: a sideways step does not turn a camera-facing quad, so only
/// its unsnapped, unquantized pixels shimmer); at 160×90 with 32-texel faces the far grass
/// is two pixels tall and yaw measured 0.0016 against 0.0004.
#[test]
fn sprites_stay_locked_to_the_world_inside_a_cell() {
    let methods = [Method::Splat, Method::SplatFacing];
    for path in ["yaw", "strafe_in_cell"] {
        let sized = (64, UVec2::new(320, 180));
        let Some(r) = run_sized("sprites", path, &methods, sized, true) else {
            return;
        };
        let (splat, facing) = (find(&r, Method::Splat), find(&r, Method::SplatFacing));
        let sprite = splat.sprite_shimmer.expect("sprites in view");
        let facing_sprite = facing.sprite_shimmer.expect("sprites in view");
        eprintln!(
            "{path}: sprites {sprite}, image {}, camera-facing sprites {facing_sprite}",
            splat.shimmer.mean
        );
        assert!(
            sprite <= 2.0 * splat.shimmer.mean.max(1e-4),
            "{path}: sprites {sprite}, image {}",
            splat.shimmer.mean
        );
        assert!(
            facing_sprite > 2.0 * sprite.max(1e-4),
            "{path}: camera-facing {facing_sprite} vs {sprite}"
        );
    }
}

/// One of the weak classes of views (issue 60), on a path of `assets/paths/classes` written
/// for it: splat's shimmer (mean and worst frame) and the better of naive's and snap's over
/// it, at faces of 64 on 160×90. With `raster`, the raster runs first, so what the scene
/// changes on purpose (a sprite's next frame) is not counted.
fn class(level: &str, path: &str, raster: bool) -> Option<(f64, f64, f64)> {
    let mut methods = vec![Method::Naive, Method::Snap, Method::Splat];
    if raster {
        methods.insert(0, Method::Raster);
    }
    let records = run(level, &format!("classes/{path}"), &methods, 64)?;
    let mean = |m| find(&records, m).shimmer.mean;
    let splat = find(&records, Method::Splat).shimmer;
    let better = mean(Method::Naive).min(mean(Method::Snap));
    let ratio = better / splat.mean.max(1e-6);
    eprintln!(
        "{path}: splat {:.4} (worst frame {:.3}), better baseline {better:.4}, {ratio:.1}×",
        splat.mean, splat.max
    );
    Some((splat.mean, ratio, splat.max))
}

/// A camera orbiting a playing sprite 2.5 units away. Measured (2026-12-07): splat 0.0083,
/// naive 0.062, snap 0.109 (7.5×), worst frame 0.039. The target is 10×: not met.
#[test]
fn a_camera_orbiting_near_a_sprite_stays_well_below_the_baselines() {
    let Some((mean, ratio, worst)) = class("sprites", "sprites_near_orbit", true) else {
        return;
    };
    assert!(
        mean < 0.011 && ratio > 6.0 && worst < 0.15,
        "{mean} {ratio}× {worst}"
    );
}

/// Walking toward the windmill and the sliding door. Measured: splat 0.0104, naive 0.113
/// (10.8×), worst frame 0.035: the target (10×, no frame over 0.15) is met.
#[test]
fn walking_toward_moving_parts_stays_ten_times_below_the_baselines() {
    let Some((mean, ratio, worst)) = class("moving_parts", "moving_toward_mill", false) else {
        return;
    };
    assert!(
        mean < 0.013 && ratio > 8.5 && worst < 0.15,
        "{mean} {ratio}× {worst}"
    );
}

/// A diagonal run (5 units a second) across both rows of the colonnade's pillars. Measured
/// (2026-12-07, the eye's outlines as strips): splat 0.0156, naive 0.116, snap 0.124
/// (7.5×), worst frame 0.077 (0.0161, 7.2× before). The target (10×) is not met.
#[test]
fn a_diagonal_run_between_pillars_stays_well_below_the_baselines() {
    let Some((mean, ratio, worst)) = class("colonnade", "colonnade_diagonal", false) else {
        return;
    };
    assert!(
        mean < 0.019 && ratio > 6.5 && worst < 0.15,
        "{mean} {ratio}× {worst}"
    );
}

/// A low camera (eye 0.48) circling outside the ring of stones. Measured (2026-12-07, the
/// eye's outlines as strips fixed to the world): splat 0.0095, naive 0.045 (4.7×), worst
/// frame 0.034; SwiftShader 0.0105, 4.7× (0.0117, 3.8× with the eye's whole-texel outlines,
/// which slid with the camera). The 10× target is not met: nine tenths of what is left is crossings
/// (docs/stability-log.md, "The eye's outlines as strips").
#[test]
fn a_low_camera_outside_the_ring_stays_below_the_baselines() {
    let Some((mean, ratio, worst)) = class("stone_circle", "circle_low_outside", false) else {
        return;
    };
    assert!(
        mean < 0.0115 && ratio > 4.0 && worst < 0.15,
        "{mean} {ratio}× {worst}"
    );
}

/// Walking 0.9 units in front of standing stones, each filling a quarter of the view as it
/// passes. Measured (2026-12-07, the eye's outlines as strips): splat 0.0100, naive 0.046
/// (4.6×), worst frame 0.044; SwiftShader 0.0102, 4.6× (0.0142, 3.2× and 0.062 with the
/// eye's whole-texel outlines).
/// The 10× target is not met: nine tenths of what is left is crossings.
#[test]
fn brushing_past_stones_stays_below_the_baselines() {
    let Some((mean, ratio, worst)) = class("stone_circle", "circle_brush_stone", false) else {
        return;
    };
    assert!(
        mean < 0.012 && ratio > 3.8 && worst < 0.15,
        "{mean} {ratio}× {worst}"
    );
}
