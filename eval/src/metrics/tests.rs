use std::sync::Arc;

use glam::{UVec2, Vec3};
use texel_render::input::{Camera, MaterialInput, ObjectInput, SceneInput};
use texel_scene::Geometry;
use texel_scene::primitives::primitive_mesh;

use super::*;
use crate::reference::CpuScene;

/// A wall 20 × 20 units at z = −6 (id 1) with a box in front of it (id 2).
fn scene() -> SceneInput {
    let object = |size: Vec3, at: Vec3, id| ObjectInput {
        mesh: Arc::new(primitive_mesh(&Geometry::Box { size }).expect("box")),
        transform: glam::Mat4::from_translation(at),
        material: MaterialInput {
            albedo: Vec3::ONE,
            emissive: Vec3::ZERO,
            casts_shadows: true,
            outlined: false,
            ..Default::default()
        },
        id,
    };
    SceneInput {
        objects: vec![
            object(Vec3::new(20.0, 20.0, 0.2), Vec3::new(0.0, 0.0, -6.0), 1),
            object(Vec3::splat(1.0), Vec3::new(0.0, 0.0, -3.0), 2),
        ],
        ..Default::default()
    }
}

const SIZE: UVec2 = UVec2::new(48, 32);

fn flat(r: &Reference, rgb: [u8; 3]) -> Vec<u8> {
    r.id.iter()
        .flat_map(|_| [rgb[0], rgb[1], rgb[2], 255])
        .collect()
}

fn view<'a>(cam: Camera, r: &'a Reference, c: &'a [u8]) -> FrameView<'a> {
    FrameView {
        camera: cam,
        reference: r,
        colour: c,
        ids: &r.id,
        from_eye: None,
        truth: None,
    }
}

#[test]
fn oklab_of_white_and_black() {
    let w = oklab_from_srgb8([255, 255, 255]);
    assert!((w[0] - 1.0).abs() < 1e-3 && w[1].abs() < 1e-3 && w[2].abs() < 1e-3);
    assert!(oklab_from_srgb8([0, 0, 0])[0].abs() < 1e-6);
    // One 8-bit step of grey is far under the threshold; a band step is over it.
    let d = |a: u8, b: u8| oklab_distance(oklab_from_srgb8([a; 3]), oklab_from_srgb8([b; 3]));
    assert!(d(128, 129) < MetricParams::default().oklab_threshold);
    assert!(d(128, 140) > MetricParams::default().oklab_threshold);
}

#[test]
fn a_still_image_does_not_flicker_and_a_changed_one_does() {
    let s = CpuScene::new(&scene());
    let cam = Camera::looking(Vec3::ZERO, -Vec3::Z);
    let r = s.gbuffer(&cam, SIZE);
    let grey = flat(&r, [100, 100, 100]);
    let red = flat(&r, [200, 30, 30]);
    let p = MetricParams::default();
    let same = flicker(&view(cam, &r, &grey), &view(cam, &r, &grey), &p).expect("sizes");
    assert!(same.tested > 500, "{same:?}");
    assert_eq!(same.flicker, 0);
    let all = flicker(&view(cam, &r, &grey), &view(cam, &r, &red), &p).expect("sizes");
    assert_eq!(all.flicker, all.tested);
    assert!((all.fraction() - 1.0).abs() < 1e-12);
}

