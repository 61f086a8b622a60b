//! Draw ranges culled and merged, terrain levels per view, UV gradients.

use super::ranges::chunk_lod_within;
use super::upload::uv_gradients;
use super::*;
use glam::Vec2;

/// A view from the origin down −Z (far plane at 100) and a range of one triangle at
/// `first` whose box is 2 units wide around `z` on the Z axis.
fn down_z() -> (glam::Mat4, impl Fn(u32, f32) -> DrawRange) {
    let mut camera = crate::input::Camera::looking(Vec3::ZERO, -Vec3::Z);
    camera.far = 100.0;
    let r = |first, z: f32| DrawRange {
        first,
        count: 3,
        min: Vec3::new(-1.0, -1.0, z - 1.0),
        max: Vec3::new(1.0, 1.0, z + 1.0),
        lod: 0,
        max_lod: 0,
        spacing: 0.0,
        terrain: false,
        instance: 0,
    };
    (camera.projection(1.0) * camera.view(), r)
}

#[test]
fn ranges_outside_a_frustum_are_skipped_and_neighbours_merge() {
    let (view_proj, r) = down_z();
    // In front, in front, behind, beyond the far plane, in front.
    let ranges = [r(0, -5.0), r(3, -9.0), r(6, 5.0), r(9, -200.0), r(12, -3.0)];
    assert_eq!(
        visible_runs(&ranges, &view_proj, LodFrom::Full),
        vec![(0, 6, 0), (12, 3, 0)]
    );
}

#[test]
fn a_probe_draws_its_nearest_ranges_first() {
    let (view_proj, r) = down_z();
    // Buffer order far, nearest, next nearest, middle: drawn nearest first, the three
    // in buffer order merged.
    let ranges = [r(0, -30.0), r(3, -3.0), r(6, -3.5), r(9, -9.0)];
    assert_eq!(
        visible_runs(&ranges, &view_proj, LodFrom::Probe(Vec3::ZERO, 64)),
        vec![(3, 9, 0), (0, 3, 0)]
    );
    // Out of buffer order they are not merged.
    let ranges = [r(0, -30.0), r(3, -3.0), r(6, -9.0), r(9, -3.5)];
    assert_eq!(
        visible_runs(&ranges, &view_proj, LodFrom::Probe(Vec3::ZERO, 64)),
        vec![(3, 3, 0), (9, 3, 0), (6, 3, 0), (0, 3, 0)]
    );
}

#[test]
fn a_capture_splits_plain_terrain_runs_from_the_rest() {
    let (view_proj, r) = down_z();
    let terrain = |first, z| DrawRange {
        terrain: true,
        instance: 0,
        ..r(first, z)
    };
    // Buffer order: terrain, terrain, object, terrain; nearest first within each kind,
    // and neighbours of different kinds never merged.
    let ranges = [
        terrain(0, -9.0),
        terrain(3, -3.0),
        r(6, -4.0),
        terrain(9, -5.0),
    ];
    let lod = LodFrom::Probe(Vec3::ZERO, 64);
    let ([plain, rest], count) =
        visible_runs_by_kind(&ranges, &view_proj, lod, CaptureCull::Footprint);
    assert_eq!(count, 4);
    assert_eq!(plain, vec![(3, 3, 0), (9, 3, 0), (0, 3, 0)]);
    assert_eq!(rest, vec![(6, 3, 0)]);
    // Drawn together, the middle three are one run.
    assert_eq!(
        visible_runs(&ranges, &view_proj, lod),
        vec![(3, 9, 0), (0, 3, 0)]
    );
}

