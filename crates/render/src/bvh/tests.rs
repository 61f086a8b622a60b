//! CPU tests of the BVH: the traversal against brute force on random, flat, edge-grazing
//! and deep scenes, and the empty, NaN and degenerate inputs.

use super::*;

/// Xorshift64*: deterministic and dependency-free (the field tests draw from it too).
pub(super) struct Rng(pub(super) u64);

impl Rng {
    pub(super) fn next(&mut self) -> f32 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 40) as f32 / (1u64 << 24) as f32
    }
    pub(super) fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.next()
    }
    fn vec(&mut self, lo: f32, hi: f32) -> Vec3 {
        Vec3::new(self.range(lo, hi), self.range(lo, hi), self.range(lo, hi))
    }
    fn pick<T: Copy>(&mut self, items: &[T]) -> T {
        items[((self.next() * items.len() as f32) as usize).min(items.len() - 1)]
    }
}

/// `n` random triangles of size up to `size` in a cube of half-side `extent`.
fn random_scene(rng: &mut Rng, n: usize, extent: f32, size: f32) -> Vec<[Vec3; 3]> {
    let mut tri = || {
        let c = rng.vec(-extent, extent);
        [0; 3].map(|_| c + rng.vec(-size, size))
    };
    (0..n).map(|_| tri()).collect()
}

/// From `origin`: half the rays aim at a random triangle (`t_max` near its distance),
/// the others go anywhere, a fifth of those unbounded.
fn ray(rng: &mut Rng, tris: &[[Vec3; 3]], origin: Vec3) -> (Vec3, Vec3, f32) {
    if rng.next() < 0.5 {
        let [a, b, c] = rng.pick(tris);
        let (u, v) = (rng.next(), rng.next());
        let target = a + (b - a) * u + (c - a) * v * (1.0 - u) + rng.vec(-0.1, 0.1);
        (origin, target - origin, rng.range(0.5, 1.5))
    } else {
        let t_max = if rng.next() < 0.2 {
            1e30
        } else {
            rng.range(0.0, 30.0)
        };
        (origin, rng.vec(-1.0, 1.0), t_max)
    }
}

/// Asserts that the traversal agrees with brute force on every ray; returns the hits.
fn agree(bvh: &GpuBvh, tris: &[[Vec3; 3]], rays: impl Iterator<Item = (Vec3, Vec3, f32)>) -> usize {
    let mut hits = 0;
    for (o, d, t_max) in rays {
        let want = any_hit_brute(tris, o, d, t_max);
        assert_eq!(
            any_hit_cpu(bvh, o, d, t_max),
            want,
            "ray {o} + t {d}, t_max {t_max}"
        );
        let nearest = tris
            .iter()
            .filter(|t| t.iter().all(|v| v.is_finite()))
            .filter_map(|t| BvhTriangle::new(0, t).hit_at(o, d, t_max))
            .min_by(f32::total_cmp);
        let first = first_hit_cpu(bvh, o, d, t_max).map(|(t, _)| t);
        assert_eq!(
            first, nearest,
            "closest hit of ray {o} + t {d}, t_max {t_max}"
        );
        hits += usize::from(want);
    }
    hits
}

/// Structural checks: depth cap, every input triangle once, indices in range.
fn check_tree(bvh: &GpuBvh, input: usize) {
    assert!(bvh.depth() <= STACK_SIZE);
    let mut ids: Vec<u32> = bvh.triangles.iter().map(|t| t.id).collect();
    ids.sort_unstable();
    ids.dedup();
    assert_eq!((ids.len(), bvh.triangles.len()), (input, input));
    for (i, n) in bvh.nodes.iter().enumerate() {
        if n.is_leaf() {
            assert!((n.first + n.count) as usize <= bvh.triangles.len());
        } else {
            assert!(n.first as usize > i && (n.first as usize) + 1 < bvh.nodes.len());
        }
    }
}

