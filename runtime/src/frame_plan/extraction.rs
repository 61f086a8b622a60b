//! Extraction, once per level: the hecs world becomes the renderer's [`SceneInput`] (one
//! object per entity with geometry, its id the entity's position in the level + 1), its
//! look and player start, and the probe-grid settings that do not depend on the viewport.

use std::sync::Arc;

use glam::Vec3;
use texel_probes::grid::{GridDefaults, GridOverride};
use texel_render::input::{
    Camera, Look, MaterialInput, ObjectInput, PointLightInput, SceneInput, SunInput, TerrainInput,
};
use texel_render::palette::PaletteInput;
use texel_render::passes::bloom::BloomInput;
use texel_render::shadow_region::{scene_floor, sun_shadow_bounds};
use texel_scene::primitives::primitive_mesh;
use texel_scene::terrain::Terrain;
use texel_scene::{
    DirectionalLight, Geometry, Material, PixelScale, PlayerStart, PointLight, Scene, Transform,
};

use super::animation::Animation;
use crate::extract::{Viewport, face_resolution, grid_overrides};
use crate::load::LoadedLevel;
use crate::occluders::SceneRays;

/// What the frame driver and the renderer need of a level, extracted from it once: the scene
/// to upload, the look, the probe-grid settings that do not depend on the viewport, and the
/// player start.
#[derive(Debug, Clone)]
pub struct PreparedLevel {
    /// Sky, ambient light, bands and haze.
    pub look: Look,
    pub(super) pixel_scale: PixelScale,
    pub(super) cell_size: f32,
    pub(super) overrides: Vec<GridOverride>,
    pub(super) start: Camera,
    /// The renderer's view of the scene, and ray queries against it for probe placement.
    pub(super) rays: SceneRays,
    /// What drives each animated object.
    pub animation: Animation,
    /// The lowest point of the scene, where sun shadows end ([`scene_floor`]).
    pub(super) floor: f32,
    /// The level's palette and its alternate, as the renderer maps to them (empty: none).
    pub palettes: Vec<PaletteInput>,
    /// The level's bloom, as the renderer takes it.
    pub bloom: Option<BloomInput>,
    /// Where each entity's objects lie in the scene, by the entity's position in the level
    /// (empty for one without geometry). In level order as extracted; an entity added or
    /// given other geometry since has its objects at the end, one removed leaves blanks
    /// (`splice`).
    pub(super) rows: Vec<std::ops::Range<usize>>,
    /// The blanks left by deleted entities (in the order deleted) and the objects they
    /// held, which an entity added with the same objects takes again (`splice`).
    pub(super) graves: Vec<(std::ops::Range<usize>, Vec<ObjectInput>)>,
}

impl PreparedLevel {
    /// Extracts what frames of `level` need.
    pub fn new(level: &LoadedLevel) -> Self {
        let s = &level.scene.settings;
        let scene = scene_input(level);
        let animation = Animation::new(level, &scene);
        let rows = object_rows(&scene, level.scene.len());
        PreparedLevel {
            rows,
            graves: Vec::new(),
            animation,
            floor: scene_floor(&scene),
            rays: SceneRays::new(scene),
            look: level_look(&level.scene),
            pixel_scale: s.pixel_scale,
            cell_size: s.cell_size,
            overrides: grid_overrides(&level.scene),
            start: start_camera(&level.scene),
            palettes: level_palettes(level),
            bloom: level_bloom(&level.scene),
        }
    }

    /// The palette to map frames to: the level's, or its alternate (the first when it has
    /// none); `None` for a level without a palette.
    pub fn palette(&self, alternate: bool) -> Option<PaletteInput> {
        let i = usize::from(alternate && self.palettes.len() > 1);
        self.palettes.get(i).cloned()
    }

    /// The renderer's view of the scene.
    pub fn scene(&self) -> &SceneInput {
        self.rays.scene()
    }

    /// The box `min..max` grown by where its contents may cast sun shadows (see
    /// [`shadow_extended`]), with the scene's lowest point found once, at load.
    pub fn shadow_region(&self, min: Vec3, max: Vec3) -> (Vec3, Vec3) {
        sun_shadow_bounds(&self.scene().suns, self.floor, min, max)
    }

    /// The grid defaults on a viewport (the face resolution may follow its height).
    pub(super) fn grid_defaults(&self, viewport: Viewport) -> GridDefaults {
        GridDefaults {
            cell_size: self.cell_size,
            face_resolution: face_resolution(self.pixel_scale, viewport),
        }
    }
}

