//! Generated levels for benchmarks and tests (`texel-run gen`): a town or a forest of any
//! number of entities at a constant density, deterministic from a seed.
//!
//! The level is square, its side growing with the square root of the count so that a walk
//! down its middle sees about as much at any size. A street runs along Z through the middle
//! (x = 0), kept clear, with the player start at its south end looking north: the walk a
//! benchmark takes. Around it:
//!
//! - a **town**: houses (boxes with a roof box), walls, lamp posts (cylinders) with point
//!   lights, balls, and copies of the given glTF meshes (crates, arches);
//! - a **forest**: trees (a cylinder trunk and a sphere crown), rocks (spheres), and copies of
//!   the meshes.
//!
//! The ground is a plane, or with `terrain` a noise terrain whose heights the entities stand
//! on. Every count, size and colour comes from one `fastrand` generator seeded with `seed`, so
//! the same options give the same file on every machine.

use glam::{Vec2, Vec3};
use texel_scene::sculpt::Placement;
use texel_scene::terrain::{GradientStop, HeightSource, Heightfield, Terrain};
use texel_scene::{
    DirectionalLight, EntityRow, Geometry, Level, Material, Name, PlayerStart, PointLight,
    Transform,
};

/// What kind of place to generate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Kind {
    /// Houses, walls, lamp posts with lights, props and meshes along streets.
    Town,
    /// Trees, rocks and meshes scattered over open ground.
    Forest,
}

/// Options of a generated level.
#[derive(Debug, Clone, PartialEq)]
pub struct GenOptions {
    /// The kind of place.
    pub kind: Kind,
    /// Entities in all (ground, sun, lights and player start included), at least 8.
    pub count: usize,
    /// The seed of every random choice.
    pub seed: u64,
    /// Entities per 100 m² of ground (the level's side follows from the count).
    pub density: f32,
    /// A noise terrain instead of a flat plane.
    pub terrain: bool,
    /// Most point lights (a town's lamp posts carry them; a forest's hang over clearings).
    pub max_lights: usize,
    /// glTF meshes placed as repeated copies, as paths relative to the level file.
    pub meshes: Vec<String>,
}

impl Default for GenOptions {
    fn default() -> Self {
        GenOptions {
            kind: Kind::Town,
            count: 1000,
            seed: 1,
            density: 4.0,
            terrain: false,
            max_lights: 64,
            meshes: Vec::new(),
        }
    }
}

/// Fewest entities a generated level has (ground, sun, player start and a few objects).
pub const MIN_COUNT: usize = 8;
/// Most entities (a level file of about 30 MiB, within the loader's 64 MiB cap).
pub const MAX_COUNT: usize = 100_000;
/// Half the width of the street kept clear along Z through the middle.
pub const STREET_HALF_WIDTH: f32 = 2.5;

/// Why options cannot make a level.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct GenError(String);

/// The level `options` describe.
pub fn generate(options: &GenOptions) -> Result<Level, GenError> {
    check(options)?;
    let mut g = Generator::new(options);
    g.fixed();
    while g.rows.len() < options.count {
        match options.kind {
            Kind::Town => g.town_item(),
            Kind::Forest => g.forest_item(),
        }
    }
    g.rows.truncate(options.count);
    Ok(Level {
        entities: g.rows,
        ..Level::default()
    })
}

fn check(o: &GenOptions) -> Result<(), GenError> {
    let bad = |m: String| Err(GenError(m));
    if !(MIN_COUNT..=MAX_COUNT).contains(&o.count) {
        return bad(format!(
            "count must be between {MIN_COUNT} and {MAX_COUNT}, not {}",
            o.count
        ));
    }
    if !(o.density.is_finite() && (0.01..=50.0).contains(&o.density)) {
        return bad(format!(
            "density must be between 0.01 and 50 entities per 100 m², not {}",
            o.density
        ));
    }
    if let Some(m) = o.meshes.iter().find(|m| m.trim().is_empty()) {
        return bad(format!("a mesh path is empty: {m:?}"));
    }
    Ok(())
}

