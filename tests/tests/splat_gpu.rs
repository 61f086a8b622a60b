//! The texel-splat renderer on the GPU, through the runtime's frame driver: golden images,
//! stability under rotation and in-cell movement, crossfades, and coverage.

use std::collections::HashMap;

use glam::{UVec2, Vec3};
use texel_render::input::{Camera, Display, Schedule};
use texel_tests::{Harness, check_golden};

const DT: f32 = 1.0 / 30.0;

fn cam(x: f32, y: f32, z: f32, yaw: f32, pitch: f32) -> Camera {
    Camera::from_yaw_pitch(Vec3::new(x, y, z), yaw, pitch)
}

/// Renders a few frames so the grid probe is complete, then returns the last image.
fn settled(h: &mut Harness, c: Camera) -> Vec<u8> {
    let mut px = Vec::new();
    for _ in 0..6 {
        px = h.frame(c, DT).2;
    }
    px
}

#[test]
fn stone_circle_golden_images_from_three_cameras() {
    let size = UVec2::new(256, 144);
    let Some(mut h) = Harness::new("assets/levels/stone_circle.ron", size, 64) else {
        return;
    };
    let cameras = [
        ("stone_circle_start", cam(0.0, 1.6, 13.0, 0.0, -5.0)),
        ("stone_circle_inside", cam(1.2, 1.6, 1.3, 140.0, 4.0)),
        ("stone_circle_high", cam(-9.0, 5.0, 6.0, -55.0, -25.0)),
    ];
    for (name, c) in cameras {
        let px = settled(&mut h, c);
        // Near-exact: flat colours, deterministic splat order (see splat.wgsl's tie-break).
        check_golden(name, &px, size, 0.002);
    }
}

type Corners = [[u32; 3]; 4];

/// Texel key → corner bits of every quad of `role` in the last frame.
fn quads(h: &Harness, role: u32) -> HashMap<u32, Corners> {
    h.renderer()
        .read_splats(&h.ctx)
        .expect("splats read back")
        .into_iter()
        .filter(|s| s.role == role)
        .map(|s| (s.key, s.corners.map(|c| c.map(f32::to_bits))))
        .collect()
}

/// Asserts every texel drawn in both frames has bit-identical corners; returns how many.
fn assert_same_corners(a: &HashMap<u32, Corners>, b: &HashMap<u32, Corners>, what: &str) -> usize {
    let mut shared = 0;
    for (key, corners) in a {
        if let Some(other) = b.get(key) {
            assert_eq!(corners, other, "{what}: texel {key} moved");
            shared += 1;
        }
    }
    shared
}

#[test]
fn yaw_in_place_keeps_every_quad_bit_identical() {
    let size = UVec2::new(192, 108);
    let Some(mut h) = Harness::new("assets/levels/stone_circle.ron", size, 48) else {
        return;
    };
    let at = |yaw: f32| cam(0.3, 1.6, 9.2, yaw, -4.0);
    settled(&mut h, at(0.0));
    let (mut eye_before, mut grid_before) = (quads(&h, 0), quads(&h, 1));
    let mut shared = 0;
    for step in 1..=24 {
        let (input, _, _) = h.frame(at(step as f32 * 2.5), DT);
        assert!(input.previous.is_none(), "yaw never changes the cell");
        let (eye, grid) = (quads(&h, 0), quads(&h, 1));
        shared += assert_same_corners(&grid_before, &grid, "grid under yaw");
        shared += assert_same_corners(&eye_before, &eye, "eye under yaw");
        (eye_before, grid_before) = (eye, grid);
    }
    assert!(shared > 10_000, "the frames shared only {shared} quads");
}