/// Where each of `count` entities' objects lie in `scene` (extracted in level order).
fn object_rows(scene: &SceneInput, count: usize) -> Vec<std::ops::Range<usize>> {
    let mut rows = vec![0..0; count];
    let mut at = 0;
    for (row, range) in rows.iter_mut().enumerate() {
        let id = entity_id(row);
        let end = at + scene.objects[at..].partition_point(|o| o.id == id);
        *range = at..end;
        at = end;
    }
    rows
}

/// The level's look: sky, ambient light, bands and haze (what every method draws with).
pub fn level_look(scene: &Scene) -> Look {
    let s = &scene.settings;
    Look {
        sky: s.sky,
        ambient: s.ambient,
        bands: s.bands,
        haze: s.haze,
    }
}

/// The level's bloom as the renderer takes it.
pub fn level_bloom(scene: &Scene) -> Option<BloomInput> {
    scene.settings.bloom.map(|b| BloomInput {
        threshold: b.threshold,
        strength: b.strength,
        radius: b.radius,
    })
}

/// The level's palette and its alternate as the renderer takes them, loaded with its assets
/// (a palette the assets lack, which a loaded level cannot have, is left out).
pub fn level_palettes(level: &LoadedLevel) -> Vec<PaletteInput> {
    let Some(setting) = &level.scene.palette else {
        return Vec::new();
    };
    (std::iter::once(&setting.file).chain(&setting.alternate))
        .filter_map(|file| level.assets.palette(file))
        .map(|p| PaletteInput {
            colours: p.colours.clone(),
            dither: setting.dither,
        })
        .collect()
}

/// The camera at the player start, or at (0, 1.6, 10) looking at the origin.
pub fn start_camera(scene: &Scene) -> Camera {
    let w = scene.world();
    for e in scene.entities() {
        if let Ok(start) = w.get::<&PlayerStart>(e) {
            let t = w.get::<&Transform>(e).map(|t| *t).unwrap_or_default();
            let eye = t.translation + Vec3::Y * start.eye_height;
            return Camera::from_yaw_pitch(eye, start.yaw, start.pitch);
        }
    }
    Camera::looking(Vec3::new(0.0, 1.6, 10.0), -Vec3::Z)
}

/// The renderer's id of the entity at `index` in the level's order (0 is the sky): the rule
/// [`scene_input`] numbers objects by and [`entity_index`] inverts.
pub fn entity_id(index: usize) -> u32 {
    index as u32 + 1
}

/// The level index of the entity a renderer id names, `None` for the sky (0).
pub fn entity_index(id: u32) -> Option<usize> {
    id.checked_sub(1).map(|i| i as usize)
}

/// The renderer's view of the scene: one object per entity with geometry, lights.
pub fn scene_input(level: &LoadedLevel) -> SceneInput {
    let mut out = SceneInput::default();
    for (index, e) in level.scene.entities().enumerate() {
        add_entity(level, index, e, &mut out);
    }
    out
}

