//! Where a cell's stable probe sits: the cell centre, unless that would blind it.
//!
//! A probe at the cell centre fails when the centre lies inside a solid (it sees only back
//! faces) or on or next to a surface (a floor whose height is a cell-centre height is seen
//! edge-on, so a low camera's grid probe shows nothing of it). [`place_probe`] then picks
//! another point of the cell from a fixed list of candidates: of those outside every solid
//! and at least [`CLEARANCE`] cell sizes from every surface the test rays meet, the first
//! that sees nearly as much of what cameras in the cell see as the best of them.
//!
//! The answer is a function of the cell and the scene only, never of where the camera is
//! inside the cell, so everything stable about a grid probe stays stable: callers cache it
//! per cell ([`Placements`]) until the scene changes.
//!
//! A probe clear of every surface may still stand in line with a big flat face, past its
//! edge; [`near_faces`] finds such faces (from the geometry, a box query) for the renderer,
//! which lays the probe's texels on them flat rather than moving the probe off the lattice
//! its neighbours keep (that was tried and cost more at the crossings than it saved).

use std::collections::HashMap;

use glam::{IVec3, Vec2, Vec3};

use crate::grid::{GridCell, GridChoice, GridDefaults, GridError, GridOverride, resolve_grid};

/// Least distance, in cell sizes, from a probe to any surface its test rays meet: nearly
/// half a cell, the most a point of the cell has from a floor through its centre. A probe
/// near a floor sees it at a grazing angle, where one texel spans a long strip (at height
/// `h`, a texel `d` away is about `d²/h` texel angles long), so light-band and shadow edges
/// on it jump by that much when the camera crosses to the next probe. Measured on
/// `low_orbit` (a camera 0.35 above the floor, faces of 128, 320×180): splat shimmer
/// 0.0071 with the probe at 0.25 above the floor, 0.0032 at 0.45, 0.0029 at 0.5 (the top of
/// the cell; eye pixels 6.7 % → 1.8 %); `wall_graze` 0.0038 → 0.0025.
pub const CLEARANCE: f32 = 0.45;

/// The first surface along a ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayHit {
    /// Distance along the (unit) ray.
    pub t: f32,
    /// Whether the ray met the surface from behind (its normal points along the ray): the
    /// ray started inside a solid, or under a one-sided surface such as a ground plane.
    pub back_face: bool,
}

/// What placement asks of the scene: the first surface along a ray.
pub trait RayQuery {
    /// The first surface along `origin + t · dir` (`dir` unit length) with `t` in
    /// `(0, max]`, if any.
    fn first_hit(&self, origin: Vec3, dir: Vec3, max: f32) -> Option<RayHit>;

    /// Every triangle that may reach into the box `min..max` (a superset is fine), its
    /// vertices counter-clockwise around its front face.
    fn triangles_in(&self, min: Vec3, max: Vec3) -> Vec<[Vec3; 3]>;
}

/// The test rays: the six axes and the eight cube diagonals (also the evaluator's test of a
/// camera's clearance, `texel_eval::survey`).
pub fn test_directions() -> [Vec3; 14] {
    let d = 1.0 / 3f32.sqrt();
    let mut out = [Vec3::ZERO; 14];
    let axes = [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z];
    out[..6].copy_from_slice(&axes);
    let mut i = 6;
    for x in [-d, d] {
        for y in [-d, d] {
            for z in [-d, d] {
                out[i] = Vec3::new(x, y, z);
                i += 1;
            }
        }
    }
    out
}

/// Candidate offsets from the cell centre, in cell sizes, in the order they are tried: the
/// centre; up (cameras stand on floors); the four horizontal directions; down; then the
/// same at twice the distance (the cell's faces), then diagonals. All stay inside the cell.
fn candidates() -> Vec<Vec3> {
    let mut out = vec![Vec3::ZERO];
    for k in [0.25f32, 0.5] {
        for d in [Vec3::Y, Vec3::X, -Vec3::X, Vec3::Z, -Vec3::Z, -Vec3::Y] {
            out.push(d * k);
        }
    }
    for y in [0.25f32, 0.45, -0.25] {
        for (x, z) in [
            (0.25f32, 0.25f32),
            (-0.25, 0.25),
            (0.25, -0.25),
            (-0.25, -0.25),
        ] {
            out.push(Vec3::new(x, y, z));
        }
    }
    out
}

