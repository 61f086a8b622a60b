//! Pixel-art terrain (Populous: The Beginning's trick, after the Godot terrain seed): a
//! heightmap coloured by an elevation gradient perturbed by a tiling displacement texture,
//! quantized to a world-anchored pixel grid whose cells double in size in distance bands.
//!
//! This module holds the level component ([`Terrain`]), its heights ([`Heightfield`]: a
//! 16-bit PNG beside the level, or baked from noise) and the mesh built from them. The
//! colouring runs on the GPU (`shaders/lib/terrain.wgsl`); [`band`] and [`cell_size`] are
//! its CPU twins, for tests and tools.

use glam::{Vec2, Vec3};
use serde::{Deserialize, Serialize};

use crate::mesh::TriMesh;
use crate::num;

/// Largest heightmap edge, in samples.
pub const MAX_HEIGHTMAP: u32 = 4097;
/// Most gradient stops.
pub const MAX_GRADIENT_STOPS: usize = 64;
/// Quads per chunk edge: the mesh is built chunk by chunk, so consecutive triangles are near
/// each other and the renderer's per-range bounds cull well. A chunk's level of detail
/// comes from its nearest point, so a smaller chunk draws fewer triangles finer than its
/// distance needs, at the price of more draw calls. Captures per frame on `terrain_walk`
/// (1280×720, faces of 128, lavapipe): 25.8 ms with chunks of 32, 21.5 with 16, 20.5 with
/// 8; with its heights baked at 257×257: 33.6, 25.6 and 29.4 ms.
pub const CHUNK_QUADS: u32 = 16;

/// Where a terrain's heights come from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum HeightSource {
    /// A 16-bit greyscale PNG, path relative to the level (0 = ground level, 65535 =
    /// `max_height`); its size sets the grid.
    File {
        /// Path relative to the level file.
        path: String,
    },
    /// Fractal noise baked on load into a `resolution` × `resolution` grid.
    Noise {
        /// Seed.
        seed: u32,
        /// Samples per edge (2..=4097).
        #[serde(with = "num::heightmap_resolution")]
        resolution: u32,
        /// Features per world unit of the first octave.
        #[serde(with = "num::positive")]
        frequency: f32,
        /// Octaves (1..=8).
        #[serde(with = "num::octaves")]
        octaves: u32,
        /// Pushes the edges down (0 = none, 1 = an island whose border is at height 0).
        #[serde(default, with = "num::unit")]
        island: f32,
    },
}

/// One colour of the elevation gradient.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GradientStop {
    /// Normalised elevation (0 = ground level, 1 = `max_height`).
    #[serde(with = "num::unit")]
    pub at: f32,
    /// Linear RGB colour.
    #[serde(with = "num::colour")]
    pub colour: Vec3,
}

/// The displacement texture that perturbs the elevation looked up in the gradient.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Displacement {
    /// Greyscale PNG, path relative to the level (its red channel is read).
    pub path: String,
    /// How far a displacement of ±0.5 moves the gradient lookup (normalised elevation).
    #[serde(with = "num::intensity")]
    pub strength: f32,
    /// World size of one tile of the texture.
    #[serde(with = "num::positive")]
    pub tile_size: f32,
}

/// A colour layer painted over the gradient: an RGBA8 PNG beside the level covering the
/// terrain's extent (any size up to the texture limit). Pixel (i, j) covers the cell of the
/// extent at ((i + 0.5) / w, (j + 0.5) / h) along X and Z (rows along Z, like the
/// heightmap). Its colour is sRGB-encoded; alpha blends it over the gradient colour in linear
/// RGB (0: the gradient, 255: the paint).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PaintLayer {
    /// PNG, path relative to the level.
    pub path: String,
}