/// The side of the square level for `count` entities at `density` per 100 m².
pub fn side(count: usize, density: f32) -> f32 {
    (count as f32 * 100.0 / density).sqrt().max(24.0)
}

struct Generator<'a> {
    o: &'a GenOptions,
    rng: fastrand::Rng,
    rows: Vec<EntityRow>,
    half: f32,
    ground: Option<(Placement, Heightfield)>,
    lights: usize,
    serial: usize,
}

impl<'a> Generator<'a> {
    fn new(o: &'a GenOptions) -> Self {
        let half = side(o.count, o.density) / 2.0;
        Generator {
            o,
            rng: fastrand::Rng::with_seed(o.seed),
            rows: Vec::with_capacity(o.count),
            half,
            ground: None,
            lights: 0,
            serial: 0,
        }
    }

    /// The ground, the sun and the player start.
    fn fixed(&mut self) {
        let size = Vec2::splat(2.0 * self.half + 8.0);
        if self.o.terrain {
            let resolution = ((size.x / 1.5) as u32).clamp(33, 1025);
            let heightmap = HeightSource::Noise {
                seed: self.o.seed as u32,
                resolution,
                frequency: 0.02,
                octaves: 4,
                island: 0.0,
            };
            let max_height = 6.0;
            let stop = |at, r, g, b| GradientStop {
                at,
                colour: Vec3::new(r, g, b),
            };
            let terrain = Terrain {
                size,
                heightmap,
                max_height,
                gradient: vec![
                    stop(0.0, 0.45, 0.42, 0.3),
                    stop(0.3, 0.25, 0.42, 0.16),
                    stop(0.7, 0.18, 0.34, 0.12),
                    stop(1.0, 0.5, 0.48, 0.45),
                ],
                displacement: None,
                paint: None,
                pixel_density: 4.0,
                band_distance: 12.0,
                band_transition: 0.3,
                casts_shadows: true,
                outlined: true,
            };
            self.ground = Heightfield::from_noise(&terrain.heightmap, size, max_height)
                .map(|field| (Placement::new(&terrain, Vec3::ZERO, &field), field));
            self.rows.push(EntityRow {
                name: Some(Name("Ground".into())),
                transform: Some(Transform::default()),
                terrain: Some(terrain),
                ..EntityRow::default()
            });
        } else {
            self.rows.push(EntityRow {
                name: Some(Name("Ground".into())),
                transform: Some(Transform::default()),
                geometry: Some(Geometry::Plane { size }),
                material: Some(material(Vec3::new(0.32, 0.42, 0.22), false)),
                ..EntityRow::default()
            });
        }
        self.rows.push(EntityRow {
            name: Some(Name("Sun".into())),
            directional_light: Some(DirectionalLight {
                direction: Vec3::new(-0.4, -1.0, -0.3),
                colour: Vec3::new(1.0, 0.95, 0.85),
                intensity: 1.0,
            }),
            ..EntityRow::default()
        });
        let start = Vec3::new(0.0, self.height(0.0, self.half - 2.0), self.half - 2.0);
        self.rows.push(EntityRow {
            name: Some(Name("Player start".into())),
            transform: Some(Transform {
                translation: start,
                ..Transform::default()
            }),
            player_start: Some(PlayerStart::default()),
            ..EntityRow::default()
        });
    }

    /// The ground's height at (x, z).
    fn height(&self, x: f32, z: f32) -> f32 {
        (self.ground.as_ref()).map_or(0.0, |(placement, field)| {
            placement.surface(field, Vec3::new(x, 0.0, z)).y
        })
    }

