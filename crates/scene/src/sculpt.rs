//! Sculpting a terrain's heights on the CPU: where a terrain's height samples lie in the
//! world ([`Placement`]), the hit of a ray on the heights ([`ray_hit`]), the brushes and one
//! application of them ([`Brush`], [`Dab`], [`dab`]), their falloff, and rectangles of
//! samples ([`Region`]) with the world box they may reach ([`Placement::region_bounds`]).
//! The editor's terrain tool and `texel-run play`'s raise and lower keys both sculpt
//! through it; no GPU, no UI.
//!
//! Heights stay in world units above the terrain's origin, clamped to `0..=max_height`: what
//! a 16-bit heightmap file can hold, so what is sculpted is what can be saved.

use std::sync::Arc;

use glam::{Vec2, Vec3};

use crate::assets::AssetLibrary;
use crate::terrain::{Heightfield, Terrain};
use crate::{Scene, Transform};

/// Raise and lower move the heights by `strength × max_height × RAISE_RATE` per second at the
/// brush's centre.
pub const RAISE_RATE: f32 = 0.5;
/// Smooth, flatten and set-height close `strength × BLEND_RATE` of the gap per second at the
/// brush's centre.
pub const BLEND_RATE: f32 = 10.0;
/// The noise brush moves the heights by up to `strength × max_height × NOISE_RATE` per second.
pub const NOISE_RATE: f32 = 0.25;
/// Most steps a ray marches over a terrain (long rays take longer steps).
const MAX_MARCH: f32 = 8192.0;

/// translation), `size` across, heights up from `origin.y`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement {
    /// The terrain's transform's translation.
    pub origin: Vec3,
    /// World extent along X and Z.
    pub size: Vec2,
    /// Samples along X.
    pub width: u32,
    /// Samples along Z.
    pub depth: u32,
    /// Top of the height range (heights lie in `0..=max_height`).
    pub max_height: f32,
}

impl Placement {
    /// The placement of `field` as the heights of `terrain` at `origin`.
    pub fn new(terrain: &Terrain, origin: Vec3, field: &Heightfield) -> Self {
        Placement {
            origin,
            size: terrain.size,
            width: field.width.max(2),
            depth: field.depth.max(2),
            max_height: terrain.max_height,
        }
    }

    /// World units between neighbouring samples along X and Z.
    pub fn spacing(&self) -> Vec2 {
        Vec2::new(
            self.size.x / (self.width - 1) as f32,
            self.size.y / (self.depth - 1) as f32,
        )
    }

    /// Grid coordinates (sample units) of the world point `p` (its X and Z).
    pub fn to_grid(&self, p: Vec3) -> Vec2 {
        let local = Vec2::new(p.x - self.origin.x, p.z - self.origin.z) + 0.5 * self.size;
        local / self.spacing()
    }

    /// The world point at grid coordinates `g` and height `h` above the origin.
    pub fn to_world(&self, g: Vec2, h: f32) -> Vec3 {
        let local = g * self.spacing() - 0.5 * self.size;
        self.origin + Vec3::new(local.x, h, local.y)
    }

    /// Whether the world point's X and Z lie over the terrain.
    pub fn covers(&self, p: Vec3) -> bool {
        let g = self.to_grid(p);
        (0.0..=(self.width - 1) as f32).contains(&g.x)
            && (0.0..=(self.depth - 1) as f32).contains(&g.y)
    }

    /// The world surface point of `field` above the world point's X and Z (clamped to the
    /// terrain's edge).
    pub fn surface(&self, field: &Heightfield, p: Vec3) -> Vec3 {
        let g = self.to_grid(p);
        let g = g.clamp(
            Vec2::ZERO,
            Vec2::new((self.width - 1) as f32, (self.depth - 1) as f32),
        );
        self.to_world(g, field.sample(g.x, g.y))
    }

    /// The world box of the samples `r` over the whole height range (a region's heights may
    /// have moved anywhere in it), one sample wider each side and a unit above and below:
    /// what a sculpted region's refresh must look at
    /// (`texel_runtime::session::Session::update_level_region`).
    pub fn region_bounds(&self, r: Region) -> (Vec3, Vec3) {
        let step = Vec2::new(
            self.size.x / (self.width.max(2) - 1) as f32,
            self.size.y / (self.depth.max(2) - 1) as f32,
        );
        let corner = self.origin - Vec3::new(0.5 * self.size.x, 0.0, 0.5 * self.size.y);
        let at = |x: u32, z: u32| corner + Vec3::new(x as f32 * step.x, 0.0, z as f32 * step.y);
        let lo = at(r.x0.saturating_sub(1), r.z0.saturating_sub(1));
        let hi = at(r.x1 + 1, r.z1 + 1);
        (
            Vec3::new(lo.x, self.origin.y - 1.0, lo.z),
            Vec3::new(hi.x, self.origin.y + self.max_height + 1.0, hi.z),
        )
    }
}

