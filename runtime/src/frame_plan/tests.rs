//! The frame plan's tests: prefetching and crossings on the bundled levels, the clock, the
//! paper schedule's faces, orthographic probes.

use glam::{UVec2, Vec3};
use texel_probes::cube::{Face, FaceMask};
use texel_probes::probe_set::{Role, Slot};
use texel_render::input::{Camera, ProbeView, Schedule};

use super::*;
use crate::load::LoadedLevel;

/// A frame driver at 320 × 180 on the bundled level `name`.
fn driver_on(name: &str) -> FrameDriver {
    FrameDriver::new(&bundled_level(name), UVec2::new(320, 180), 1.2).expect("driver")
}

/// The bundled level `name` (`assets/levels/NAME.ron`), loaded.
fn bundled_level(name: &str) -> LoadedLevel {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    crate::load::load_level(&root.join(format!("assets/levels/{name}.ron"))).expect("level loads")
}

/// The one-unit cell (stone_circle's grid) holding `p`: cells are centred on whole
/// coordinates.
fn cell_of(p: Vec3) -> glam::IVec3 {
    p.round().as_ivec3()
}

/// Frames of a walk through `path` (camera position per frame, looking down -z) on
/// stone_circle: faces prefetched before the first crossing, and that crossing's frame
/// (the first whose camera is in another cell) with the stable faces it still captured.
fn first_crossing_of(path: impl Fn(f32) -> Vec3) -> (usize, (usize, usize)) {
    let mut driver = driver_on("stone_circle");
    let dt = 1.0 / 30.0;
    let mut prefetched = 0;
    for i in 0..60 {
        let camera = Camera::from_yaw_pitch(path(i as f32 * dt), 0.0, -5.0);
        let input = driver.frame(camera, dt, Schedule::Ours).expect("frame");
        if let Some(p) = input.prefetch {
            assert_eq!(p.draw, FaceMask::EMPTY, "a prefetched probe is not drawn");
            assert_ne!(p.slot, input.grid.slot);
            prefetched += input.captures.iter().filter(|c| c.slot == p.slot).count();
        }
        if cell_of(camera.position) != cell_of(path(0.0)) {
            let stable = input.captures.iter().filter(|c| c.slot != Slot::Eye);
            return (prefetched, (i, stable.count()));
        }
    }
    panic!("the walk crosses no cell");
}

/// Walking slowly toward a cell boundary, quiet frames capture the next cell's grid
/// probe ahead of time, so the crossing frame captures no stable face.
#[test]
fn a_slow_walk_prefetches_the_next_cell_before_crossing_it() {
    // 1 unit/s toward -z; the cell boundary at z = 12.5 comes after 15 frames.
    let (prefetched, (frame, stable)) = first_crossing_of(|t| Vec3::new(0.0, 1.6, 13.0 - t));
    assert!(prefetched >= 2, "prefetched {prefetched} faces");
    assert_eq!(
        stable, 0,
        "the crossing at frame {frame} captured {stable} faces"
    );
}

/// A diagonal walk that crosses its cell's z boundary 0.1 s before its x boundary:
/// the point the look-ahead reaches lies in the diagonal cell, but the camera enters
/// the cell beside its own first. The prefetch goes to the cell it enters.
#[test]
fn a_diagonal_walk_prefetches_the_cell_it_enters_not_the_one_ahead() {
    // z reaches 12.5 at t = 0.4 s (x = 0.46), x reaches 0.5 at t = 0.5 s.
    let path = |t: f32| Vec3::new(0.30 + 0.4 * t, 1.6, 12.9 - t);
    let (prefetched, (frame, stable)) = first_crossing_of(path);
    assert!(prefetched >= 2, "prefetched {prefetched} faces");
    assert_eq!(
        stable, 0,
        "the crossing at frame {frame} captured {stable} faces"
    );
}

