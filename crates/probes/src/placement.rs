//! Where a cell's stable probe sits: the cell centre, unless that would blind it.
//!
//! A probe at the cell centre fails when the centre lies inside a solid (it sees only back
//! faces) or on or next to a surface (a floor whose height is a cell-centre height is seen
//! edge-on, so a low camera's grid probe shows nothing of it). [`place_probe`] then picks
//! another point of the cell from a fixed list of candidates, the first that is outside
//! every solid and at least [`CLEARANCE`] cell sizes from every surface the test rays meet.
//!
//! The answer is a function of the cell and the scene only, never of where the camera is
//! inside the cell, so everything stable about a grid probe stays stable: callers cache it
//! per cell ([`Placements`]) until the scene changes.

use std::collections::HashMap;

use glam::{IVec3, Vec3};

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
}

/// The test rays: the six axes and the eight cube diagonals.
fn test_directions() -> [Vec3; 14] {
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

/// The probe position for `cell`: its centre when that is at least [`CLEARANCE`] cell
/// sizes from every surface and outside every solid; else the first candidate point of
/// the cell that is; else the free candidate with the most clearance; else the centre.
pub fn place_probe(cell: &GridCell, scene: &impl RayQuery) -> Vec3 {
    let centre = cell.origin();
    let s = cell.cell_size;
    let need = CLEARANCE * s;
    // Rays reach across the cell and a little beyond: enough to see what would blind it.
    let reach = 2.0 * s;
    let mut best: Option<(f32, Vec3)> = None;
    for offset in candidates() {
        let p = centre + offset * s;
        match fit(p, reach, scene) {
            Fit::Free(c) if c >= need => return p,
            Fit::Free(c) if best.is_none_or(|(b, _)| c > b) => best = Some((c, p)),
            _ => {}
        }
    }
    best.map_or(centre, |(_, p)| p)
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

    /// A ground plane at `y = ground` (front face up) and an axis-aligned solid box.
    struct Scene {
        ground: f32,
        solid: Option<(Vec3, Vec3)>,
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
            if let Some((lo, hi)) = self.solid {
                let inside = o.cmpgt(lo).all() && o.cmplt(hi).all();
                let inv = d.recip();
                let (a, b) = ((lo - o) * inv, (hi - o) * inv);
                let (t0, t1) = (a.min(b).max_element(), a.max(b).min_element());
                if t0 <= t1 {
                    if inside {
                        keep(t1, true);
                    } else {
                        keep(t0, false);
                    }
                }
            }
            best
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
            solid: None,
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
            solid: None,
        };
        let p = place_probe(&cell(0, 0, 0), &scene);
        assert!(p.y >= CLEARANCE && p.y <= 0.5, "{p}");
        assert_eq!((p.x, p.z), (0.0, 0.0));
    }

    #[test]
    fn a_centre_under_the_floor_or_inside_a_solid_is_never_chosen() {
        let under = Scene {
            ground: 0.1,
            solid: None,
        };
        // No point of the cell is CLEARANCE above this floor: the free candidate with the
        // most clearance is the top of the cell.
        let p = place_probe(&cell(0, 0, 0), &under);
        assert_eq!(p, Vec3::new(0.0, 0.5, 0.0));
        let boxed = Scene {
            ground: -10.0,
            solid: Some((Vec3::new(-0.2, -0.3, -0.2), Vec3::new(0.2, 0.1, 0.2))),
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
            solid: None,
        };
        let mut cache = Placements::new();
        let a = cache.position(&cell(1, 0, 1), &scene);
        let b = cache.position(&cell(1, 0, 1), &scene);
        assert_eq!(a, b);
        assert_eq!(cache.len(), 1);
        assert_ne!(cache.position(&cell(2, 0, 1), &scene), a);
    }
}