    /// A random spot off the street, and the ground's height there.
    fn spot(&mut self, clearance: f32) -> Vec3 {
        let reach = self.half - clearance;
        let side = if self.rng.bool() { 1.0 } else { -1.0 };
        let min = STREET_HALF_WIDTH + clearance;
        let x = side * (min + self.rng.f32() * (reach - min).max(0.0));
        let z = (self.rng.f32() * 2.0 - 1.0) * reach;
        Vec3::new(x, self.height(x, z), z)
    }

    fn push(&mut self, what: &str, at: Vec3, yaw: f32, geometry: Geometry, albedo: Vec3) {
        self.serial += 1;
        self.rows.push(EntityRow {
            name: Some(Name(format!("{what} {}", self.serial))),
            transform: Some(Transform {
                translation: at,
                rotation: Vec3::new(0.0, yaw, 0.0),
                scale: Vec3::ONE,
            }),
            geometry: Some(geometry),
            material: Some(material(albedo, true)),
            ..EntityRow::default()
        });
    }

    /// A box of `size` standing on `base` (its bottom face's centre), turned by `yaw`.
    fn push_box(&mut self, what: &str, base: Vec3, yaw: f32, size: Vec3, albedo: Vec3) {
        let centre = base + Vec3::Y * size.y / 2.0;
        self.push(what, centre, yaw, Geometry::Box { size }, albedo);
    }

    fn tint(&mut self, base: Vec3, spread: f32) -> Vec3 {
        let r = &mut self.rng;
        (base + Vec3::new(r.f32(), r.f32(), r.f32()) * spread - spread / 2.0)
            .clamp(Vec3::ZERO, Vec3::ONE)
    }

    fn mesh(&mut self, at: Vec3) -> bool {
        if self.o.meshes.is_empty() {
            return false;
        }
        let path = self.o.meshes[self.rng.usize(..self.o.meshes.len())].clone();
        let yaw = self.rng.f32() * 360.0;
        let albedo = self.tint(Vec3::new(0.55, 0.45, 0.35), 0.2);
        self.push("Mesh", at, yaw, Geometry::Mesh { path }, albedo);
        true
    }

    fn light(&mut self, at: Vec3) {
        if self.lights >= self.o.max_lights {
            return;
        }
        self.lights += 1;
        self.rows.push(EntityRow {
            name: Some(Name(format!("Light {}", self.lights))),
            transform: Some(Transform {
                translation: at,
                ..Transform::default()
            }),
            point_light: Some(PointLight::default()),
            ..EntityRow::default()
        });
    }

    fn town_item(&mut self) {
        let roll = self.rng.f32();
        if roll < 0.35 {
            // A house: walls and a roof.
            let size = Vec3::new(
                3.0 + self.rng.f32() * 4.0,
                2.5 + self.rng.f32() * 4.0,
                3.0 + self.rng.f32() * 4.0,
            );
            let at = self.spot(size.x.max(size.z) / 2.0);
            let yaw = (self.rng.u32(0..4) * 90) as f32;
            let wall = self.tint(Vec3::new(0.7, 0.62, 0.5), 0.2);
            self.push_box("House", at, yaw, size, wall);
            let roof = Vec3::new(size.x + 0.4, 0.5, size.z + 0.4);
            let red = self.tint(Vec3::new(0.55, 0.22, 0.16), 0.15);
            self.push_box("Roof", at + Vec3::Y * size.y, yaw, roof, red);
        } else if roll < 0.5 {
            let length = 2.0 + self.rng.f32() * 5.0;
            let at = self.spot(length / 2.0);
            let yaw = self.rng.f32() * 180.0;
            let stone = self.tint(Vec3::new(0.5, 0.48, 0.45), 0.1);
            self.push_box("Wall", at, yaw, Vec3::new(length, 1.2, 0.4), stone);
        } else if roll < 0.6 {
            // A lamp post at the street's edge, with its light.
            let side = if self.rng.bool() { 1.0 } else { -1.0 };
            let z = (self.rng.f32() * 2.0 - 1.0) * (self.half - 1.0);
            let x = side * (STREET_HALF_WIDTH + 0.5);
            let at = Vec3::new(x, self.height(x, z), z);
            let iron = Vec3::new(0.15, 0.15, 0.17);
            let post = Geometry::Cylinder {
                radius: 0.1,
                height: 3.0,
                segments: 8,
            };
            self.push("Lamp post", at + Vec3::Y * 1.5, 0.0, post, iron);
            self.light(at + Vec3::Y * 3.2);
        } else if roll < 0.8 {
            let at = self.spot(1.0);
            if !self.mesh(at) {
                let wood = self.tint(Vec3::new(0.5, 0.36, 0.2), 0.1);
                let size = Vec3::splat(0.6 + self.rng.f32() * 0.6);
                let yaw = self.rng.f32() * 90.0;
                self.push_box("Crate", at, yaw, size, wood);
            }
        } else {
            let radius = 0.2 + self.rng.f32() * 0.5;
            let at = self.spot(radius);
            let colour = self.tint(Vec3::new(0.5, 0.5, 0.6), 0.5);
            let ball = Geometry::Sphere {
                radius,
                segments: 12,
            };
            self.push("Ball", at + Vec3::Y * radius, 0.0, ball, colour);
        }
    }

