//! Where a moved shadow caster's shadow may have come or gone: its old and new bounds pushed
//! along each sun to the scene's lowest point and away from each point light out to its
//! reach. The frame driver relights the stable faces that see such a region
//! (`FrameInput::relight`); the terrain splats pass marks the region in a table of shadow
//! epochs ([`ShadowTiles`]) so that only the terrain pixels and records there are made again.

use glam::{Vec2, Vec3};

use crate::input::{PointLightInput, SceneInput, SunInput};

/// How far a sun's shadow is followed down from a caster's corner, along the ray.
const SUN_REACH: f32 = 200.0;

/// World bounds of the object-space box `min..max` under `m`.
pub fn bounds_under(m: glam::Mat4, min: Vec3, max: Vec3) -> (Vec3, Vec3) {
    corners(min, max).fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), c| {
            let p = m.transform_point3(c);
            (lo.min(p), hi.max(p))
        },
    )
}

/// The eight corners of the box `min..max`.
fn corners(min: Vec3, max: Vec3) -> impl Iterator<Item = Vec3> {
    (0..8).map(move |i| {
        Vec3::new(
            if i & 1 == 0 { min.x } else { max.x },
            if i & 2 == 0 { min.y } else { max.y },
            if i & 4 == 0 { min.z } else { max.z },
        )
    })
}

/// The lowest point of `scene`'s objects (infinity for none). A mesh shared by many objects
/// (copies of one glTF file) has its bounds found once.
pub fn scene_floor(scene: &SceneInput) -> f32 {
    let mut bounds: std::collections::HashMap<
        *const texel_geom::mesh::TriMesh,
        Option<(Vec3, Vec3)>,
    > = std::collections::HashMap::new();
    scene
        .objects
        .iter()
        .filter_map(|o| {
            let local = *bounds
                .entry(std::sync::Arc::as_ptr(&o.mesh))
                .or_insert_with(|| o.mesh.bounds());
            local.map(|(lo, hi)| bounds_under(o.transform, lo, hi).0.y)
        })
        .fold(f32::INFINITY, f32::min)
}

/// The box `min..max` grown by where its contents may cast sun shadows: each corner pushed
/// along every sun's direction until it has dropped to `floor` (at most 200 units along the
/// ray).
pub fn sun_shadow_bounds(suns: &[SunInput], floor: f32, min: Vec3, max: Vec3) -> (Vec3, Vec3) {
    let floor = floor.min(min.y);
    let (mut lo, mut hi) = (min, max);
    for sun in suns {
        let d = sun.direction.normalize_or_zero();
        if d.y >= -1e-3 {
            continue;
        }
        for c in corners(min, max) {
            let t = ((c.y - floor) / -d.y).min(SUN_REACH);
            let p = c + d * t;
            lo = lo.min(p);
            hi = hi.max(p);
        }
    }
    (lo, hi)
}

/// Bounds of the shadow a box `min..max` can cast from a point light at `light` that reaches
/// `radius`: the box and its corners pushed away from the light out to the reach; `None` when
/// the light does not reach the box. A light inside the box: its whole reach.
pub fn point_shadow_bounds(light: Vec3, radius: f32, min: Vec3, max: Vec3) -> Option<(Vec3, Vec3)> {
    if light.clamp(min, max).distance(light) >= radius {
        return None;
    }
    if light.cmpge(min).all() && light.cmple(max).all() {
        return Some((light - Vec3::splat(radius), light + Vec3::splat(radius)));
    }
    let (mut lo, mut hi) = (min, max);
    for c in corners(min, max) {
        let far = light + (c - light).normalize_or_zero() * radius;
        lo = lo.min(far);
        hi = hi.max(far);
    }
    Some((lo, hi))
}

/// A scene's lights and the lowest point a shadow on its terrains can fall on: what the
/// terrain splats pass needs to tell where a moved caster's shadow may have come or gone.
#[derive(Debug, Clone, Default)]
pub struct ShadowLights {
    suns: Vec<SunInput>,
    points: Vec<PointLightInput>,
    floor: f32,
}

/// Angular step of a point light's shadow wedge's far arc ([`ShadowLights::footprints`]).
const ARC_STEP: f32 = std::f32::consts::FRAC_PI_8;

