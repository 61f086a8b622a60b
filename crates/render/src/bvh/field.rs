//! Terrains as shadow casters: a heightfield's rays walk a max-height quadtree over its cells
//! instead of its triangles in the BVH.
//!
//! A terrain of 257 × 257 samples is 131,072 triangles; in the BVH their boxes overlap
//! along every slope, and a shadow or edge ray skimming the hills (the probes see terrain at
//! grazing angles) opens hundreds of them. Here the terrain's cells form a quadtree whose
//! nodes hold the highest height under them: a ray skips a node when it passes above that
//! height over the whole node, and only in the cells it may cross are the two triangles
//! tested, with the same Möller–Trumbore test as the BVH's and the same split of each cell
//! as the terrain's mesh (`texel_scene::terrain::Heightfield::lod_mesh` level 0: triangles
//! `(x, z) (x, z + 1) (x + 1, z)` and `(x + 1, z) (x, z + 1) (x + 1, z + 1)`), so the answer
//! is the triangles' answer. `field_hit` in `shaders/lib/bvh.wgsl` is [`HeightField::hit`],
//! step for step.
//!
//! The walk happens in the field's grid space (x and z in cells, y in world units above the
//! corner): an affine map of the ray, so `t` means the same point in both.
//!
//! # GPU layout
//!
//! Every field's numbers sit in one `r32float` 2D array texture read as a flat list
//! ([`DATA_WIDTH`] texels a row, as many rows a layer): a field's heights (samples row by
//! row along X, one row per Z sample), then its levels, finest first: level 0 holds each
//! cell's highest corner, level k the highest of its 2 × 2 children at level k − 1
//! (`ceil(cells / 2^k)` nodes per axis), up to one node. Each field's record
//! (`BvhField`, [`GpuField`]) says where its heights and levels start; up to
//! [`MAX_FIELDS`] records sit in one uniform block after the field count ([`GpuFields`]).

use bytemuck::{Pod, Zeroable};
use glam::{UVec2, Vec2, Vec3};

use super::{BvhTriangle, DIR_EPS};

/// Terrains walked as fields (`BVH_MAX_FIELDS`); more terrains keep their triangles in the
/// BVH.
pub const MAX_FIELDS: usize = 8;
/// Cells per axis a field may have (node coordinates are kept in 14 bits).
pub const MAX_CELLS: u32 = 4096;
/// Texels per row of the data texture, and rows per layer.
pub const DATA_WIDTH: u32 = 2048;
/// Quadtree levels a field may have: 4096 cells per axis make 13.
pub const MAX_LEVELS: usize = 16;
/// Entries of the walk's stack (`FIELD_STACK` in WGSL): four children pushed per level
/// below the root, one of them taken at once, so 3 × 13 + 1 at most.
pub const FIELD_STACK: usize = 48;

/// One terrain's heights, ready to walk.
#[derive(Clone, Debug, PartialEq)]
pub struct HeightField {
    /// World position of sample (0, 0) at height 0.
    pub corner: Vec3,
    /// World size of a cell along X and Z.
    pub step: Vec2,
    /// Cells along X and Z (samples − 1).
    pub cells: UVec2,
    /// Heights above `corner`, row by row (Z), each row along X.
    pub heights: Vec<f32>,
    /// Level k: the highest height over each node, `dims(k)` of them, row by row.
    pub levels: Vec<Vec<f32>>,
}

impl HeightField {
    /// A field over `samples` heights spanning `size` from `corner`, or `None` when it cannot
    /// be one (fewer than 2 or more than [`MAX_CELLS`] + 1 samples per axis, a height count
    /// that does not match, a non-finite height or corner, an extent that is not positive).
    pub fn new(corner: Vec3, size: Vec2, samples: UVec2, heights: &[f32]) -> Option<Self> {
        if !walkable(corner, size, samples, heights) {
            return None;
        }
        let cells = samples - 1;
        let step = size / cells.as_vec2();
        let w = samples.x as usize;
        let at = |x: u32, z: u32| heights[z as usize * w + x as usize];
        let mut level0 = Vec::with_capacity((cells.x * cells.y) as usize);
        for z in 0..cells.y {
            for x in 0..cells.x {
                level0.push(
                    at(x, z)
                        .max(at(x + 1, z))
                        .max(at(x, z + 1))
                        .max(at(x + 1, z + 1)),
                );
            }
        }
        let mut field = HeightField {
            corner,
            step,
            cells,
            heights: heights.to_vec(),
            levels: vec![level0],
        };
        while field.dims(field.levels.len() - 1) != UVec2::ONE {
            let k = field.levels.len();
            let (child, dims) = (field.dims(k - 1), field.dims(k));
            let below = &field.levels[k - 1];
            let mut level = Vec::with_capacity((dims.x * dims.y) as usize);
            for j in 0..dims.y {
                for i in 0..dims.x {
                    let mut m = f32::NEG_INFINITY;
                    for (ci, cj) in [(2 * i, 2 * j), (2 * i + 1, 2 * j), (2 * i, 2 * j + 1)]
                        .into_iter()
                        .chain([(2 * i + 1, 2 * j + 1)])
                    {
                        if ci < child.x && cj < child.y {
                            m = m.max(below[(cj * child.x + ci) as usize]);
                        }
                    }
                    level.push(m);
                }
            }
            field.levels.push(level);
        }
        Some(field)
    }