/// Adds what entity `e`, at `index` in the level's order, brings to `out`: its object (and
/// its terrain's), its sprite, its lights.
pub(super) fn add_entity(level: &LoadedLevel, index: usize, e: hecs::Entity, out: &mut SceneInput) {
    let w = level.scene.world();
    {
        let t = w.get::<&Transform>(e).map(|t| *t).unwrap_or_default();
        if let Ok(g) = w.get::<&Geometry>(e) {
            let primitive = !matches!(&*g, Geometry::Mesh { .. });
            let mesh = match &*g {
                Geometry::Mesh { path } => level.assets.get(path).cloned(),
                other => primitive_mesh(other).map(Arc::new),
            };
            let m = w
                .get::<&Material>(e)
                .map(|m| (*m).clone())
                .unwrap_or_default();
            if let Some(mesh) = mesh {
                // Its own animator, or an animated ancestor's, moves it.
                if level.scene.carried(e).is_some() {
                    out.animated.push(out.objects.len());
                }
                out.objects.push(ObjectInput {
                    mesh,
                    transform: t.matrix(),
                    material: MaterialInput {
                        albedo: m.albedo,
                        emissive: m.emissive,
                        casts_shadows: m.casts_shadows,
                        outlined: m.outlined,
                        maps: level.assets.surface_maps(&m, primitive),
                        terrain: None,
                        specular: (m.specular).map_or(glam::Vec2::ZERO, |s| {
                            glam::Vec2::new(s.strength, s.shininess)
                        }),
                    },
                    id: entity_id(index),
                });
            }
        }
        if let Ok(terrain) = w.get::<&Terrain>(e)
            && let Some((input, mesh)) = terrain_input(&terrain, &t, &level.assets)
        {
            out.objects.push(ObjectInput {
                mesh,
                transform: glam::Mat4::from_translation(t.translation),
                material: MaterialInput {
                    albedo: Vec3::ONE,
                    emissive: Vec3::ZERO,
                    casts_shadows: terrain.casts_shadows,
                    outlined: terrain.outlined,
                    maps: Default::default(),
                    terrain: Some(out.terrains.len()),
                    specular: glam::Vec2::ZERO,
                },
                id: entity_id(index),
            });
            out.terrains.push(input);
        }
        if let Ok(sprite) = w.get::<&texel_scene::sprite::Sprite>(e)
            && let Some(input) =
                crate::level_sprites::sprite_input(&sprite, &t, &level.assets, entity_id(index))
        {
            out.sprites.push(input);
        }
        if let Ok(sun) = w.get::<&DirectionalLight>(e) {
            out.suns.push(SunInput {
                direction: sun.direction,
                colour: sun.colour * sun.intensity,
            });
        }
        if let Ok(p) = w.get::<&PointLight>(e) {
            out.points.push(PointLightInput {
                position: t.translation,
                colour: p.colour * p.intensity,
                radius: p.radius,
            });
        }
    }
}

/// A terrain's colouring and mesh, `None` when its heights are not loaded. Only the
/// transform's translation applies (terrains lie along the world axes).
pub fn terrain_input(
    terrain: &Terrain,
    t: &Transform,
    assets: &texel_scene::assets::AssetLibrary,
) -> Option<(TerrainInput, Arc<texel_scene::TriMesh>)> {
    let field = assets.heightfield(terrain)?;
    // Skirts deep enough to hide the cracks between levels: the largest height step between
    // neighbouring samples bounds what a coarser level can miss.
    let mesh = Arc::new(field.lod_mesh(terrain.size, skirt_depth(field)));
    let corner = t.translation - Vec3::new(0.5 * terrain.size.x, 0.0, 0.5 * terrain.size.y);
    let displacement = terrain.displacement.as_ref().and_then(|d| {
        let image = assets.texture(&d.path)?.clone();
        let texture = texel_render::input::TextureRef {
            image,
            sampler: Default::default(),
        };
        Some((texture, d.strength, d.tile_size))
    });
    Some((
        TerrainInput {
            corner,
            size: terrain.size,
            samples: glam::UVec2::new(field.width, field.depth),
            heights: Arc::new(field.heights.clone()),
            max_height: terrain.max_height,
            gradient: terrain.gradient.iter().map(|g| (g.at, g.colour)).collect(),
            displacement,
            paint: assets.paint(terrain).cloned(),
            pixel_density: terrain.pixel_density,
            band_distance: terrain.band_distance,
            band_transition: terrain.band_transition,
        },
        mesh,
    ))
}

/// How deep a terrain's chunk skirts hang: the steepest step between neighbouring samples,
/// times the widest stride a coarse level skips (bounded by the whole height range).
fn skirt_depth(field: &texel_scene::terrain::Heightfield) -> f32 {
    let mut step: f32 = 0.0;
    let (w, d) = (i64::from(field.width), i64::from(field.depth));
    for z in 0..d {
        for x in 0..w {
            let h = field.at(x, z);
            step = step
                .max((field.at(x + 1, z) - h).abs())
                .max((field.at(x, z + 1) - h).abs());
        }
    }
    let (lo, hi) = field
        .heights
        .iter()
        .fold((f32::MAX, f32::MIN), |(a, b), &h| (a.min(h), b.max(h)));
    (step * texel_scene::terrain::CHUNK_QUADS as f32 * 0.5)
        .min(hi - lo)
        .max(0.05)
}

/// The box `min..max` grown by where its contents may cast sun shadows: each corner pushed
/// along every sun's direction until it has dropped to the lowest point of the scene (at
/// most 200 units along the ray; [`sun_shadow_bounds`]).
pub fn shadow_extended(scene: &SceneInput, min: Vec3, max: Vec3) -> (Vec3, Vec3) {
    sun_shadow_bounds(&scene.suns, scene_floor(scene), min, max)
}
