//! Golden images of the colonnade, whose floor lies in the long wall's and the architraves'
//! shadows (issue 17: no dark streaks across it), from the player start and from a low
//! camera looking back down the colonnade.

use glam::{UVec2, Vec3};
use texel_render::input::Camera;
use texel_tests::{Harness, check_golden};

#[test]
fn colonnade_golden_images_from_the_start_and_a_low_camera() {
    let size = UVec2::new(320, 180);
    let Some(mut h) = Harness::new("assets/levels/colonnade.ron", size, 96) else {
        return;
    };
    let cameras = [
        ("colonnade_start", h.session.start_camera()),
        (
            "colonnade_low",
            Camera::from_yaw_pitch(Vec3::new(-1.0, 2.5, -4.0), 200.0, -20.0),
        ),
    ];
    for (name, c) in cameras {
        let mut px = Vec::new();
        // Enough frames for the grid probe to hold every face the view needs.
        for _ in 0..6 {
            px = h.frame(c, 1.0 / 30.0).2;
        }
        check_golden(name, &px, size, 0.002);
    }
}