    /// Nodes per axis at level `k`.
    pub fn dims(&self, k: usize) -> UVec2 {
        (self.cells + (1 << k) - 1) >> k as u32
    }

    /// Floats this field takes in the data texture.
    pub fn data_len(&self) -> usize {
        self.heights.len() + self.levels.iter().map(Vec::len).sum::<usize>()
    }

    fn height(&self, x: u32, z: u32) -> f32 {
        self.heights[(z * (self.cells.x + 1) + x) as usize]
    }

    /// Cell (`x`, `z`)'s two triangles in grid space, as the mesh splits it.
    fn cell_triangles(&self, x: u32, z: u32) -> [BvhTriangle; 2] {
        let p = |x: u32, z: u32| Vec3::new(x as f32, self.height(x, z), z as f32);
        let (a, b, c, e) = (p(x, z), p(x + 1, z), p(x, z + 1), p(x + 1, z + 1));
        [
            BvhTriangle::new(0, &[a, c, b]),
            BvhTriangle::new(0, &[b, c, e]),
        ]
    }

    /// The field's triangles in world space, as the terrain mesh's level 0 holds them.
    pub fn triangles(&self) -> Vec<[Vec3; 3]> {
        let mut out = Vec::with_capacity(2 * (self.cells.x * self.cells.y) as usize);
        let world = |x: u32, z: u32| {
            self.corner
                + Vec3::new(
                    x as f32 * self.step.x,
                    self.height(x, z),
                    z as f32 * self.step.y,
                )
        };
        for z in 0..self.cells.y {
            for x in 0..self.cells.x {
                let (a, b, c, e) = (
                    world(x, z),
                    world(x + 1, z),
                    world(x, z + 1),
                    world(x + 1, z + 1),
                );
                out.push([a, c, b]);
                out.push([b, c, e]);
            }
        }
        out
    }

    /// Where a walk starts: the part of the ray over the field's cells and below its highest
    /// height, and the finest level whose nodes cover that part's cells two by two at most
    /// (that level and its first and last node along X and Z), or `None` when no part is
    /// left. A ray that climbs away from the hills (toward a light) or runs a short way
    /// (an edge ray) starts a few levels above the cells, not at the root.
    fn start(&self, o: Vec3, d: Vec3, inv: Vec2, t_max: f32) -> Option<(u32, UVec2, UVec2)> {
        let oxz = Vec2::new(o.x, o.z);
        let cells = self.cells.as_vec2();
        let (t0, t1) = (
            (Vec2::splat(-NODE_MARGIN) - oxz) * inv,
            (cells + NODE_MARGIN - oxz) * inv,
        );
        let mut near = t0.min(t1).max_element().max(0.0);
        let mut far = t0.max(t1).min_element().min(t_max);
        let top = self.levels[self.levels.len() - 1][0];
        let top = top + height_margin(top);
        if d.y > 0.0 {
            far = far.min((top - o.y) / d.y);
        } else if d.y < 0.0 {
            near = near.max((top - o.y) / d.y);
        } else if o.y > top {
            return None;
        }
        if near > far {
            return None;
        }
        let dxz = Vec2::new(d.x, d.z);
        let (a, b) = (oxz + dxz * near, oxz + dxz * far);
        let last = (self.cells - 1).as_vec2();
        let cell = |p: Vec2| p.floor().clamp(Vec2::ZERO, last).as_uvec2();
        let (lo, hi) = (cell(a.min(b) - NODE_MARGIN), cell(a.max(b) + NODE_MARGIN));
        let mut k = 0;
        while k + 1 < self.levels.len() as u32
            && ((hi.x >> k) - (lo.x >> k) > 1 || (hi.y >> k) - (lo.y >> k) > 1)
        {
            k += 1;
        }
        Some((k, lo >> k, hi >> k))
    }

