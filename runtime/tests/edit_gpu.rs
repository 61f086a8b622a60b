//! Edits taken in alone (`Session::update_entities`): the frames after them are the frames a
//! full rebuild draws after the same edits, byte for byte, and an edit far from the camera
//! marks no face the camera sees. Faces of 32, a 96×64 picture: lavapipe is slow.

use std::path::PathBuf;

use anyhow::Context as _;
use glam::{UVec2, Vec3};
use texel_render::context::{GpuContext, test_context};
use texel_render::input::{Camera, Schedule};
use texel_runtime::frame_plan::RowEdit;
use texel_runtime::load::LoadedLevel;
use texel_runtime::session::{
    EditUpdate, FrameRequest, Session, SessionError, set_face_resolution,
};
use texel_scene::assets::AssetLibrary;
use texel_scene::{
    DirectionalLight, EntityRow, Geometry, Material, Name, PointLight, Scene, Transform,
};

pub(crate) const SIZE: UVec2 = UVec2::new(96, 64);

/// Entities of [`yard`] by position.
const CRATE: usize = 2;
const PILLAR: usize = 3;
const BALL: usize = 4;
const LAMP: usize = 5;
const FAR: usize = 6;
/// The crate's twin in [`yard_and_boxes`].
const TWIN: usize = 7;

/// A ground, a sun, boxes and a sphere before the camera, a point light among them, and a
/// box far behind the camera.
fn yard() -> anyhow::Result<LoadedLevel> {
    let mut scene = Scene::new();
    let thing = |name: &str, at: Vec3, geometry: Geometry, albedo: Vec3| EntityRow {
        name: Some(Name(name.into())),
        transform: Some(Transform {
            translation: at,
            ..Transform::default()
        }),
        geometry: Some(geometry),
        material: Some(Material {
            albedo,
            ..Material::default()
        }),
        ..EntityRow::default()
    };
    let cube = |s: f32| Geometry::Box {
        size: Vec3::splat(s),
    };
    scene.spawn(thing(
        "Ground",
        Vec3::ZERO,
        Geometry::Plane {
            size: glam::Vec2::splat(60.0),
        },
        Vec3::new(0.3, 0.45, 0.2),
    ));
    scene.spawn(EntityRow {
        name: Some(Name("Sun".into())),
        directional_light: Some(DirectionalLight {
            direction: Vec3::new(-0.4, -1.0, -0.3),
            ..DirectionalLight::default()
        }),
        ..EntityRow::default()
    });
    scene.spawn(thing(
        "Crate",
        Vec3::new(-1.0, 0.5, 0.0),
        cube(1.0),
        Vec3::new(0.7, 0.5, 0.3),
    ));
    scene.spawn(thing(
        "Pillar",
        Vec3::new(1.5, 1.0, -1.0),
        cube(0.8),
        Vec3::new(0.6, 0.6, 0.65),
    ));
    let ball = Geometry::Sphere {
        radius: 0.6,
        segments: 12,
    };
    scene.spawn(thing(
        "Ball",
        Vec3::new(0.2, 0.6, -2.5),
        ball,
        Vec3::new(0.8, 0.2, 0.2),
    ));
    scene.spawn(EntityRow {
        name: Some(Name("Lamp".into())),
        transform: Some(Transform {
            translation: Vec3::new(0.5, 1.5, 0.8),
            ..Transform::default()
        }),
        point_light: Some(PointLight {
            colour: Vec3::new(1.0, 0.8, 0.5),
            intensity: 2.0,
            radius: 4.0,
        }),
        ..EntityRow::default()
    });
    scene.spawn(thing(
        "Far",
        Vec3::new(0.0, 0.5, 90.0),
        cube(1.0),
        Vec3::splat(0.5),
    ));
    let mut level = LoadedLevel {
        path: PathBuf::from("yard.ron"),
        scene,
        assets: AssetLibrary::default(),
    };
    set_face_resolution(&mut level, 32).map_err(anyhow::Error::msg)?;
    Ok(level)
}

pub(crate) fn camera() -> Camera {
    Camera::from_yaw_pitch(Vec3::new(0.0, 2.5, 6.0), 0.0, -15.0)
}

