//! CPU tests of the heightfield walk: against brute force over the cells' triangles on
//! random fields and rays (many of them skimming the surface, as the probes' rays do), the
//! quadtree's maxima, the world triangles against the terrain mesh's, and bad input.

use super::*;
use crate::bvh::tests::Rng;

/// A bumpy field of `w` × `d` samples: smooth hills plus noise, some cliffs.
fn field(rng: &mut Rng, w: u32, d: u32, size: Vec2) -> HeightField {
    let mut heights = Vec::new();
    for z in 0..d {
        for x in 0..w {
            let (u, v) = (x as f32 * 0.37, z as f32 * 0.23);
            let cliff = if (x / 5 + z / 7).is_multiple_of(4) {
                2.0
            } else {
                0.0
            };
            heights.push(3.0 * (u.sin() * v.cos()) + cliff + rng.range(-0.3, 0.3));
        }
    }
    HeightField::new(Vec3::new(-7.0, 1.5, 3.0), size, UVec2::new(w, d), &heights)
        .expect("a valid field")
}

/// Brute force in grid space: every cell's two triangles, the same test.
fn brute(f: &HeightField, origin: Vec3, dir: Vec3, t_max: f32) -> bool {
    let (o, d) = f.to_grid(origin, dir);
    (0..f.cells.y)
        .any(|z| (0..f.cells.x).any(|x| f.cell_triangles(x, z).iter().any(|t| t.hit(o, d, t_max))))
}

/// A point on the field's surface (world space) at grid coordinates (`gx`, `gz`), on the
/// triangle the mesh puts there.
fn surface(f: &HeightField, gx: f32, gz: f32) -> Vec3 {
    let (x, z) = (
        gx.floor().min(f.cells.x as f32 - 1.0),
        gz.floor().min(f.cells.y as f32 - 1.0),
    );
    let (fx, fz) = (gx - x, gz - z);
    let (x, z) = (x as u32, z as u32);
    let h = |x, z| f.height(x, z);
    // Below the diagonal from (x + 1, z) to (x, z + 1): triangle a c b; above it: b c e.
    let y = if fx + fz <= 1.0 {
        h(x, z) + fx * (h(x + 1, z) - h(x, z)) + fz * (h(x, z + 1) - h(x, z))
    } else {
        h(x + 1, z + 1)
            + (1.0 - fx) * (h(x, z + 1) - h(x + 1, z + 1))
            + (1.0 - fz) * (h(x + 1, z) - h(x + 1, z + 1))
    };
    f.corner + Vec3::new(gx * f.step.x, y, gz * f.step.y)
}

#[test]
fn the_walk_matches_brute_force_on_random_fields_and_skimming_rays() {
    let mut rng = Rng(0x2545_f491_4f6c_dd1d);
    let mut hits = 0;
    let mut total = 0;
    for (w, d) in [(2, 2), (3, 2), (9, 9), (17, 5), (33, 40), (65, 65)] {
        let size = Vec2::new(w as f32 * 0.7, d as f32 * 1.3);
        let f = field(&mut rng, w, d, size);
        for _ in 0..600 {
            // From just above a surface point (a shadow or edge ray's start), or from above
            // the field, or from outside it.
            let (gx, gz) = (
                rng.range(-0.2, w as f32 - 0.8),
                rng.range(-0.2, d as f32 - 0.8),
            );
            let start = match (rng.next() * 3.0) as u32 {
                0 => {
                    surface(
                        &f,
                        gx.clamp(0.0, (w - 1) as f32),
                        gz.clamp(0.0, (d - 1) as f32),
                    ) + Vec3::Y * rng.range(0.01, 0.2)
                }
                1 => f.corner + Vec3::new(gx * f.step.x, rng.range(-1.0, 8.0), gz * f.step.y),
                _ => {
                    f.corner
                        + Vec3::new(
                            rng.range(-20.0, 40.0),
                            rng.range(-2.0, 9.0),
                            rng.range(-20.0, 60.0),
                        )
                }
            };
            // Shallow directions mostly: skimming the hills.
            let dir = Vec3::new(
                rng.range(-1.0, 1.0),
                rng.range(-0.15, 0.4),
                rng.range(-1.0, 1.0),
            );
            let t_max = if rng.next() < 0.3 {
                1e30
            } else {
                rng.range(0.0, 40.0)
            };
            let want = brute(&f, start, dir, t_max);
            for far_first in [false, true] {
                assert_eq!(
                    f.hit_from(start, dir, t_max, far_first),
                    want,
                    "field {w}x{d}: ray {start} + t {dir}, t_max {t_max}, far first {far_first}"
                );
            }
            hits += usize::from(want);
            total += 1;
        }
    }
    // Both answers are well represented.
    assert!(
        hits > total / 5 && hits < total * 4 / 5,
        "{hits} hits of {total}"
    );
}

#[test]
fn each_level_holds_the_highest_height_under_its_nodes() {
    let mut rng = Rng(7);
    let f = field(&mut rng, 21, 12, Vec2::new(10.0, 6.0));
    assert_eq!(f.dims(0), UVec2::new(20, 11));
    assert_eq!(
        *f.levels.last().unwrap(),
        vec![f.heights.iter().copied().fold(f32::MIN, f32::max)]
    );
    for k in 0..f.levels.len() {
        let dims = f.dims(k);
        assert_eq!(f.levels[k].len(), (dims.x * dims.y) as usize);
        for j in 0..dims.y {
            for i in 0..dims.x {
                // The samples under node (i, j): cells [i 2^k, (i + 1) 2^k), their far corners too.
                let xs = (i << k)..=((i + 1) << k).min(f.cells.x);
                let zs = (j << k)..=((j + 1) << k).min(f.cells.y);
                let top = zs
                    .flat_map(|z| xs.clone().map(move |x| (x, z)))
                    .map(|(x, z)| f.height(x, z))
                    .fold(f32::MIN, f32::max);
                assert_eq!(
                    f.levels[k][(j * dims.x + i) as usize],
                    top,
                    "level {k} node ({i}, {j})"
                );
            }
        }
    }
}