    /// The ray in grid space: origin and direction.
    fn to_grid(&self, origin: Vec3, dir: Vec3) -> (Vec3, Vec3) {
        let inv = self.step.recip();
        let o = origin - self.corner;
        (
            Vec3::new(o.x * inv.x, o.y, o.z * inv.y),
            Vec3::new(dir.x * inv.x, dir.y, dir.z * inv.y),
        )
    }

    /// Whether the ray `origin + t * dir` crosses one of the field's triangles at `t` in
    /// `(T_MIN, t_max)`: `field_hit` in `shaders/lib/bvh.wgsl`, on the CPU.
    pub fn hit(&self, origin: Vec3, dir: Vec3, t_max: f32) -> bool {
        self.hit_from(origin, dir, t_max, false)
    }

    /// [`HeightField::hit`], the quadtree's children taken farthest first when `far_first`
    /// (the same answer, sooner for a ray whose hit lies near `t_max`).
    pub fn hit_from(&self, origin: Vec3, dir: Vec3, t_max: f32, far_first: bool) -> bool {
        let (o, d) = self.to_grid(origin, dir);
        let safe = Vec2::select(
            Vec2::new(d.x, d.z).abs().cmplt(Vec2::splat(DIR_EPS)),
            Vec2::splat(DIR_EPS),
            Vec2::new(d.x, d.z),
        );
        let inv = safe.recip();
        let oxz = Vec2::new(o.x, o.z);
        let mut stack = [0u32; FIELD_STACK];
        let Some((k, lo, hi)) = self.start(o, d, inv, t_max) else {
            return false;
        };
        let mut sp = 0;
        for j in lo.y..=hi.y {
            for i in lo.x..=hi.x {
                stack[sp] = node_key(k, i, j);
                sp += 1;
            }
        }
        while sp > 0 {
            sp -= 1;
            let (k, i, j) = node_parts(stack[sp]);
            let lo = (UVec2::new(i, j) << k).as_vec2() - NODE_MARGIN;
            let hi = ((UVec2::new(i, j) + 1) << k).min(self.cells).as_vec2() + NODE_MARGIN;
            let (t0, t1) = ((lo - oxz) * inv, (hi - oxz) * inv);
            let near = t0.min(t1).max_element().max(0.0);
            let far = t0.max(t1).min_element().min(t_max);
            if near > far {
                continue;
            }
            let y = (o.y + d.y * near).min(o.y + d.y * far);
            let dims = self.dims(k as usize);
            let top = self.levels[k as usize][(j * dims.x + i) as usize];
            if y > top + height_margin(top) {
                continue;
            }
            if k == 0 {
                if self.cell_triangles(i, j).iter().any(|t| t.hit(o, d, t_max)) {
                    return true;
                }
                continue;
            }
            let child = self.dims(k as usize - 1);
            // Farthest child first, so the nearest is taken next (or the other way round).
            let (nx, nz) = (
                u32::from((d.x < 0.0) != far_first),
                u32::from((d.z < 0.0) != far_first),
            );
            for (a, b) in [(1 - nx, 1 - nz), (nx, 1 - nz), (1 - nx, nz), (nx, nz)] {
                let (ci, cj) = (2 * i + a, 2 * j + b);
                if ci < child.x && cj < child.y {
                    if sp == FIELD_STACK {
                        return true; // cannot happen (see FIELD_STACK); err towards shadow
                    }
                    stack[sp] = node_key(k - 1, ci, cj);
                    sp += 1;
                }
            }
        }
        false
    }
}

/// Whether [`HeightField::new`] takes these: 2 to [`MAX_CELLS`] + 1 samples per axis, as
/// many heights, all finite, a finite corner and a positive finite extent.
pub fn walkable(corner: Vec3, size: Vec2, samples: UVec2, heights: &[f32]) -> bool {
    let ok_axis = |n: u32| (2..=MAX_CELLS + 1).contains(&n);
    ok_axis(samples.x)
        && ok_axis(samples.y)
        && heights.len() == (samples.x * samples.y) as usize
        && corner.is_finite()
        && size.x > 0.0
        && size.y > 0.0
        && size.is_finite()
        && heights.iter().all(|h| h.is_finite())
}