#[test]
fn moving_inside_a_cell_keeps_grid_quads_bit_identical() {
    let size = UVec2::new(192, 108);
    let Some(mut h) = Harness::new("assets/levels/stone_circle.ron", size, 48) else {
        return;
    };
    // Cell of (0, 2, 9): x, z in [-0.5, 0.5) around it; stay well inside.
    let at = |i: u32| {
        cam(
            -0.3 + 0.05 * i as f32,
            1.6,
            9.2 - 0.04 * i as f32,
            3.0,
            -4.0,
        )
    };
    settled(&mut h, at(0));
    let mut before = quads(&h, 1);
    let mut shared = 0;
    let home = Vec3::new(0.0, 2.0, 9.0);
    for i in 1..=10 {
        let (input, _, _) = h.frame(at(i), DT);
        // Near the cell's edge the next cell's probe may fill behind the cell's own, which
        // then draws as the previous probe (role 2) of a crossing's first frame.
        let role = match input.previous {
            Some(p) if p.origin == home => 2,
            _ => {
                assert_eq!(input.grid.origin, home);
                1
            }
        };
        let now = quads(&h, role);
        shared += assert_same_corners(&before, &now, "grid while strafing");
        before = now;
    }
    assert!(shared > 5_000, "the frames shared only {shared} grid quads");
}

#[test]
fn a_cell_crossing_crossfades_over_several_frames() {
    let size = UVec2::new(160, 90);
    let Some(mut h) = Harness::new("assets/levels/stone_circle.ron", size, 32) else {
        return;
    };
    settled(&mut h, cam(0.0, 1.6, 9.3, 0.0, -4.0));
    // Step over the boundary at z = 8.5 and stand still.
    let mut fades = Vec::new();
    for _ in 0..40 {
        let (input, stats, _) = h.frame(cam(0.0, 1.6, 8.4, 0.0, -4.0), DT);
        if input.previous.is_some() {
            fades.push((input.fade_t, stats.counters.faces_captured));
        }
    }
    assert!(
        fades.len() >= 2,
        "the crossfade took {} frames",
        fades.len()
    );
    assert!(
        fades.windows(2).all(|w| w[1].0 >= w[0].0),
        "fade_t never goes back while standing still: {fades:?}"
    );
    let partial = fades.iter().filter(|(t, _)| *t > 0.0 && *t < 1.0).count();
    assert!(
        partial >= 2,
        "at least two frames show both probes: {fades:?}"
    );
}

/// While a crossfade runs, each stable probe keeps the pixels the Bayer pattern hands to the
/// other behind them, where the other cannot see their point, so the eye probe fills little
/// more as `fade_t` moves under a still camera. (Discarding them let the eye show through in
/// the pattern wherever the owner could not see what the other probe did: here the eye's share
/// tripled over the fade, 757 -> 2,236 pixels; kept behind, 766 -> 1,266: what is left is where
/// the owner sees past the point and the eye, from the camera, still sees it.)
#[test]
fn during_a_crossfade_the_stable_probes_fill_for_each_other() {
    let size = UVec2::new(160, 90);
    let Some(mut h) = Harness::new("assets/levels/stone_circle.ron", size, 32) else {
        return;
    };
    // Looking past the near stones, where the two probes see around them differently.
    settled(&mut h, cam(0.6, 1.6, 7.7, 15.0, -4.0));
    // Step over the boundary at z = 7.5 and stand still.
    let c = cam(0.6, 1.6, 7.3, 15.0, -4.0);
    let mut fading = Vec::new();
    for _ in 0..30 {
        let (input, _, _) = h.frame(c, DT);
        if input.previous.is_some() {
            let ids = h.renderer().read_frame_ids(&h.ctx).unwrap();
            let eye = ids.from_eye.iter().filter(|e| **e).count();
            fading.push((input.fade_t, eye));
        }
    }
    assert!(fading.len() >= 4, "no crossfade ran: {fading:?}");
    let first = fading[0].1;
    for &(t, eye) in &fading {
        assert!(
            eye <= 2 * first,
            "at fade_t {t} the eye showed {eye} pixels, {first} when the fade began: {fading:?}"
        );
    }
}

#[test]
fn inside_a_closed_room_no_pixel_is_left_uncovered() {
    let size = UVec2::new(160, 90);
    let Some(mut h) = Harness::new("tests/data/closed_room.ron", size, 32) else {
        return;
    };
    let cameras = [
        cam(0.0, 1.6, 0.0, 0.0, 0.0),
        cam(1.7, 1.2, -1.4, 120.0, -30.0),
        cam(-1.9, 2.5, 1.8, -60.0, 35.0),
        cam(0.4, 0.3, 0.2, 200.0, -80.0),
    ];
    for c in cameras {
        let px = settled(&mut h, c);
        let keys = texel_render::target::read_texture_layer(
            &h.ctx,
            h.renderer().keys_texture().expect("keys"),
            0,
            4,
        )
        .expect("keys read back");
        // Key 0 is a pixel no texel coloured: neither a quad nor the eye-probe fill (which
        // leaves the sky's pixels at 0).
        let holes = keys
            .chunks_exact(4)
            .filter(|k| u32::from_le_bytes([k[0], k[1], k[2], k[3]]) == 0)
            .count();
        assert_eq!(
            holes, 0,
            "{holes} pixels show no texel from {:?}",
            c.position
        );
        assert_eq!(px.len(), (size.x * size.y * 4) as usize);
    }
}

