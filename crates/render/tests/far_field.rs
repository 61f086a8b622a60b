//! The eye's far field (`texel_render::far_field`) changes what the eye draws each frame, not
//! what it holds: where its far faces were captured at the eye's own origin, the eye's faces
//! and the frame equal, byte for byte, those of an eye drawing everything; and a scene that
//! holds nothing beyond the eye's distance draws the frames it drew without a far field,
//! whether its far faces are fresh or not.

use crate::common;

use glam::{Mat4, UVec2, Vec3};
use texel_probes::probe_set::Slot;
use texel_render::context::{GpuContext, test_context};
use texel_render::far_field::FarFieldInput;
use texel_render::frame::Renderer;
use texel_render::input::{Camera, SceneInput, Schedule};
use texel_scene::primitives::box_mesh;

/// Texels per face edge of every probe here.
const N: u32 = 48;

/// The boxes scene with a field of boxes 8 to 30 m away beyond it, standing a little above
/// the ground (a box's bottom on the ground would tie with it in depth, which the order of
/// drawing breaks, and the far faces draw first).
fn deep_scene() -> SceneInput {
    let mut scene = common::boxes_scene();
    let mut rng = fastrand::Rng::with_seed(5);
    for i in 0..60 {
        let at = Vec3::new(rng.f32() * 36.0 - 18.0, 0.0, -8.0 - rng.f32() * 22.0);
        let size = Vec3::new(
            0.5 + rng.f32() * 2.0,
            0.5 + rng.f32() * 4.0,
            0.5 + rng.f32(),
        );
        let colour = Vec3::new(rng.f32(), rng.f32(), rng.f32());
        let at = Mat4::from_translation(at + Vec3::Y * (size.y / 2.0 + 0.02));
        scene
            .objects
            .push(common::object(box_mesh(size), at, colour, 10 + i));
    }
    scene
}

/// Frames (and the eye's lit faces) along `cameras` (position, look), the grid probe at
/// `grid`, with the far field `far`.
fn walk(
    ctx: &GpuContext,
    scene: &SceneInput,
    cameras: &[(Vec3, Vec3)],
    grid: Vec3,
    far: Option<FarFieldInput>,
) -> Vec<(Vec<u8>, Vec<Vec<u8>>, u32)> {
    let mut r = Renderer::headless(ctx).unwrap();
    r.set_scene(ctx, scene).expect("scene");
    let size = UVec2::new(192, 108);
    cameras
        .iter()
        .map(|&(eye, look)| {
            let mut input =
                common::frame(Camera::looking(eye, look), grid, N, size, Schedule::Ours);
            input.far_field = far;
            let (stats, pixels) = r.render_offscreen(ctx, &input).unwrap();
            let (_, lit) = r.read_lit_faces(ctx, Slot::Eye).unwrap();
            (pixels, lit, stats.counters.far_faces_captured)
        })
        .collect()
}

#[test]
fn an_eye_over_far_faces_captured_where_it_stands_equals_an_eye_drawing_everything() {
    let Some(ctx) = test_context() else { return };
    let scene = deep_scene();
    // Faces of 48 and cells of 0.25: the far faces draw what lies wholly beyond 6 m, the eye
    // what reaches within 6.25 m. Each camera is more than a cell from the last, so every
    // far face is captured again.
    let far = FarFieldInput { cell: 0.25 };
    assert_eq!((far.distance(N), far.overlap()), (6.0, 0.25));
    let cameras = [
        (Vec3::new(0.3, 1.6, 3.0), Vec3::new(0.0, -0.2, -1.0)),
        (Vec3::new(1.2, 2.2, 1.5), Vec3::new(-0.4, -0.3, -1.0)),
        (Vec3::new(-2.0, 1.2, 0.0), Vec3::new(0.6, -0.1, -1.0)),
    ];
    let grid = Vec3::new(0.0, 1.5, 2.0);
    let split = walk(&ctx, &scene, &cameras, grid, Some(far));
    let whole = walk(&ctx, &scene, &cameras, grid, None);
    for (k, ((pa, la, captured), (pb, lb, none))) in split.iter().zip(&whole).enumerate() {
        assert!(*captured > 0, "view {k}: its far faces were captured");
        assert_eq!(*none, 0);
        assert_eq!(
            common::differing_pixels(pa, pb),
            0,
            "view {k}: the frames differ"
        );
        for (f, (a, b)) in la.iter().zip(lb).enumerate() {
            assert_eq!(
                common::differing_pixels(a, b),
                0,
                "view {k}: eye face {f} differs"
            );
        }
        let far_boxes = pa.chunks(4).filter(|p| p[..3] != pa[..3]).count();
        assert!(far_boxes > pa.len() / 8, "view {k} shows something");
    }
}

#[test]
fn a_scene_all_within_the_eyes_distance_draws_what_it_drew_without_a_far_field() {
    let Some(ctx) = test_context() else { return };
    // The boxes scene: a ground of 40 m reaching within 24 m of the eye (faces of 48, cells
    // of 1 m), so the eye draws everything; its far faces stay empty. The far faces are captured on the
    // first frame, then one a frame once the camera is half a cell away (0.15 m steps: from
    // the fifth frame on).
    let scene = common::boxes_scene();
    let far = FarFieldInput { cell: 1.0 };
    let cameras: Vec<(Vec3, Vec3)> = (0..6)
        .map(|i| {
            let at = Vec3::new(0.3 + 0.15 * i as f32, 1.6, 3.0);
            (at, Vec3::new(-0.1, -0.25, -1.0))
        })
        .collect();
    let grid = Vec3::new(0.0, 1.5, 2.0);
    let split = walk(&ctx, &scene, &cameras, grid, Some(far));
    let whole = walk(&ctx, &scene, &cameras, grid, None);
    let refreshed: Vec<bool> = split.iter().map(|s| s.2 > 0).collect();
    assert_eq!(refreshed, [true, false, false, false, true, true]);
    for (k, ((pa, la, _), (pb, lb, _))) in split.iter().zip(&whole).enumerate() {
        assert_eq!(
            common::differing_pixels(pa, pb),
            0,
            "frame {k}: the frames differ"
        );
        for (f, (a, b)) in la.iter().zip(lb).enumerate() {
            assert_eq!(
                common::differing_pixels(a, b),
                0,
                "frame {k}: eye face {f} differs"
            );
        }
    }
}