/// A change the truth made too (a sprite's next frame, a part turning) is not shimmer; it
/// still counts in the flicker of every pixel.
#[test]
fn a_change_the_truth_made_too_is_not_shimmer() {
    let s = CpuScene::new(&scene());
    let cam = Camera::looking(Vec3::ZERO, -Vec3::Z);
    let r = s.gbuffer(&cam, SIZE);
    let (grey, red) = (flat(&r, [100, 100, 100]), flat(&r, [200, 30, 30]));
    let p = MetricParams::default();
    // The truth turns red with the method: every tested pixel is intended change.
    let before = FrameView {
        truth: Some(&grey),
        ..view(cam, &r, &grey)
    };
    let after = FrameView {
        truth: Some(&red),
        ..view(cam, &r, &red)
    };
    let c = flicker(&before, &after, &p).expect("sizes");
    assert!(c.tested > 500, "{c:?}");
    assert_eq!((c.tested_held, c.flicker_held), (0, 0));
    assert_eq!(c.fraction(), 0.0);
    assert!((c.all_fraction() - 1.0).abs() < 1e-12);
    let (_, mask) = flicker_map(&before, &after, &p).expect("sizes");
    assert!(mask.contains(&map::INTENDED) && !mask.contains(&map::FLICKER));
    // The truth holds while the method changes: shimmer, as without a truth.
    let held = FrameView {
        truth: Some(&grey),
        ..view(cam, &r, &red)
    };
    let c = flicker(&before, &held, &p).expect("sizes");
    assert_eq!(c.tested_held, c.tested);
    assert!((c.fraction() - 1.0).abs() < 1e-12);
    // A truth of the wrong size is refused.
    let short = FrameView {
        truth: Some(&grey[4..]),
        ..view(cam, &r, &red)
    };
    assert!(flicker(&before, &short, &p).is_err());
}

#[test]
fn points_hidden_in_the_previous_frame_and_id_edges_are_not_tested() {
    let s = CpuScene::new(&scene());
    let a = Camera::looking(Vec3::ZERO, -Vec3::Z);
    // Moving sideways uncovers wall that the box hid at `a`.
    let b = Camera::looking(Vec3::new(1.5, 0.0, 0.0), -Vec3::Z);
    let (ra, rb) = (s.gbuffer(&a, SIZE), s.gbuffer(&b, SIZE));
    let (ca, cb) = (flat(&ra, [90, 90, 90]), flat(&rb, [200, 200, 200]));
    let p = MetricParams::default();
    let f = flicker(&view(a, &ra, &ca), &view(b, &rb, &cb), &p).expect("sizes");
    let geometry = rb.id.iter().filter(|i| **i != 0).count() as u64;
    assert!(f.tested > 0 && f.tested < geometry, "{f:?} of {geometry}");
    // Every tested pixel changed colour, so the count is exactly the tested set.
    assert_eq!(f.flicker, f.tested);
    // The occlusion test: a pixel of b showing wall where a saw the box must be skipped.
    let vp = view_proj(&a, SIZE);
    let mut uncovered = 0;
    for (i, id) in rb.id.iter().enumerate() {
        if *id == 1
            && let Some(q) = project(&vp, SIZE, Vec3::from(rb.world[i]))
            && q.x >= 0.0
            && q.y >= 0.0
            && (q.x as u32) < SIZE.x
            && (q.y as u32) < SIZE.y
            && ra.id[(q.y as u32 * SIZE.x + q.x as u32) as usize] == 2
        {
            uncovered += 1;
        }
    }
    assert!(uncovered > 0, "the path must uncover some wall");
    assert!(f.tested + uncovered <= geometry);
}

#[test]
fn eye_sourced_flicker_is_counted_separately() {
    let s = CpuScene::new(&scene());
    let cam = Camera::looking(Vec3::ZERO, -Vec3::Z);
    let r = s.gbuffer(&cam, SIZE);
    let (a, b) = (flat(&r, [10, 10, 10]), flat(&r, [250, 250, 250]));
    let eye: Vec<bool> = (0..r.id.len()).map(|i| i % 2 == 0).collect();
    let mut cur = view(cam, &r, &b);
    cur.from_eye = Some(&eye);
    let f = flicker(&view(cam, &r, &a), &cur, &MetricParams::default()).expect("sizes");
    assert!(f.flicker > 0);
    let share = f.flicker_eye as f64 / f.flicker as f64;
    assert!((share - 0.5).abs() < 0.1, "{share}");
    // The map marks exactly the pixels counted, eye ones apart, and nothing untested.
    let (g, m) = flicker_map(&view(cam, &r, &a), &cur, &MetricParams::default()).expect("sizes");
    assert_eq!(g, f);
    let n = |k: u8| m.iter().filter(|&&v| v == k).count() as u64;
    assert_eq!(n(map::FLICKER) + n(map::FLICKER_EYE), f.flicker);
    assert_eq!(n(map::FLICKER_EYE), f.flicker_eye);
    assert_eq!(n(map::STABLE), 0, "every tested pixel changed");
    let still = flicker_map(
        &view(cam, &r, &a),
        &view(cam, &r, &a),
        &MetricParams::default(),
    );
    let (_, still) = still.expect("sizes");
    assert_eq!(
        still.iter().filter(|&&v| v == map::STABLE).count() as u64,
        f.tested
    );
}