/// A heightmap terrain, centred on its transform's translation (rotation and scale are not
/// applied: a terrain is laid out along the world's axes).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Terrain {
    /// World extent along X and Z.
    #[serde(with = "num::size2")]
    pub size: Vec2,
    /// The heights.
    pub heightmap: HeightSource,
    /// Height of the top of the range, world units.
    #[serde(with = "num::positive")]
    pub max_height: f32,
    /// Colours by normalised elevation, ascending `at` (checked while parsing).
    #[serde(deserialize_with = "de_gradient")]
    pub gradient: Vec<GradientStop>,
    /// Optional displacement texture.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub displacement: Option<Displacement>,
    /// Optional colour paint over the gradient.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub paint: Option<PaintLayer>,
    /// Terrain pixels per world unit in the nearest band.
    #[serde(with = "num::positive")]
    pub pixel_density: f32,
    /// Distance from the probe within which the nearest band applies; each doubling of the
    /// distance past it halves the density.
    #[serde(with = "num::positive")]
    pub band_distance: f32,
    /// Share of each band (0..1) over which its cells are promoted to the next band's by a
    /// Bayer pattern, toward its far end.
    #[serde(with = "num::unit")]
    pub band_transition: f32,
    /// Whether it blocks shadow rays.
    #[serde(default = "yes")]
    pub casts_shadows: bool,
    /// Whether outlines are drawn on it.
    #[serde(default = "yes")]
    pub outlined: bool,
}

const fn yes() -> bool {
    true
}

/// What of `t` a terrain placed by it does not apply (a terrain is laid out along the world's
/// axes, from its translation only): a sentence naming the rotation and the scale where they
/// are not the identity's, for the loader's warning and the editor's inspector; `None` where
/// nothing is left out.
pub fn unapplied_transform(t: &crate::Transform) -> Option<String> {
    let rotated = t.rotation != glam::Vec3::ZERO;
    let scaled = t.scale != glam::Vec3::ONE;
    let what = match (rotated, scaled) {
        (false, false) => return None,
        (true, false) => format!("rotation {:?}", t.rotation.to_array()),
        (false, true) => format!("scale {:?}", t.scale.to_array()),
        (true, true) => format!(
            "rotation {:?} and scale {:?}",
            t.rotation.to_array(),
            t.scale.to_array()
        ),
    };
    Some(format!(
        "{what} not applied: a terrain lies along the world's axes, placed by its \
         translation only (set its size and max_height instead)"
    ))
}

impl Terrain {
    /// The band of a point at `distance` from the probe origin (0 = the nearest, finest),
    /// before the texel constraint: 0 within `band_distance`, then one more per doubling.
    pub fn distance_band(&self, distance: f32) -> u32 {
        if distance <= self.band_distance {
            0
        } else {
            (distance / self.band_distance).log2().ceil().max(0.0) as u32
        }
    }

    /// The band at `distance` from a probe whose faces have `face_resolution` texels: the
    /// distance band, raised until a terrain pixel is at least as large as the probe texel
    /// there (`2d / N` world units), so a terrain pixel is never smaller than an art pixel.
    pub fn band(&self, distance: f32, face_resolution: u32) -> u32 {
        let texel = 2.0 * distance / face_resolution as f32;
        let mut b = self.distance_band(distance);
        while self.cell_size(b) < texel && b < 30 {
            b += 1;
        }
        b
    }

    /// The band of every point under an orthographic probe whose texels are `texel` world
    /// units: the finest whose pixel is at least a texel. There are no distance bands: an
    /// orthographic view shows a pixel at one size on screen wherever it lies
    /// (`shaders/lib/terrain.wgsl` `BandFrom`).
    pub fn ortho_band(&self, texel: f32) -> u32 {
        let mut b = 0;
        while self.cell_size(b) < texel && b < 30 {
            b += 1;
        }
        b
    }

    /// World size of a terrain pixel in band `b`: `2^b / pixel_density`.
    pub fn cell_size(&self, band: u32) -> f32 {
        (1u64 << band.min(62)) as f32 / self.pixel_density
    }
}

