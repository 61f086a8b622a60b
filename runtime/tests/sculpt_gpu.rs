//! `texel-run play`'s terrain keys without a window: a dab at the centre ray of a camera on
//! `terrain_hills` through the session, as the play loop makes it.

use anyhow::Context as _;
use glam::{UVec2, Vec2, Vec3};
use texel_render::context::test_context;
use texel_render::input::{Camera, FrameInput, Schedule};
use texel_runtime::load::{LoadedLevel, load_level};
use texel_runtime::play_sculpt::dab_at_centre;
use texel_runtime::session::{FrameRequest, Session, set_face_resolution, shadow_extended};
use texel_scene::sculpt::scene_ray_hit;

const DT: f32 = 1.0 / 30.0;

fn hills() -> anyhow::Result<LoadedLevel> {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/levels/terrain_hills.ron");
    let mut level = load_level(&path).context("terrain_hills loads")?;
    set_face_resolution(&mut level, 64).map_err(anyhow::Error::msg)?;
    Ok(level)
}

/// The terrain's height under `p` (X, Z) in `level`, from straight above.
fn ground(level: &LoadedLevel, p: Vec3) -> Option<f32> {
    let above = Vec3::new(p.x, 1000.0, p.z);
    scene_ray_hit(&level.scene, &level.assets, above, -Vec3::Y).map(|h| h.point.y)
}

/// Draws `n` frames of `camera`; returns the last picture and how many faces of each kind
/// (eye, stable) were captured.
fn frames(
    ctx: &texel_render::context::GpuContext,
    session: &mut Session,
    camera: Camera,
    size: UVec2,
    n: usize,
) -> anyhow::Result<(Vec<u8>, usize, usize)> {
    let request = FrameRequest {
        camera,
        dt: DT,
        schedule: Schedule::Ours,
        size,
    };
    let (mut px, mut eye, mut stable) = (Vec::new(), 0, 0);
    for _ in 0..n {
        let (drawn, p) = session.draw_offscreen(ctx, &request)?;
        let (e, s) = count_captures(&drawn.input);
        (px, eye, stable) = (p, eye + e, stable + s);
    }
    Ok((px, eye, stable))
}

fn count_captures(input: &FrameInput) -> (usize, usize) {
    let eye = (input.captures.iter())
        .filter(|w| w.slot == texel_probes::probe_set::Slot::Eye)
        .count();
    (eye, input.captures.len() - eye)
}

/// The screen rectangle (pixels, x0, y0, x1, y1) holding the world box `lo..hi` seen by
/// `camera` in a `size` picture.
fn screen_rect(camera: &Camera, size: UVec2, lo: Vec3, hi: Vec3) -> [f32; 4] {
    let m = camera.projection(size.x as f32 / size.y as f32) * camera.view();
    let mut r = [f32::MAX, f32::MAX, f32::MIN, f32::MIN];
    for i in 0..8 {
        let c = Vec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        );
        let clip = m * c.extend(1.0);
        assert!(clip.w > 0.0, "the dab's box lies in front of the camera");
        let ndc = Vec2::new(clip.x, clip.y) / clip.w;
        let px = Vec2::new(
            (ndc.x + 1.0) * 0.5 * size.x as f32,
            (1.0 - ndc.y) * 0.5 * size.y as f32,
        );
        r = [
            r[0].min(px.x),
            r[1].min(px.y),
            r[2].max(px.x),
            r[3].max(px.y),
        ];
    }
    r
}