/// Draws `n` frames; returns the last picture and how many faces were captured in each.
pub(crate) fn frames(
    ctx: &GpuContext,
    session: &mut Session,
    n: usize,
) -> Result<(Vec<u8>, Vec<u32>), SessionError> {
    frames_at(ctx, session, n, SIZE)
}

/// [`frames`] at output size `size`.
fn frames_at(
    ctx: &GpuContext,
    session: &mut Session,
    n: usize,
    size: UVec2,
) -> Result<(Vec<u8>, Vec<u32>), SessionError> {
    let request = FrameRequest {
        camera: camera(),
        dt: 1.0 / 30.0,
        schedule: Schedule::Ours,
        size,
    };
    let (mut px, mut captured) = (Vec::new(), Vec::new());
    for _ in 0..n {
        let (drawn, p) = session.draw_offscreen(ctx, &request)?;
        captured.push(drawn.stats.counters.faces_captured);
        px = p;
    }
    Ok((px, captured))
}

/// Changes the row of the entity at `index` with `f`.
pub(crate) fn edit(level: &mut LoadedLevel, index: usize, f: impl FnOnce(&mut EntityRow)) {
    let e = level.scene.entities().nth(index).expect("entity");
    let mut row = level.scene.row(e).expect("row");
    f(&mut row);
    level.scene.set_row(e, row).expect("set row");
}

/// A crate moved and turned, a pillar recoloured and a lamp moved, each taken in alone and
/// in place, then a ball moved (whose change covers part of the stable faces, lit again
/// only there): once the marked faces are captured again, the picture is the one a session
/// made afresh on the edited level draws, byte for byte (the shadow tree refit, not
/// rebuilt, answers every shadow ray alike).
#[test]
fn frames_after_edits_in_place_equal_a_full_rebuild() -> anyhow::Result<()> {
    let Some(ctx) = test_context() else {
        return Ok(());
    };
    let mut level = yard()?;
    let mut session = Session::headless(&ctx, &level, SIZE, camera().fov_y)?;
    let (before, _) = frames(&ctx, &mut session, 10)?;
    edit(&mut level, CRATE, |r| {
        let t = r.transform.as_mut().expect("transform");
        t.translation += Vec3::new(0.6, 0.0, -0.4);
        t.rotation.y = 30.0;
    });
    edit(&mut level, PILLAR, |r| {
        r.material.as_mut().expect("material").albedo = Vec3::new(0.2, 0.3, 0.8);
    });
    edit(&mut level, LAMP, |r| {
        r.transform.as_mut().expect("transform").translation.x -= 1.0;
    });
    let update = session.update_entities(&ctx, &level, &[CRATE, PILLAR, LAMP])?;
    let EditUpdate::InPlace { faces_marked } = update else {
        anyhow::bail!("the edits were not taken in place: {update:?}");
    };
    assert!(faces_marked > 0, "the edits are in view");
    frames(&ctx, &mut session, 10)?;
    // The ball, alone: its region (with its shadows) covers part of the stable faces.
    edit(&mut level, BALL, |r| {
        r.transform.as_mut().expect("transform").translation += Vec3::new(-0.3, 0.0, -0.4);
    });
    let update = session.update_entities(&ctx, &level, &[BALL])?;
    assert!(matches!(update, EditUpdate::InPlace { .. }), "{update:?}");
    let request = FrameRequest {
        camera: camera(),
        dt: 1.0 / 30.0,
        schedule: Schedule::Ours,
        size: SIZE,
    };
    let (drawn, _) = session.draw_offscreen(&ctx, &request)?;
    assert!(
        !drawn.input.partial.is_empty(),
        "some stable face is lit again only where the ball shows"
    );
    let (after, _) = frames(&ctx, &mut session, 9)?;
    assert!(after != before, "the edits show");

    assert_full_rebuild_draws(&ctx, &level, &after)
}

