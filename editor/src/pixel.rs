//! Pixel-perfect tools: how a textured entity's texture compares with the art pixel, and
//! where to stand to see it 1:1.
//!
//! In a texel-splat world the art pixel is the probe texel: at Chebyshev distance `d` from
//! the probe, on faces of `N` texels, a texel spans `2d / N` world units, so a texture of `ρ`
//! pixels per world unit is 1:1 at `d = N / (2ρ)` (`texel_probes::resolution`). The face
//! resolution `N` is the level's on the viewport (a fixed one, or the one its pixel size asks
//! for at the viewport's height and field of view).

use std::collections::HashMap;

use glam::{IVec3, Vec3};
use texel_probes::resolution::{
    ResolutionRange, face_resolution_for_density, one_to_one_distance, texture_pixels_per_art_pixel,
};
use texel_runtime::extract::{Viewport as ExtractViewport, face_resolution};
use texel_scene::assets::AssetLibrary;
use texel_scene::density::surface_density;
use texel_scene::primitives::primitive_mesh;
use texel_scene::{EntityRow, Geometry, LevelSettings};

use crate::camera::EditorCamera;

/// How a textured entity's texture meets the art pixel on the current viewport.
#[derive(Debug, Clone, PartialEq)]
pub struct PixelInfo {
    /// The albedo texture (level-relative path, or the glTF image's name).
    pub texture: String,
    /// Texture pixels per world unit along the surface (`surface_density`).
    pub density: f32,
    /// The level's face resolution on the viewport.
    pub face_resolution: u32,
    /// Distance at which one texture pixel is one art pixel.
    pub one_to_one: f32,
    /// The level's reference distance.
    pub reference_distance: f32,
    /// Texture pixels per art pixel at the reference distance (1 is pixel-perfect, below 1
    /// magnified, above minified).
    pub at_reference: f32,
}

/// The pixel-perfect numbers of `row` (`None` when it has no loaded texture), with the level
/// `settings` on `viewport`.
pub fn pixel_info(
    row: &EntityRow,
    settings: &LevelSettings,
    assets: &AssetLibrary,
    viewport: ExtractViewport,
) -> Option<PixelInfo> {
    let (geometry, material) = (row.geometry.as_ref()?, row.material.as_ref()?);
    let transform = row.transform.unwrap_or_default();
    let density = surface_density(geometry, material, &transform, assets)?;
    let rho = density.pixels_per_unit();
    let n = face_resolution(settings.pixel_scale, viewport);
    let one_to_one = one_to_one_distance(n, rho).ok()?;
    let reference_distance = settings.reference_distance;
    Some(PixelInfo {
        texture: density.texture,
        density: rho,
        face_resolution: n,
        one_to_one,
        reference_distance,
        at_reference: texture_pixels_per_art_pixel(rho, reference_distance, n),
    })
}

/// The face resolution that makes a texture of `density` pixels per world unit 1:1 at
/// `distance`: the exact value, and that value rounded and clamped to the engine's range
/// (multiples of 8 in 16..=2048).
pub fn face_resolution_for_one_to_one(density: f32, distance: f32) -> Result<(f32, u32), String> {
    let raw = face_resolution_for_density(density, distance).map_err(|e| e.to_string())?;
    let snapped = ResolutionRange::default()
        .snap(raw)
        .map_err(|e| e.to_string())?;
    Ok((raw, snapped))
}

/// A set of an entity's triangles sharing one world normal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Face {
    /// Area-weighted centroid, world space.
    pub centroid: Vec3,
    /// Unit normal (area-weighted mean of its triangles').
    pub normal: Vec3,
    /// Total area.
    pub area: f32,
    /// Σ area × how squarely each triangle faces the eye (cosine toward it, clamped at 0).
    pub facing: f32,
}

/// Triangles whose unit normals agree this closely are one face (about 1.8°).
const SAME_NORMAL: f32 = 0.9995;
/// Normals are bucketed on a lattice of this step before being compared.
const NORMAL_STEP: f32 = 1.0 / 64.0;

#[derive(Default)]
struct Group {
    normal: Vec3,
    weighted_normal: Vec3,
    weighted_centroid: Vec3,
    area: f32,
    facing: f32,
}