/// Which of a scene's terrains cast through their fields (the first [`MAX_FIELDS`] that are
/// [`walkable`]); the others' triangles stay in the BVH.
pub fn walked_terrains(terrains: &[crate::input::TerrainInput]) -> Vec<bool> {
    let mut left = MAX_FIELDS;
    terrains
        .iter()
        .map(|t| {
            let walk = left > 0 && walkable(t.corner, t.size, t.samples, &t.heights);
            left -= usize::from(walk);
            walk
        })
        .collect()
}

/// Cells a node's rectangle is grown by on each side before the ray is clipped to it, far
/// more than the slab test's rounding, so no cell the ray crosses is skipped.
pub const NODE_MARGIN: f32 = 1e-3;

/// How far above a node's highest height a ray may pass and still open it: more than the
/// rounding of the ray's height at the node's ends.
fn height_margin(top: f32) -> f32 {
    1e-4 * (1.0 + top.abs())
}

fn node_key(k: u32, i: u32, j: u32) -> u32 {
    k << 28 | i << 14 | j
}

fn node_parts(key: u32) -> (u32, u32, u32) {
    (key >> 28, (key >> 14) & 0x3fff, key & 0x3fff)
}

/// One field's record (112 bytes; WGSL `BvhField` in `lib/bvh.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuField {
    /// World position of sample (0, 0) at height 0.
    pub corner: [f32; 3],
    /// Quadtree levels.
    pub levels: u32,
    /// 1 / cell size along X and Z.
    pub inv_step: [f32; 2],
    /// Cells along X and Z.
    pub cells: [u32; 2],
    /// Where the heights start in the data.
    pub heights_at: u32,
    /// The terrain (index into `SceneInput::terrains`) whose heights these are.
    pub terrain: u32,
    _pad: [u32; 2],
    /// Where each level starts in the data.
    pub level_at: [u32; MAX_LEVELS],
}

/// The uniform block of fields (`BvhFields` in WGSL).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuFields {
    /// Records in use.
    pub count: u32,
    _pad: [u32; 3],
    /// The records.
    pub fields: [GpuField; MAX_FIELDS],
}

const _: () = assert!(size_of::<GpuField>() == 112 && size_of::<GpuFields>() == 16 + 8 * 112);

/// The fields' records and their data, one flat list (at least one float: bindings need
/// something); each field with the index of the terrain it walks.
pub fn pack(fields: &[(usize, &HeightField)]) -> (GpuFields, Vec<f32>) {
    let mut block = GpuFields::zeroed();
    let mut data = Vec::with_capacity(fields.iter().map(|f| f.1.data_len()).sum::<usize>().max(1));
    for (slot, &(terrain, f)) in block.fields.iter_mut().zip(fields) {
        let mut rec = GpuField {
            terrain: terrain as u32,
            corner: f.corner.to_array(),
            levels: f.levels.len() as u32,
            inv_step: f.step.recip().to_array(),
            cells: f.cells.to_array(),
            heights_at: data.len() as u32,
            ..GpuField::default()
        };
        data.extend_from_slice(&f.heights);
        for (k, level) in f.levels.iter().enumerate() {
            rec.level_at[k] = data.len() as u32;
            data.extend_from_slice(level);
        }
        *slot = rec;
        block.count += 1;
    }
    if data.is_empty() {
        data.push(0.0);
    }
    (block, data)
}

/// The data texture's size (`DATA_WIDTH` wide, rows up to `DATA_WIDTH` a layer, layers) for
/// `len` floats.
pub fn data_extent(len: usize) -> wgpu::Extent3d {
    let rows = (len.max(1) as u32).div_ceil(DATA_WIDTH);
    wgpu::Extent3d {
        width: DATA_WIDTH,
        height: rows.min(DATA_WIDTH),
        depth_or_array_layers: rows.div_ceil(DATA_WIDTH),
    }
}

/// The data texture for `data` (from [`pack`]): `r32float`, [`data_extent`] in size, the
/// rest zero; its view as the 2D array `bvh_field_data` binds.
pub fn upload_data(device: &wgpu::Device, queue: &wgpu::Queue, data: &[f32]) -> wgpu::TextureView {
    use wgpu::util::DeviceExt;
    let extent = data_extent(data.len());
    let mut texels = data.to_vec();
    texels.resize(
        (extent.width * extent.height * extent.depth_or_array_layers) as usize,
        0.0,
    );
    let texture = device.create_texture_with_data(
        queue,
        &wgpu::TextureDescriptor {
            label: Some("bvh::field_data"),
            size: extent,
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::R32Float,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        bytemuck::cast_slice(&texels),
    );
    texture.create_view(&wgpu::TextureViewDescriptor {
        label: Some("bvh::field_data"),
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    })
}

#[cfg(test)]
mod tests;