#[test]
fn the_eye_draws_terrain_chunks_coarser_than_a_stable_probe() {
    // A chunk 10 units away, samples 0.25 apart, levels 0..=4. On faces of 64 a texel
    // there is 2·10/64 = 0.3125: a stable probe keeps samples within 2 texels (0.625:
    // level 1, 0.5 apart), the eye within EYE_LOD_SAMPLE_TEXELS (level 3 at 8).
    let chunk = |lod| DrawRange {
        first: lod * 3,
        count: 3,
        min: Vec3::new(-1.0, -1.0, -11.0),
        max: Vec3::new(1.0, 1.0, -10.0),
        lod,
        max_lod: 4,
        spacing: 0.25,
        terrain: true,
        instance: 0,
    };
    assert_eq!(chunk_lod(&chunk(0), Vec3::ZERO, 64), 1);
    let eye = chunk_lod_within(&chunk(0), Vec3::ZERO, 64, EYE_LOD_SAMPLE_TEXELS);
    assert_eq!(eye, 3);
    let (view_proj, _) = down_z();
    let ranges: Vec<DrawRange> = (0..=4).map(chunk).collect();
    let drawn = |lod| visible_runs(&ranges, &view_proj, lod);
    assert_eq!(drawn(LodFrom::Probe(Vec3::ZERO, 64)), vec![(3, 3, 0)]);
    assert_eq!(drawn(LodFrom::Eye(Vec3::ZERO, 64)), vec![(eye * 3, 3, 0)]);
    assert_eq!(drawn(LodFrom::Full), vec![(0, 3, 0)]);
}

#[test]
fn uv_gradients_recover_a_linear_map() {
    // u = 2x + z, v = 3y on a tilted triangle.
    let p = [
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(1.0, 0.5, 0.0),
        Vec3::new(0.0, 1.0, 1.0),
    ];
    let uv = p.map(|q| Vec2::new(2.0 * q.x + q.z, 3.0 * q.y));
    let (gu, gv) = uv_gradients(p, uv);
    for q in [p[1] - p[0], p[2] - p[0], (p[1] + p[2]) * 0.5 - p[0]] {
        let want = Vec2::new(2.0 * q.x + q.z, 3.0 * q.y);
        assert!((Vec2::new(gu.dot(q), gv.dot(q)) - want).length() < 1e-5);
    }
    assert_eq!(
        uv_gradients([Vec3::ZERO; 3], [Vec2::ZERO; 3]),
        (Vec3::ZERO, Vec3::ZERO)
    );
}

#[test]
fn a_probe_leaves_out_what_spans_less_than_a_texel_where_it_sees_it() {
    // A box of diagonal 2·√3 ≈ 3.46 straight ahead: one texel at distance d on faces of
    // 64 is d/32 there, so it is drawn up to d ≈ 111 and not beyond.
    let (_, r) = down_z();
    let probe = LodFrom::Probe(Vec3::ZERO, 64);
    assert!(spans_a_texel(&r(0, -100.0), probe));
    assert!(!spans_a_texel(&r(0, -125.0), probe));
    // Toward a face's corner a texel subtends a third: drawn three times as far.
    let corner = |d: f32| DrawRange {
        min: Vec3::splat(-d) - 1.0,
        max: Vec3::splat(-d) + 1.0,
        ..r(0, 0.0)
    };
    let d = |c: f32| (Vec3::splat(c - 1.0)).length();
    assert!(spans_a_texel(&corner(180.0), probe), "{}", d(180.0));
    assert!(!spans_a_texel(&corner(200.0), probe), "{}", d(200.0));
    // The eye likewise; a full-detail raster and terrain chunks draw everything; an
    // orthographic face compares with its texel's world size.
    assert!(!spans_a_texel(&r(0, -125.0), LodFrom::Eye(Vec3::ZERO, 64)));
    assert!(spans_a_texel(&r(0, -125.0), LodFrom::Full));
    let terrain = DrawRange {
        terrain: true,
        instance: 0,
        ..r(0, -1000.0)
    };
    assert!(spans_a_texel(&terrain, probe));
    assert!(spans_a_texel(&r(0, -1000.0), LodFrom::Texel(3.4)));
    assert!(!spans_a_texel(&r(0, -1.0), LodFrom::Texel(3.5)));
    // And the far box is not among a probe face's runs.
    let mut camera = crate::input::Camera::looking(Vec3::ZERO, -Vec3::Z);
    camera.far = 1000.0;
    let far = camera.projection(1.0) * camera.view();
    assert_eq!(
        visible_runs(&[r(0, -5.0), r(3, -125.0)], &far, probe),
        vec![(0, 3, 0)]
    );
    assert_eq!(
        visible_runs(&[r(0, -5.0), r(3, -125.0)], &far, LodFrom::Full),
        vec![(0, 6, 0)]
    );
}