#[test]
fn bvh_traversal_matches_brute_force_on_random_scenes() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    for scene in 0..24 {
        let n = [1, 2, 3, 7, 40, 300, 1500][scene % 7];
        let tris = random_scene(&mut rng, n, 10.0, 1.0 + (scene % 3) as f32 * 2.0);
        let bvh = build_bvh(&tris);
        check_tree(&bvh, n);
        let rays: Vec<_> = (0..500)
            .map(|_| {
                let origin = rng.vec(-12.0, 12.0);
                ray(&mut rng, &tris, origin)
            })
            .collect();
        let hits = agree(&bvh, &tris, rays.into_iter());
        assert!(
            hits > 50 && hits < 490,
            "scene {scene}: {hits} hits, test too weak"
        );
    }
}

#[test]
fn bvh_axis_aligned_rays_and_flat_scenes() {
    // Coplanar, axis-aligned triangles: flat boxes and zero direction components.
    let mut tris = Vec::new();
    for (x, z) in (0..100).map(|i| (i / 10, i % 10)) {
        let p = Vec3::new(x as f32, 0.0, z as f32);
        tris.push([p, p + Vec3::X, p + Vec3::Z]);
    }
    let bvh = build_bvh(&tris);
    check_tree(&bvh, tris.len());
    let mut rng = Rng(7);
    let dirs = [Vec3::Y, Vec3::NEG_Y, Vec3::X, Vec3::Z * 0.5];
    let rays = (0..8000).map(|_| {
        let o = Vec3::new(rng.range(0.05, 9.95), rng.range(-3.0, 3.0), 4.37);
        (o, rng.pick(&dirs), 10.0)
    });
    assert!(agree(&bvh, &tris, rays) > 1000);
    let above = Vec3::new(2.3, 1.0, 4.4);
    assert!(any_hit_cpu(&bvh, above, Vec3::NEG_Y, 10.0));
    assert!(
        !any_hit_cpu(&bvh, above, Vec3::NEG_Y, 0.5),
        "t_max stops the ray"
    );
    assert!(!any_hit_cpu(&bvh, above, Vec3::Y, 10.0));
    let on = Vec3::new(2.3, 0.0, 4.4);
    assert!(!any_hit_cpu(&bvh, on, Vec3::Y, 10.0), "t > T_MIN");
}

#[test]
fn bvh_rays_aimed_at_box_edges_agree_with_brute_force() {
    // Rays aimed exactly at edges and corners of axis-aligned faces, which lie on the
    // faces of their boxes: without the box padding, slab rounding drops hundreds.
    let mut rng = Rng(5);
    let mut tris = Vec::new();
    for i in 0..40 {
        let lo = rng.vec(-5.0, 5.0);
        let size = rng.vec(0.1, 2.0);
        let (x, y, z) = (Vec3::X * size.x, Vec3::Y * size.y, Vec3::Z * size.z);
        let p = if i % 2 == 0 { lo } else { lo + z };
        tris.extend([[p, p + x, p + y], [p + x, p + x + y, p + y]]);
        tris.extend([[lo, lo + x, lo + z], [lo, lo + z, lo + y]]);
    }
    let bvh = build_bvh(&tris);
    let rays: Vec<_> = (0..20_000)
        .map(|_| {
            let t = rng.pick(&tris);
            let (a, b) = (rng.pick(&t), rng.pick(&t));
            let o = rng.vec(-8.0, 8.0);
            (o, a + (b - a) * rng.next() - o, rng.pick(&[2.0f32, 1e30]))
        })
        .collect();
    assert!(agree(&bvh, &tris, rays.into_iter()) > 5000);
}

#[test]
fn bvh_empty_input_hits_nothing() {
    let bvh = build_bvh(&[]);
    assert_eq!(bvh, GpuBvh::empty());
    assert_eq!(
        (bvh.nodes.len(), bvh.triangles.len(), bvh.depth()),
        (1, 0, 0)
    );
    assert!(bvh.nodes[0].is_leaf());
    for dir in [Vec3::X, Vec3::NEG_Y, Vec3::new(1.0, 2.0, 3.0)] {
        assert!(!any_hit_cpu(&bvh, Vec3::ZERO, dir, 1e30));
    }
}

