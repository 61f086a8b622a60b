//! Which point lights can reach where: a grid over the ground plane (X, Z), each cell
//! listing the point lights whose reach overlaps its column, so the shade pass traces a
//! texel's shadow rays toward the lights near it instead of testing every light of the level
//! (a town of 1,000 with 62 lamp posts spent about 13 µs a texel, most of its shading, only
//! finding that the other lights were out of reach).
//!
//! It is written after the point lights' records, in the same buffer (the shade pass has no
//! storage binding to spare: it uses the eight every device offers), as 32-bit words: the
//! records (8 words each), then a header (columns, rows, the grid's origin and cell size as
//! float bits), then a `(first, count)` pair per cell, row by row, then the cells' lists of
//! point-light indices, ascending (so lights add up in the order they always did and the
//! frame is the same, byte for byte). `shaders/shade.wgsl` reads it (`near_points`).
//!
//! A light reaches less than its radius, in three dimensions, so a cell lists it when the
//! circle of its radius around it in X, Z overlaps the cell's rectangle (grown by a little,
//! for rounding): no light that reaches a point of the column is left out. Cells are at least
//! the lights' mean radius wide and at most [`CELLS_MAX`] a side.
//!
//! With the grid come the lights' caster roots (the header's sixth word says where they
//! start, 0 for none): per point light, a node of the shadow trees under which lies every
//! still instance whose box meets the light's ball (its radius and [`CASTER_PAD`] twice),
//! or [`CASTERS_NONE`] where none does. A shadow ray toward a point light runs within that
//! ball (it starts where the light reaches, at most [`CASTER_PAD`] off the surface), so it
//! walks that subtree rather than the whole top level and finds the same casters. The node
//! is the top level's own where one subtree holds them all; else a little tree of its own
//! ([`CASTER_NODES`] nodes a light, after the other trees: [`caster_nodes`]) over copies of
//! at most four top-level nodes that do ([`TopLevel::ball_cut`]): a town's lamps stand at
//! the street's edge, and its top level splits at the street first.

use glam::Vec3;

use super::GpuPointLight;
use crate::bvh::instances::TopLevel;
use crate::bvh::{BvhNode, INNER};

/// Farthest off its surface a shadow ray may start and still walk its light's caster root
/// (the shade pass's `LIGHT_CASTERS_PAD`; farther, it walks the whole top level).
pub const CASTER_PAD: f32 = 0.25;
/// Top-level nodes a light's caster root may gather (the copies under its own tree).
pub const CASTER_ROOTS: usize = 4;
/// Nodes of a light's own caster tree: a root, two inner nodes, four copies.
pub const CASTER_NODES: usize = 7;
/// An unused caster root of a light (`BVH_STATICS_NONE`).
pub const CASTERS_NONE: u32 = 0xffff_fffe;
/// A light's caster root where it walks the whole top level (`BVH_STATICS_ALL`).
pub const CASTERS_ALL: u32 = 0xffff_ffff;

/// Most cells along each side of the grid.
pub const CELLS_MAX: u32 = 128;
/// Words of the header.
pub const HEADER_WORDS: usize = 8;