/// What a fast walk's frames draw through a crossing: the trigger frame leaves every
/// pixel to the previous probe (fade 0), and the very next frame, its grid probe
/// prefetched, already hands pixels over; the frame the fade reaches 1 draws the grid
/// probe alone. (The fade used to move only after a frame was drawn, so each crossing held
/// at 0 for two frames, both drawing both probes' quads, and ended a frame late.)
#[test]
fn a_crossing_hands_pixels_over_from_the_frame_after_its_trigger() {
    let mut driver = driver_on("stone_circle");
    let dt = 1.0 / 30.0;
    let mut drawn = Vec::new();
    let mut trigger = None;
    for i in 0..30 {
        // 6 units/s toward -z: a cell every five frames.
        let camera = Camera::from_yaw_pitch(Vec3::new(0.0, 1.6, 13.4 - 0.2 * i as f32), 0.0, -5.0);
        let input = driver.frame(camera, dt, Schedule::Ours).expect("frame");
        drawn.push((input.previous.is_some(), input.fade_t));
        if trigger.is_none() && camera.position.z < 12.5 {
            trigger = Some(i);
        }
    }
    let trigger = trigger.expect("the walk crosses a cell");
    assert_eq!(drawn[trigger].1, 0.0, "the trigger frame: {drawn:?}");
    let (previous, t) = drawn[trigger + 1];
    assert!(
        previous && t > 0.0 && t <= 0.5,
        "the frame after it: {drawn:?}"
    );
    let end = (trigger..drawn.len())
        .find(|&i| !drawn[i].0)
        .expect("the fade ends");
    assert_eq!(drawn[end].1, 1.0, "{drawn:?}");
    assert!(end - trigger <= 3, "frames with both probes: {drawn:?}");
}

/// Walking slowly toward a cell boundary, once the next cell's probe has every face the
/// view needs captured, frames before the crossing draw it behind the grid probe: the
/// grid probe as the previous one owning every pixel (fade 0), the next as the grid
/// probe in its own slot, just as the crossing's first frame draws them; a camera at
/// rest draws its grid probe alone.
#[test]
fn a_walk_draws_the_next_cells_probe_behind_the_grid_probe_before_the_crossing() {
    let mut driver = driver_on("stone_circle");
    let dt = 1.0 / 30.0;
    let still = Camera::from_yaw_pitch(Vec3::new(0.0, 1.6, 13.0), 0.0, -5.0);
    for i in 0..10 {
        let input = driver.frame(still, dt, Schedule::Ours).expect("frame");
        assert!(input.previous.is_none(), "frame {i} at rest");
    }
    let home = driver.frame(still, dt, Schedule::Ours).expect("frame").grid;
    let mut fillers = Vec::new();
    for i in 1..30 {
        // 1 unit/s toward -z: the boundary at z = 12.5 after 15 frames.
        let z = 13.0 - i as f32 * dt;
        let camera = Camera::from_yaw_pitch(Vec3::new(0.0, 1.6, z), 0.0, -5.0);
        let input = driver.frame(camera, dt, Schedule::Ours).expect("frame");
        let drawn = |v: &ProbeView| (v.role, v.origin, v.slot);
        if z >= 12.5 {
            assert_eq!(input.grid.origin.z < 13.0, input.previous.is_some());
            assert_eq!(input.filling_ahead, input.previous.is_some(), "frame {i}");
            assert_eq!(input.cell_probe().origin, home.origin, "frame {i}");
            if let Some(p) = &input.previous {
                assert_eq!(drawn(p), (Role::Previous, home.origin, home.slot));
                assert_eq!(
                    input.fade_t, 0.0,
                    "frame {i}: the grid probe owns every pixel"
                );
                assert_ne!(input.grid.slot, home.slot, "frame {i}");
                assert_eq!(input.grid.origin, home.origin - Vec3::Z, "frame {i}");
                fillers.push((drawn(&input.grid), drawn(p)));
            }
            continue;
        }
        // The crossing's first frame draws what the last frame before it drew.
        let previous = input.previous.expect("the crossing starts a fade");
        let last = *fillers.last().expect("frames with the next probe behind");
        assert_eq!((drawn(&input.grid), drawn(&previous)), last);
        assert_eq!(input.fade_t, 0.0);
        assert!(!input.filling_ahead, "a crossing is not ahead of itself");
        assert_eq!(input.cell_probe().origin, input.grid.origin);
        assert!(fillers.len() >= 2, "{fillers:?}");
        return;
    }
    panic!("the walk crosses no cell");
}