/// The ball moved a little beside the lamp and under the sun: the stable faces that may
/// see it or its shadows are captured again only where it shows, and of the rest only the
/// texels whose rays toward a light meet its old or new bounds are lit again
/// (`texel_render::input::LightFilter`): far fewer than its region projects to, and the
/// picture is a full rebuild's, byte for byte.
#[test]
fn moving_one_object_relights_only_where_it_and_its_shadows_fall() -> anyhow::Result<()> {
    let Some(ctx) = test_context() else {
        return Ok(());
    };
    let mut level = yard()?;
    // The lamp behind the ball, reaching far: the ball's shadows may fall toward the
    // camera, over much of what the stable faces see.
    edit(&mut level, LAMP, |r| {
        r.transform.as_mut().expect("transform").translation = Vec3::new(0.3, 2.2, -4.5);
        r.point_light.as_mut().expect("light").radius = 8.0;
    });
    let mut session = Session::headless(&ctx, &level, SIZE, camera().fov_y)?;
    let (before, _) = frames(&ctx, &mut session, 10)?;
    edit(&mut level, BALL, |r| {
        r.transform.as_mut().expect("transform").translation.x += 0.15;
    });
    let update = session.update_entities(&ctx, &level, &[BALL])?;
    assert!(matches!(update, EditUpdate::InPlace { .. }), "{update:?}");
    let request = FrameRequest {
        camera: camera(),
        dt: 1.0 / 30.0,
        schedule: Schedule::Ours,
        size: SIZE,
    };
    let (drawn, _) = session.draw_offscreen(&ctx, &request)?;
    let part = &drawn.input.partial;
    assert!(!part.is_empty(), "stable faces captured in part");
    let c = &drawn.stats.counters;
    let lit = c.texels_shaded - c.eye_texels_shaded;
    let light: u64 = part.iter().map(|p| p.light.area()).sum();
    let shown: u64 = part.iter().map(|p| p.rect.area()).sum();
    assert!(
        lit < light / 4,
        "{lit} stable texels lit, of {light} the region projects to ({shown} where the ball may show)"
    );
    let (after, _) = frames(&ctx, &mut session, 9)?;
    assert!(after != before, "the ball moved");
    assert_full_rebuild_draws(&ctx, &level, &after)
}

/// The ball recoloured alone: its shadows and silhouettes stay, so the stable faces are
/// captured and lit again only where it shows, no more, and the picture is a full
/// rebuild's, byte for byte.
#[test]
fn a_colour_changed_alone_is_lit_again_only_where_it_shows() -> anyhow::Result<()> {
    let Some(ctx) = test_context() else {
        return Ok(());
    };
    let mut level = yard()?;
    let mut session = Session::headless(&ctx, &level, SIZE, camera().fov_y)?;
    let (before, _) = frames(&ctx, &mut session, 10)?;
    edit(&mut level, BALL, |r| {
        r.material.as_mut().expect("material").albedo = Vec3::new(0.2, 0.3, 0.9);
    });
    let update = session.update_entities(&ctx, &level, &[BALL])?;
    assert!(matches!(update, EditUpdate::InPlace { .. }), "{update:?}");
    let request = FrameRequest {
        camera: camera(),
        dt: 1.0 / 30.0,
        schedule: Schedule::Ours,
        size: SIZE,
    };
    let (drawn, _) = session.draw_offscreen(&ctx, &request)?;
    let part = &drawn.input.partial;
    assert!(!part.is_empty(), "stable faces captured in part");
    for p in part {
        assert_eq!(p.light, p.rect, "lit only where the ball may show");
        assert!(p.filter.casters.is_empty() && p.filter.lit.is_empty());
    }
    let c = &drawn.stats.counters;
    let shown: u64 = part.iter().map(|p| p.rect.area()).sum();
    assert!(c.texels_shaded - c.eye_texels_shaded <= shown);
    let (after, _) = frames(&ctx, &mut session, 9)?;
    assert!(after != before, "the ball's colour shows");
    assert_full_rebuild_draws(&ctx, &level, &after)
}

/// Asserts that a session made afresh on `level` draws `after` (an edited session's frame),
/// byte for byte, once settled.
pub(crate) fn assert_full_rebuild_draws(
    ctx: &GpuContext,
    level: &LoadedLevel,
    after: &[u8],
) -> anyhow::Result<()> {
    let mut fresh = Session::headless(ctx, level, SIZE, camera().fov_y)?;
    let (rebuilt, _) = frames(ctx, &mut fresh, 30)?;
    let differ = (after.chunks_exact(4).zip(rebuilt.chunks_exact(4)))
        .filter(|(a, b)| a != b)
        .count();
    assert_eq!(differ, 0, "pixels differing from a full rebuild's frame");
    Ok(())
}