/// How a point fares: inside a solid, or free with its clearance (distance to the nearest
/// surface the test rays meet, capped at the ray length).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Fit {
    Inside,
    Free(f32),
}

fn fit(p: Vec3, reach: f32, scene: &impl RayQuery) -> Fit {
    // Rays start a little behind the point, so a surface through it counts (at distance 0).
    let back = 1e-3 * reach;
    let mut nearest = reach;
    for dir in test_directions() {
        if let Some(hit) = scene.first_hit(p - dir * back, dir, reach + back) {
            if hit.back_face {
                return Fit::Inside;
            }
            nearest = nearest.min((hit.t - back).max(0.0));
        }
    }
    Fit::Free(nearest)
}

/// How far, in cell sizes, faces are looked for around a cell.
const PLANE_REACH: f32 = 4.0;

/// A flat face near a probe: a point on it and its unit normal (toward its front).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FacePlane {
    /// A point of the face.
    pub point: Vec3,
    /// Its unit normal.
    pub normal: Vec3,
}

/// How near, in cell sizes, a face's plane passes by a stable probe for the renderer to lay
/// that face's texels flat on it ([`near_faces`]).
pub const NEAR_FACE: f32 = 0.4;

/// Normals of one flat face agree this closely (half a degree): a curved surface's
/// triangles, a hillside's, do not, so its tangent planes are not taken for faces.
const FLAT_DOT: f32 = 0.99995;

/// Least width, in cell sizes, of a face whose texels are laid flat ([`near_faces`]): a
/// standing stone's face (0.91 wide) and a round pillar's facets are narrower, and so are
/// two stones' faces that share a plane apart.
const FACE_WIDTH: f32 = 1.0;

/// The least width of points `q` (2D): the least, over the edges of their convex hull
/// (where the width is least, one edge lies flush), of their extent across it.
fn least_width(q: &[Vec2]) -> f32 {
    let hull = convex_hull(q);
    let mut least = f32::INFINITY;
    for (i, a) in hull.iter().enumerate() {
        let b = hull[(i + 1) % hull.len()];
        let Some(d) = (b - *a).try_normalize() else {
            continue;
        };
        let across = d.perp();
        let extent = (hull.iter())
            .map(|p| (p - a).dot(across).abs())
            .fold(0.0, f32::max);
        least = least.min(extent);
    }
    if least.is_finite() { least } else { 0.0 }
}

/// The convex hull of `q`, counter-clockwise (Andrew's monotone chain).
fn convex_hull(q: &[Vec2]) -> Vec<Vec2> {
    let mut p = q.to_vec();
    p.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    p.dedup();
    if p.len() < 3 {
        return p;
    }
    // The lower chain left to right, then the upper one right to left, each without its
    // last point (the next chain's first).
    fn chain<'a>(hull: &mut Vec<Vec2>, points: impl Iterator<Item = &'a Vec2>) {
        let start = hull.len();
        for &x in points {
            while hull.len() >= start + 2 && {
                let (o, a) = (hull[hull.len() - 2], hull[hull.len() - 1]);
                (a - o).perp_dot(x - o) <= 0.0
            } {
                hull.pop();
            }
            hull.push(x);
        }
        hull.pop();
    }
    let mut hull = Vec::with_capacity(2 * p.len());
    chain(&mut hull, p.iter());
    chain(&mut hull, p.iter().rev());
    hull
}