#[test]
fn picking_names_the_entity_under_a_pixel() {
    let size = UVec2::new(160, 90);
    let Some(mut h) = Harness::new("assets/levels/stone_circle.ron", size, 32) else {
        return;
    };
    settled(&mut h, cam(0.0, 1.6, 13.0, 0.0, -5.0));
    // Level order: 1 is the ground (bottom of the view); the sky (top row) is nothing.
    let ground = h.renderer().pick(&h.ctx, UVec2::new(80, 88)).unwrap();
    assert_eq!(ground, Some(1));
    assert_eq!(h.renderer().pick(&h.ctx, UVec2::new(80, 1)).unwrap(), None);
    assert_eq!(h.renderer().pick(&h.ctx, UVec2::new(500, 1)).unwrap(), None);
    // Somewhere in the middle band there are stones (ids above 1).
    let stones = (40..120)
        .step_by(4)
        .filter_map(|x| h.renderer().pick(&h.ctx, UVec2::new(x, 45)).unwrap())
        .filter(|id| *id > 1)
        .count();
    assert!(stones > 0, "no stone picked across the middle of the view");
}

#[test]
fn frame_ids_agree_with_picking_and_mark_eye_pixels() {
    let size = UVec2::new(160, 90);
    let Some(mut h) = Harness::new("assets/levels/stone_circle.ron", size, 32) else {
        return;
    };
    settled(&mut h, cam(0.0, 1.6, 13.0, 0.0, -5.0));
    let ids = h.renderer().read_frame_ids(&h.ctx).unwrap();
    assert_eq!(ids.entity.len(), (size.x * size.y) as usize);
    for (x, y) in [(80, 88), (80, 1), (60, 45), (100, 50)] {
        let picked = h
            .renderer()
            .pick(&h.ctx, UVec2::new(x, y))
            .unwrap()
            .unwrap_or(0);
        assert_eq!(
            ids.entity[(y * size.x + x) as usize],
            picked,
            "pixel ({x}, {y})"
        );
    }
    let eye = ids.from_eye.iter().filter(|e| **e).count();
    // Settled in one cell, the grid probe draws almost everything.
    assert!(
        eye * 5 < ids.from_eye.len(),
        "{eye} of {} pixels from the eye",
        ids.from_eye.len()
    );
}

#[test]
fn flat_ground_shows_no_seams_while_faces_arrive_over_frames() {
    // Faces are captured a few per frame; a face shaded before its neighbour arrived must not
    // keep an outline along the seam (the shade pass only looks into valid faces, and
    // re-shades the borders of its neighbours when a face arrives).
    let size = UVec2::new(192, 108);
    let Some(mut h) = Harness::new("tests/data/flat_ground.ron", size, 32) else {
        return;
    };
    let c = cam(0.3, 1.6, 0.2, 45.0, -35.0);
    let px = settled(&mut h, c);
    let mut colours = std::collections::BTreeSet::new();
    // Rows well below the horizon: only ground.
    for y in 60..size.y {
        for x in 0..size.x {
            let i = ((y * size.x + x) * 4) as usize;
            colours.insert([px[i], px[i + 1], px[i + 2]]);
        }
    }
    assert_eq!(
        colours.len(),
        1,
        "an evenly lit plane must be one flat colour: {colours:?}"
    );
}