/// The box 90 units behind the camera brought into view, in place: the faces find it
/// through the draw ranges' tree the edit refit (`texel_render::gpu_scene::RangeIndex`), so
/// the picture is the one a session made afresh on the edited level draws, byte for byte.
#[test]
fn a_box_brought_into_view_in_place_draws_as_a_full_rebuild() -> anyhow::Result<()> {
    let Some(ctx) = test_context() else {
        return Ok(());
    };
    let mut level = yard()?;
    let mut session = Session::headless(&ctx, &level, SIZE, camera().fov_y)?;
    let (before, _) = frames(&ctx, &mut session, 10)?;
    edit(&mut level, FAR, |r| {
        r.transform.as_mut().expect("transform").translation = Vec3::new(-1.0, 0.5, 2.0);
    });
    let update = session.update_entities(&ctx, &level, &[FAR])?;
    assert!(
        matches!(update, EditUpdate::InPlace { faces_marked } if faces_marked > 0),
        "{update:?}"
    );
    let (after, _) = frames(&ctx, &mut session, 20)?;
    assert!(after != before, "the box shows");
    assert_full_rebuild_draws(&ctx, &level, &after)
}

/// A box 90 units behind the camera, moved: no face the camera sees is marked, the next
/// frame captures only what a settled frame does, and the picture holds still; the level
/// read again as it was (`Session::reload`) takes in that row alone.
#[test]
fn an_edit_far_from_the_camera_marks_no_visible_face() -> anyhow::Result<()> {
    let Some(ctx) = test_context() else {
        return Ok(());
    };
    let mut level = yard()?;
    let mut session = Session::headless(&ctx, &level, SIZE, camera().fov_y)?;
    frames(&ctx, &mut session, 10)?;
    let (before, settled) = frames(&ctx, &mut session, 1)?;
    edit(&mut level, FAR, |r| {
        r.transform.as_mut().expect("transform").translation.x += 3.0;
    });
    let update = session.update_entities(&ctx, &level, &[FAR])?;
    assert_eq!(update, EditUpdate::InPlace { faces_marked: 0 });
    let (after, captured) = frames(&ctx, &mut session, 1)?;
    assert_eq!(captured, settled, "only the faces a settled frame captures");
    assert!(after == before, "the picture holds still");
    let far = session
        .scene()
        .objects
        .iter()
        .find(|o| o.id == FAR as u32 + 1);
    let x = far.context("the far box")?.transform.w_axis.x;
    assert!(
        (x - 3.0).abs() < 1e-6,
        "the session holds the moved box: x = {x}"
    );
    // The level read again as it was (a file reverted on disk): the far box's row alone.
    let reverted = yard()?;
    let update = session.reload(&ctx, &level, &reverted)?;
    assert_eq!(update, EditUpdate::InPlace { faces_marked: 0 });
    let far = session
        .scene()
        .objects
        .iter()
        .find(|o| o.id == FAR as u32 + 1);
    let x = far.context("the far box")?.transform.w_axis.x;
    assert!(
        x.abs() < 1e-6,
        "the session holds the reverted box: x = {x}"
    );
    Ok(())
}