/// Heights on a regular grid over a terrain's extent, world units above its origin.
#[derive(Debug, Clone, PartialEq)]
pub struct Heightfield {
    /// Samples along X.
    pub width: u32,
    /// Samples along Z.
    pub depth: u32,
    /// `width * depth` heights, row by row (Z), each row along X.
    pub heights: Vec<f32>,
}

impl Heightfield {
    /// A flat field of `width` × `depth` samples at height `h`.
    pub fn flat(width: u32, depth: u32, h: f32) -> Self {
        Heightfield {
            width,
            depth,
            heights: vec![h; (width * depth) as usize],
        }
    }

    /// The height at sample (`x`, `z`), clamped to the grid.
    pub fn at(&self, x: i64, z: i64) -> f32 {
        let x = x.clamp(0, i64::from(self.width) - 1) as usize;
        let z = z.clamp(0, i64::from(self.depth) - 1) as usize;
        self.heights[z * self.width as usize + x]
    }

    /// Bilinear height at grid coordinates (`gx`, `gz`) (sample units).
    pub fn sample(&self, gx: f32, gz: f32) -> f32 {
        let (x0, z0) = (gx.floor(), gz.floor());
        let (fx, fz) = (gx - x0, gz - z0);
        let (x0, z0) = (x0 as i64, z0 as i64);
        let a = self.at(x0, z0) * (1.0 - fx) + self.at(x0 + 1, z0) * fx;
        let b = self.at(x0, z0 + 1) * (1.0 - fx) + self.at(x0 + 1, z0 + 1) * fx;
        a * (1.0 - fz) + b * fz
    }

    /// Bakes fractal noise (`HeightSource::Noise`) over a terrain of `size` and height
    /// `max_height`.
    pub fn from_noise(source: &HeightSource, size: Vec2, max_height: f32) -> Option<Self> {
        use noise::{Fbm, MultiFractal, NoiseFn, Perlin};
        let HeightSource::Noise {
            seed,
            resolution,
            frequency,
            octaves,
            island,
        } = *source
        else {
            return None;
        };
        let fbm = Fbm::<Perlin>::new(seed)
            .set_octaves(octaves as usize)
            .set_frequency(f64::from(frequency));
        let n = resolution.max(2);
        let mut heights = Vec::with_capacity((n * n) as usize);
        for z in 0..n {
            for x in 0..n {
                let u = x as f32 / (n - 1) as f32;
                let v = z as f32 / (n - 1) as f32;
                let p = [f64::from((u - 0.5) * size.x), f64::from((v - 0.5) * size.y)];
                let h = (fbm.get(p) as f32 * 0.5 + 0.5).clamp(0.0, 1.0);
                // Distance to the nearest edge, 0 at the border and 1 in the middle.
                let edge = (1.0 - (2.0 * u - 1.0).abs()).min(1.0 - (2.0 * v - 1.0).abs());
                let fall = 1.0 - island * (1.0 - (edge * 3.0).min(1.0)).powi(2);
                heights.push(h * fall.max(0.0) * max_height);
            }
        }
        Some(Heightfield {
            width: n,
            depth: n,
            heights,
        })
    }

    /// From 16-bit samples (0..=65535 → 0..=`max_height`).
    pub fn from_u16(width: u32, depth: u32, samples: &[u16], max_height: f32) -> Self {
        Heightfield {
            width,
            depth,
            heights: samples
                .iter()
                .map(|&s| f32::from(s) / 65535.0 * max_height)
                .collect(),
        }
    }

    /// The samples as 16-bit values for `max_height` (clamped).
    pub fn to_u16(&self, max_height: f32) -> Vec<u16> {
        self.heights
            .iter()
            .map(|h| ((h / max_height).clamp(0.0, 1.0) * 65535.0).round() as u16)
            .collect()
    }