/// Where the ray from `origin` along `dir` first meets the surface of `field` placed at
/// `place`, marching it over the terrain's box in steps of half a sample and refining the
/// crossing by bisection. `None` when it misses (or `dir` is not a direction).
pub fn ray_hit(place: &Placement, field: &Heightfield, origin: Vec3, dir: Vec3) -> Option<Vec3> {
    if field.width != place.width || field.depth != place.depth {
        return None;
    }
    let dir = dir.try_normalize()?;
    if !origin.is_finite() {
        return None;
    }
    let half = 0.5 * place.size;
    let lo = place.origin + Vec3::new(-half.x, -1e-3, -half.y);
    let hi = place.origin + Vec3::new(half.x, place.max_height + 1e-3, half.y);
    let (mut t0, mut t1) = (0.0f32, f32::MAX);
    for k in 0..3 {
        if dir[k].abs() < 1e-12 {
            if origin[k] < lo[k] || origin[k] > hi[k] {
                return None;
            }
            continue;
        }
        let (a, b) = ((lo[k] - origin[k]) / dir[k], (hi[k] - origin[k]) / dir[k]);
        t0 = t0.max(a.min(b));
        t1 = t1.min(a.max(b));
    }
    if t0 > t1 {
        return None;
    }
    let above = |t: f32| {
        let p = origin + dir * t;
        let g = place.to_grid(p);
        p.y - (place.origin.y + field.sample(g.x, g.y))
    };
    let step = (0.5 * place.spacing().min_element()).max((t1 - t0) / MAX_MARCH);
    let mut prev = t0;
    if above(prev) <= 0.0 {
        return Some(origin + dir * prev);
    }
    loop {
        let t = (prev + step).min(t1);
        if above(t) <= 0.0 {
            let (mut a, mut b) = (prev, t);
            for _ in 0..24 {
                let m = 0.5 * (a + b);
                if above(m) <= 0.0 {
                    b = m;
                } else {
                    a = m;
                }
            }
            return Some(origin + dir * b);
        }
        if t >= t1 {
            return None;
        }
        prev = t;
    }
}

/// What a brush does.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum BrushKind {
    /// Raises the ground (Ctrl lowers).
    #[default]
    Raise,
    /// Lowers the ground (Ctrl raises).
    Lower,
    /// Pulls each sample toward the mean of its neighbours.
    Smooth,
    /// Pulls the ground toward the height under the stroke's start.
    Flatten,
    /// Pulls the ground toward a given height.
    SetHeight,
    /// Adds value noise (Ctrl subtracts it).
    Noise,
    /// Paints the terrain's colour layer (Ctrl erases it); the heights stay ([`dab`] does
    /// nothing; the editor's paint stroke does the painting).
    Paint,
}

impl BrushKind {
    /// Every brush, in the order the tool lists them.
    pub const ALL: [BrushKind; 7] = [
        BrushKind::Raise,
        BrushKind::Lower,
        BrushKind::Smooth,
        BrushKind::Flatten,
        BrushKind::SetHeight,
        BrushKind::Noise,
        BrushKind::Paint,
    ];

    /// The brush's name in the tool.
    pub fn label(self) -> &'static str {
        match self {
            BrushKind::Raise => "Raise",
            BrushKind::Lower => "Lower",
            BrushKind::Smooth => "Smooth",
            BrushKind::Flatten => "Flatten",
            BrushKind::SetHeight => "Set height",
            BrushKind::Noise => "Noise",
            BrushKind::Paint => "Paint",
        }
    }
}

/// A sculpting brush.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Brush {
    /// What it does.
    pub kind: BrushKind,
    /// Radius, world units.
    pub radius: f32,
    /// How fast it works, 0..=1.
    pub strength: f32,
    /// Share of the radius (0..=1) over which its effect eases out toward the rim.
    pub falloff: f32,
    /// The height [`BrushKind::SetHeight`] pulls toward, world units above the terrain's
    /// origin.
    pub height: f32,
    /// The colour [`BrushKind::Paint`] lays down, sRGB (its strength is the paint's opacity).
    pub colour: [u8; 3],
}

impl Default for Brush {
    fn default() -> Self {
        Brush {
            kind: BrushKind::Raise,
            radius: 4.0,
            strength: 0.5,
            falloff: 0.5,
            height: 2.0,
            colour: [196, 72, 48],
        }
    }
}

/// The brush's weight at `d` = distance from its centre over its radius: 1 inside the
/// un-faded core, easing (smoothstep) to 0 at the rim, 0 outside.
pub fn falloff_weight(d: f32, falloff: f32) -> f32 {
    if d.is_nan() || d >= 1.0 {
        return 0.0;
    }
    let inner = 1.0 - falloff.clamp(0.0, 1.0);
    if d <= inner {
        return 1.0;
    }
    let s = 1.0 - (d - inner) / (1.0 - inner).max(1e-6);
    s * s * (3.0 - 2.0 * s)
}