impl ShadowLights {
    /// `scene`'s; the floor is its terrains' lowest surface point (their skirts, below it,
    /// are never lit), or the scene's lowest point without terrains.
    pub fn new(scene: &SceneInput) -> Self {
        let terrain_floor = (scene.terrains.iter())
            .map(|t| {
                let low = t.heights.iter().copied().fold(0.0f32, f32::min);
                t.corner.y + low
            })
            .fold(f32::INFINITY, f32::min);
        ShadowLights {
            suns: scene.suns.clone(),
            points: scene.points.clone(),
            floor: if terrain_floor.is_finite() {
                terrain_floor
            } else {
                scene_floor(scene)
            },
        }
    }

    /// Where, seen from above, a caster within `min..max` may cast a shadow on anything below
    /// it: convex polygons in world X, Z (each as its corners' hull), one for the box itself,
    /// one per sun (the box's footprint swept along the sun down to the scene's lowest point,
    /// at most 200 units along the ray, as [`sun_shadow_bounds`]), one per point light that
    /// reaches it (the wedge from the light through the footprint out to the light's reach;
    /// its whole reach when the light stands over the footprint).
    pub fn footprints(&self, min: Vec3, max: Vec3) -> Vec<Vec<Vec2>> {
        let foot = [
            Vec2::new(min.x, min.z),
            Vec2::new(max.x, min.z),
            Vec2::new(max.x, max.z),
            Vec2::new(min.x, max.z),
        ];
        let mut out = vec![hull(foot.to_vec())];
        let floor = self.floor.min(min.y);
        for sun in &self.suns {
            let d = sun.direction.normalize_or_zero();
            if d.y >= -1e-3 {
                continue;
            }
            let t = ((max.y - floor) / -d.y).min(SUN_REACH);
            let s = Vec2::new(d.x, d.z) * t;
            out.push(hull(foot.iter().flat_map(|&c| [c, c + s]).collect()));
        }
        for p in &self.points {
            if p.position.clamp(min, max).distance(p.position) >= p.radius {
                continue;
            }
            let l = Vec2::new(p.position.x, p.position.z);
            let r = p.radius;
            let inside = l.cmpge(foot[0]).all() && l.cmple(foot[2]).all();
            let angles: Vec<f32> = foot.iter().map(|&c| (c - l).y.atan2((c - l).x)).collect();
            // The footprint's angular extent from the light: from the first corner, the
            // corners' angles unwrapped into one half turn (the footprint is convex and the
            // light outside it, so it spans less than a half turn).
            let a0 = angles[0];
            let unwrap = |a: f32| {
                let mut d = a - a0;
                while d > std::f32::consts::PI {
                    d -= std::f32::consts::TAU;
                }
                while d < -std::f32::consts::PI {
                    d += std::f32::consts::TAU;
                }
                d
            };
            let (lo, hi) = angles.iter().fold((0f32, 0f32), |(lo, hi), &a| {
                let d = unwrap(a);
                (lo.min(d), hi.max(d))
            });
            let (from, to) = if inside {
                (0.0, std::f32::consts::TAU)
            } else {
                (a0 + lo, a0 + hi)
            };
            // Points on the arc at most ARC_STEP apart, pushed out so the chords between them
            // pass outside the arc.
            let steps = ((to - from) / ARC_STEP).ceil().max(1.0) as usize;
            let step = (to - from) / steps as f32;
            let reach = r / (0.5 * step).cos();
            let mut points: Vec<Vec2> = (0..=steps)
                .map(|k| {
                    let a = from + step * k as f32;
                    l + reach * Vec2::new(a.cos(), a.sin())
                })
                .collect();
            points.push(l);
            points.extend(foot);
            out.push(hull(points));
        }
        out
    }
}

