//! Calibration of the shimmer metric on synthetic "methods" (CPU only): a full-resolution
//! render whose colour is a checker of the world position must score near 0 under a moving
//! camera, and screen-locked noise must score near 1. If either fails, the metric measures
//! something other than flicker.

use std::sync::Arc;

use glam::{Mat4, UVec2, Vec3};
use texel_eval::meter::{OwnedFrame, PathMeter};
use texel_eval::metrics::{MetricParams, Reference};
use texel_eval::reference::CpuScene;
use texel_render::input::{Camera, MaterialInput, ObjectInput, SceneInput};
use texel_scene::Geometry;
use texel_scene::primitives::primitive_mesh;

fn scene() -> SceneInput {
    let object = |g: Geometry, at: Vec3, id| ObjectInput {
        mesh: Arc::new(primitive_mesh(&g).expect("primitive")),
        transform: Mat4::from_translation(at),
        material: MaterialInput {
            albedo: Vec3::ONE,
            emissive: Vec3::ZERO,
            casts_shadows: true,
            outlined: false,
            ..Default::default()
        },
        id,
    };
    let cube = |s: f32| Geometry::Box {
        size: Vec3::splat(s),
    };
    SceneInput {
        objects: vec![
            object(
                Geometry::Box {
                    size: Vec3::new(24.0, 0.2, 24.0),
                },
                Vec3::new(0.0, -0.1, 0.0),
                1,
            ),
            object(cube(1.5), Vec3::new(-1.5, 0.75, -4.0), 2),
            object(cube(1.0), Vec3::new(1.5, 0.5, -6.0), 3),
            object(cube(2.0), Vec3::new(0.0, 1.0, -10.0), 4),
        ],
        ..Default::default()
    }
}

/// A moving camera: strafing, walking forward and turning at once.
fn camera(i: u32) -> Camera {
    let t = i as f32;
    Camera::from_yaw_pitch(
        Vec3::new(-1.0 + 0.11 * t, 1.6, 3.0 - 0.07 * t),
        -6.0 + 1.3 * t,
        -12.0,
    )
}

const SIZE: UVec2 = UVec2::new(160, 90);
const FRAMES: u32 = 10;

/// Runs `colour(reference, pixel, frame)` as a method along the path.
fn score(colour: impl Fn(&Reference, usize, u32) -> [u8; 3]) -> texel_eval::meter::Scores {
    let cpu = CpuScene::new(&scene());
    let mut meter = PathMeter::new(MetricParams::default());
    for f in 0..FRAMES {
        let cam = camera(f);
        let reference = cpu.gbuffer(&cam, SIZE);
        let pixels: Vec<u8> = (0..reference.id.len())
            .flat_map(|i| {
                let [r, g, b] = colour(&reference, i, f);
                [r, g, b, 255]
            })
            .collect();
        let ids = reference.id.clone();
        meter
            .push(OwnedFrame {
                camera: cam,
                reference,
                colour: pixels,
                ids,
                from_eye: None,
                truth: None,
            })
            .expect("consistent sizes");
    }
    meter.scores()
}

/// A 0.5-unit world-space checker: 4–20 pixels per square nearby, under a pixel only on the
/// far ground at grazing angles (where even a full-resolution render aliases).
fn checker(r: &Reference, i: usize, _frame: u32) -> [u8; 3] {
    if r.id[i] == 0 {
        return [130, 170, 220];
    }
    // Offset so that no surface of the scene lies on a checker boundary (the ground is at
    // y = 0, box faces at multiples of 0.25): there float noise would pick either side.
    let p = Vec3::from(r.world[i]) * 2.0 + 0.37;
    let parity = (p.x.floor() + p.y.floor() + p.z.floor()) as i64 & 1;
    let shade = (r.id[i] * 37 % 120) as u8;
    if parity == 0 {
        [60 + shade, 60, 60]
    } else {
        [200, 200 - shade, 120]
    }
}

fn hash(mut x: u32) -> u32 {
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^ (x >> 16)
}

fn screen_noise(_r: &Reference, i: usize, frame: u32) -> [u8; 3] {
    let h = hash(i as u32 ^ hash(frame.wrapping_add(1)));
    [h as u8, (h >> 8) as u8, (h >> 16) as u8]
}

#[test]
fn a_world_space_texture_rendered_at_full_resolution_scores_near_zero() {
    let s = score(checker);
    assert_eq!(s.shimmer_per_frame.len(), FRAMES as usize - 1);
    // Measured: mean 0.008, max 0.011. What remains is checker corners (two edges inside
    // one 2×2 neighbourhood) and the far ground, where squares shrink under a pixel and a
    // full-resolution render really does alias. Noise scores ~1, a hundred times more.
    assert!(s.shimmer.mean < 0.012, "{:?}", s.shimmer);
    assert!(s.shimmer.max < 0.02, "{:?}", s.shimmer);
    assert_eq!(s.coverage_error, 0.0);
    assert_eq!(s.hole_rate, 0.0);
}

#[test]
fn screen_locked_noise_scores_near_one() {
    let s = score(screen_noise);
    // Random colours match one of four random neighbours within the threshold rarely.
    assert!(s.shimmer.mean > 0.95, "{:?}", s.shimmer);
    assert!(s.shimmer.max <= 1.0);
}

#[test]
fn a_texture_locked_to_the_screen_but_not_the_world_scores_high() {
    // Checker in screen space, 4 px squares: moves against the world when the camera moves.
    let s = score(|_r, i, _| {
        let (x, y) = (i as u32 % SIZE.x / 4, i as u32 / SIZE.x / 4);
        if (x + y) % 2 == 0 {
            [30, 30, 30]
        } else {
            [230, 230, 230]
        }
    });
    assert!(s.shimmer.mean > 0.05, "{:?}", s.shimmer);
}