#[test]
fn world_triangles_are_the_terrain_meshs_level_zero() {
    let heights: Vec<f32> = (0..5 * 4).map(|i| (i as f32 * 0.7).sin() * 2.0).collect();
    let hf = texel_scene::terrain::Heightfield {
        width: 5,
        depth: 4,
        heights: heights.clone(),
    };
    let size = Vec2::new(8.0, 6.0);
    let mesh = hf.lod_mesh(size, 1.0);
    let at = Vec3::new(2.0, 0.5, -1.0);
    let corner = at - Vec3::new(4.0, 0.0, 3.0);
    let f = HeightField::new(corner, size, UVec2::new(5, 4), &heights).unwrap();
    let piece = mesh.pieces.iter().find(|p| p.lod == 0).unwrap();
    // Level 0's surface triangles come first in its piece (the skirt follows).
    let tris = f.triangles();
    for (t, mine) in tris.iter().enumerate() {
        let first = (piece.first_triangle as usize + t) * 3;
        let theirs: Vec<Vec3> = mesh.indices[first..first + 3]
            .iter()
            .map(|&i| mesh.positions[i as usize] + at)
            .collect();
        for (a, b) in mine.iter().zip(&theirs) {
            assert!(
                a.distance(*b) < 1e-5,
                "triangle {t}: {mine:?} against {theirs:?}"
            );
        }
    }
}

#[test]
fn fields_that_cannot_be_walked_are_refused() {
    let ok = |s: UVec2, h: &[f32]| HeightField::new(Vec3::ZERO, Vec2::ONE, s, h).is_some();
    assert!(ok(UVec2::new(2, 2), &[0.0; 4]));
    assert!(!ok(UVec2::new(1, 2), &[0.0; 2]), "one sample along X");
    assert!(!ok(UVec2::new(2, 2), &[0.0; 3]), "too few heights");
    assert!(
        !ok(UVec2::new(2, 2), &[0.0, f32::NAN, 0.0, 0.0]),
        "NaN height"
    );
    assert!(
        !ok(UVec2::new(2, 2), &[0.0, f32::INFINITY, 0.0, 0.0]),
        "infinite height"
    );
    assert!(!ok(
        UVec2::new(MAX_CELLS + 2, 2),
        &vec![0.0; 2 * (MAX_CELLS as usize + 2)]
    ));
    assert!(
        HeightField::new(Vec3::ZERO, Vec2::new(0.0, 1.0), UVec2::new(2, 2), &[0.0; 4]).is_none()
    );
    assert!(HeightField::new(Vec3::NAN, Vec2::ONE, UVec2::new(2, 2), &[0.0; 4]).is_none());
}

#[test]
fn packing_places_every_field_after_the_last() {
    let mut rng = Rng(11);
    let (a, b) = (
        field(&mut rng, 9, 5, Vec2::new(4.0, 2.0)),
        field(&mut rng, 3, 3, Vec2::ONE),
    );
    let (block, data) = pack(&[(3, &a), (0, &b)]);
    assert_eq!(block.count, 2);
    assert_eq!((block.fields[0].terrain, block.fields[1].terrain), (3, 0));
    assert_eq!(data.len(), a.data_len() + b.data_len());
    let (ra, rb) = (block.fields[0], block.fields[1]);
    assert_eq!(ra.heights_at, 0);
    assert_eq!(
        &data[ra.level_at[0] as usize..][..a.levels[0].len()],
        &a.levels[0][..]
    );
    assert_eq!(rb.heights_at as usize, a.data_len());
    assert_eq!(rb.levels as usize, b.levels.len());
    let last = b.levels.len() - 1;
    assert_eq!(data[rb.level_at[last] as usize], b.levels[last][0]);
    assert_eq!(pack(&[]).1, vec![0.0]);
    let e = data_extent(DATA_WIDTH as usize * DATA_WIDTH as usize + 1);
    assert_eq!(
        (e.width, e.height, e.depth_or_array_layers),
        (DATA_WIDTH, DATA_WIDTH, 2)
    );
    let e = data_extent(5);
    assert_eq!((e.height, e.depth_or_array_layers), (1, 1));
}

#[test]
fn the_first_walkable_terrains_are_walked_the_rest_keep_their_triangles() {
    let terrain = |h: f32| crate::input::TerrainInput {
        corner: Vec3::ZERO,
        size: Vec2::ONE,
        samples: UVec2::new(2, 2),
        heights: std::sync::Arc::new(vec![h; 4]),
        max_height: 1.0,
        gradient: vec![(0.0, Vec3::ONE)],
        displacement: None,
        paint: None,
        pixel_density: 1.0,
        band_distance: 1.0,
        band_transition: 0.0,
    };
    let mut terrains = vec![terrain(f32::NAN)];
    terrains.extend((0..MAX_FIELDS + 1).map(|_| terrain(0.5)));
    let walked = walked_terrains(&terrains);
    assert!(
        !walked[0],
        "a NaN height: its triangles (the BVH drops NaN ones)"
    );
    assert!(walked[1..=MAX_FIELDS].iter().all(|&w| w));
    assert!(!walked[MAX_FIELDS + 1], "past MAX_FIELDS: triangles");
}