/// The big flat faces within [`PLANE_REACH`] cells whose planes pass within [`NEAR_FACE`]
/// cells of a stable probe at `centre` on a lattice of cell size `s`: placement keeps probes [`CLEARANCE`] off surfaces,
/// so these are faces the probe sees past their edges, in line with them, at a grazing
/// angle (each texel a long strip on the face). Their texels' quads, standing across the
/// face toward the probe, are seen from a camera elsewhere in the cell, farther off the
/// plane and so more steeply, like the slats of a blind, and the eye probe fills between
/// them: the renderer lays those quads flat on the plane instead (`shaders/cull.wgsl`).
/// Only faces at least [`FACE_WIDTH`] cells wide count: a round pillar's facets, whose
/// planes pass as near a probe beside it, stay standing.
///
/// A face is a set of triangles in one plane (normals within [`FLAT_DOT`], offsets within
/// 0.005 cells) joined by shared vertices; it counts when it spans at least [`FACE_WIDTH`]
/// cells every way (the least width of its vertices' hull). Found from the geometry, not by
/// rays, so neighbouring probes find the same faces.
pub fn near_faces(centre: Vec3, s: f32, scene: &impl RayQuery) -> Vec<FacePlane> {
    let near = NEAR_FACE * s;
    let r = Vec3::splat(PLANE_REACH * s);
    let tris: Vec<([Vec3; 3], Vec3)> = (scene.triangles_in(centre - r, centre + r).into_iter())
        .filter_map(|t| {
            let n = (t[1] - t[0]).cross(t[2] - t[0]).try_normalize()?;
            ((centre - t[0]).dot(n).abs() < near).then_some((t, n))
        })
        .collect();
    // Each triangle's plane (the first it lies in within FLAT_DOT and 0.005 cells), then
    // union-find over the triangles: one plane and a shared vertex join two (found through
    // a map of vertices, so a dense mesh costs its size, not its square).
    let mut planes: Vec<(Vec3, Vec3)> = Vec::new();
    let plane_of: Vec<usize> = (tris.iter())
        .map(|(t, n)| {
            let same = |(m, q): &(Vec3, Vec3)| {
                m.dot(*n) >= FLAT_DOT && (t[0] - *q).dot(*m).abs() < 0.005 * s
            };
            planes.iter().position(same).unwrap_or_else(|| {
                planes.push((*n, t[0]));
                planes.len() - 1
            })
        })
        .collect();
    let mut parent: Vec<usize> = (0..tris.len()).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    let grain = 1e-4 * s;
    let mut at_vertex: HashMap<(usize, [i64; 3]), usize> = HashMap::new();
    for (i, (t, _)) in tris.iter().enumerate() {
        for v in t {
            let key = (
                plane_of[i],
                (*v / grain).round().to_array().map(|x| x as i64),
            );
            let j = *at_vertex.entry(key).or_insert(i);
            let (x, y) = (root(&mut parent, i), root(&mut parent, j));
            parent[x] = y;
        }
    }
    let mut by_root: HashMap<usize, Vec<Vec3>> = HashMap::new();
    for (i, (t, _)) in tris.iter().enumerate() {
        let k = root(&mut parent, i);
        by_root.entry(k).or_default().extend(t);
    }
    // In a fixed order (the map's is not), so the same faces come first on every run.
    let mut faces: Vec<(usize, Vec<Vec3>)> = by_root.into_iter().collect();
    faces.sort_by_key(|(k, _)| *k);
    (faces.into_iter())
        .filter_map(|(k, points)| {
            let normal = tris[k].1;
            let u = normal.any_orthonormal_vector();
            let v = normal.cross(u);
            let flat: Vec<Vec2> = (points.iter())
                .map(|p| Vec2::new(p.dot(u), p.dot(v)))
                .collect();
            (least_width(&flat) >= FACE_WIDTH * s).then_some(FacePlane {
                point: points[0],
                normal,
            })
        })
        .collect()
}

