//! Textured surfaces through the texel-splat renderer: a golden image of the textured level,
//! probe texels that do not depend on where the camera was when they were captured, and
//! texture sampling sized by the probe texel's footprint (far texels average, not alias).

use glam::{UVec2, Vec3, Vec4};
use texel_render::input::{Camera, MAX_NEAR_FACES};
use texel_tests::{Harness, check_golden};

const DT: f32 = 1.0 / 30.0;

fn cam(x: f32, y: f32, z: f32, yaw: f32, pitch: f32) -> Camera {
    Camera::from_yaw_pitch(Vec3::new(x, y, z), yaw, pitch)
}

#[test]
fn textured_level_golden_images() {
    let size = UVec2::new(256, 144);
    let Some(mut h) = Harness::new("assets/levels/textured.ron", size, 64) else {
        return;
    };
    let (px, _) = h.settle(cam(0.3, 1.6, 6.2, 8.0, -12.0));
    check_golden("textured_start", &px, size, 0.002);
}

/// A grid probe captured again from another camera position (after leaving its cell and
/// coming back) lights every texel exactly as before: texture sampling depends on the probe
/// texel's footprint only, never on the camera.
#[test]
fn textured_probe_texels_do_not_depend_on_the_camera() {
    let size = UVec2::new(160, 90);
    let Some(mut h) = Harness::new("assets/levels/textured.ron", size, 48) else {
        return;
    };
    let home = cam(-0.3, 1.6, 5.2, 0.0, -12.0);
    assert_eq!(h.frame(home, DT).0.grid.origin, Vec3::new(0.0, 2.0, 5.0));
    // Back elsewhere in the same cell, looking the same way, so the view needs the same faces.
    let away = [
        cam(2.2, 1.6, 3.1, 30.0, -5.0),
        cam(-2.1, 1.6, 1.9, -40.0, -5.0),
    ];
    let back = cam(0.35, 1.6, 4.7, 0.0, -12.0);
    let colours = h.assert_recaptured_identically(home, &away, back, &[0, 1, 2, 3, 4, 5]);
    assert!(colours > 200, "textures give many colours, found {colours}");
}

/// A one-pixel black-and-white checker of 1/16-unit squares seen from 1.5 units up: straight
/// below the probe a texel covers less than a texture pixel, toward the horizon several. Sampled at the probe texel's
/// footprint, far texels are the mean grey; sampled at full resolution they would alias into
/// black and white.
#[test]
fn far_texels_average_the_texture_instead_of_aliasing() {
    let size = UVec2::new(128, 72);
    let Some(mut h) = Harness::new("tests/data/checker_floor.ron", size, 64) else {
        return;
    };
    let c = cam(0.0, 1.5, 0.0, 0.0, -20.0);
    let (_, n, faces) = h.grid_lit_faces(c);
    // The −Z face (index 5 in Face order: +X −X +Y −Y +Z −Z) looks toward the horizon; from
    // just below its middle row to 7/8 of the way down it sees floor from 24 to 2 units away,
    // where a texel spans two or more texture pixels.
    let face = &faces[5];
    let (mut extreme, mut floor, mut grey) = (0, 0, 0);
    for y in (n / 2 + 2)..(n * 7 / 8) {
        for x in 0..n {
            let i = ((y * n + x) * 4) as usize;
            let v = face[i];
            floor += 1;
            if !(40..=215).contains(&v) {
                extreme += 1;
            }
            if (150..=215).contains(&v) {
                grey += 1;
            }
        }
    }
    let near = &faces[3];
    let near_extreme = near
        .chunks_exact(4)
        .filter(|c| c[0] < 40 || c[0] > 215)
        .count();
    assert!(
        extreme * 20 < floor,
        "{extreme} of {floor} far floor texels are black or white (aliased)"
    );
    assert!(
        grey * 2 > floor,
        "only {grey} of {floor} far texels are grey"
    );
    assert!(
        near_extreme * 3 > near.len() / 4,
        "straight below, texels still show the checker ({near_extreme} extreme)"
    );
}

/// The texel-density debug view colours texels by texture pixels per probe texel: on the
/// checker floor, green straight below the probe (about one texture pixel per texel) and
/// red toward the horizon (many); turning it off captures the texture again.
#[test]
fn texel_density_view_marks_one_to_one_green_and_minified_red() {
    let size = UVec2::new(128, 72);
    let Some(mut h) = Harness::new("tests/data/checker_floor.ron", size, 64) else {
        return;
    };
    h.session
        .set_texture_density_view(true)
        .expect("density view");
    let c = cam(0.0, 1.5, 0.0, 0.0, -20.0);
    let (_, n, faces) = h.grid_lit_faces(c);
    let texel = |f: usize, x: u32, y: u32| {
        let i = ((y * n + x) * 4) as usize;
        [faces[f][i], faces[f][i + 1], faces[f][i + 2]]
    };
    let below = texel(3, n / 2, n / 2);
    assert!(
        below[1] > below[0] && below[1] > below[2],
        "straight below: {below:?}"
    );
    let far = texel(5, n / 2, n / 2 + 3);
    assert!(
        far[0] > far[1] && far[0] > far[2],
        "toward the horizon: {far:?}"
    );
    h.session
        .set_texture_density_view(false)
        .expect("density view off");
    let (_, _, faces) = h.grid_lit_faces(c);
    let i = ((n / 2 * n + n / 2) * 4) as usize;
    let v = faces[3][i];
    assert!(
        !(40..=215).contains(&v),
        "the checker is back straight below: {v}"
    );
}

/// A grid probe in line with a big wall face, past its top (the cell above and behind the
/// brick wall: its probe 0.25 off the back face's plane, `texel_probes::placement::
/// near_faces`), has its texels on that face laid flat on the plane, so a camera twice as
/// far off the plane, which sees the face more steeply, sees them tile it instead of
/// standing across it like slats with the eye probe filling between them in stripes. The
/// same frame drawn with the quads standing (no near faces handed over) leaves the eye more.
#[test]
fn a_wall_face_seen_past_its_top_is_not_left_to_the_eye() {
    let size = UVec2::new(160, 90);
    let Some(mut h) = Harness::new("assets/levels/textured.ron", size, 64) else {
        return;
    };
    let c = cam(-4.25, 2.71, -5.25, -117.7, -16.3);
    h.settle(c);
    let (mut input, _, _) = h.frame(c, DT);
    assert_eq!(input.grid.origin, Vec3::new(-4.0, 3.0, -5.0));
    assert!(
        (input.grid.near_faces.iter()).any(|f| f.truncate().abs_diff_eq(-Vec3::Z, 1e-4)),
        "{:?}",
        input.grid.near_faces
    );
    let eye = |h: &Harness| {
        let ids = h.renderer().read_frame_ids(&h.ctx).expect("ids read back");
        ids.from_eye.iter().filter(|e| **e).count()
    };
    let flat = eye(&h);
    input.grid.near_faces = [Vec4::ZERO; MAX_NEAR_FACES];
    (h.session.renderer_mut())
        .render_offscreen(&h.ctx, &input)
        .expect("frame renders");
    let standing = eye(&h);
    // Measured: lavapipe 1,233 against 2,145 of 14,400 pixels, SwiftShader 2,535 against
    // 3,382.
    assert!(
        flat * 5 <= standing * 4,
        "the eye probe drew {flat} pixels, {standing} with the quads standing"
    );
}