#[test]
fn bvh_skips_nan_and_infinite_triangles() {
    let good = [
        Vec3::new(-1.0, -1.0, 0.0),
        Vec3::new(1.0, -1.0, 0.0),
        Vec3::Y,
    ];
    let nan = [Vec3::new(f32::NAN, 0.0, 0.0), Vec3::X, Vec3::Y];
    let inf = [Vec3::ZERO, Vec3::new(0.0, f32::INFINITY, 0.0), Vec3::X];
    let bvh = build_bvh(&[nan, good, inf, nan]);
    assert_eq!(bvh.triangles.len(), 1);
    assert_eq!(bvh.triangles[0].id, 1, "ids index the input slice");
    assert!(any_hit_cpu(&bvh, Vec3::new(0.0, 0.0, -1.0), Vec3::Z, 2.0));
    assert!(!any_hit_cpu(&bvh, Vec3::new(5.0, 0.0, -1.0), Vec3::Z, 2.0));
    assert_eq!(build_bvh(&[nan, inf]), GpuBvh::empty());
}

#[test]
fn bvh_degenerate_triangles_do_not_panic() {
    let p = Vec3::new(1.0, 2.0, 3.0);
    let bvh = build_bvh(&[[p, p, p]; 50]);
    check_tree(&bvh, 50);
    assert!(!any_hit_cpu(&bvh, Vec3::ZERO, p, 10.0));
    let line = build_bvh(&[[Vec3::ZERO, Vec3::X, Vec3::X * 2.0]]);
    assert!(!any_hit_cpu(&line, Vec3::new(1.0, -1.0, 0.0), Vec3::Y, 5.0));
}

#[test]
fn bvh_depth_is_capped() {
    // Nested shells of ever smaller triangles make a deep, unbalanced tree.
    let tris: Vec<[Vec3; 3]> = (0..300)
        .map(|i| [Vec3::X, Vec3::Y, Vec3::Z].map(|v| v * 0.9f32.powi(i)))
        .collect();
    let uncapped = build_with_depth_limit(&tris, usize::MAX).depth();
    assert!(
        uncapped > STACK_SIZE,
        "scene too shallow ({uncapped}) to test the cap"
    );
    assert_eq!(build_bvh(&tris).depth(), STACK_SIZE);
    let mut rng = Rng(3);
    for limit in [0, 1, 2, 5, STACK_SIZE] {
        let bvh = build_with_depth_limit(&tris, limit);
        check_tree(&bvh, tris.len());
        assert!(bvh.depth() <= limit, "depth {} > {limit}", bvh.depth());
        let rays: Vec<_> = (0..300)
            .map(|_| {
                let origin = rng.vec(-0.2, 1.2);
                ray(&mut rng, &tris, origin)
            })
            .collect();
        agree(&bvh, &tris, rays.into_iter());
    }
}

#[test]
fn bvh_build_time_for_ten_thousand_triangles() {
    let tris = random_scene(&mut Rng(11), 10_000, 50.0, 1.0);
    let start = std::time::Instant::now();
    let bvh = build_bvh(&tris);
    let took = start.elapsed();
    let profile = if cfg!(debug_assertions) {
        "debug"
    } else {
        "release"
    };
    let (nodes, depth) = (bvh.nodes.len(), bvh.depth());
    eprintln!("bvh: 10k triangles, {nodes} nodes, depth {depth}, {took:?} ({profile})");
    check_tree(&bvh, tris.len());
}