/// The convex hull of `points`, counter-clockwise (Andrew's monotone chain); degenerate
/// input gives what is left (a segment or a point).
fn hull(mut points: Vec<Vec2>) -> Vec<Vec2> {
    points.retain(|p| p.is_finite());
    points.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    points.dedup();
    if points.len() < 3 {
        return points;
    }
    let cross = |o: Vec2, a: Vec2, b: Vec2| (a - o).perp_dot(b - o);
    let mut out: Vec<Vec2> = Vec::with_capacity(2 * points.len());
    for pass in 0..2 {
        let start = out.len();
        let ordered: Box<dyn Iterator<Item = &Vec2>> = if pass == 0 {
            Box::new(points.iter())
        } else {
            Box::new(points.iter().rev())
        };
        for &p in ordered {
            while out.len() >= start + 2 && cross(out[out.len() - 2], out[out.len() - 1], p) <= 0.0
            {
                out.pop();
            }
            out.push(p);
        }
        out.pop();
    }
    out
}

/// Whether the square `lo`..`hi` and the convex polygon `poly` (a hull, counter-clockwise)
/// overlap: no separating axis among the square's two and the polygon's edge normals.
fn square_meets(lo: Vec2, hi: Vec2, poly: &[Vec2]) -> bool {
    let (pmin, pmax) = poly.iter().fold(
        (Vec2::splat(f32::INFINITY), Vec2::splat(f32::NEG_INFINITY)),
        |(a, b), &p| (a.min(p), b.max(p)),
    );
    if pmax.x < lo.x || pmin.x > hi.x || pmax.y < lo.y || pmin.y > hi.y {
        return false;
    }
    if poly.len() < 3 {
        return true;
    }
    let corners = [lo, Vec2::new(hi.x, lo.y), hi, Vec2::new(lo.x, hi.y)];
    for (k, &a) in poly.iter().enumerate() {
        let b = poly[(k + 1) % poly.len()];
        // The outward normal of a counter-clockwise edge.
        let n = Vec2::new((b - a).y, -(b - a).x);
        if corners.iter().all(|&c| n.dot(c - a) > 0.0) {
            return false;
        }
    }
    true
}

/// Levels of tiles: level k's tiles are [`TILE_BASE`] · 2^k units square.
pub const TILE_LEVELS: u32 = 16;
/// The side of a level-0 tile, world units.
pub const TILE_BASE: f32 = 0.25;
/// Tiles along each side of a level's table: tile (x, z) of a level is its entry (x mod
/// 32, z mod 32).
pub const TILE_WRAP: i32 = 32;
/// Entries of the table of shadow epochs (`shadow_tiles` in `terrain_splat.wgsl`): 64 KiB,
/// a uniform binding's least limit.
pub const TILE_ENTRIES: usize = TILE_LEVELS as usize * (TILE_WRAP * TILE_WRAP) as usize;

/// When shadows last changed around each patch of ground, at every scale: the world's XZ
/// plane cut into square tiles at [`TILE_LEVELS`] levels (level k's tiles [`TILE_BASE`] ·
/// 2^k units), each level's tiles wrapped onto a table of [`TILE_WRAP`]² entries holding the
/// epoch of the last change ([`ShadowTiles::mark`]) that overlapped one of them. Tiles
/// sharing an entry only make more work (a tile looks changed when one 32 tiles off did),
/// and a change wider than the table at a level marks that whole level. A terrain pixel or
/// record reads the tiles its square overlaps at the first level whose tiles are at least
/// as wide (at most 2 × 2 of them) and is stamped with their latest epoch, so a change there
/// makes it again (`terrain_splat.wgsl` `tile_epoch`).
#[derive(Debug, Clone)]
pub struct ShadowTiles {
    entries: Vec<u32>,
    epoch: u32,
}

impl Default for ShadowTiles {
    fn default() -> Self {
        ShadowTiles {
            entries: vec![0; TILE_ENTRIES],
            epoch: 0,
        }
    }
}

impl ShadowTiles {
    /// The entries, for the GPU.
    pub fn entries(&self) -> &[u32] {
        &self.entries
    }