/// Groups world-space `triangles` by normal and returns the face that most faces `eye`: the
/// group with the largest area-weighted facing (when none faces it, the largest group).
/// Groups are by normal only: parallel faces at different places (both sides of a notch)
/// are one face whose centroid lies between them. `None` without a triangle of some area.
pub fn facing_face(triangles: impl IntoIterator<Item = [Vec3; 3]>, eye: Vec3) -> Option<Face> {
    let mut groups: Vec<Group> = Vec::new();
    let mut buckets: HashMap<IVec3, Vec<usize>> = HashMap::new();
    for [a, b, c] in triangles {
        let cross = (b - a).cross(c - a);
        let area = 0.5 * cross.length();
        let n = cross.normalize_or_zero();
        if !(area.is_finite() && area > 0.0) || n == Vec3::ZERO {
            continue;
        }
        let centroid = (a + b + c) / 3.0;
        if !centroid.is_finite() {
            continue;
        }
        let key = (n / NORMAL_STEP).round().as_ivec3();
        let mut found = None;
        'search: for dz in -1..=1 {
            for dy in -1..=1 {
                for dx in -1..=1 {
                    let k = key + IVec3::new(dx, dy, dz);
                    for &g in buckets.get(&k).into_iter().flatten() {
                        if groups[g].normal.dot(n) > SAME_NORMAL {
                            found = Some(g);
                            break 'search;
                        }
                    }
                }
            }
        }
        let g = found.unwrap_or_else(|| {
            groups.push(Group {
                normal: n,
                ..Group::default()
            });
            buckets.entry(key).or_default().push(groups.len() - 1);
            groups.len() - 1
        });
        let toward = (eye - centroid).normalize_or_zero();
        let g = &mut groups[g];
        g.weighted_normal += n * area;
        g.weighted_centroid += centroid * area;
        g.area += area;
        g.facing += area * n.dot(toward).max(0.0);
    }
    let best = groups
        .iter()
        .max_by(|x, y| {
            (x.facing, x.area)
                .partial_cmp(&(y.facing, y.area))
                .unwrap_or(std::cmp::Ordering::Equal)
        })
        .filter(|g| g.area > 0.0)?;
    Some(Face {
        centroid: best.weighted_centroid / best.area,
        normal: best.weighted_normal.try_normalize().unwrap_or(best.normal),
        area: best.area,
        facing: best.facing,
    })
}

/// The world-space triangles of `row`'s geometry (a primitive, or its glTF mesh when
/// loaded).
pub fn world_triangles(row: &EntityRow, assets: &AssetLibrary) -> Option<Vec<[Vec3; 3]>> {
    let geometry = row.geometry.as_ref()?;
    let owned;
    let mesh = match geometry {
        Geometry::Mesh { path } => &**assets.get(path)?,
        g => {
            owned = primitive_mesh(g)?;
            &owned
        }
    };
    let m = row.transform.unwrap_or_default().matrix();
    let p = |i: u32| {
        mesh.positions
            .get(i as usize)
            .map(|&v| m.transform_point3(v))
    };
    Some(
        mesh.indices
            .chunks_exact(3)
            .filter_map(|t| Some([p(t[0])?, p(t[1])?, p(t[2])?]))
            .collect(),
    )
}

/// Points `camera` straight at `face` from `distance` along its normal. The camera looks
/// along −normal; on floors and ceilings it looks straight down or up (pitch ±90°, which the
/// render camera supports with +Z as the view's up) and keeps its heading.
pub fn look_at_face(camera: &mut EditorCamera, face: &Face, distance: f32) {
    let forward = -face.normal;
    let pitch = forward.y.clamp(-1.0, 1.0).asin().to_degrees();
    if forward.y.abs() < 0.999 {
        camera.yaw_deg = (-forward.x)
            .atan2(-forward.z)
            .to_degrees()
            .rem_euclid(360.0);
        camera.pitch_deg = pitch;
    } else {
        camera.pitch_deg = pitch.signum() * 90.0;
    }
    camera.distance = distance;
    camera.eye = face.centroid + face.normal * distance;
}