/// Trees appended after another keep their own triangles: a traversal from the returned
/// root agrees with brute force over that tree's input alone, and the first tree is unchanged.
#[test]
fn appended_trees_are_traversed_from_their_own_roots() {
    let mut rng = Rng(7);
    let a = random_scene(&mut rng, 300, 10.0, 1.0);
    let b = random_scene(&mut rng, 200, 10.0, 1.0);
    let mut both = build_bvh(&a);
    let alone = both.clone();
    let root = both.append(&build_bvh(&b));
    assert_eq!(root as usize, alone.nodes.len());
    let mut hits = [0usize; 2];
    for _ in 0..400 {
        let origin = rng.vec(-12.0, 12.0);
        for (k, tris) in [&a, &b].into_iter().enumerate() {
            let (o, d, t) = ray(&mut rng, tris, origin);
            let r = if k == 0 { 0 } else { root };
            let got = any_hit_cpu_from(&both, r, o, d, t);
            assert_eq!(got, any_hit_brute(tris, o, d, t), "tree {k}");
            hits[k] += got as usize;
        }
    }
    assert!(hits[0] > 50 && hits[1] > 50, "{hits:?}");
}

/// The top-level tree over boxes: every box is in exactly one leaf, each node bounds its
/// subtree, and children indices are absolute.
#[test]
fn a_top_level_tree_bounds_every_box_once() {
    let mut rng = Rng(11);
    let boxes: Vec<(Vec3, Vec3)> = (0..37)
        .map(|_| {
            let c = rng.vec(-20.0, 20.0);
            (c - Vec3::splat(0.5), c + Vec3::splat(0.7))
        })
        .collect();
    let offset = 100;
    let (nodes, order) = build_tlas(&boxes, offset, 1);
    let mut seen = vec![0; boxes.len()];
    let mut todo = vec![0usize];
    while let Some(i) = todo.pop() {
        let n = nodes[i];
        let (min, max) = (Vec3::from(n.min), Vec3::from(n.max));
        if n.is_leaf() {
            assert!(n.count >= 1 && n.count <= 2);
            for slot in n.first..n.first + n.count {
                let k = order[(slot - 1) as usize] as usize;
                seen[k] += 1;
                assert!(min.cmple(boxes[k].0).all() && max.cmpge(boxes[k].1).all());
            }
        } else {
            let c = (n.first - offset) as usize;
            for child in [c, c + 1] {
                let m = nodes[child];
                assert!(min.cmple(Vec3::from(m.min)).all() && max.cmpge(Vec3::from(m.max)).all());
                todo.push(child);
            }
        }
    }
    assert!(seen.iter().all(|&s| s == 1), "{seen:?}");
    assert!(nodes.len() < 2 * boxes.len());
    assert!(build_tlas(&[], 0, 1).0.is_empty());
}

/// Boxes entered by a ray walking the top-level tree `nodes` (root first, children at
/// `first - offset`) as `bvh_top_hit` does, every leaf missed: an unshadowed ray's work.
fn top_boxes_entered(nodes: &[BvhNode], offset: u32, origin: Vec3, dir: Vec3, t_max: f32) -> usize {
    let inv_dir = safe_inv_dir(dir);
    let (mut entered, mut todo) = (0, vec![0usize]);
    while let Some(i) = todo.pop() {
        entered += 1;
        let n = &nodes[i];
        if box_entry(n, origin, inv_dir, t_max).is_some() && !n.is_leaf() {
            let c = (n.first - offset) as usize;
            todo.extend([c, c + 1]);
        }
    }
    entered
}

/// Levels below the root of the top-level tree `nodes`.
fn top_depth(nodes: &[BvhNode], offset: u32) -> usize {
    let mut todo = vec![(0usize, 0usize)];
    let mut deepest = 0;
    while let Some((i, d)) = todo.pop() {
        deepest = deepest.max(d);
        if !nodes[i].is_leaf() {
            let c = (nodes[i].first - offset) as usize;
            todo.extend([(c, d + 1), (c + 1, d + 1)]);
        }
    }
    deepest
}

