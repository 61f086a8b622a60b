//! Unit tests of the sculpting math: placements, brushes, dabs, regions.

use super::*;

fn flat(n: u32, h: f32) -> (Heightfield, Placement) {
    let field = Heightfield::flat(n, n, h);
    let place = Placement {
        origin: Vec3::ZERO,
        size: Vec2::splat((n - 1) as f32),
        width: n,
        depth: n,
        max_height: 10.0,
    };
    (field, place)
}

#[test]
fn grid_and_world_are_inverse() {
    let (_, mut place) = flat(33, 0.0);
    place.origin = Vec3::new(5.0, 1.0, -3.0);
    place.size = Vec2::new(64.0, 32.0);
    let p = Vec3::new(7.5, 0.0, 2.25);
    let g = place.to_grid(p);
    let back = place.to_world(g, 2.0);
    assert!((back - Vec3::new(7.5, 3.0, 2.25)).length() < 1e-4, "{back}");
    assert_eq!(place.to_grid(Vec3::new(-27.0, 0.0, -19.0)), Vec2::ZERO);
}

#[test]
fn rays_hit_a_flat_field_where_they_cross_its_height() {
    let (field, place) = flat(17, 2.0);
    let hit = ray_hit(
        &place,
        &field,
        Vec3::new(-2.0, 10.0, 1.0),
        Vec3::new(1.0, -1.0, 0.0),
    )
    .expect("hit");
    assert!((hit - Vec3::new(6.0, 2.0, 1.0)).length() < 1e-3, "{hit}");
    // Pointing away, or passing beside it.
    assert!(ray_hit(&place, &field, Vec3::new(0.0, 10.0, 0.0), Vec3::Y).is_none());
    assert!(
        ray_hit(
            &place,
            &field,
            Vec3::new(20.0, 10.0, 0.0),
            Vec3::new(1.0, -1.0, 0.0)
        )
        .is_none()
    );
    assert!(ray_hit(&place, &field, Vec3::ZERO, Vec3::ZERO).is_none());
}

#[test]
fn a_ray_stops_at_the_first_hill_in_its_way() {
    let (mut field, place) = flat(33, 0.0);
    // A wall 5 high across x = -4 (grid column 12).
    for z in 0..33 {
        field.heights[z * 33 + 12] = 5.0;
    }
    let hit = ray_hit(
        &place,
        &field,
        Vec3::new(-16.0, 3.0, 0.0),
        Vec3::new(1.0, -0.05, 0.0),
    )
    .expect("hit");
    assert!(hit.x < -4.0 && hit.x > -5.5, "{hit}");
}

#[test]
fn falloff_is_one_at_the_core_and_zero_at_the_rim() {
    assert_eq!(falloff_weight(0.0, 0.5), 1.0);
    assert_eq!(falloff_weight(0.5, 0.5), 1.0);
    assert!(falloff_weight(0.75, 0.5) > 0.0 && falloff_weight(0.75, 0.5) < 1.0);
    assert_eq!(falloff_weight(1.0, 0.5), 0.0);
    assert_eq!(falloff_weight(f32::NAN, 0.5), 0.0);
    assert_eq!(falloff_weight(0.99, 0.0), 1.0);
}

#[test]
fn brushes_raise_smooth_and_flatten_within_their_radius() {
    let (mut field, place) = flat(33, 1.0);
    let brush = Brush::default();
    let d = Dab {
        centre: Vec3::ZERO,
        dt: 0.1,
        invert: false,
        target: 0.0,
    };
    let r = dab(&mut field, &place, &brush, &d).expect("touched");
    let centre = field.at(16, 16);
    assert!(centre > 1.0);
    assert!(field.at(19, 16) < centre && field.at(19, 16) > 1.0);
    assert_eq!(field.at(0, 0), 1.0);
    assert!(r.x0 >= 12 && r.x1 <= 21, "{r:?}");
    // Ctrl lowers by as much.
    dab(&mut field, &place, &brush, &Dab { invert: true, ..d });
    assert!((field.at(16, 16) - 1.0).abs() < 1e-5);
    // Heights stay in range.
    let set = Brush {
        kind: BrushKind::SetHeight,
        height: 50.0,
        strength: 1.0,
        ..brush
    };
    dab(&mut field, &place, &set, &Dab { dt: 1.0, ..d });
    assert_eq!(field.at(16, 16), 10.0);
    let flatten = Brush {
        kind: BrushKind::Flatten,
        strength: 1.0,
        ..brush
    };
    dab(
        &mut field,
        &place,
        &flatten,
        &Dab {
            dt: 1.0,
            target: 3.0,
            ..d
        },
    );
    assert_eq!(field.at(16, 16), 3.0);
}

