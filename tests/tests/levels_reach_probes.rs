//! A level's probe-grid settings, loaded by the scene crate and extracted by the runtime,
//! decide the probe origins the probe crate computes.

use glam::Vec3;
use texel_probes::grid::resolve_grid;
use texel_runtime::extract::{Viewport, grid_settings, level_face_resolution};
use texel_runtime::load::load_level;
use texel_tests::repo_root;

const VIEW: Viewport = Viewport {
    height: 720,
    fov_y: std::f32::consts::FRAC_PI_3,
};

#[test]
fn sandbox_override_volume_decides_the_grid_inside_it() {
    let loaded = load_level(&repo_root().join("assets/levels/sandbox.ron")).unwrap();
    let (defaults, overrides) = grid_settings(&loaded.scene, VIEW);
    assert_eq!(overrides.len(), 1);
    assert_eq!(
        defaults.face_resolution, 128,
        "sandbox fixes FaceResolution(128)"
    );

    // Inside the volume (centred at (0, 1.5, -2), 6 × 3 × 6): half-unit cells, 96 texels.
    let inside = resolve_grid(Vec3::new(0.3, 1.6, -2.2), &defaults, &overrides).unwrap();
    assert_eq!(inside.override_index, Some(0));
    assert_eq!(inside.key.face_resolution, 96);
    assert_eq!(inside.origin(), Vec3::new(0.5, 1.5, -2.0));

    // Outside it: the level's one-unit cells.
    let outside = resolve_grid(Vec3::new(0.3, 1.6, 6.2), &defaults, &overrides).unwrap();
    assert_eq!(outside.override_index, None);
    assert_eq!(outside.key.face_resolution, 128);
    assert_eq!(outside.origin(), Vec3::new(0.0, 2.0, 6.0));
}

#[test]
fn pixel_size_levels_get_a_resolution_from_the_screen() {
    let loaded = load_level(&repo_root().join("assets/levels/stone_circle.ron")).unwrap();
    // 2.5 screen pixels per texel on a 720-pixel, 60° view: N = 720 / (2.5 tan 30°) ≈ 499.
    let n = level_face_resolution(&loaded.scene, VIEW);
    assert!((488..=504).contains(&n) && n.is_multiple_of(8), "{n}");
    let smaller = level_face_resolution(
        &loaded.scene,
        Viewport {
            height: 360,
            ..VIEW
        },
    );
    assert!(
        smaller < n,
        "a smaller screen needs fewer texels: {smaller} vs {n}"
    );
}
