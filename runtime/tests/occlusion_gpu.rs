//! A stable face captured again in part leaves out what lies behind what it already holds
//! (`texel_render::passes::occlusion`), and an edit in place keeps the eye's far faces it
//! cannot reach (`texel_render::far_field`): the frames after an edit are the ones drawn
//! without either, and a full rebuild's, byte for byte.

use std::path::PathBuf;

use glam::Vec3;
use texel_render::context::{GpuContext, test_context};
use texel_render::input::{FrameInput, Schedule};
use texel_runtime::load::LoadedLevel;
use texel_runtime::session::{EditUpdate, FrameRequest, Session, set_face_resolution};
use texel_scene::assets::AssetLibrary;
use texel_scene::{DirectionalLight, EntityRow, Geometry, Material, Name, Scene, Transform};

use crate::edit_gpu::{SIZE, assert_full_rebuild_draws, camera, edit, frames};

/// Entities of [`alley`] by position.
const PANEL: usize = 3;
const BEHIND_PANEL: usize = 4;
const DISTANT: usize = 5;

/// A ground, a sun, a wall across the view with boxes floating behind it (hidden from the
/// probes near the camera), a panel before the wall with a box behind it (hidden by it; far
/// enough behind that what the probes held where the panel was does not bound it), and a
/// box far ahead.
fn alley() -> anyhow::Result<LoadedLevel> {
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
    let cube = |size: Vec3| Geometry::Box { size };
    scene.spawn(thing(
        "Ground",
        Vec3::ZERO,
        Geometry::Plane {
            size: glam::Vec2::splat(300.0),
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
        "Wall",
        Vec3::new(0.0, 2.0, -6.0),
        cube(Vec3::new(12.0, 4.0, 0.4)),
        Vec3::new(0.6, 0.55, 0.5),
    ));
    scene.spawn(thing(
        "Panel",
        Vec3::new(0.5, 2.0, -1.2),
        cube(Vec3::new(1.2, 4.0, 0.4)),
        Vec3::new(0.7, 0.5, 0.3),
    ));
    scene.spawn(thing(
        "Behind panel",
        Vec3::new(0.5, 0.4, -4.2),
        cube(Vec3::splat(0.8)),
        Vec3::new(0.1, 0.2, 0.9),
    ));
    scene.spawn(thing(
        "Distant",
        Vec3::new(0.0, 3.0, -120.0),
        cube(Vec3::splat(6.0)),
        Vec3::new(0.9, 0.9, 0.2),
    ));
    for i in 0..8 {
        let at = Vec3::new(-4.0 + 1.2 * i as f32, 1.6, -11.0 - 0.3 * i as f32);
        scene.spawn(thing(
            &format!("Hidden {i}"),
            at,
            cube(Vec3::splat(1.0)),
            Vec3::new(0.2, 0.7, 0.3),
        ));
    }
    let mut level = LoadedLevel {
        path: PathBuf::from("alley.ron"),
        scene,
        assets: AssetLibrary::default(),
    };
    set_face_resolution(&mut level, 32).map_err(anyhow::Error::msg)?;
    Ok(level)
}

/// What the frames after an edit drew, summed over them.
#[derive(Debug, Default)]
struct After {
    /// The last frame's picture.
    picture: Vec<u8>,
    /// Objects left out behind what stable faces held.
    occluded: u64,
    /// Stable faces captured in part.
    partial: usize,
    /// The eye's far faces captured.
    far_faces: u32,
}

/// A session on [`alley`], settled, with the stable faces' occlusion `on`; then the
/// entity `index` moved by `by` in place and frames drawn till the faces settle.
fn moved(on: bool, index: usize, by: Vec3) -> anyhow::Result<After> {
    let ctx = context()?;
    let mut level = alley()?;
    let mut session = Session::headless(&ctx, &level, SIZE, camera().fov_y)?;
    session.renderer_mut().set_capture_occlusion(on);
    frames(&ctx, &mut session, 10)?;
    edit(&mut level, index, |r| {
        r.transform.as_mut().expect("transform").translation += by;
    });
    let update = session.update_entities(&ctx, &level, &[index])?;
    anyhow::ensure!(
        matches!(update, EditUpdate::InPlace { faces_marked } if faces_marked > 0),
        "{update:?}"
    );
    let request = FrameRequest {
        camera: camera(),
        dt: 1.0 / 30.0,
        schedule: Schedule::Ours,
        size: SIZE,
    };
    let mut after = After::default();
    for _ in 0..12 {
        let (drawn, px) = session.draw_offscreen(&ctx, &request)?;
        let input: &FrameInput = &drawn.input;
        after.partial += input.partial.iter().filter(|p| p.rect.area() > 0).count();
        after.occluded += drawn.stats.counters.objects_occluded;
        after.far_faces += drawn.stats.counters.far_faces_captured;
        after.picture = px;
    }
    Ok(after)
}

fn context() -> anyhow::Result<GpuContext> {
    test_context().ok_or_else(|| anyhow::anyhow!("no GPU"))
}

/// Pixels where two pictures differ.
fn differing(a: &[u8], b: &[u8]) -> usize {
    (a.chunks_exact(4).zip(b.chunks_exact(4)))
        .filter(|(a, b)| a != b)
        .count()
}

/// The panel before the wall moved a little: the stable faces captured again where it shows
/// leave out boxes behind the wall, and draw the picture they draw without doing so, and
/// a full rebuild's.
#[test]
fn a_partial_capture_leaves_out_what_its_face_hides_and_draws_the_same() -> anyhow::Result<()> {
    if test_context().is_none() {
        return Ok(());
    }
    let by = Vec3::new(0.3, 0.0, 0.0);
    let culled = moved(true, PANEL, by)?;
    let drawn = moved(false, PANEL, by)?;
    assert!(culled.partial > 0, "some stable face is captured in part");
    assert!(culled.occluded > 0, "the wall hides what lies behind it");
    assert_eq!(drawn.occluded, 0, "off, nothing is left out");
    let differ = differing(&culled.picture, &drawn.picture);
    assert_eq!(differ, 0, "pixels differing with occlusion off");
    let mut edited = alley()?;
    edit(&mut edited, PANEL, |r| {
        r.transform.as_mut().expect("transform").translation += by;
    });
    assert_full_rebuild_draws(&context()?, &edited, &culled.picture)
}

/// The panel moved aside uncovers the box behind it: where a face showed the panel, what
/// it held bounds nothing (the panel moved), so the box is drawn there: the picture is a
/// full rebuild's, and shows the box where it showed the panel.
#[test]
fn an_object_uncovered_by_the_move_is_drawn() -> anyhow::Result<()> {
    if test_context().is_none() {
        return Ok(());
    }
    let by = Vec3::new(2.0, 0.0, 0.0);
    let culled = moved(true, PANEL, by)?;
    assert!(culled.partial > 0, "some stable face is captured in part");
    let mut edited = alley()?;
    edit(&mut edited, PANEL, |r| {
        r.transform.as_mut().expect("transform").translation += by;
    });
    assert_full_rebuild_draws(&context()?, &edited, &culled.picture)?;
    // The box shows: without it the picture differs.
    let mut without = alley()?;
    edit(&mut without, PANEL, |r| {
        r.transform.as_mut().expect("transform").translation += by;
    });
    edit(&mut without, BEHIND_PANEL, |r| {
        r.transform.as_mut().expect("transform").translation.y = -50.0;
    });
    let ctx = context()?;
    let mut session = Session::headless(&ctx, &without, SIZE, camera().fov_y)?;
    let (no_box, _) = frames(&ctx, &mut session, 30)?;
    assert!(
        differing(&no_box, &culled.picture) > 0,
        "the uncovered box shows"
    );
    Ok(())
}

/// The panel moved: its boxes lie well within the eye's far distance, so no far face is
/// captured again; the box far ahead moved: the far face that drew it is.
#[test]
fn an_edit_captures_again_only_the_far_faces_it_reaches() -> anyhow::Result<()> {
    if test_context().is_none() {
        return Ok(());
    }
    let near = moved(true, PANEL, Vec3::new(0.3, 0.0, 0.0))?;
    assert_eq!(near.far_faces, 0, "no far face captured again");
    let by = Vec3::new(4.0, 0.0, 0.0);
    let far = moved(true, DISTANT, by)?;
    assert!(
        far.far_faces > 0,
        "the far face that drew it is captured again"
    );
    let mut edited = alley()?;
    edit(&mut edited, DISTANT, |r| {
        r.transform.as_mut().expect("transform").translation += by;
    });
    assert_full_rebuild_draws(&context()?, &edited, &far.picture)
}