/// One application of a brush.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dab {
    /// The brush's centre, a world point (its X and Z count).
    pub centre: Vec3,
    /// Seconds this dab stands for.
    pub dt: f32,
    /// Ctrl is held: raise lowers, lower raises, noise is subtracted.
    pub invert: bool,
    /// The height [`BrushKind::Flatten`] pulls toward (the stroke's start), world units
    /// above the terrain's origin.
    pub target: f32,
}

/// A rectangle of samples, `x0..x1` × `z0..z1`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Region {
    /// First column.
    pub x0: u32,
    /// First row.
    pub z0: u32,
    /// One past the last column.
    pub x1: u32,
    /// One past the last row.
    pub z1: u32,
}

impl Region {
    /// Every sample of `field`.
    pub fn whole(field: &Heightfield) -> Self {
        Region {
            x0: 0,
            z0: 0,
            x1: field.width,
            z1: field.depth,
        }
    }

    /// The smallest region holding both.
    pub fn union(self, o: Region) -> Region {
        Region {
            x0: self.x0.min(o.x0),
            z0: self.z0.min(o.z0),
            x1: self.x1.max(o.x1),
            z1: self.z1.max(o.z1),
        }
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        (self.x1.saturating_sub(self.x0) as usize) * (self.z1.saturating_sub(self.z0) as usize)
    }

    /// Whether it holds no sample.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Whether it lies inside a `width` × `depth` grid.
    pub fn fits(&self, width: u32, depth: u32) -> bool {
        self.x0 <= self.x1 && self.z0 <= self.z1 && self.x1 <= width && self.z1 <= depth
    }
}

/// The heights of `region` of `field`, row by row.
pub fn copy_region(field: &Heightfield, region: Region) -> Vec<f32> {
    let w = field.width as usize;
    let mut out = Vec::with_capacity(region.len());
    for z in region.z0..region.z1 {
        let row = z as usize * w;
        out.extend_from_slice(&field.heights[row + region.x0 as usize..row + region.x1 as usize]);
    }
    out
}

/// Writes `values` (row by row, as [`copy_region`] gives them) into `region` of `field`.
pub fn paste_region(field: &mut Heightfield, region: Region, values: &[f32]) {
    let (w, rw) = (field.width as usize, (region.x1 - region.x0) as usize);
    for (k, z) in (region.z0..region.z1).enumerate() {
        let row = z as usize * w + region.x0 as usize;
        field.heights[row..row + rw].copy_from_slice(&values[k * rw..(k + 1) * rw]);
    }
}

/// Applies one dab of `brush` to `field` (placed at `place`) and returns the samples it
/// changed, `None` when the brush covers no sample (or paints, which leaves the heights).
/// Heights stay within `0..=max_height`.
pub fn dab(field: &mut Heightfield, place: &Placement, brush: &Brush, dab: &Dab) -> Option<Region> {
    if brush.kind == BrushKind::Paint
        || field.width != place.width
        || field.depth != place.depth
        || brush.radius.is_nan()
        || brush.radius <= 0.0
        || !dab.centre.is_finite()
        || !dab.dt.is_finite()
    {
        return None;
    }
    let spacing = place.spacing();
    let g = place.to_grid(dab.centre);
    let reach = Vec2::splat(brush.radius) / spacing;
    let (w, d) = (field.width as f32, field.depth as f32);
    let x0 = (g.x - reach.x).floor().clamp(0.0, w) as u32;
    let x1 = ((g.x + reach.x).ceil() + 1.0).clamp(0.0, w) as u32;
    let z0 = (g.y - reach.y).floor().clamp(0.0, d) as u32;
    let z1 = ((g.y + reach.y).ceil() + 1.0).clamp(0.0, d) as u32;
    let region = Region { x0, z0, x1, z1 };
    if region.is_empty() {
        return None;
    }
    let max = place.max_height;
    let strength = brush.strength.clamp(0.0, 1.0);
    let dt = dab.dt.max(0.0);
    let sign = match (brush.kind, dab.invert) {
        (BrushKind::Lower, false) | (BrushKind::Raise | BrushKind::Noise, true) => -1.0,
        _ => 1.0,
    };
    let noise_scale = (brush.radius / 3.0).max(1e-3);
    // New heights are worked out from the old ones first (smoothing reads neighbours), then
    // written.
    let before: &Heightfield = field;
    let mut changed = Vec::new();
    let mut touched: Option<Region> = None;
    for z in region.z0..region.z1 {
        for x in region.x0..region.x1 {
            let offset = (Vec2::new(x as f32, z as f32) - g) * spacing;
            let weight = falloff_weight(offset.length() / brush.radius, brush.falloff);
            if weight <= 0.0 {
                continue;
            }
            let (xi, zi) = (i64::from(x), i64::from(z));
            let h = before.at(xi, zi);
            let blend = (strength * BLEND_RATE * weight * dt).min(1.0);
            let next = match brush.kind {
                BrushKind::Raise | BrushKind::Lower => {
                    h + sign * strength * max * RAISE_RATE * weight * dt
                }
                BrushKind::Smooth => {
                    let mut sum = 0.0;
                    for dz in -1..=1 {
                        for dx in -1..=1 {
                            sum += before.at(xi + dx, zi + dz);
                        }
                    }
                    h + (sum / 9.0 - h) * blend
                }
                BrushKind::Flatten => h + (dab.target - h) * blend,
                BrushKind::SetHeight => h + (brush.height - h) * blend,
                BrushKind::Noise => {
                    let p = place.to_world(Vec2::new(x as f32, z as f32), 0.0);
                    let n = value_noise(p.x / noise_scale, p.z / noise_scale);
                    h + sign * n * strength * max * NOISE_RATE * weight * dt
                }
                BrushKind::Paint => h,
            };
            let next = next.clamp(0.0, max);
            if next.is_finite() {
                changed.push(((z * before.width + x) as usize, next));
            }
            let here = Region {
                x0: x,
                z0: z,
                x1: x + 1,
                z1: z + 1,
            };
            touched = Some(touched.map_or(here, |t| t.union(here)));
        }
    }
    for (i, h) in changed {
        field.heights[i] = h;
    }
    touched
}