/// A camera that steps over a cell boundary and straight back: the fade turns toward the
/// previous probe and ends there at once. That frame draws fade 0 with both probes (the
/// previous one owns every pixel), and from the next the same probe, in the same slot,
/// is the grid probe alone: no pixel changes owner.
#[test]
fn a_fade_that_ends_back_in_the_cell_it_left_keeps_the_previous_probe_drawing() {
    let mut driver = driver_on("stone_circle");
    let dt = 1.0 / 30.0;
    // The cell boundary at z = 12.5: two frames past it, then back.
    let zs = [13.0, 13.0, 13.0, 12.9, 12.8, 12.4, 12.8, 12.9, 13.0];
    let drawn: Vec<_> = (zs.iter())
        .map(|&z| {
            let camera = Camera::from_yaw_pitch(Vec3::new(0.0, 1.6, z), 0.0, -5.0);
            driver.frame(camera, dt, Schedule::Ours).expect("frame")
        })
        .collect();
    let home = drawn[0].grid;
    let crossing = &drawn[5];
    let previous = crossing
        .previous
        .expect("the step over the boundary starts a fade");
    assert_eq!((previous.origin, previous.slot), (home.origin, home.slot));
    assert_eq!(crossing.fade_t, 0.0);
    let back = &drawn[6];
    assert_eq!(back.fade_t, 0.0, "the frame the fade ends back home");
    let previous = back.previous.expect("the previous probe draws that frame");
    assert_eq!((previous.origin, previous.slot), (home.origin, home.slot));
    for (i, input) in drawn.iter().enumerate().skip(7) {
        assert!(input.previous.is_none(), "frame {i}: no fade runs");
        assert_eq!(input.fade_t, 1.0);
        let grid = (input.grid.origin, input.grid.slot);
        assert_eq!(grid, (home.origin, home.slot), "frame {i}");
    }
}

/// The animation clock: each frame poses the moving objects at the time the frames'
/// `dt` add up to (the same poses `Animation` gives), a paused clock stands still, and
/// the faces whose view a moved object's shadow may change are lit again, as rectangles.
#[test]
fn frames_pose_moving_objects_by_the_sum_of_their_dt() {
    let mut driver = driver_on("moving_parts");
    let animation = driver.level.animation.clone();
    assert_eq!(
        animation.poses(0.0).len(),
        5,
        "windmill blades, hub, door, platform"
    );
    let camera = Camera::from_yaw_pitch(Vec3::new(-1.2, 2.0, 5.2), 8.0, -6.0);
    let dt = 1.0 / 30.0;
    let mut t = 0.0;
    let mut relit = 0;
    for _ in 0..12 {
        let input = driver.frame(camera, dt, Schedule::Ours).expect("frame");
        assert_eq!(input.poses, animation.poses(t));
        relit += input.relight.len();
        for r in &input.relight {
            assert!(r.rect.area() > 0 && r.rect.x1 <= 64 * 64, "{r:?}");
        }
        t = Animation::next_time(t, dt);
    }
    assert!((driver.time() - 12.0 * f64::from(dt)).abs() < 1e-9);
    assert!(relit > 0, "moving shadows relight some faces");
    driver.set_paused(true);
    let a = driver.frame(camera, dt, Schedule::Ours).expect("frame");
    let b = driver.frame(camera, dt, Schedule::Ours).expect("frame");
    assert_eq!(a.poses, b.poses);
    assert!(
        b.relight.is_empty(),
        "nothing moved: nothing to light again"
    );
    driver.set_time(2.0);
    let c = driver.frame(camera, dt, Schedule::Ours).expect("frame");
    assert_eq!(c.poses, animation.poses(2.0));
    driver.set_time(f64::NAN);
    assert_eq!(driver.time(), 2.0);
}