/// The buffer's words: `points`' records, of which the first `point_count` are real lights
/// (the rest padding), then the grid over those (one cell listing all unless `grid`), then
/// with the grid, the lights' caster roots (`roots`, one a real light: [`caster_nodes`]).
pub(super) fn light_words(
    points: &[GpuPointLight],
    point_count: u32,
    grid: bool,
    roots: &[u32],
) -> Vec<u32> {
    let mut words: Vec<u32> = bytemuck::cast_slice(points).to_vec();
    let real = &points[..(point_count as usize).min(points.len())];
    let grid = match grid {
        true => Grid::over(real),
        false => Grid::over(&[]),
    };
    let cells = (grid.columns * grid.rows) as usize;
    let header = words.len();
    words.extend([
        grid.columns,
        grid.rows,
        grid.origin[0].to_bits(),
        grid.origin[1].to_bits(),
        grid.cell.to_bits(),
        0,
        0,
        0,
    ]);
    let pairs = words.len();
    words.resize(pairs + 2 * cells, 0);
    // Each light is put in the cells its reach's square covers (not every cell tested against
    // every light: an edit writes the grid again), in light order, so lists are ascending.
    let mut lists: Vec<Vec<u32>> = vec![Vec::new(); cells];
    for (i, l) in real.iter().enumerate() {
        let (columns, rows) = grid.cells_under(l);
        for row in rows {
            for column in columns.clone() {
                let (lo, hi) = grid.rect(column, row);
                if grid.all || reaches(l, lo, hi) {
                    lists[(row * grid.columns + column) as usize].push(i as u32);
                }
            }
        }
    }
    for (cell, list) in lists.iter().enumerate() {
        let first = words.len() as u32;
        words.extend(list);
        words[pairs + 2 * cell] = first;
        words[pairs + 2 * cell + 1] = list.len() as u32;
    }
    debug_assert_eq!(header + HEADER_WORDS, pairs);
    if !grid.all && roots.len() == real.len() {
        words[header + 5] = words.len() as u32;
        words.extend(roots);
    }
    words
}

/// Each real light's caster root and the nodes of the lights' own caster trees, which
/// start at node `at` ([`CASTER_NODES`] a light, unused ones zeroed); no roots without a
/// top level over still instances.
pub(super) fn caster_nodes(
    points: &[GpuPointLight],
    point_count: u32,
    top: Option<&TopLevel>,
    at: u32,
) -> (Vec<u32>, Vec<BvhNode>) {
    let real = &points[..(point_count as usize).min(points.len())];
    let mut nodes = vec![bytemuck::Zeroable::zeroed(); CASTER_NODES * real.len()];
    let Some(top) = top else {
        return (Vec::new(), nodes);
    };
    let roots = (real.iter().enumerate())
        .map(|(i, l)| {
            let own = &mut nodes[CASTER_NODES * i..CASTER_NODES * (i + 1)];
            caster_root(l, top, own, at + (CASTER_NODES * i) as u32)
        })
        .collect();
    (roots, nodes)
}

/// Light `l`'s caster root in `top`, writing its own tree into `own` (whose first node is
/// node `at`) where it needs one.
fn caster_root(l: &GpuPointLight, top: &TopLevel, own: &mut [BvhNode], at: u32) -> u32 {
    let centre = Vec3::from(l.position);
    let radius = l.radius + 2.0 * CASTER_PAD;
    if !(centre.is_finite() && radius.is_finite()) {
        return CASTERS_ALL;
    }
    // Grown a little for rounding, as the grid's cells are.
    let radius = radius + 1.0e-4 * (1.0 + radius + centre.abs().max_element());
    let cut = top.ball_cut(centre, radius, CASTER_ROOTS);
    let node = |i: u32| top.nodes[(i - top.node_offset) as usize];
    let inner = |first: u32, a: &BvhNode, b: &BvhNode| BvhNode {
        min: Vec3::from(a.min).min(Vec3::from(b.min)).to_array(),
        first,
        max: Vec3::from(a.max).max(Vec3::from(b.max)).to_array(),
        count: INNER,
    };
    match cut[..] {
        [] => CASTERS_NONE,
        [only] => only,
        // The root's children at 1 and 2; a pair of copies under 1 (at 3, 4) and, for four,
        // under 2 (at 5, 6), else a copy at 2.
        [a, b] => {
            (own[1], own[2]) = (node(a), node(b));
            own[0] = inner(at + 1, &own[1], &own[2]);
            at
        }
        _ => {
            (own[3], own[4]) = (node(cut[0]), node(cut[1]));
            own[1] = inner(at + 3, &own[3], &own[4]);
            own[2] = match cut[2..] {
                [c, d] => {
                    (own[5], own[6]) = (node(c), node(d));
                    inner(at + 5, &own[5], &own[6])
                }
                _ => node(cut[2]),
            };
            own[0] = inner(at + 1, &own[1], &own[2]);
            at
        }
    }
}