#[test]
fn runs_draw_what_one_quad_per_texel_draws() {
    let size = UVec2::new(256, 144);
    let n = 64;
    let Some(mut h) = Harness::new("assets/levels/stone_circle.ron", size, n) else {
        return;
    };
    let c = cam(0.0, 1.6, 13.0, 0.0, -5.0);
    settled(&mut h, c);
    let (_, merged, merged_px) = h.frame(c, DT);
    let runs = h.renderer().read_splats(&h.ctx).expect("splats");
    h.session.renderer_mut().set_runs(false);
    let (input, single, single_px) = h.frame(c, DT);
    let texels = h.renderer().read_splats(&h.ctx).expect("splats");
    h.session.renderer_mut().set_runs(true);

    let (m, s) = (merged.counters, single.counters);
    assert!(
        m.quads_splatted * 10 < s.quads_splatted * 6,
        "runs should save quads: {m:?} vs {s:?}"
    );
    // Without runs the cull pass looks at every texel of the stable faces it draws; with
    // them, at each run's head once (measured: 1,428 against 16,716 on lavapipe, 1,429 on
    // SwiftShader).
    let stable_faces = input.grid.draw.count() as u64;
    assert!(
        s.cull_entries >= stable_faces * u64::from(n * n) && stable_faces > 0,
        "{} entries for {stable_faces} faces of {n}² texels",
        s.cull_entries
    );
    assert!(
        m.cull_entries > 0 && m.cull_entries * 5 < s.cull_entries,
        "runs should save the cull pass entries: {} against {}",
        m.cull_entries,
        s.cull_entries
    );
    // Every grid texel a single quad draws lies in exactly one run (an outlined quad's
    // strips share its key: its body stands for it).
    let mut in_runs = HashMap::new();
    for r in runs.iter().filter(|r| r.role == 1 && r.part == 0) {
        let step = if r.column { n } else { 1 };
        for i in 0..r.texels {
            *in_runs.entry(r.key + i * step).or_insert(0) += 1;
        }
    }
    assert!(
        in_runs.values().all(|&k| k == 1),
        "a texel lies in two runs"
    );
    let grid: Vec<u32> = texels
        .iter()
        .filter(|t| t.role == 1 && t.part == 0)
        .map(|t| t.key)
        .collect();
    assert!(grid.len() > 1000 && texels.iter().all(|t| t.texels == 1));
    let missing = grid.iter().filter(|k| !in_runs.contains_key(k)).count();
    assert_eq!(missing, 0, "{missing} drawn texels are in no run");
    // The same picture, and the same texels on screen.
    let differ = merged_px
        .chunks(4)
        .zip(single_px.chunks(4))
        .filter(|(a, b)| a.iter().zip(*b).any(|(x, y)| x.abs_diff(*y) > 8))
        .count();
    assert!(
        differ * 100 <= merged_px.len() / 4,
        "{differ} pixels differ between runs and single quads"
    );
    let (a, b) = (m.screen_visible_texels, s.screen_visible_texels);
    assert!(a.abs_diff(b) * 50 <= b, "visible texels {a} vs {b}");
}

/// Faces lit under the paper schedule (which draws texel by texel) get their runs before our
/// schedule draws them: switching schedules (Tab in `texel-run play`) shows the same picture.
#[test]
fn switching_from_the_paper_schedule_draws_the_same_frame() {
    let size = UVec2::new(160, 90);
    let level = "assets/levels/stone_circle.ron";
    let Some(mut h) = Harness::new(level, size, 32) else {
        return;
    };
    let c = cam(0.0, 1.6, 9.3, 20.0, -4.0);
    for _ in 0..4 {
        h.frame_with(c, DT, Schedule::Paper);
    }
    let switched = settled(&mut h, c);
    let mut fresh = Harness::new(level, size, 32).expect("a second harness");
    let direct = settled(&mut fresh, c);
    let differ = switched
        .chunks(4)
        .zip(direct.chunks(4))
        .filter(|(a, b)| a != b)
        .count();
    assert!(
        differ * 200 <= switched.len() / 4,
        "{differ} pixels differ after switching from the paper schedule"
    );
}