/// A new output size keeps the probes where the face resolution stays
/// (`FrameDriver::resize`): on a level of fixed faces, and on a level of pixel size when the
/// session measures it on one viewport's height (`Session::set_face_height`, as the
/// editor's smaller frames while the view moves or a drag lands). Planned afresh instead,
/// the smaller frame captures every face it draws from again.
#[test]
fn a_smaller_frame_from_the_same_probes_captures_nothing_anew() -> anyhow::Result<()> {
    let Some(ctx) = test_context() else {
        return Ok(());
    };
    let small = SIZE / 2;
    let level = yard()?;
    let mut session = Session::headless(&ctx, &level, SIZE, camera().fov_y)?;
    frames(&ctx, &mut session, 10)?;
    let (before, settled) = frames(&ctx, &mut session, 1)?;
    let (_, captured) = frames_at(&ctx, &mut session, 1, small)?;
    assert_eq!(
        captured, settled,
        "fixed faces: only what a settled frame captures"
    );
    let (after, captured) = frames(&ctx, &mut session, 1)?;
    assert_eq!(captured, settled);
    assert!(after == before, "back at the first size, the same picture");
    // Faces that follow the viewport's height: 64 and 32 pixels ask for different ones.
    let mut level = yard()?;
    level.scene.settings.pixel_scale = texel_scene::PixelScale::PixelSize(1.0);
    for keep in [true, false] {
        let mut session = Session::headless(&ctx, &level, SIZE, camera().fov_y)?;
        if keep {
            session.set_face_height(Some(SIZE.y));
        }
        frames(&ctx, &mut session, 10)?;
        let (_, settled) = frames(&ctx, &mut session, 1)?;
        let (_, captured) = frames_at(&ctx, &mut session, 1, small)?;
        match keep {
            true => assert_eq!(
                captured, settled,
                "kept: only what a settled frame captures"
            ),
            false => assert!(
                captured[0] > settled[0],
                "planned afresh: {captured:?} against {settled:?}"
            ),
        }
    }
    Ok(())
}

/// [`yard`], a twin of its crate and `n` small boxes in rows behind it (a level of a few
/// hundred entities, so a row removed near its start renumbers many).
fn yard_and_boxes(n: usize) -> anyhow::Result<LoadedLevel> {
    let mut level = yard()?;
    // The crate's twin, in view: the two (and the far box) draw one shared mesh, whose
    // vertices the first of them, the crate, holds.
    level.scene.spawn(EntityRow {
        name: Some(Name("Twin".into())),
        transform: Some(Transform {
            translation: Vec3::new(-2.8, 0.5, -1.5),
            ..Transform::default()
        }),
        geometry: Some(Geometry::Box { size: Vec3::ONE }),
        ..EntityRow::default()
    });
    for i in 0..n {
        let (x, z) = ((i % 20) as f32 - 10.0, -8.0 - (i / 20) as f32 * 1.5);
        level.scene.spawn(EntityRow {
            name: Some(Name(format!("Box {i}"))),
            transform: Some(Transform {
                translation: Vec3::new(x * 1.2, 0.25, z),
                ..Transform::default()
            }),
            geometry: Some(Geometry::Box {
                size: Vec3::splat(0.5),
            }),
            ..EntityRow::default()
        });
    }
    Ok(level)
}

/// Asserts that `session` (settled) shows what a session made afresh on `level` shows,
/// byte for byte, and names the same entity at every pixel; that picking the pixel
/// showing `row` names it; returns the settled picture.
fn assert_fresh_draws_and_picks(
    ctx: &GpuContext,
    session: &mut Session,
    level: &LoadedLevel,
    row: usize,
) -> anyhow::Result<Vec<u8>> {
    let (after, _) = frames(ctx, session, 20)?;
    assert_full_rebuild_draws(ctx, level, &after)?;
    let ids = session.renderer().read_frame_ids(ctx)?;
    let mut fresh = Session::headless(ctx, level, SIZE, camera().fov_y)?;
    frames(ctx, &mut fresh, 30)?;
    let fresh_ids = fresh.renderer().read_frame_ids(ctx)?;
    assert!(ids.entity == fresh_ids.entity, "the entity at every pixel");
    let id = texel_runtime::frame_plan::entity_id(row);
    let at = (ids.entity.iter().position(|&e| e == id)).context("the row shows")?;
    let pixel = UVec2::new(at as u32 % SIZE.x, at as u32 / SIZE.x);
    let picked = session.renderer().pick(ctx, pixel)?;
    let picked = picked.and_then(texel_runtime::frame_plan::entity_index);
    assert_eq!(picked, Some(row), "picking the pixel {pixel}");
    Ok(after)
}