/// The grid's placement.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Grid {
    columns: u32,
    rows: u32,
    /// The corner of cell (0, 0): least X, least Z.
    origin: [f32; 2],
    /// A cell's side.
    cell: f32,
    /// Every cell lists every light (there is one cell).
    all: bool,
}

impl Grid {
    /// The grid over `lights`' reach; one cell over everything, listing every light, when
    /// they are none or their numbers are not finite.
    fn over(lights: &[GpuPointLight]) -> Grid {
        let everything = Grid {
            columns: 1,
            rows: 1,
            origin: [-1.0e30, -1.0e30],
            cell: 1.0e31,
            all: true,
        };
        let finite = |l: &GpuPointLight| {
            l.position.iter().all(|v| v.is_finite()) && l.radius.is_finite() && l.radius >= 0.0
        };
        if lights.is_empty() || !lights.iter().all(finite) {
            return everything;
        }
        let (mut lo, mut hi) = ([f32::INFINITY; 2], [f32::NEG_INFINITY; 2]);
        for l in lights {
            for (k, axis) in [0, 2].into_iter().enumerate() {
                lo[k] = lo[k].min(l.position[axis] - l.radius);
                hi[k] = hi[k].max(l.position[axis] + l.radius);
            }
        }
        let extent = (hi[0] - lo[0]).max(hi[1] - lo[1]);
        let mean_radius = lights.iter().map(|l| l.radius).sum::<f32>() / lights.len() as f32;
        let cell = mean_radius.max(extent / CELLS_MAX as f32).max(1.0e-3);
        if !(extent.is_finite() && cell.is_finite()) {
            return everything;
        }
        let count = |k: usize| (((hi[k] - lo[k]) / cell).ceil() as u32).clamp(1, CELLS_MAX);
        Grid {
            columns: count(0),
            rows: count(1),
            origin: lo,
            cell,
            all: false,
        }
    }

    /// The columns and rows whose cells the square around `l`'s reach may touch (every cell
    /// when the grid is one cell over everything).
    fn cells_under(&self, l: &GpuPointLight) -> (std::ops::Range<u32>, std::ops::Range<u32>) {
        if self.all {
            return (0..self.columns, 0..self.rows);
        }
        let span = |k: usize, axis: usize, n: u32| {
            let at = |v: f32| ((v - self.origin[k]) / self.cell).floor();
            let lo = at(l.position[axis] - l.radius) - 1.0;
            let hi = at(l.position[axis] + l.radius) + 2.0;
            (lo.max(0.0) as u32).min(n)..(hi.max(0.0) as u32).min(n)
        };
        (span(0, 0, self.columns), span(1, 2, self.rows))
    }

    /// Cell (`column`, `row`)'s rectangle in X, Z, grown by a little for rounding (the
    /// shader finds a point's cell by `floor`; the last cells reach past the lights).
    fn rect(&self, column: u32, row: u32) -> ([f32; 2], [f32; 2]) {
        let pad = 1.0e-3 * self.cell + 1.0e-4;
        let at = |k: usize, n: u32| self.origin[k] + n as f32 * self.cell;
        (
            [at(0, column) - pad, at(1, row) - pad],
            [at(0, column + 1) + pad, at(1, row + 1) + pad],
        )
    }
}

/// Whether `l`'s reach overlaps the column over the rectangle `lo..hi` (X, Z).
fn reaches(l: &GpuPointLight, lo: [f32; 2], hi: [f32; 2]) -> bool {
    let p = [l.position[0], l.position[2]];
    let d = |k: usize| (lo[k] - p[k]).max(p[k] - hi[k]).max(0.0);
    d(0) * d(0) + d(1) * d(1) <= l.radius * l.radius
}

#[cfg(test)]
mod tests {
    use super::*;
    use bytemuck::Zeroable;

    fn light(x: f32, z: f32, radius: f32) -> GpuPointLight {
        GpuPointLight {
            position: [x, 1.0, z],
            radius,
            colour: [1.0; 4],
        }
    }

