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

use super::GpuPointLight;

/// Most cells along each side of the grid.
pub const CELLS_MAX: u32 = 128;
/// Words of the header.
pub const HEADER_WORDS: usize = 8;

/// The buffer's words: `points`' records, of which the first `point_count` are real lights
/// (the rest padding), then the grid over those (one cell listing all unless `grid`).
pub(super) fn light_words(points: &[GpuPointLight], point_count: u32, grid: bool) -> Vec<u32> {
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
    words
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
        let words = light_words(&lights, lights.len() as u32, true);
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

    #[test]
    fn no_lights_or_lights_at_infinity_make_one_cell_holding_all() {
        let none = light_words(&[GpuPointLight::zeroed()], 0, true);
        assert_eq!(near(&none, 1, 3.0, 4.0), Vec::<u32>::new());
        let odd = [light(f32::INFINITY, 0.0, 3.0), light(1.0, 2.0, 3.0)];
        let words = light_words(&odd, 2, true);
        assert_eq!((words[16], words[17]), (1, 1), "one cell");
        assert_eq!(near(&words, 2, -5.0e5, 7.0e6), [0, 1]);
    }

    #[test]
    fn the_grid_is_at_most_cells_max_a_side() {
        let far = [light(-1.0e5, 0.0, 1.0), light(1.0e5, 3.0e4, 1.0)];
        let words = light_words(&far, 2, true);
        assert!(words[16] <= CELLS_MAX && words[17] <= CELLS_MAX);
        assert_eq!(near(&words, 2, 1.0e5, 3.0e4), [1]);
        assert_eq!(near(&words, 2, -1.0e5 + 0.5, 0.2), [0]);
    }
}