/// An entity added in the middle of a level of 207 (a box before the camera), another
/// given geometry (the lamp made a lamp post) and a second lamp added: taken in by
/// extracting them alone (the scene uploaded again, every other object where it was, only
/// the faces that may see them captured again), the frames are a fresh session's.
#[test]
fn an_entity_added_draws_as_a_fresh_session() -> anyhow::Result<()> {
    let Some(ctx) = test_context() else {
        return Ok(());
    };
    let mut level = yard_and_boxes(199)?;
    let mut session = Session::headless(&ctx, &level, SIZE, camera().fov_y)?;
    let (before, _) = frames(&ctx, &mut session, 10)?;
    let added = EntityRow {
        name: Some(Name("Added".into())),
        transform: Some(Transform {
            translation: Vec3::new(-0.8, 0.4, 1.6),
            ..Transform::default()
        }),
        geometry: Some(Geometry::Box {
            size: Vec3::new(0.6, 0.8, 0.6),
        }),
        ..EntityRow::default()
    };
    level.scene.spawn_at(PILLAR, added);
    let update = session.edit_rows(&ctx, &level, &[RowEdit::Insert(PILLAR)])?;
    assert!(
        matches!(update, EditUpdate::Uploaded { faces_marked } if faces_marked > 0),
        "{update:?}"
    );
    let after = assert_fresh_draws_and_picks(&ctx, &mut session, &level, PILLAR)?;
    assert!(after != before, "the box shows");
    // The lamp (one row later now) gains a post; a second lamp is added at the end.
    let lamp = LAMP + 1;
    edit(&mut level, lamp, |r| {
        r.geometry = Some(Geometry::Box {
            size: Vec3::new(0.3, 1.5, 0.3),
        })
    });
    let mut second = level
        .scene
        .row(level.scene.entities().nth(lamp).context("lamp")?);
    if let Some(r) = second.as_mut() {
        r.transform.as_mut().expect("transform").translation.x += 1.5;
        r.geometry = None;
    }
    let end = level.scene.len();
    level.scene.spawn_at(end, second.context("lamp row")?);
    let edits = [RowEdit::Set(lamp), RowEdit::Insert(end)];
    let update = session.edit_rows(&ctx, &level, &edits)?;
    assert!(matches!(update, EditUpdate::Uploaded { .. }), "{update:?}");
    assert_fresh_draws_and_picks(&ctx, &mut session, &level, lamp)?;
    Ok(())
}

/// The crate deleted from the middle of a level of 207 (every later entity renumbered), its
/// removal taken in alone and in place (its objects blanked, the later records' ids
/// rewritten): the frames are a fresh session's on the edited level, and a pick names the
/// right row; the delete undone (the row inserted again, taking its blank again in place)
/// likewise; the lamp deleted (a point light removed: uploaded again) likewise.
#[test]
fn an_entity_deleted_and_restored_draws_as_a_fresh_session() -> anyhow::Result<()> {
    let Some(ctx) = test_context() else {
        return Ok(());
    };
    let mut level = yard_and_boxes(199)?;
    let mut session = Session::headless(&ctx, &level, SIZE, camera().fov_y)?;
    let (before, _) = frames(&ctx, &mut session, 10)?;
    let e = level.scene.entities().nth(CRATE).context("crate")?;
    let row = level.scene.despawn(e).context("crate row")?;
    let update = session.edit_rows(&ctx, &level, &[RowEdit::Remove(CRATE)])?;
    assert!(
        matches!(update, EditUpdate::InPlace { faces_marked } if faces_marked > 0),
        "blanked in place: {update:?}"
    );
    // The crate's twin, drawn from the vertices the crate held, one row earlier now.
    let deleted = assert_fresh_draws_and_picks(&ctx, &mut session, &level, TWIN - 1)?;
    assert!(deleted != before, "the crate is gone");
    level.scene.spawn_at(CRATE, row);
    let update = session.edit_rows(&ctx, &level, &[RowEdit::Insert(CRATE)])?;
    assert!(
        matches!(update, EditUpdate::InPlace { .. }),
        "the crate takes its blank again: {update:?}"
    );
    assert_fresh_draws_and_picks(&ctx, &mut session, &level, CRATE)?;
    let e = level.scene.entities().nth(LAMP).context("lamp")?;
    level.scene.despawn(e).context("lamp row")?;
    let update = session.edit_rows(&ctx, &level, &[RowEdit::Remove(LAMP)])?;
    assert!(matches!(update, EditUpdate::Uploaded { .. }), "{update:?}");
    assert_fresh_draws_and_picks(&ctx, &mut session, &level, PILLAR)?;
    Ok(())
}