/// An orthographic camera's grid probe is one face whose texels lie on a world lattice: after
/// a pan long enough to move the probe (a quarter face), every texel the two probes share
/// (the same world line) is lit exactly alike, so a pan never resamples anything.
#[test]
fn orthographic_grid_probes_share_their_texels_across_a_pan() {
    let size = UVec2::new(160, 90);
    let Some(mut h) = Harness::new("assets/levels/stone_circle.ron", size, 32) else {
        return;
    };
    let ortho = |x: f32| Camera {
        ortho_height: Some(12.0),
        ..cam(x, 9.0, 14.0, 0.0, -35.0)
    };
    let (a, n, faces_a) = h.grid_lit_faces(ortho(-2.0));
    let (b, n_b, faces_b) = h.grid_lit_faces(ortho(11.0));
    assert_eq!(n, n_b);
    let (fa, fb) = (
        a.grid.ortho.expect("orthographic"),
        b.grid.ortho.expect("orthographic"),
    );
    assert_eq!(fa, fb, "a pan keeps the probe's direction and size");
    assert_ne!(a.grid.origin, b.grid.origin, "the pan moved the probe");
    // The same world line: columns and rows shifted by the origins' offset, whole texels.
    let texel = fa.texel(n);
    let shift = (b.grid.origin - a.grid.origin) / texel;
    let (dx, dy) = (shift.dot(fa.right), shift.dot(fa.down));
    assert!(
        (dx - dx.round()).abs() < 1e-3 && (dy - dy.round()).abs() < 1e-3,
        "origins {} texels apart, not whole",
        shift
    );
    let (dx, dy) = (dx.round() as i64, dy.round() as i64);
    assert!(dx != 0, "shifted {dx} columns");
    let (mut shared, mut same, mut lit) = (0, 0, std::collections::HashSet::new());
    // Away from the faces' borders (outlines look at neighbours across them).
    for y in 1..n as i64 - 1 {
        for x in 1..n as i64 - 1 {
            let (xb, yb) = (x - dx, y - dy);
            if xb < 1 || yb < 1 || xb >= n as i64 - 1 || yb >= n as i64 - 1 {
                continue;
            }
            let i = ((y * n as i64 + x) * 4) as usize;
            let j = ((yb * n as i64 + xb) * 4) as usize;
            let (ca, cb) = (&faces_a[0][i..i + 3], &faces_b[0][j..j + 3]);
            shared += 1;
            if ca == cb {
                same += 1;
            }
            lit.insert([ca[0], ca[1], ca[2]]);
        }
    }
    assert!(
        shared > 1000 && lit.len() > 20,
        "{shared} shared texels, {} colours",
        lit.len()
    );
    assert_eq!(same, shared, "{same} of {shared} shared texels lit alike");
}

#[test]
fn past_the_far_plane_the_sky_shows_not_an_unlit_texel() {
    // The probes capture farther than this camera's far plane: the ground's quads past it
    // are clipped (and texel marching stops at it), and the eye probe's fill there must show
    // the sky (as the raster does), not the eye texels the shade pass left unlit because
    // their quads cannot reach the view.
    for display in [Display::Splat, Display::March] {
        let size = UVec2::new(160, 90);
        let Some(mut h) = Harness::new("tests/data/flat_ground.ron", size, 32) else {
            return;
        };
        h.session.renderer_mut().set_display(display);
        let mut c = cam(0.0, 1.6, 0.0, 0.0, -5.0);
        c.far = 20.0;
        let px = settled(&mut h, c);
        let pixel = |x: u32, y: u32| {
            let i = ((y * size.x + x) * 4) as usize;
            [px[i], px[i + 1], px[i + 2]]
        };
        let sky = pixel(0, 0);
        let dark = px
            .chunks_exact(4)
            .filter(|p| p[0].max(p[1]).max(p[2]) < 24)
            .count();
        assert_eq!(
            dark, 0,
            "{display:?}: {dark} pixels are black (unlit eye texels)"
        );
        // Pitched down 5° with a vertical field of view of 60°, the horizon lies 7.5 rows
        // above the middle; the ground 20 units ahead (the far plane) 0.7 rows above it.
        // Between them, past the far plane, the sky shows.
        let row = size.y / 2 - 4;
        for x in (0..size.x).step_by(8) {
            assert_eq!(
                pixel(x, row),
                sky,
                "{display:?}: pixel ({x}, {row}), past the far plane"
            );
        }
        // And nearer than the far plane the ground does.
        let near = pixel(size.x / 2, size.y - 1);
        assert_ne!(near, sky, "{display:?}: the ground before the far plane");
    }
}