    /// The terrain's mesh with levels of detail: per chunk of [`CHUNK_QUADS`]² quads, one
    /// piece per level (every 1st, 2nd, 4th, … sample up to one quad per chunk), each with a
    /// skirt hanging from its border (`skirt` deep) so neighbouring chunks at different
    /// levels leave no crack to see through. A capture draws each chunk at the level its
    /// distance needs (`texel_geom::LodPiece`); shadows and G-buffers take level 0.
    pub fn lod_mesh(&self, size: Vec2, skirt: f32) -> TriMesh {
        use texel_geom::LodPiece;
        let (w, d) = (self.width.max(2), self.depth.max(2));
        let step = Vec2::new(size.x / (w - 1) as f32, size.y / (d - 1) as f32);
        let pos = |x: u32, z: u32| {
            Vec3::new(
                -0.5 * size.x + x as f32 * step.x,
                self.at(i64::from(x), i64::from(z)),
                -0.5 * size.y + z as f32 * step.y,
            )
        };
        let normal = |x: u32, z: u32, stride: u32| {
            let (x, z, k) = (i64::from(x), i64::from(z), i64::from(stride));
            let dx = (self.at(x + k, z) - self.at(x - k, z)) / (2.0 * k as f32 * step.x);
            let dz = (self.at(x, z + k) - self.at(x, z - k)) / (2.0 * k as f32 * step.y);
            Vec3::new(-dx, 1.0, -dz).normalize()
        };
        let mut m = TriMesh::default();
        // Chunks with their far corners, levels and bounds.
        let mut chunks = Vec::new();
        for cz in (0..d - 1).step_by(CHUNK_QUADS as usize) {
            for cx in (0..w - 1).step_by(CHUNK_QUADS as usize) {
                let (x1, z1) = ((cx + CHUNK_QUADS).min(w - 1), (cz + CHUNK_QUADS).min(d - 1));
                let span = (x1 - cx).max(z1 - cz);
                let max_lod = span.max(1).ilog2();
                let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
                for z in cz..=z1 {
                    for x in cx..=x1 {
                        lo = lo.min(pos(x, z));
                        hi = hi.max(pos(x, z));
                    }
                }
                chunks.push((cx, cz, x1, z1, max_lod, lo, hi));
            }
        }
        // Level by level, so that chunks drawn at the same level are one run of triangles.
        let top = chunks.iter().map(|c| c.4).max().unwrap_or(0);
        for lod in 0..=top {
            for (chunk, &(cx, cz, x1, z1, max_lod, lo, hi)) in chunks.iter().enumerate() {
                let chunk = chunk as u32;
                if lod > max_lod {
                    continue;
                }
                {
                    let stride = 1u32 << lod;
                    let first = m.triangle_count() as u32;
                    // Sample columns and rows of this level, always including the chunk's
                    // far edges so neighbours meet.
                    let line = |a: u32, b: u32| {
                        let mut v: Vec<u32> = (a..b).step_by(stride as usize).collect();
                        v.push(b);
                        v
                    };
                    let (xs, zs) = (line(cx, x1), line(cz, z1));
                    let base = m.positions.len() as u32;
                    let cols = xs.len() as u32;
                    for &z in &zs {
                        for &x in &xs {
                            let p = pos(x, z);
                            m.positions.push(p);
                            m.normals.push(normal(x, z, stride));
                            m.colors.push([1.0; 4]);
                            m.uvs.push(Vec2::new(p.x, p.z));
                        }
                    }
                    for j in 0..zs.len() as u32 - 1 {
                        for i in 0..cols - 1 {
                            let a = base + j * cols + i;
                            let (b, c, e) = (a + 1, a + cols, a + cols + 1);
                            m.indices.extend_from_slice(&[a, c, b, b, c, e]);
                        }
                    }
                    // The skirt: the border's samples, and copies `skirt` below them.
                    let mut border: Vec<(u32, u32)> = Vec::new();
                    border.extend(xs.iter().map(|&x| (x, cz)));
                    border.extend(zs[1..].iter().map(|&z| (x1, z)));
                    border.extend(xs.iter().rev().skip(1).map(|&x| (x, z1)));
                    border.extend(zs.iter().rev().skip(1).map(|&z| (cx, z)));
                    let centre = 0.5 * (pos(cx, cz) + pos(x1, z1));
                    for pair in border.windows(2) {
                        let [(ax, az), (bx, bz)] = [pair[0], pair[1]];
                        let (pa, pb) = (pos(ax, az), pos(bx, bz));
                        let out = {
                            let mid = 0.5 * (pa + pb) - centre;
                            Vec3::new(mid.x, 0.0, mid.z).normalize_or_zero()
                        };
                        let k = m.positions.len() as u32;
                        for p in [pa, pb, pb - Vec3::Y * skirt, pa - Vec3::Y * skirt] {
                            m.positions.push(p);
                            m.normals.push(out);
                            m.colors.push([1.0; 4]);
                            m.uvs.push(Vec2::new(p.x, p.z));
                        }
                        // Facing outward, counter-clockwise seen from outside.
                        let tri = |a: u32, b: u32, c: u32, m: &TriMesh| {
                            let n = (m.positions[b as usize] - m.positions[a as usize])
                                .cross(m.positions[c as usize] - m.positions[a as usize]);
                            if n.dot(out) >= 0.0 {
                                [a, b, c]
                            } else {
                                [a, c, b]
                            }
                        };
                        let t1 = tri(k, k + 1, k + 2, &m);
                        let t2 = tri(k, k + 2, k + 3, &m);
                        m.indices.extend_from_slice(&t1);
                        m.indices.extend_from_slice(&t2);
                    }
                    m.pieces.push(LodPiece {
                        first_triangle: first,
                        triangles: m.triangle_count() as u32 - first,
                        chunk,
                        lod,
                        max_lod,
                        spacing: step.x.max(step.y),
                        min: lo - Vec3::Y * skirt,
                        max: hi,
                    });
                }
            }
        }
        m.pieces.sort_by_key(|p| p.first_triangle);
        m
    }
}