/// The paper schedule does the reference's work: with the camera level, the eye and
/// the grid probe each capture and draw five faces (all but the one behind), every
/// frame, where ours captures only what its frustum test needs, once.
#[test]
fn the_paper_schedule_captures_the_reference_faces_every_frame() {
    let level = bundled_level("stone_circle");
    let camera = Camera::from_yaw_pitch(Vec3::new(0.2, 1.6, 13.0), 0.0, 0.0);
    let behind = Face::ALL
        .into_iter()
        .min_by(|a, b| {
            camera
                .forward
                .dot(a.axis())
                .total_cmp(&camera.forward.dot(b.axis()))
        })
        .expect("six faces");
    let five: FaceMask = Face::ALL.into_iter().filter(|f| *f != behind).collect();
    let size = UVec2::new(320, 180);
    let mut paper = FrameDriver::new(&level, size, 1.0).expect("driver");
    let mut ours = FrameDriver::new(&level, size, 1.0).expect("driver");
    for frame in 0..3 {
        let input = paper
            .frame(camera, 1.0 / 60.0, Schedule::Paper)
            .expect("frame");
        assert_eq!(input.eye.draw, five, "frame {frame}");
        assert_eq!(input.grid.draw, five, "frame {frame}");
        let of = |slot| {
            let faces = input.captures.iter().filter(|c| c.slot == slot);
            faces.map(|c| c.face).collect::<FaceMask>()
        };
        assert_eq!(of(input.eye.slot), five, "frame {frame}");
        assert_eq!(of(input.grid.slot), five, "frame {frame}");
        let input = ours
            .frame(camera, 1.0 / 60.0, Schedule::Ours)
            .expect("frame");
        assert!(input.eye.draw.count() < 5 && input.grid.draw.count() < 5);
        let stable = input
            .captures
            .iter()
            .filter(|c| c.slot != Slot::Eye)
            .count();
        assert_eq!(stable == 0, frame > 1, "ours captures the grid probe once");
    }
}

/// An orthographic camera's probes are orthographic faces whose origins stand on a
/// lattice of whole texels: panning moves the grid probe by whole texels (so it samples
/// the same world lines), the grid's face holds the whole view, the eye's stands in the
/// camera's plane, and a turn within half a step keeps the grid's direction.
#[test]
fn orthographic_probes_stand_on_a_texel_lattice_and_hold_the_view() {
    let level = bundled_level("stone_circle");
    let size = UVec2::new(320, 180);
    let mut driver = FrameDriver::new(&level, size, 1.2).expect("driver");
    let camera = |x: f32, yaw: f32| Camera {
        ortho_height: Some(12.0),
        ..Camera::from_yaw_pitch(Vec3::new(x, 9.0, 14.0), yaw, -35.0)
    };
    let mut grids = Vec::new();
    for k in 0..40 {
        let c = camera(-2.0 + 0.77 * k as f32, 1.0);
        let input = driver.frame(c, 1.0 / 30.0, Schedule::Ours).expect("frame");
        let (grid, eye) = (input.grid, input.eye);
        let (gf, ef) = (
            grid.ortho.expect("ortho grid"),
            eye.ortho.expect("ortho eye"),
        );
        assert_eq!(grid.draw.bits(), 1, "one face");
        // The eye looks exactly along the view, from the camera's plane.
        assert!((ef.forward - c.forward).length() < 1e-5);
        assert!((eye.origin - c.position).dot(c.forward).abs() < 1e-3);
        // The grid's direction is the view's rounded to 5°: here yaw 0.
        assert!((gf.forward - camera(0.0, 0.0).forward).length() < 1e-5);
        // The whole view (its corners, with the pixel snap's margin) lies on the face.
        let h = 12.0;
        let w = h * size.x as f32 / size.y as f32;
        let up = ef.down * -1.0;
        for (sx, sy) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
            let corner = c.position + ef.right * (sx * 0.5 * w) + up * (sy * 0.5 * h);
            let (u, v, _) = gf.locate(grid.origin, corner);
            assert!(u.abs() < 1.0 && v.abs() < 1.0, "view corner at ({u}, {v})");
        }
        grids.push((grid.origin, gf, grid.face_resolution));
    }
    let (o0, f0, n) = grids[0];
    let texel = f0.texel(n);
    let moved = grids.iter().filter(|g| g.0 != o0).count();
    assert!(moved > 0, "a 30-unit pan moves the grid probe");
    for (o, f, _) in &grids {
        assert_eq!(*f, f0);
        let d = (*o - o0) / texel;
        for a in [d.dot(f0.right), d.dot(f0.down)] {
            assert!((a - a.round()).abs() < 2e-3, "{a} texels apart");
        }
    }
}