/// Moves `camera` to see `row`'s texture 1:1: perpendicular to the face of it that most faces
/// the camera, from the 1:1 distance of its texture with the level's face resolution on
/// `viewport`. Returns that face and distance; an error says why it cannot (no texture
/// loaded, no geometry).
pub fn frame_one_to_one(
    camera: &mut EditorCamera,
    row: &EntityRow,
    settings: &LevelSettings,
    assets: &AssetLibrary,
    viewport: ExtractViewport,
) -> Result<(Face, f32), String> {
    let info = pixel_info(row, settings, assets, viewport)
        .ok_or("the selected entity has no loaded texture")?;
    let triangles = world_triangles(row, assets).ok_or("the selected entity has no geometry")?;
    let face = facing_face(triangles, camera.eye).ok_or("the selected entity has no faces")?;
    let d = info.one_to_one;
    if !(d.is_finite() && d > 0.0) {
        return Err(format!("no usable 1:1 distance ({d})"));
    }
    look_at_face(camera, &face, d);
    Ok((face, d))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec2;
    use texel_scene::{Material, PixelScale, TextureMap, Transform};

    fn unit_box_triangles(at: Vec3) -> Vec<[Vec3; 3]> {
        let row = EntityRow {
            transform: Some(Transform::from_translation(at)),
            geometry: Some(Geometry::Box { size: Vec3::ONE }),
            ..EntityRow::default()
        };
        world_triangles(&row, &AssetLibrary::default()).expect("box")
    }

    #[test]
    fn the_face_toward_the_eye_wins() {
        let tris = unit_box_triangles(Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(tris.len(), 12);
        let f = facing_face(tris.clone(), Vec3::new(1.3, 0.4, 6.0)).expect("face");
        assert!((f.normal - Vec3::Z).length() < 1e-5, "{f:?}");
        assert!((f.centroid - Vec3::new(1.0, 0.0, 0.5)).length() < 1e-5);
        assert!((f.area - 1.0).abs() < 1e-5);
        // From above and a little to the side the top wins.
        let f = facing_face(tris, Vec3::new(1.5, 9.0, 0.5)).expect("face");
        assert!((f.normal - Vec3::Y).length() < 1e-5, "{f:?}");
    }

    #[test]
    fn degenerate_input_gives_no_face() {
        assert!(facing_face(Vec::new(), Vec3::ZERO).is_none());
        let flat = [[Vec3::ZERO, Vec3::X, Vec3::X * 2.0]];
        assert!(facing_face(flat, Vec3::ZERO).is_none());
        let nan = [[Vec3::NAN, Vec3::X, Vec3::Y]];
        assert!(facing_face(nan, Vec3::ZERO).is_none());
    }

    #[test]
    fn looking_at_a_floor_looks_straight_down_and_keeps_the_heading() {
        let mut c = EditorCamera::default();
        let yaw = c.yaw_deg;
        let face = Face {
            centroid: Vec3::new(1.0, 0.0, 2.0),
            normal: Vec3::Y,
            area: 1.0,
            facing: 1.0,
        };
        look_at_face(&mut c, &face, 3.0);
        assert_eq!(c.pitch_deg, -90.0);
        assert_eq!(c.yaw_deg, yaw);
        assert!((c.forward() - Vec3::NEG_Y).length() < 1e-5);
        assert!((c.eye - Vec3::new(1.0, 3.0, 2.0)).length() < 1e-6);
        // A wall facing +X: the camera looks along −X, level.
        let wall = Face {
            normal: Vec3::X,
            ..face
        };
        look_at_face(&mut c, &wall, 2.0);
        assert!(
            (c.forward() - Vec3::NEG_X).length() < 1e-5,
            "{:?}",
            c.forward()
        );
        assert!(c.pitch_deg.abs() < 1e-4);
    }

    #[test]
    fn numbers_follow_the_resolution_relations() {
        let mut assets = AssetLibrary::default();
        let image = texel_scene::texture::Image::solid("t", 16, 16, [255; 4]);
        assets.insert_texture("t.png", std::sync::Arc::new(image));
        let row = EntityRow {
            transform: Some(Transform::default()),
            geometry: Some(Geometry::Plane {
                size: Vec2::splat(2.0),
            }),
            material: Some(Material {
                texture: Some(TextureMap::new("t.png")),
                ..Material::default()
            }),
            ..EntityRow::default()
        };
        let settings = LevelSettings {
            pixel_scale: PixelScale::FaceResolution(128),
            ..LevelSettings::default()
        };
        let view = ExtractViewport {
            height: 400,
            fov_y: 1.0,
        };
        let info = pixel_info(&row, &settings, &assets, view).expect("info");
        assert_eq!(info.density, 16.0);
        assert_eq!(info.face_resolution, 128);
        assert_eq!(info.one_to_one, 4.0);
        assert_eq!(info.at_reference, 1.0);
        assert!(pixel_info(&row, &settings, &AssetLibrary::default(), view).is_none());
        assert_eq!(face_resolution_for_one_to_one(16.0, 4.0), Ok((128.0, 128)));
        assert_eq!(
            face_resolution_for_one_to_one(16.0, 4.1).map(|r| r.1),
            Ok(128)
        );
        assert_eq!(
            face_resolution_for_one_to_one(1.0, 1.0).map(|r| r.1),
            Ok(16)
        );
        assert_eq!(
            face_resolution_for_one_to_one(1e6, 1e6).map(|r| r.1),
            Ok(2048)
        );
        assert!(face_resolution_for_one_to_one(0.0, 4.0).is_err());
        assert!(face_resolution_for_one_to_one(16.0, f32::NAN).is_err());
    }
}