impl crate::components::Validate for Terrain {
    fn validate(&self) -> Result<(), (&'static str, String)> {
        let field = |name, r: Result<f32, String>| r.map(|_| ()).map_err(|m| (name, m));
        field("size", num::check_positive(self.size.x, "size"))?;
        field("size", num::check_positive(self.size.y, "size"))?;
        field(
            "max_height",
            num::check_positive(self.max_height, "max height"),
        )?;
        field(
            "pixel_density",
            num::check_positive(self.pixel_density, "pixel density"),
        )?;
        field(
            "band_distance",
            num::check_positive(self.band_distance, "band distance"),
        )?;
        check_gradient(&self.gradient).map_err(|m| ("gradient", m))?;
        match &self.heightmap {
            HeightSource::File { path } if path.trim().is_empty() => {
                return Err(("heightmap", "heightmap path is empty".to_owned()));
            }
            _ => {}
        }
        if let Some(d) = &self.displacement
            && d.path.trim().is_empty()
        {
            return Err(("displacement", "displacement path is empty".to_owned()));
        }
        if let Some(p) = &self.paint
            && p.path.trim().is_empty()
        {
            return Err(("paint", "paint layer path is empty".to_owned()));
        }
        Ok(())
    }
}

fn de_gradient<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Vec<GradientStop>, D::Error> {
    let stops = Vec::<GradientStop>::deserialize(d)?;
    check_gradient(&stops).map_err(serde::de::Error::custom)?;
    Ok(stops)
}

/// A gradient has 1..=[`MAX_GRADIENT_STOPS`] stops in ascending order.
pub fn check_gradient(stops: &[GradientStop]) -> Result<(), String> {
    if stops.is_empty() {
        return Err("the gradient needs at least one colour stop".to_owned());
    }
    if stops.len() > MAX_GRADIENT_STOPS {
        return Err(format!(
            "the gradient has {} stops, at most {MAX_GRADIENT_STOPS} are allowed",
            stops.len()
        ));
    }
    if stops.windows(2).any(|w| w[1].at < w[0].at) {
        return Err("gradient stops must be in ascending order of `at`".to_owned());
    }
    Ok(())
}

#[cfg(test)]
mod tests;