    fn forest_item(&mut self) {
        let roll = self.rng.f32();
        if roll < 0.6 {
            let height = 2.0 + self.rng.f32() * 3.0;
            let crown = 1.0 + self.rng.f32() * 1.5;
            let at = self.spot(crown);
            let bark = self.tint(Vec3::new(0.35, 0.25, 0.15), 0.08);
            let trunk = Geometry::Cylinder {
                radius: 0.2,
                height,
                segments: 8,
            };
            self.push("Trunk", at + Vec3::Y * height / 2.0, 0.0, trunk, bark);
            let leaves = self.tint(Vec3::new(0.2, 0.42, 0.15), 0.15);
            let ball = Geometry::Sphere {
                radius: crown,
                segments: 12,
            };
            self.push(
                "Crown",
                at + Vec3::Y * (height + crown * 0.7),
                0.0,
                ball,
                leaves,
            );
        } else if roll < 0.85 {
            let radius = 0.3 + self.rng.f32() * 0.9;
            let at = self.spot(radius);
            let grey = self.tint(Vec3::new(0.45, 0.44, 0.42), 0.1);
            let rock = Geometry::Sphere {
                radius,
                segments: 8,
            };
            self.push("Rock", at + Vec3::Y * radius * 0.5, 0.0, rock, grey);
        } else if roll < 0.97 {
            let at = self.spot(1.0);
            if !self.mesh(at) {
                let log = self.tint(Vec3::new(0.4, 0.3, 0.2), 0.1);
                let yaw = self.rng.f32() * 180.0;
                let size = Vec3::new(2.0, 0.4, 0.4);
                self.push_box("Log", at, yaw, size, log);
            }
        } else {
            let at = self.spot(1.0);
            self.light(at + Vec3::Y * 2.5);
        }
    }
}