/// Camera positions a cell's probe is judged from: its centre and the eight points halfway
/// to its corners, those outside every solid.
fn camera_samples(cell: &GridCell, reach: f32, scene: &impl RayQuery) -> Vec<Vec3> {
    let (centre, s) = (cell.origin(), cell.cell_size);
    let mut out = vec![centre];
    for x in [-0.25f32, 0.25] {
        for y in [-0.25f32, 0.25] {
            for z in [-0.25f32, 0.25] {
                out.push(centre + Vec3::new(x, y, z) * s);
            }
        }
    }
    out.retain(|&q| fit(q, reach, scene) != Fit::Inside);
    out
}

/// The directions a camera sample looks along: sixteen headings, level and 20° down
/// (cameras look across the ground; that band is the view a probe must share).
fn look_directions() -> Vec<Vec3> {
    let mut out = Vec::with_capacity(32);
    for pitch in [0.0f32, -20.0] {
        let (sp, cp) = pitch.to_radians().sin_cos();
        for k in 0..16 {
            let (sy, cy) = (k as f32 * std::f32::consts::TAU / 16.0).sin_cos();
            out.push(Vec3::new(cy * cp, sp, sy * cp));
        }
    }
    out
}

/// How far a camera sample's look reaches, in cell sizes: what a camera a cell away from the
/// probe sees past a near solid's edge lies within a few cells of it.
const LOOK_REACH: f32 = 8.0;

/// A candidate that sees at least `1 - SEES_TIE` times as many of the cameras' points as
/// the one that sees most counts as a tie with it. Candidates on open ground differ by up to
/// 3 % (a point behind a distant stone's edge; measured on the stone circle's floor cells);
/// a probe moved in front of a standing stone's face, when the cell's cameras stand by its
/// edge and see past it, misses 7 % (the eye probe then drew 14 % of the pixels of a walk
/// past that edge).
/// Among near ties the earliest is taken, so neighbouring cells keep one offset and the
/// probes one lattice.
const SEES_TIE: f32 = 0.05;

/// The points the cameras at `samples` see (the first surface along each look direction, or
/// the end of the look where there is none).
fn seen_points(samples: &[Vec3], s: f32, scene: &impl RayQuery) -> Vec<Vec3> {
    let reach = LOOK_REACH * s;
    let dirs = look_directions();
    let mut out = Vec::with_capacity(samples.len() * dirs.len());
    for &q in samples {
        for &dir in &dirs {
            let t = scene.first_hit(q, dir, reach).map_or(reach, |h| h.t);
            out.push(q + dir * t);
        }
    }
    out
}

/// How many of `points` a probe at `p` sees: nothing nearer along its ray to the point
/// (within a small share of the distance, so the surface a point lies on does not count).
fn sees(p: Vec3, points: &[Vec3], scene: &impl RayQuery) -> usize {
    (points.iter())
        .filter(|&&x| {
            let d = x - p;
            let len = d.length();
            len < 1e-4 || scene.first_hit(p, d / len, len * 0.98 - 1e-3).is_none()
        })
        .count()
}

/// The probe position for `cell`: its centre when that is at least [`CLEARANCE`] cell
/// sizes from every surface and outside every solid. Else, of the candidate points of the
/// cell that are, the earliest that sees nearly ([`SEES_TIE`]) as many of the points cameras
/// in the cell see as the candidate that sees most: the first clear candidate may stand in
/// front of a solid whose edge the cell's cameras see past, and what they see there, that
/// probe does not, so the eye probe draws it, shimmering like low-resolution rendering.
/// With no such candidate, the free one with the most clearance; else the centre.
pub fn place_probe(cell: &GridCell, scene: &impl RayQuery) -> Vec3 {
    let centre = cell.origin();
    let s = cell.cell_size;
    let need = CLEARANCE * s;
    // Rays reach across the cell and a little beyond: enough to see what would blind it.
    let reach = 2.0 * s;
    let mut best: Option<(f32, Vec3)> = None;
    // What the cell's cameras see, worked out when the first candidate needs judging; each
    // clear candidate with how many of those points it sees.
    let mut points: Option<Vec<Vec3>> = None;
    let mut clear: Vec<(usize, Vec3)> = Vec::new();
    for offset in candidates() {
        let p = centre + offset * s;
        match fit(p, reach, scene) {
            Fit::Free(c) if c >= need && offset == Vec3::ZERO => return p,
            Fit::Free(c) if c >= need => {
                let points = points.get_or_insert_with(|| {
                    seen_points(&camera_samples(cell, reach, scene), s, scene)
                });
                let n = sees(p, points, scene);
                // No candidate sees more than all of them: the first clear one that sees
                // nearly all is the earliest near tie (open ground), found without the rest.
                if clear.is_empty() && n as f32 >= points.len() as f32 * (1.0 - SEES_TIE) {
                    return p;
                }
                clear.push((n, p));
            }
            Fit::Free(c) if best.is_none_or(|(b, _)| c > b) => best = Some((c, p)),
            _ => {}
        }
    }
    let most = clear.iter().map(|&(n, _)| n).max().unwrap_or(0) as f32;
    (clear.iter())
        .find(|&&(n, _)| n as f32 >= most * (1.0 - SEES_TIE))
        .map(|&(_, p)| p)
        .or(best.map(|(_, p)| p))
        .unwrap_or(centre)
}