    /// The lights `words` lists for the point (x, z), as the shader finds them.
    fn near(words: &[u32], records: usize, x: f32, z: f32) -> Vec<u32> {
        let h = 8 * records;
        let (columns, rows) = (words[h], words[h + 1]);
        let f = |i: usize| f32::from_bits(words[h + i]);
        let (ox, oz, cell) = (f(2), f(3), f(4));
        let (c, r) = (((x - ox) / cell).floor(), ((z - oz) / cell).floor());
        if !(c >= 0.0 && r >= 0.0 && c < columns as f32 && r < rows as f32) {
            return Vec::new();
        }
        let at = h + HEADER_WORDS + 2 * (r as usize * columns as usize + c as usize);
        let (first, count) = (words[at] as usize, words[at + 1] as usize);
        words[first..first + count].to_vec()
    }

    #[test]
    fn every_light_that_reaches_a_point_is_listed_for_it_in_order() {
        let mut rng = fastrand::Rng::with_seed(7);
        let mut lights: Vec<GpuPointLight> = (0..60)
            .map(|_| {
                light(
                    rng.f32() * 200.0 - 100.0,
                    rng.f32() * 90.0,
                    2.0 + rng.f32() * 10.0,
                )
            })
            .collect();
        lights.push(light(0.0, 0.0, 0.0));
        let words = light_words(&lights, lights.len() as u32, true, &[]);
        for _ in 0..20_000 {
            let p = [
                rng.f32() * 260.0 - 130.0,
                rng.f32() * 4.0,
                rng.f32() * 150.0 - 30.0,
            ];
            let listed = near(&words, lights.len(), p[0], p[2]);
            assert!(
                listed.windows(2).all(|w| w[0] < w[1]),
                "ascending: {listed:?}"
            );
            for (i, l) in lights.iter().enumerate() {
                let d = glam::Vec3::from(l.position).distance(glam::Vec3::from(p));
                if d < l.radius {
                    assert!(
                        listed.contains(&(i as u32)),
                        "light {i} reaches {p:?}: {listed:?}"
                    );
                }
            }
        }
        // A cell lists only lights that come near it: far fewer than all of them.
        let mean = (0..400)
            .map(|k| {
                near(
                    &words,
                    lights.len(),
                    (k % 20) as f32 * 10.0 - 95.0,
                    (k / 20) as f32 * 4.5,
                )
                .len()
            })
            .sum::<usize>() as f32
            / 400.0;
        assert!(mean < 12.0, "{mean} lights a cell on average");
    }