    /// Marks every tile, at every level, that overlaps one of the convex polygons `areas`
    /// (world X, Z; [`ShadowLights::footprints`]) with a new epoch. Returns the number of
    /// entries marked.
    pub fn mark(&mut self, areas: &[Vec<Vec2>]) -> usize {
        self.epoch += 1;
        let epoch = self.epoch;
        let per_level = (TILE_WRAP * TILE_WRAP) as usize;
        for level in 0..TILE_LEVELS {
            let side = TILE_BASE * (1u32 << level) as f32;
            let table = &mut self.entries[level as usize * per_level..][..per_level];
            for poly in areas.iter().filter(|p| !p.is_empty()) {
                let (pmin, pmax) = poly.iter().fold(
                    (Vec2::splat(f32::INFINITY), Vec2::splat(f32::NEG_INFINITY)),
                    |(a, b), &p| (a.min(p), b.max(p)),
                );
                let lo = (pmin / side).floor();
                let hi = (pmax / side).floor();
                let wide = hi - lo + 1.0;
                if !(wide.x <= TILE_WRAP as f32 && wide.y <= TILE_WRAP as f32) {
                    table.fill(epoch);
                    continue;
                }
                for x in lo.x as i32..=hi.x as i32 {
                    for z in lo.y as i32..=hi.y as i32 {
                        let t0 = Vec2::new(x as f32, z as f32) * side;
                        if square_meets(t0, t0 + side, poly) {
                            table[wrapped(x, z)] = epoch;
                        }
                    }
                }
            }
        }
        self.entries.iter().filter(|&&e| e == epoch).count()
    }
}

/// The entry of tile (`x`, `z`) within its level's table.
fn wrapped(x: i32, z: i32) -> usize {
    (z.rem_euclid(TILE_WRAP) * TILE_WRAP + x.rem_euclid(TILE_WRAP)) as usize
}