/// Probe positions per cell, computed on first use and kept until the scene changes
/// (make a new one then).
#[derive(Debug, Default)]
pub struct Placements {
    cache: HashMap<(IVec3, u32), Vec3>,
}

impl Placements {
    /// An empty cache.
    pub fn new() -> Self {
        Self::default()
    }

    /// The probe position of `cell` (see [`place_probe`]).
    pub fn position(&mut self, cell: &GridCell, scene: &impl RayQuery) -> Vec3 {
        *self
            .cache
            .entry((cell.index, cell.cell_size.to_bits()))
            .or_insert_with(|| place_probe(cell, scene))
    }

    /// The grid that applies at `position` (`grid::resolve_grid`), its probe placed.
    pub fn resolve(
        &mut self,
        position: Vec3,
        defaults: &GridDefaults,
        overrides: &[GridOverride],
        scene: &impl RayQuery,
    ) -> Result<GridChoice, GridError> {
        let mut choice = resolve_grid(position, defaults, overrides)?;
        let cell = choice.key.cell;
        choice.key.offset = self.position(&cell, scene) - cell.origin();
        Ok(choice)
    }

    /// Forgets the placements of the cells whose search volume (a cell around its origin)
    /// meets the box `min..max`, after the scene changed there; the others stay.
    pub fn forget_near(&mut self, min: Vec3, max: Vec3) {
        self.cache.retain(|&(index, bits), _| {
            let size = f32::from_bits(bits);
            let o = index.as_vec3() * size;
            let (lo, hi) = (o - Vec3::splat(size), o + Vec3::splat(size));
            !(lo.cmple(max).all() && hi.cmpge(min).all())
        });
    }

    /// Cells placed so far.
    pub fn len(&self) -> usize {
        self.cache.len()
    }

