//! Unit tests of terrains: heightfields, their meshes and levels of detail, their checks.

use super::*;

#[test]
fn a_rotated_or_scaled_terrain_is_told_what_is_not_applied() {
    let mut t = crate::Transform {
        translation: Vec3::new(5.0, 1.0, -3.0),
        ..Default::default()
    };
    assert_eq!(unapplied_transform(&t), None, "a translation is applied");
    t.rotation = Vec3::new(0.0, 30.0, 0.0);
    let m = unapplied_transform(&t).expect("a rotation is not applied");
    assert!(
        m.starts_with("rotation [0.0, 30.0, 0.0] not applied"),
        "{m}"
    );
    t.scale = Vec3::new(2.0, 1.0, 1.0);
    let m = unapplied_transform(&t).expect("nor a scale");
    assert!(
        m.contains("rotation") && m.contains("scale [2.0, 1.0, 1.0]"),
        "{m}"
    );
    t.rotation = Vec3::ZERO;
    let m = unapplied_transform(&t).unwrap();
    assert!(m.starts_with("scale [2.0, 1.0, 1.0] not applied"), "{m}");
}

fn terrain() -> Terrain {
    Terrain {
        size: Vec2::splat(64.0),
        heightmap: HeightSource::Noise {
            seed: 3,
            resolution: 65,
            frequency: 0.05,
            octaves: 4,
            island: 1.0,
        },
        max_height: 8.0,
        gradient: vec![GradientStop {
            at: 0.0,
            colour: Vec3::ONE,
        }],
        displacement: None,
        paint: None,
        pixel_density: 8.0,
        band_distance: 6.0,
        band_transition: 0.25,
        casts_shadows: true,
        outlined: true,
    }
}

/// Property: the band never decreases with distance, and a terrain pixel is never smaller
/// than the probe texel there, for every face resolution.
#[test]
fn bands_grow_with_distance_and_never_undercut_a_texel() {
    let t = terrain();
    for n in [16u32, 64, 128, 384, 2048] {
        let mut last = 0;
        for i in 0..4000 {
            let d = 0.01 + i as f32 * 0.1;
            let b = t.band(d, n);
            assert!(b >= last, "band fell from {last} to {b} at {d} (N {n})");
            assert!(t.cell_size(b) >= 2.0 * d / n as f32 * 0.9999);
            last = b;
        }
    }
    // Under an orthographic probe: the finest pixel no smaller than its texel, however
    // far (`t`'s nearest pixel is an eighth of a unit).
    for (texel, band) in [(0.1, 0), (0.125, 0), (0.13, 1), (0.25, 1), (0.9, 3)] {
        let b = t.ortho_band(texel);
        assert_eq!(b, band, "texel {texel}");
        assert!(t.cell_size(b) >= texel && (b == 0 || t.cell_size(b - 1) < texel));
    }
    assert_eq!(t.distance_band(6.0), 0);
    assert_eq!(t.distance_band(6.1), 1);
    assert_eq!(t.distance_band(12.0), 1);
    assert_eq!(t.distance_band(12.5), 2);
}

#[test]
fn noise_islands_sink_at_the_border_and_meshes_are_chunked_and_upright() {
    let t = terrain();
    let h = Heightfield::from_noise(&t.heightmap, t.size, t.max_height).unwrap();
    assert_eq!((h.width, h.depth), (65, 65));
    assert!(h.heights.iter().all(|v| (0.0..=8.0).contains(v)));
    assert!(
        h.at(0, 32) < 1e-4 && h.at(32, 0) < 1e-4,
        "the border is at sea level"
    );
    assert!(h.heights.iter().any(|v| *v > 1.0), "there are hills");
    let m = h.lod_mesh(t.size, 0.5);
    // The first piece is the first chunk at full detail: CHUNK_QUADS² quads facing up,
    // within the chunk, then its skirt.
    let first = m.pieces[0];
    assert_eq!((first.lod, first.first_triangle), (0, 0));
    let surface = (CHUNK_QUADS * CHUNK_QUADS * 2) as usize;
    let chunk = 64.0 / 64.0 * CHUNK_QUADS as f32;
    for tri in m.indices[..surface * 3].chunks_exact(3) {
        let [a, b, c] = [0, 1, 2].map(|k| m.positions[tri[k] as usize]);
        assert!((b - a).cross(c - a).y > 0.0, "triangles face up");
        for p in [a, b, c] {
            assert!(p.x <= -32.0 + chunk + 1e-4 && p.z <= -32.0 + chunk + 1e-4);
        }
    }
    let level0: u32 = m
        .pieces
        .iter()
        .filter(|p| p.lod == 0)
        .map(|p| p.triangles)
        .sum();
    let chunks = (64 / CHUNK_QUADS).pow(2) as usize;
    assert_eq!(
        level0 as usize,
        chunks * (surface + 4 * CHUNK_QUADS as usize * 2),
        "surface and skirts"
    );
    let round = Heightfield::from_u16(65, 65, &h.to_u16(8.0), 8.0);
    assert!(
        round
            .heights
            .iter()
            .zip(&h.heights)
            .all(|(a, b)| (a - b).abs() <= 8.0 / 65535.0)
    );
    assert!((h.sample(10.5, 20.0) - 0.5 * (h.at(10, 20) + h.at(11, 20))).abs() < 1e-5);
}

#[test]
fn lod_meshes_hold_every_level_of_every_chunk() {
    let t = terrain();
    let h = Heightfield::from_noise(&t.heightmap, t.size, t.max_height).unwrap();
    let m = h.lod_mesh(t.size, 0.5);
    // 64 quads per edge: (64 / CHUNK_QUADS)² chunks, each with levels 0..=log2(CHUNK_QUADS).
    let chunks = (64 / CHUNK_QUADS).pow(2) as usize;
    let top = CHUNK_QUADS.ilog2();
    assert_eq!(m.pieces.len(), chunks * (top as usize + 1));
    let total: u32 = m.pieces.iter().map(|p| p.triangles).sum();
    assert_eq!(total as usize, m.triangle_count());
    let level0: Vec<_> = m.pieces.iter().filter(|p| p.lod == 0).collect();
    // Level 0 is the full mesh plus skirts: CHUNK_QUADS² × 2 surface triangles per chunk.
    for p in &level0 {
        let q = CHUNK_QUADS;
        assert_eq!(p.triangles, q * q * 2 + 4 * q * 2);
        assert_eq!(p.max_lod, top);
    }
    let coarsest = m.pieces.iter().find(|p| p.lod == top).unwrap();
    assert_eq!(coarsest.triangles, 2 + 4 * 2);
    // Every level of a chunk shares its bounds.
    for p in &m.pieces {
        let l0 = level0.iter().find(|q| q.chunk == p.chunk).unwrap();
        assert_eq!((p.min, p.max), (l0.min, l0.max));
    }
}

#[test]
fn bad_gradients_are_refused() {
    assert!(check_gradient(&[]).unwrap_err().contains("at least one"));
    let s = |at| GradientStop {
        at,
        colour: Vec3::ONE,
    };
    assert!(
        check_gradient(&[s(0.5), s(0.2)])
            .unwrap_err()
            .contains("ascending")
    );
    assert!(check_gradient(&[s(0.0), s(1.0)]).is_ok());
}