#[test]
fn coverage_counts_wrong_ids_and_holes() {
    let reference = Reference {
        size: UVec2::new(4, 1),
        world: vec![[0.0; 3]; 4],
        id: vec![0, 1, 1, 2],
        poses: Vec::new(),
        sprites: Vec::new(),
    };
    let colour = vec![0; 16];
    let ids = [0, 1, 0, 1];
    let f = FrameView {
        camera: Camera::looking(Vec3::ZERO, -Vec3::Z),
        reference: &reference,
        colour: &colour,
        ids: &ids,
        from_eye: Some(&[false, true, true, true]),
        truth: None,
    };
    let c = coverage(&f).expect("sizes");
    assert_eq!(c.error, 0.5);
    assert_eq!(c.holes, 0.25);
    assert_eq!(c.eye, 0.75);
    let short = FrameView {
        ids: &ids[..3],
        ..f
    };
    assert!(coverage(&short).is_err());
}

#[test]
fn summaries_use_nearest_rank() {
    let v: Vec<f64> = (1..=100).map(f64::from).collect();
    let s = Summary::of(&v);
    assert_eq!((s.mean, s.p95, s.max), (50.5, 95.0, 100.0));
    assert_eq!(Summary::of(&[]), Summary::default());
    assert_eq!(percentile(&[3.0], 0.5), 3.0);
}

/// A moving object's pixels are followed with it: a pattern fixed to a box that moved does
/// not flicker once the references carry the box's poses, and does when they do not (the
/// box then looks like a still surface whose colours slid); its pixels are counted apart.
#[test]
fn moving_pixels_are_followed_with_their_object() {
    let cam = Camera::looking(Vec3::ZERO, -Vec3::Z);
    let at = |x: f32| glam::Mat4::from_translation(Vec3::new(x, 0.0, -3.0));
    let frame = |x: f32| {
        let mut scene = scene();
        scene.objects[1].transform = at(x);
        let r = CpuScene::new(&scene).gbuffer(&cam, SIZE);
        // Stripes a quarter unit wide on the box, fixed to it; the wall grey.
        let colour: Vec<u8> = (r.id.iter().zip(&r.world))
            .flat_map(|(&id, w)| {
                let v = if id == 2 && ((w[0] - x) * 4.0).floor() as i32 % 2 == 0 {
                    220
                } else if id == 2 {
                    40
                } else {
                    120
                };
                [v, v, v, 255]
            })
            .collect();
        (r, colour)
    };
    let p = MetricParams::default();
    let ((mut a, ca), (mut b, cb)) = (frame(0.0), frame(0.13));
    let still = flicker(&view(cam, &a, &ca), &view(cam, &b, &cb), &p).expect("sizes");
    assert!(still.flicker > 20, "a sliding pattern flickers: {still:?}");
    assert_eq!(still.tested_moving, 0);
    a.poses = vec![(2, at(0.0))];
    b.poses = vec![(2, at(0.13))];
    let moved = flicker(&view(cam, &a, &ca), &view(cam, &b, &cb), &p).expect("sizes");
    assert!(moved.tested_moving > 30, "{moved:?}");
    assert_eq!(moved.flicker_moving, 0, "{moved:?}");
    assert_eq!(moved.moving_fraction(), Some(0.0));
    assert_eq!(moved.still_fraction(), Some(0.0));
}