/// A dab at the crosshair raises the ground under it, marks fewer probe faces than a full
/// rebuild captures, and the frames after it change only where the dab's box (and its
/// shadow) shows.
#[test]
fn a_play_dab_at_the_crosshair_raises_the_ground_and_changes_only_the_picture_near_it()
-> anyhow::Result<()> {
    let Some(ctx) = test_context() else {
        return Ok(());
    };
    let mut level = hills()?;
    let size = UVec2::new(256, 144);
    // Over the sea off the island's south shore, looking north and down at the slope west
    // of the stone circle, 25 units away: the grid probe draws three faces, and the dab's box
    // (the whole height range over the brush) lies in the view of one.
    let camera = Camera::from_yaw_pitch(Vec3::new(-12.0, 10.0, 50.0), 0.0, -12.0);
    let hit = scene_ray_hit(&level.scene, &level.assets, camera.position, camera.forward)
        .context("the centre ray meets the terrain")?;
    let height_before = ground(&level, hit.point).context("ground under the crosshair")?;
    let mut session = Session::headless(&ctx, &level, size, camera.fov_y)?;
    let (_, _, settle_stable) = frames(&ctx, &mut session, camera, size, 8)?;
    let (before, _, idle_stable) = frames(&ctx, &mut session, camera, size, 2)?;
    let (again, _, _) = frames(&ctx, &mut session, camera, size, 1)?;
    assert_eq!(idle_stable, 0, "the probes have settled");
    assert!(before == again, "a settled picture holds still");

    // A frame of R held for the most dabs one frame makes (three: 0.75 units at the centre).
    let dab = dab_at_centre(&ctx, &mut session, &mut level, &camera, true, 3)?
        .context("the dab lands")?;
    assert!((dab.centre - hit.point).length() < 1e-3, "{}", dab.centre);
    let height_after = ground(&level, hit.point).context("ground")?;
    assert!(
        (height_after - height_before - 0.75).abs() < 0.01,
        "three dabs raise the ground under the crosshair by 0.75: {height_before} → \
         {height_after}"
    );
    let (after, _, dab_stable) = frames(&ctx, &mut session, camera, size, 8)?;

    // What a full rebuild captures: the same session given the level afresh.
    session.set_level(&ctx, &level)?;
    let (rebuilt, full_eye, full_stable) = frames(&ctx, &mut session, camera, size, 8)?;
    let full = full_eye + full_stable;
    eprintln!(
        "dab marked {} faces, captured {dab_stable} stable faces again; a rebuild captured \
         {full} ({full_stable} stable); settling captured {settle_stable} stable",
        dab.faces_marked
    );
    assert!(dab.faces_marked > 0, "the dab is in view");
    assert!(
        (dab.faces_marked as usize) < full && dab_stable < full_stable,
        "a dab marks {} faces and captures {dab_stable} stable ones; a rebuild {full} and \
         {full_stable}",
        dab.faces_marked
    );
    assert!(
        after == rebuilt,
        "the refreshed picture is the rebuilt level's"
    );

    // Every changed pixel lies where the dab's box or its shadow shows.
    let (lo, hi) = shadow_extended(session.scene(), dab.min, dab.max);
    let [x0, y0, x1, y1] = screen_rect(&camera, size, lo, hi);
    let (mut changed, mut outside) = (0, Vec::new());
    for (i, (a, b)) in before
        .chunks_exact(4)
        .zip(after.chunks_exact(4))
        .enumerate()
    {
        if a == b {
            continue;
        }
        changed += 1;
        let (x, y) = ((i as u32 % size.x) as f32, (i as u32 / size.x) as f32);
        if x + 1.0 < x0 - 1.0 || x > x1 + 1.0 || y + 1.0 < y0 - 1.0 || y > y1 + 1.0 {
            outside.push((x, y));
        }
    }
    let centre = (size.x / 2, size.y / 2);
    let near_centre = (centre.1 - 3..centre.1 + 3).any(|y| {
        (centre.0 - 3..centre.0 + 3).any(|x| {
            let i = ((y * size.x + x) * 4) as usize;
            before[i..i + 4] != after[i..i + 4]
        })
    });
    eprintln!(
        "{changed} pixels changed; the dab's box spans x {x0:.0}..{x1:.0}, y {y0:.0}..{y1:.0}"
    );
    assert!(
        changed > 20 && near_centre,
        "the dab shows at the crosshair"
    );
    assert!(
        outside.is_empty(),
        "pixels changed away from the dab: {outside:?}"
    );
    assert!(
        changed < (size.x * size.y / 4) as usize,
        "a dab changes a small part of the picture: {changed}"
    );
    Ok(())
}

/// Where the centre ray meets no terrain (the sky) a dab does nothing and marks nothing.
#[test]
fn a_play_dab_at_the_sky_changes_nothing() -> anyhow::Result<()> {
    let mut level = hills()?;
    let camera = Camera::from_yaw_pitch(Vec3::new(0.0, 9.0, 40.0), 0.0, 20.0);
    let before = ground(&level, Vec3::new(0.0, 0.0, 30.0));
    assert!(texel_runtime::play_sculpt::dab_level(&mut level, &camera, true, 3).is_none());
    assert_eq!(ground(&level, Vec3::new(0.0, 0.0, 30.0)), before);
    Ok(())
}