/// The entry of tile (`x`, `z`) of `level` (`tile_entry` in `terrain_splat.wgsl`).
pub fn tile_entry(level: u32, x: i32, z: i32) -> usize {
    level as usize * (TILE_WRAP * TILE_WRAP) as usize + wrapped(x, z)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sun_pushes_a_box_down_to_the_floor_along_its_rays() {
        let sun = SunInput {
            direction: Vec3::new(1.0, -1.0, 0.0),
            colour: Vec3::ONE,
        };
        let (lo, hi) = sun_shadow_bounds(&[sun], 0.0, Vec3::new(0.0, 1.0, 0.0), Vec3::ONE * 2.0);
        assert!(lo.abs_diff_eq(Vec3::ZERO, 1e-5), "{lo}");
        // The top corners drop 2 and move 2 along +X.
        assert!(hi.abs_diff_eq(Vec3::new(4.0, 2.0, 2.0), 1e-5), "{hi}");
    }

    #[test]
    fn a_point_light_out_of_reach_casts_nothing() {
        assert!(point_shadow_bounds(Vec3::splat(10.0), 1.0, Vec3::ZERO, Vec3::ONE).is_none());
        let (lo, hi) =
            point_shadow_bounds(Vec3::new(0.5, 3.0, 0.5), 4.0, Vec3::ZERO, Vec3::ONE).unwrap();
        assert!(lo.y < -0.5 && hi.y <= 1.0 + 1e-6, "{lo} {hi}");
    }

    #[test]
    fn marking_a_square_stamps_its_tiles_at_every_level() {
        let mut t = ShadowTiles::default();
        let square = hull(vec![
            Vec2::new(1.0, 1.0),
            Vec2::new(1.9, 1.0),
            Vec2::new(1.9, 1.4),
            Vec2::new(1.0, 1.4),
        ]);
        let marked = t.mark(std::slice::from_ref(&square));
        // Level 0 (0.25): 4 × 2 tiles; level 1 (0.5): 2 × 1; levels 2-15: 1 each.
        assert_eq!(marked, 8 + 2 + 14);
        assert_eq!(t.entries[tile_entry(0, 3, 4)], 0);
        assert_eq!(t.entries[tile_entry(0, 4, 4)], 1);
        assert_eq!(t.entries[tile_entry(0, 7, 5)], 1);
        assert_eq!(t.entries[tile_entry(5, 0, 0)], 1);
        // A second change far away: a new epoch there; the first's tiles keep theirs.
        let far = hull(vec![
            Vec2::splat(-50.0),
            Vec2::new(-49.9, -50.0),
            Vec2::splat(-49.9),
        ]);
        t.mark(&[far]);
        assert_eq!(t.entries[tile_entry(0, -200, -200)], 2);
        assert_eq!(t.entries[tile_entry(0, 4, 4)], 1);
        // An area wider than a level's table marks the whole level: 2 × 10⁴ units is more
        // than 32 tiles up to level 11 (512 units), 21 at level 12.
        let huge = hull(vec![
            Vec2::splat(-1e4),
            Vec2::new(1e4, -1e4),
            Vec2::splat(1e4),
        ]);
        t.mark(&[huge]);
        assert!(t.entries[..tile_entry(12, 0, 0)].iter().all(|&e| e == 3));
        let level12 = &t.entries[tile_entry(12, 0, 0)..tile_entry(13, 0, 0)];
        assert!(level12.iter().any(|&e| e != 3));
        assert_eq!(t.entries[tile_entry(15, 0, 0)], 3);
    }

    #[test]
    fn a_diagonal_strip_marks_the_tiles_along_it_not_its_bounding_box() {
        let strip = hull(vec![
            Vec2::new(0.0, 0.0),
            Vec2::new(0.5, 0.0),
            Vec2::new(10.5, 10.0),
            Vec2::new(10.0, 10.0),
        ]);
        assert!(square_meets(
            Vec2::new(5.0, 5.0),
            Vec2::new(5.25, 5.25),
            &strip
        ));
        assert!(!square_meets(
            Vec2::new(8.0, 1.0),
            Vec2::new(8.25, 1.25),
            &strip
        ));
        assert!(!square_meets(
            Vec2::new(1.0, 8.0),
            Vec2::new(1.25, 8.25),
            &strip
        ));
        let mut t = ShadowTiles::default();
        let marked = t.mark(&[strip]);
        // Level 1's box holds 22 × 21 tiles (level 0's is wider than its table: all 1,024
        // marked); the strip crosses about 2 × 21 of them.
        let level1 = t.entries[tile_entry(1, 0, 0)..tile_entry(2, 0, 0)]
            .iter()
            .filter(|&&e| e == 1)
            .count();
        assert!(level1 < 100, "{level1} tiles of level 1");
        assert!(marked < 1024 + 200, "{marked} entries");
    }

    #[test]
    fn the_footprints_hold_what_a_ray_toward_a_light_through_the_box_can_start_from() {
        let scene = SceneInput {
            suns: vec![SunInput {
                direction: Vec3::new(-0.45, -0.7, -0.55),
                colour: Vec3::ONE,
            }],
            points: vec![PointLightInput {
                position: Vec3::new(2.0, 5.2, 20.0),
                colour: Vec3::ONE,
                radius: 9.0,
            }],
            ..Default::default()
        };
        let mut lights = ShadowLights::new(&scene);
        lights.floor = 0.0;
        let (min, max) = (Vec3::new(5.5, 5.5, 17.5), Vec3::new(6.5, 7.5, 18.5));
        let areas = lights.footprints(min, max);
        assert_eq!(areas.len(), 3);
        // Where a ray toward a light through a point of the box can start: down the sun's
        // rays to the floor, and away from the lantern out to its reach.
        let mut rng = 1u32;
        let mut next = || {
            rng = rng.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (rng >> 8) as f32 / (1u32 << 24) as f32
        };
        let d = scene.suns[0].direction.normalize();
        let light = scene.points[0].position;
        for _ in 0..2000 {
            let b = min + (max - min) * Vec3::new(next(), next(), next());
            let sun_start = b + d * (b.y / -d.y) * next();
            let away = (b - light).normalize();
            let point_start = b + away * (9.0 - b.distance(light)) * next();
            for p in [sun_start, point_start] {
                let q = Vec2::new(p.x, p.z);
                assert!(
                    areas.iter().any(|a| square_meets(q, q, a)),
                    "{p}, shadowed through {b}, lies in no footprint"
                );
            }
        }
        // Beyond the lantern from the box, and far up-sun: outside every footprint.
        for q in [Vec2::new(-4.0, 22.0), Vec2::new(20.0, 30.0)] {
            assert!(!areas.iter().any(|a| square_meets(q, q, a)), "{q}");
        }
    }
}