/// Culling never drops what a face sees. On two levels (the terrain's chunks and objects
/// toward the stone circle; a generated town's street), along a walk through cell
/// crossings, frames whose captures leave out what lies outside each face's frustum are the
/// frames of captures that draw everything, pixel for pixel, while drawing less. Leaving
/// out, besides, what spans less than a texel (the town's far props: at faces of 32 a texel
/// is a sixteenth of its distance) draws fewer objects and changes at most a few pixels (a
/// sub-texel object may still cover a texel's centre).
#[test]
fn culled_captures_draw_the_frames_of_captures_that_draw_everything() {
    use texel_render::gpu_scene::CaptureCull;
    let size = UVec2::new(128, 72);
    let dir = tempfile::tempdir().expect("a temporary folder");
    let town = dir.path().join("town.ron");
    let options = texel_runtime::generate::GenOptions {
        count: 400,
        max_lights: 4,
        ..Default::default()
    };
    (texel_runtime::generate::generate(&options).expect("a town"))
        .save(&town)
        .expect("the town saves");
    // The town's street runs along Z through x = 0 from z = side / 2 = 50.
    let walks = [
        (
            "assets/levels/terrain_hills.ron".to_owned(),
            Vec3::new(-8.0, 7.2, 40.0),
            -15.0,
        ),
        (town.display().to_string(), Vec3::new(0.0, 1.6, 48.0), 0.0),
    ];
    type Walk = (Vec<Vec<u8>>, u64, u64);
    let walk = |level: &str, start: Vec3, yaw: f32, cull: CaptureCull| -> Option<Walk> {
        let mut h = Harness::new(level, size, 32)?;
        h.session.renderer_mut().set_capture_cull(cull);
        let (mut frames, mut objects, mut triangles) = (Vec::new(), 0, 0);
        for i in 0..8 {
            let p = start - Vec3::Z * (1.1 * i as f32);
            let (_, stats, px) = h.frame(cam(p.x, p.y, p.z, yaw, -6.0), DT);
            objects += stats.counters.objects_captured;
            triangles += stats.counters.triangles_captured;
            frames.push(px);
            // The memory counted is the memory held: three slots of six 32² faces, each
            // texel in seven textures of at least 4 bytes; vertices of 3 floats or more
            // for every triangle captured on a face.
            let c = stats.counters;
            assert!(c.gpu_probe_bytes >= 3 * 6 * 32 * 32 * 7 * 4, "{c:?}");
            assert!(
                c.gpu_scene_bytes >= c.triangles_captured / c.faces_captured.max(1) as u64 * 36,
                "{c:?}"
            );
            assert!(c.gpu_bvh_bytes > 0, "{c:?}");
        }
        Some((frames, objects, triangles))
    };
    let differing = |a: &Walk, b: &Walk| -> Vec<usize> {
        (a.0.iter().zip(&b.0))
            .map(|(x, y)| x.chunks(4).zip(y.chunks(4)).filter(|(p, q)| p != q).count())
            .collect()
    };
    for (level, start, yaw) in &walks {
        let Some(everything) = walk(level, *start, *yaw, CaptureCull::Nothing) else {
            return;
        };
        let frustum = walk(level, *start, *yaw, CaptureCull::Frustum).expect("a harness");
        let footprint = walk(level, *start, *yaw, CaptureCull::Footprint).expect("a harness");
        println!(
            "{level}: objects, triangles captured: everything {:?}, frustum {:?}, footprint {:?}",
            (everything.1, everything.2),
            (frustum.1, frustum.2),
            (footprint.1, footprint.2)
        );
        let d = differing(&everything, &frustum);
        assert!(
            d.iter().all(|&n| n == 0),
            "{level}: pixels differing per frame with frustum culling: {d:?}"
        );
        assert!(
            frustum.1 * 2 < everything.1 && frustum.2 < everything.2,
            "{level}: frustum culling should draw less"
        );
        let d = differing(&everything, &footprint);
        let pixels = (size.x * size.y) as usize;
        assert!(
            d.iter().all(|&n| n * 100 <= pixels),
            "{level}: pixels differing per frame without sub-texel objects: {d:?}"
        );
        assert!(footprint.1 <= frustum.1 && footprint.2 <= frustum.2);
        if level.ends_with("town.ron") {
            assert!(
                footprint.1 < frustum.1,
                "{level}: the town's far props should be left out"
            );
        }
    }
}