/// A town's still casters (houses of metres, lamp posts a fifth of a metre wide along a
/// street, crates): shadow rays from the ground toward a sun and toward lamps at 3 m enter
/// fewer of the top level's boxes split by the surface area heuristic than at medians
/// (0.90 of them here; 0.87 of the pairs on the generated town of 10,000's street).
#[test]
fn a_top_level_split_by_area_costs_shadow_rays_fewer_boxes() {
    let mut rng = Rng(5);
    let mut boxes = Vec::new();
    for _ in 0..3000 {
        let c = Vec3::new(rng.range(-100.0, 100.0), 0.0, rng.range(-100.0, 100.0));
        let (h, w) = match rng.next() {
            r if r < 0.4 => (rng.range(2.5, 6.5), rng.range(1.5, 3.5)),
            r if r < 0.6 => (3.0, 0.1),
            _ => (rng.range(0.6, 1.2), rng.range(0.3, 0.6)),
        };
        boxes.push((c - Vec3::new(w, 0.0, w), c + Vec3::new(w, h, w)));
    }
    let offset = 7;
    let (median, _) = build_tlas_split(&boxes, offset, 1, false);
    let (sah, _) = build_tlas(&boxes, offset, 1);
    let (mut by_median, mut by_area) = (0, 0);
    for _ in 0..2000 {
        let p = Vec3::new(rng.range(-100.0, 100.0), 0.01, rng.range(-100.0, 100.0));
        let lamp = p + Vec3::new(rng.range(-5.0, 5.0), 3.2, rng.range(-5.0, 5.0));
        for (dir, t_max) in [
            (Vec3::new(0.3, 0.8, 0.5).normalize(), 1.0e4),
            (lamp - p, 1.0),
        ] {
            by_median += top_boxes_entered(&median, offset, p, dir, t_max);
            by_area += top_boxes_entered(&sah, offset, p, dir, t_max);
        }
    }
    assert!(
        (by_area as f64) < 0.95 * by_median as f64,
        "{by_area} boxes by area against {by_median} at medians"
    );
}

/// However lopsided the boxes (each twice as far out as the last, so every area split
/// peels one off), the top level stays within the traversal's stack.
#[test]
fn a_top_level_stays_within_the_stack() {
    let boxes: Vec<(Vec3, Vec3)> = (0..2000)
        .map(|k| {
            let x = 1.02f32.powi(k);
            (Vec3::new(x, 0.0, 0.0), Vec3::new(x + 0.5, 1.0, 1.0))
        })
        .collect();
    let (nodes, order) = build_tlas(&boxes, 0, 1);
    assert!(
        top_depth(&nodes, 0) < STACK_SIZE,
        "{}",
        top_depth(&nodes, 0)
    );
    assert_eq!(order.len(), boxes.len());
}

/// The box query returns exactly the triangles whose bounds meet the box, as the brute
/// force over the slice does, whatever the tree's shape.
#[test]
fn the_box_query_finds_exactly_the_triangles_whose_bounds_meet_the_box() {
    let tris: Vec<[Vec3; 3]> = (0..400)
        .map(|i| {
            let c = Vec3::new((i % 20) as f32, (i / 20) as f32 * 0.5, (i % 7) as f32);
            [c, c + Vec3::X * 0.3, c + Vec3::Z * 0.3]
        })
        .collect();
    let bvh = build_bvh(&tris);
    let (min, max) = (Vec3::new(3.2, 1.0, 1.5), Vec3::new(8.1, 4.0, 4.2));
    let key = |t: &[Vec3; 3]| t.map(|v| v.to_array().map(f32::to_bits));
    let mut found: Vec<_> = triangles_in_box_cpu(&bvh, min, max)
        .iter()
        .map(key)
        .collect();
    let mut brute: Vec<_> = (tris.iter())
        .filter(|t| {
            let (lo, hi) = (t[0].min(t[1]).min(t[2]), t[0].max(t[1]).max(t[2]));
            lo.cmple(max).all() && hi.cmpge(min).all()
        })
        .map(key)
        .collect();
    found.sort();
    brute.sort();
    assert!(!brute.is_empty());
    assert_eq!(found, brute);
}