fn material(albedo: Vec3, casts_shadows: bool) -> Material {
    Material {
        albedo,
        casts_shadows,
        ..Material::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn options(kind: Kind, count: usize) -> GenOptions {
        GenOptions {
            kind,
            count,
            meshes: vec!["m/crate.glb".into()],
            ..GenOptions::default()
        }
    }

    fn text(level: &Level) -> String {
        level.to_ron_string(Path::new("gen.ron")).expect("valid")
    }

    #[test]
    fn the_same_seed_gives_the_same_level_and_another_seed_another() {
        for kind in [Kind::Town, Kind::Forest] {
            let a = generate(&options(kind, 300)).unwrap();
            let b = generate(&options(kind, 300)).unwrap();
            assert_eq!(text(&a), text(&b));
            let other = GenOptions {
                seed: 2,
                ..options(kind, 300)
            };
            assert_ne!(text(&a), text(&generate(&other).unwrap()));
        }
    }

    #[test]
    fn a_level_has_exactly_the_count_asked_for_and_reads_back() {
        for (kind, count, terrain) in [
            (Kind::Town, 8, false),
            (Kind::Town, 1001, true),
            (Kind::Forest, 777, false),
            (Kind::Forest, 50, true),
        ] {
            let o = GenOptions {
                terrain,
                ..options(kind, count)
            };
            let level = generate(&o).unwrap();
            assert_eq!(level.entities.len(), count);
            let back = Level::from_ron_str(&text(&level), Path::new("gen.ron")).unwrap();
            assert_eq!(back.entities.len(), count);
            assert_eq!(
                level
                    .entities
                    .iter()
                    .filter(|e| e.terrain.is_some())
                    .count(),
                usize::from(terrain)
            );
        }
    }

    #[test]
    fn the_street_stays_clear_and_the_density_holds() {
        let level = generate(&options(Kind::Town, 4000)).unwrap();
        let half = side(4000, 4.0) / 2.0;
        let mut meshes = 0;
        for e in &level.entities {
            let (Some(t), Some(g)) = (&e.transform, &e.geometry) else {
                continue;
            };
            if matches!(g, Geometry::Plane { .. }) {
                continue;
            }
            meshes += usize::from(matches!(g, Geometry::Mesh { .. }));
            let p = t.translation;
            assert!(p.x.abs() > STREET_HALF_WIDTH, "{:?} on the street", e.name);
            assert!(
                p.x.abs() <= half && p.z.abs() <= half,
                "{:?} outside",
                e.name
            );
        }
        // A mesh is used many times (instancing's case).
        assert!(meshes > 100, "{meshes} mesh copies");
        // Four times the entities, twice the side.
        assert!((side(4000, 4.0) / side(1000, 4.0) - 2.0).abs() < 1e-3);
    }

    #[test]
    fn bad_options_are_refused_with_the_reason() {
        for (o, phrase) in [
            (options(Kind::Town, 3), "count"),
            (options(Kind::Town, MAX_COUNT + 1), "count"),
            (
                GenOptions {
                    density: f32::NAN,
                    ..options(Kind::Town, 100)
                },
                "density",
            ),
            (
                GenOptions {
                    meshes: vec![" ".into()],
                    ..options(Kind::Town, 100)
                },
                "mesh path",
            ),
        ] {
            let e = generate(&o).unwrap_err();
            assert!(e.to_string().contains(phrase), "{e}");
        }
    }

    /// The largest town fits lavapipe's limits (a storage binding of 128 MiB, a buffer of
    /// 2 GiB): its boxes and balls cast through one shape each (`gpu_scene::shapes`), where
    /// their 3.1 M triangles in one flat tree needed a binding of 189 MiB. CPU only: the
    /// scene check the renderer makes before uploading.
    #[test]
    fn the_largest_town_fits_lavapipes_limits() {
        use texel_render::gpu_scene::shapes::ShadowShapes;
        let level = generate(&GenOptions {
            count: MAX_COUNT,
            ..GenOptions::default()
        })
        .expect("generates");
        let loaded = crate::load::LoadedLevel {
            path: "town.ron".into(),
            scene: texel_scene::Scene::from_level(&level),
            assets: Default::default(),
        };
        let scene = crate::frame_plan::scene_input(&loaded);
        let lavapipe = wgpu::Limits {
            max_storage_buffer_binding_size: 128 << 20,
            max_buffer_size: 2 << 30,
            ..wgpu::Limits::default()
        };
        let shapes = ShadowShapes::new(&scene, true);
        assert!(shapes.instances() > 90_000, "{}", shapes.instances());
        texel_render::validate::scene_shaped(&lavapipe, &scene, &shapes).expect("fits");
        let flat = ShadowShapes::new(&scene, false);
        let e = texel_render::validate::scene_shaped(&lavapipe, &scene, &flat).unwrap_err();
        assert!(e.to_string().contains("shadow BVH"), "{e}");
    }
}