#[test]
fn value_noise_is_bounded_and_varies() {
    let v: Vec<f32> = (0..200)
        .map(|i| value_noise(i as f32 * 0.37, i as f32 * 0.11))
        .collect();
    assert!(v.iter().all(|x| (-1.0..=1.0).contains(x)));
    assert!(v.iter().any(|x| *x > 0.2) && v.iter().any(|x| *x < -0.2));
}

#[test]
fn region_bounds_hold_the_samples_and_the_whole_height_range() {
    let (_, mut place) = flat(17, 0.0);
    place.origin = Vec3::new(10.0, 2.0, -4.0);
    let r = Region {
        x0: 4,
        z0: 6,
        x1: 7,
        z1: 8,
    };
    let (lo, hi) = place.region_bounds(r);
    // Samples 3..=7 along X and 5..=8 along Z, each a unit apart from x, z = -8.
    assert_eq!(lo, Vec3::new(10.0 - 8.0 + 3.0, 1.0, -4.0 - 8.0 + 5.0));
    assert_eq!(hi, Vec3::new(10.0 - 8.0 + 8.0, 13.0, -4.0 - 8.0 + 9.0));
    for x in r.x0..r.x1 {
        for z in r.z0..r.z1 {
            let p = place.to_world(Vec2::new(x as f32, z as f32), 0.0);
            assert!(p.cmpge(lo).all() && p.cmple(hi).all(), "{p}");
        }
    }
}

#[test]
fn a_dab_off_the_terrain_or_of_paint_changes_nothing() {
    let (mut field, place) = flat(17, 1.0);
    let before = field.clone();
    let d = Dab {
        centre: Vec3::new(100.0, 0.0, 0.0),
        dt: 0.1,
        invert: false,
        target: 0.0,
    };
    assert_eq!(dab(&mut field, &place, &Brush::default(), &d), None);
    let paint = Brush {
        kind: BrushKind::Paint,
        ..Brush::default()
    };
    let d = Dab {
        centre: Vec3::ZERO,
        ..d
    };
    assert_eq!(dab(&mut field, &place, &paint, &d), None);
    assert_eq!(field, before);
}

#[test]
fn scene_rays_hit_the_nearest_terrain_with_heights() {
    let terrain = |seed| Terrain {
        size: Vec2::splat(16.0),
        heightmap: crate::terrain::HeightSource::Noise {
            seed,
            resolution: 17,
            frequency: 0.1,
            octaves: 1,
            island: 0.0,
        },
        max_height: 4.0,
        gradient: Vec::new(),
        displacement: None,
        paint: None,
        pixel_density: 6.0,
        band_distance: 8.0,
        band_transition: 0.3,
        casts_shadows: true,
        outlined: true,
    };
    let row = |t: &Terrain, x: f32| crate::EntityRow {
        transform: Some(Transform::from_translation(Vec3::new(x, 0.0, 0.0))),
        terrain: Some(t.clone()),
        ..crate::EntityRow::default()
    };
    let (near, far) = (terrain(1), terrain(2));
    let mut scene = Scene::default();
    let mut assets = AssetLibrary::default();
    for (t, x) in [(&far, 40.0), (&near, 0.0)] {
        scene.spawn(row(t, x));
        assets.insert_heightfield(t, Arc::new(Heightfield::flat(17, 17, 1.0)));
    }
    // A terrain whose heights are not loaded is not hit.
    scene.spawn(row(&terrain(3), -40.0));
    let origin = Vec3::new(-12.0, 3.0, 0.0);
    let hit = scene_ray_hit(&scene, &assets, origin, Vec3::X).map(|h| h.terrain);
    assert_eq!(hit, None, "a level ray above both");
    // Down to the near terrain's height at x = -2; from x = 30, at x = 40 over the far one.
    let down = Vec3::new(1.0, -0.2, 0.0);
    let hit = scene_ray_hit(&scene, &assets, origin, down).expect("hit");
    assert_eq!(hit.terrain, near);
    assert!(
        (hit.point - Vec3::new(-2.0, 1.0, 0.0)).length() < 1e-3,
        "{}",
        hit.point
    );
    let beyond = Vec3::new(30.0, 3.0, 0.0);
    let hit = scene_ray_hit(&scene, &assets, beyond, down).expect("hit");
    assert_eq!(hit.terrain, far);
    assert!(
        (hit.point - Vec3::new(40.0, 1.0, 0.0)).length() < 1e-3,
        "{}",
        hit.point
    );
    assert!(scene_ray_hit(&Scene::default(), &assets, origin, down).is_none());
}