/// Smooth value noise in -1..=1 on a unit lattice: hashed corner values, smoothstep-blended,
/// plus a second octave at twice the frequency.
pub fn value_noise(x: f32, z: f32) -> f32 {
    fn corner(i: i32, j: i32) -> f32 {
        let mut h = (i as u32).wrapping_mul(0x8da6_b343) ^ (j as u32).wrapping_mul(0xd816_3841);
        h ^= h >> 15;
        h = h.wrapping_mul(0x2c1b_3c6d);
        h ^= h >> 12;
        h = h.wrapping_mul(0x297a_2d39);
        h ^= h >> 15;
        (h & 0xffff) as f32 / 32767.5 - 1.0
    }
    fn octave(x: f32, z: f32) -> f32 {
        let (fx, fz) = (x.floor(), z.floor());
        let (i, j) = (fx as i32, fz as i32);
        let ease = |t: f32| t * t * (3.0 - 2.0 * t);
        let (u, v) = (ease(x - fx), ease(z - fz));
        let a = corner(i, j) + (corner(i + 1, j) - corner(i, j)) * u;
        let b = corner(i, j + 1) + (corner(i + 1, j + 1) - corner(i, j + 1)) * u;
        a + (b - a) * v
    }
    if !(x.is_finite() && z.is_finite()) {
        return 0.0;
    }
    (octave(x, z) * 2.0 + octave(2.0 * x + 17.3, 2.0 * z - 5.1)) / 3.0
}

/// A terrain of a scene that a ray meets ([`scene_ray_hit`]).
#[derive(Debug, Clone)]
pub struct TerrainHit {
    /// The terrain's entity.
    pub entity: hecs::Entity,
    /// Its terrain component.
    pub terrain: Terrain,
    /// Its heights.
    pub field: Arc<Heightfield>,
    /// Where they lie in the world.
    pub place: Placement,
    /// The surface point the ray meets first.
    pub point: Vec3,
}

/// The nearest point where the ray from `origin` along `dir` meets one of the terrains of
/// `scene` whose heights `assets` holds ([`ray_hit`] on each; a terrain lies along the world
/// axes at its transform's translation). `None` when it meets none.
pub fn scene_ray_hit(
    scene: &Scene,
    assets: &AssetLibrary,
    origin: Vec3,
    dir: Vec3,
) -> Option<TerrainHit> {
    let world = scene.world();
    scene
        .entities()
        .filter_map(|entity| {
            let terrain = world.get::<&Terrain>(entity).ok()?;
            let field = assets.heightfield(&terrain)?.clone();
            let at = world
                .get::<&Transform>(entity)
                .map_or(Vec3::ZERO, |t| t.translation);
            let place = Placement::new(&terrain, at, &field);
            let point = ray_hit(&place, &field, origin, dir)?;
            Some(TerrainHit {
                entity,
                terrain: (*terrain).clone(),
                field,
                place,
                point,
            })
        })
        .min_by(|a, b| {
            let (da, db) = (a.point.distance(origin), b.point.distance(origin));
            da.total_cmp(&db)
        })
}

#[cfg(test)]
mod tests;