    /// Shadow rays toward point lights, from anywhere a light reaches and up to
    /// `CASTER_PAD` off the surface, meet a still instance walking from the light's caster
    /// root exactly when they do walking the whole top level (boxes of many sizes, scaled
    /// and turned, over a town's street; lights among them).
    #[test]
    fn a_lights_caster_root_holds_every_caster_its_rays_may_meet() {
        use crate::bvh::instances::{any_hit_instances_cpu, instance_record};
        use crate::bvh::{GpuBvh, build_bvh};
        use glam::{Mat4, Quat};
        let corners = |i: u32| {
            Vec3::new(
                [-1.0, 1.0][(i & 1) as usize],
                [-1.0, 1.0][(i >> 1 & 1) as usize],
                [-1.0, 1.0][(i >> 2) as usize],
            )
        };
        let faces = [
            [0, 1, 3, 2],
            [4, 6, 7, 5],
            [0, 4, 5, 1],
            [2, 3, 7, 6],
            [0, 2, 6, 4],
            [1, 5, 7, 3],
        ];
        let cube: Vec<[Vec3; 3]> = (faces.iter())
            .flat_map(|f| [[f[0], f[1], f[2]], [f[0], f[2], f[3]]].map(|t| t.map(corners)))
            .collect();
        let mut rng = fastrand::Rng::with_seed(3);
        let mut bvh = GpuBvh::empty();
        let root = bvh.append(&build_bvh(&cube));
        let records: Vec<_> = (0..1500)
            .map(|_| {
                let at = Vec3::new(rng.f32() * 80.0 - 40.0, 0.0, rng.f32() * 80.0 - 40.0);
                let size = Vec3::new(
                    0.1 + rng.f32() * 3.0,
                    0.2 + rng.f32() * 3.0,
                    0.1 + rng.f32() * 3.0,
                );
                let turn = Quat::from_rotation_y(rng.f32() * 6.0);
                instance_record(
                    &bvh,
                    root,
                    Mat4::from_scale_rotation_translation(size, turn, at + Vec3::Y * size.y),
                )
            })
            .collect();
        let (top, placed) = crate::bvh::instances::tests::top_over(&mut bvh, &records);
        let mut lights: Vec<GpuPointLight> = (0..40)
            .map(|_| {
                light(
                    rng.f32() * 90.0 - 45.0,
                    rng.f32() * 90.0 - 45.0,
                    1.0 + rng.f32() * 8.0,
                )
            })
            .collect();
        // Lights far from every box: nothing to walk.
        lights.extend([light(500.0, 0.0, 8.0), light(0.0, -300.0, 2.0)]);
        let at = bvh.nodes.len() as u32;
        let (roots, nodes) = caster_nodes(&lights, lights.len() as u32, Some(&top), at);
        bvh.nodes.extend_from_slice(&nodes);
        assert_eq!(roots.len(), lights.len());
        let own = roots
            .iter()
            .filter(|&&r| r >= at && r != CASTERS_NONE)
            .count();
        assert!(own > 0, "{own} lights with trees of their own");
        assert_eq!(roots[40..], [CASTERS_NONE; 2]);
        let (mut hits, mut rays) = (0, 0);
        for (l, &root) in lights.iter().zip(&roots) {
            let centre = Vec3::from(l.position);
            for _ in 0..400 {
                let p =
                    centre + (Vec3::new(rng.f32(), rng.f32(), rng.f32()) * 2.0 - 1.0) * l.radius;
                let (to, dist) = ((centre - p).normalize(), centre.distance(p));
                if dist >= l.radius || p.y < 0.0 {
                    continue;
                }
                let off = (Vec3::new(rng.f32(), rng.f32(), rng.f32()) * 2.0 - 1.0).normalize()
                    * CASTER_PAD
                    * rng.f32();
                let (start, t_max) = (p + off, dist - off.length());
                let whole = any_hit_instances_cpu(&bvh, &placed, top.node_offset, start, to, t_max);
                let near = root != CASTERS_NONE
                    && any_hit_instances_cpu(&bvh, &placed, root, start, to, t_max);
                assert_eq!(whole, near, "light at {centre}, ray from {start}");
                hits += usize::from(whole);
                rays += 1;
            }
        }
        assert!(
            hits > rays / 20 && hits < rays - rays / 20,
            "{hits} of {rays} rays hit"
        );
    }

    #[test]
    fn no_lights_or_lights_at_infinity_make_one_cell_holding_all() {
        let none = light_words(&[GpuPointLight::zeroed()], 0, true, &[]);
        assert_eq!(near(&none, 1, 3.0, 4.0), Vec::<u32>::new());
        let odd = [light(f32::INFINITY, 0.0, 3.0), light(1.0, 2.0, 3.0)];
        let words = light_words(&odd, 2, true, &[]);
        assert_eq!((words[16], words[17]), (1, 1), "one cell");
        assert_eq!(near(&words, 2, -5.0e5, 7.0e6), [0, 1]);
    }

    #[test]
    fn the_grid_is_at_most_cells_max_a_side() {
        let far = [light(-1.0e5, 0.0, 1.0), light(1.0e5, 3.0e4, 1.0)];
        let words = light_words(&far, 2, true, &[]);
        assert!(words[16] <= CELLS_MAX && words[17] <= CELLS_MAX);
        assert_eq!(near(&words, 2, 1.0e5, 3.0e4), [1]);
        assert_eq!(near(&words, 2, -1.0e5 + 0.5, 0.2), [0]);
    }
}