    /// Whether no cell was placed yet.
    pub fn is_empty(&self) -> bool {
        self.cache.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A ground plane at `y = ground` (front face up) and solid boxes, each `lo..hi` turned
    /// by `turn` degrees about the vertical through its centre.
    struct Scene {
        ground: f32,
        solids: Vec<Solid>,
    }

    struct Solid {
        lo: Vec3,
        hi: Vec3,
        turn: f32,
    }

    impl Solid {
        fn upright(lo: Vec3, hi: Vec3) -> Self {
            Solid { lo, hi, turn: 0.0 }
        }

        /// The box's twelve triangles, counter-clockwise seen from outside.
        fn triangles(&self) -> Vec<[Vec3; 3]> {
            let c = (self.lo + self.hi) * 0.5;
            let h = (self.hi - self.lo) * 0.5;
            let turn = glam::Quat::from_rotation_y(self.turn.to_radians());
            let (x, y, z) = (Vec3::X, Vec3::Y, Vec3::Z);
            let mut out = Vec::new();
            for (n, u, v) in [
                (x, y, z),
                (-x, z, y),
                (y, z, x),
                (-y, x, z),
                (z, x, y),
                (-z, y, x),
            ] {
                let f = n * (n.abs().dot(h));
                let (u, v) = (u * u.dot(h), v * v.dot(h));
                let k = |a: f32, b: f32| c + turn * (f + u * a + v * b);
                out.push([k(-1.0, -1.0), k(1.0, -1.0), k(1.0, 1.0)]);
                out.push([k(-1.0, -1.0), k(1.0, 1.0), k(-1.0, 1.0)]);
            }
            out
        }

        /// The ray's entry (or, from inside, exit) and whether it starts inside.
        fn hit(&self, o: Vec3, d: Vec3) -> Option<(f32, bool)> {
            // Into the box's frame: a rotation keeps the ray's parameter.
            let c = (self.lo + self.hi) * 0.5;
            let back = glam::Quat::from_rotation_y(-self.turn.to_radians());
            let (o, d) = (c + back * (o - c), back * d);
            let inside = o.cmpgt(self.lo).all() && o.cmplt(self.hi).all();
            let inv = d.recip();
            let (a, b) = ((self.lo - o) * inv, (self.hi - o) * inv);
            let (t0, t1) = (a.min(b).max_element(), a.max(b).min_element());
            (t0 <= t1).then_some(if inside { (t1, true) } else { (t0, false) })
        }
    }

    impl RayQuery for Scene {
        fn first_hit(&self, o: Vec3, d: Vec3, max: f32) -> Option<RayHit> {
            let mut best: Option<RayHit> = None;
            let mut keep = |t: f32, back_face: bool| {
                if t > 0.0 && t <= max && best.is_none_or(|b| t < b.t) {
                    best = Some(RayHit { t, back_face });
                }
            };
            if d.y != 0.0 {
                keep((self.ground - o.y) / d.y, d.y > 0.0);
            }
            for solid in &self.solids {
                if let Some((t, inside)) = solid.hit(o, d) {
                    keep(t, inside);
                }
            }
            best
        }

        fn triangles_in(&self, min: Vec3, max: Vec3) -> Vec<[Vec3; 3]> {
            let g = |x: f32, z: f32| Vec3::new(x, self.ground, z);
            let (a, b) = (min - 1.0, max + 1.0);
            let mut out = vec![
                [g(a.x, a.z), g(a.x, b.z), g(b.x, b.z)],
                [g(a.x, a.z), g(b.x, b.z), g(b.x, a.z)],
            ];
            for solid in &self.solids {
                out.extend(solid.triangles());
            }
            out
        }
    }

    fn cell(x: i32, y: i32, z: i32) -> GridCell {
        GridCell {
            index: IVec3::new(x, y, z),
            cell_size: 1.0,
        }
    }

    #[test]
    fn a_clear_centre_stays_put() {
        let scene = Scene {
            ground: 0.0,
            solids: Vec::new(),
        };
        assert_eq!(
            place_probe(&cell(3, 2, -1), &scene),
            Vec3::new(3.0, 2.0, -1.0)
        );
    }

    #[test]
    fn a_centre_on_the_floor_moves_up_into_the_cell() {
        let scene = Scene {
            ground: 0.0,
            solids: Vec::new(),
        };
        let p = place_probe(&cell(0, 0, 0), &scene);
        assert!(p.y >= CLEARANCE && p.y <= 0.5, "{p}");
        assert_eq!((p.x, p.z), (0.0, 0.0));
    }

    #[test]
    fn a_centre_under_the_floor_or_inside_a_solid_is_never_chosen() {
        let under = Scene {
            ground: 0.1,
            solids: Vec::new(),
        };
        // No point of the cell is CLEARANCE above this floor: the free candidate with the
        // most clearance is the top of the cell.
        let p = place_probe(&cell(0, 0, 0), &under);
        assert_eq!(p, Vec3::new(0.0, 0.5, 0.0));
        let boxed = Scene {
            ground: -10.0,
            solids: vec![Solid::upright(
                Vec3::new(-0.2, -0.3, -0.2),
                Vec3::new(0.2, 0.1, 0.2),
            )],
        };
        let p = place_probe(&cell(0, 0, 0), &boxed);
        assert!(
            matches!(fit(p, 2.0, &boxed), Fit::Free(c) if c >= CLEARANCE),
            "{p}"
        );
        assert!(
            (p - Vec3::ZERO).abs().max_element() <= 0.5,
            "{p} left the cell"
        );
    }

    #[test]
    fn placement_depends_on_the_cell_only_and_is_cached() {
        let scene = Scene {
            ground: 0.0,
            solids: Vec::new(),
        };
        let mut cache = Placements::new();
        let a = cache.position(&cell(1, 0, 1), &scene);
        let b = cache.position(&cell(1, 0, 1), &scene);
        assert_eq!(a, b);
        assert_eq!(cache.len(), 1);
        assert_ne!(cache.position(&cell(2, 0, 1), &scene), a);
    }

    /// The share of what cameras anywhere in `cell` see (a 5 × 5 × 5 lattice of cameras, 64
    /// headings at four pitches, reaching eight cells) that a probe at `p` sees too: a
    /// finer judge than the one placement uses.
    fn share_seen(p: Vec3, cell: &GridCell, scene: &Scene) -> f32 {
        let steps = [-0.4f32, -0.2, 0.0, 0.2, 0.4];
        let (mut seen, mut all) = (0, 0);
        for x in steps {
            for y in steps {
                for z in steps {
                    let q = cell.origin() + Vec3::new(x, y, z) * cell.cell_size;
                    if fit(q, 2.0, scene) == Fit::Inside {
                        continue;
                    }
                    for pitch in [10.0f32, 0.0, -10.0, -25.0] {
                        for k in 0..64 {
                            let heading = k as f32 * std::f32::consts::TAU / 64.0;
                            let (sp, cp) = pitch.to_radians().sin_cos();
                            let dir = Vec3::new(heading.cos() * cp, sp, heading.sin() * cp);
                            let t = scene.first_hit(q, dir, 8.0).map_or(8.0, |h| h.t);
                            let target = q + dir * t;
                            let (to, len) = ((target - p).normalize(), (target - p).length());
                            all += 1;
                            if scene.first_hit(p, to, len - 1e-2).is_none() {
                                seen += 1;
                            }
                        }
                    }
                }
            }
        }
        seen as f32 / all as f32
    }

    #[test]
    fn a_probe_moved_off_a_standing_slab_sees_what_cameras_by_its_edge_see_past_it() {
        // A standing stone of the stone circle (0.91 wide, 2.7 tall, 0.54 thick, turned 326°),
        // its face 0.15 from the centre of the cell its neighbour walks through, where a walk
        // past its edge had 14 % of its pixels drawn by the eye probe.
        let (centre, half) = (
            Vec3::new(-3.857, 1.368, 4.596),
            Vec3::new(0.4545, 1.3675, 0.2695),
        );
        let scene = Scene {
            ground: 0.0,
            solids: vec![Solid {
                lo: centre - half,
                hi: centre + half,
                turn: 326.0,
            }],
        };
        let cell = cell(-4, 2, 5);
        let placed = place_probe(&cell, &scene);
        assert!(matches!(fit(placed, 2.0, &scene), Fit::Free(c) if c >= CLEARANCE));
        // The rule before: the first candidate with the clearance, in front of the face.
        let first = (candidates().into_iter())
            .map(|o| cell.origin() + o)
            .find(|&p| matches!(fit(p, 2.0, &scene), Fit::Free(c) if c >= CLEARANCE))
            .expect("a clear candidate");
        let (now, before) = (
            share_seen(placed, &cell, &scene),
            share_seen(first, &cell, &scene),
        );
        assert!(
            now >= before + 0.03 && now >= 0.95,
            "{placed}: {now} against {first}: {before}"
        );
    }

    #[test]
    fn a_probe_past_a_wall_top_finds_the_wall_face_it_stands_in_line_with() {
        // The textured level's brick wall (8 × 2.5 × 0.5 on the floor): the probe of the
        // cell above and behind it stands 0.56 from the box, clear of it, but 0.25 off its
        // back face's plane.
        let wall = Solid::upright(Vec3::new(-4.0, 0.0, -4.75), Vec3::new(4.0, 2.5, -4.25));
        let scene = Scene {
            ground: 0.0,
            solids: vec![wall],
        };
        let p = place_probe(&cell(-2, 3, -5), &scene);
        assert_eq!(p, Vec3::new(-2.0, 3.0, -5.0));
        let faces = near_faces(p, 1.0, &scene);
        assert_eq!(faces.len(), 1, "{faces:?}");
        assert!(faces[0].normal.abs_diff_eq(-Vec3::Z, 1e-5));
        assert!((faces[0].point.z + 4.75).abs() < 1e-4);
        // Half a cell farther back, and over the open floor half a cell up, none.
        assert!(near_faces(Vec3::new(-2.0, 3.0, -5.5), 1.0, &scene).is_empty());
        assert!(near_faces(Vec3::new(0.0, 0.5, 3.0), 1.0, &scene).is_empty());
    }

    #[test]
    fn narrow_faces_and_apart_faces_in_one_plane_are_not_faces_to_lay_flat() {
        // Two slabs 0.8 wide, a metre apart, their front faces in one plane (a trilithon's
        // uprights), and a probe 0.2 off that plane beside them.
        let slab = |x: f32| Solid::upright(Vec3::new(x, 0.0, -0.3), Vec3::new(x + 0.8, 3.2, 0.3));
        let scene = Scene {
            ground: -10.0,
            solids: vec![slab(0.0), slab(1.8)],
        };
        assert!(near_faces(Vec3::new(-1.0, 1.5, 0.5), 1.0, &scene).is_empty());
        // One slab as wide as both, and its face counts.
        let wide = Scene {
            ground: -10.0,
            solids: vec![Solid::upright(
                Vec3::new(0.0, 0.0, -0.3),
                Vec3::new(2.6, 3.2, 0.3),
            )],
        };
        assert_eq!(near_faces(Vec3::new(-1.0, 1.5, 0.5), 1.0, &wide).len(), 1);
    }

    #[test]
    fn the_least_width_of_a_turned_rectangle_is_its_short_side() {
        let turn = glam::Mat2::from_angle(20f32.to_radians());
        let mut q: Vec<Vec2> = [(0.0, 0.0), (0.91, 0.0), (0.91, 2.7), (0.0, 2.7)]
            .iter()
            .map(|&(x, y)| turn * Vec2::new(x, y))
            .collect();
        q.push(turn * Vec2::new(0.4, 1.3));
        assert!((least_width(&q) - 0.91).abs() < 1e-4, "{}", least_width(&q));
        assert_eq!(least_width(&q[..2]), 0.0);
        assert_eq!(least_width(&[]), 0.0);
    }

    #[test]
    fn probes_over_open_ground_keep_one_offset() {
        // A floor through the cells' centres inside a ring of eight standing stones (4 units
        // out, turned to face its middle): every cell's probe takes the same offset (the top
        // of the cell), so the probes stay one lattice. Stones hide a few of what a cell's
        // cameras see from one candidate or another, which must not decide.
        let half = Vec3::new(0.45, 1.35, 0.27);
        let solids = (0..8)
            .map(|k| {
                let a = k as f32 * std::f32::consts::TAU / 8.0;
                let c = Vec3::new(4.0 * a.sin(), 1.2, 4.0 * a.cos());
                Solid {
                    lo: c - half,
                    hi: c + half,
                    turn: a.to_degrees(),
                }
            })
            .collect();
        let scene = Scene {
            ground: 0.0,
            solids,
        };
        for x in -2..=2 {
            for z in -2..=2 {
                let p = place_probe(&cell(x, 0, z), &scene);
                assert_eq!(p, Vec3::new(x as f32, 0.5, z as f32));
            }
        }
    }
}
