//! Texture density: how many texture pixels a textured surface lays over one world unit,
//! the quantity the pixel-perfect tools compare with the art pixel
//! (`texel_probes::resolution::texture_pixels_per_art_pixel`).

use glam::Vec3;
use texel_geom::texture::Image;

use crate::assets::AssetLibrary;
use crate::components::{Geometry, Material, Transform};
use crate::mesh::TriMesh;

/// A textured surface's density.
#[derive(Debug, Clone, PartialEq)]
pub struct SurfaceDensity {
    /// The albedo texture (level-relative path, or the glTF image's name).
    pub texture: String,
    /// Texture pixels per world unit along the surface.
    pixels_per_unit: f32,
}

impl SurfaceDensity {
    /// Texture pixels per world unit along the surface.
    pub fn pixels_per_unit(&self) -> f32 {
        self.pixels_per_unit
    }
}

/// Mean scale of a transform (geometric mean of the three axes): non-uniform scales make
/// the density direction-dependent; this is its average.
fn mean_scale(t: &Transform) -> f32 {
    (t.scale.x * t.scale.y * t.scale.z).abs().cbrt()
}

/// The density of an entity's albedo texture, `None` when it has none (or the file is not
/// loaded). Primitives: the material's density × its UV scale; glTF meshes: measured over
/// the triangles (texture pixels covered over world area, area-weighted). Both divided by
/// the transform's mean scale.
pub fn surface_density(
    geometry: &Geometry,
    material: &Material,
    transform: &Transform,
    assets: &AssetLibrary,
) -> Option<SurfaceDensity> {
    let scale = mean_scale(transform);
    if !(scale.is_finite() && scale > 0.0) {
        return None;
    }
    match geometry {
        Geometry::Mesh { path } => {
            let mesh = assets.get(path)?;
            let override_image = material.texture.as_ref().and_then(|t| {
                assets
                    .texture(&t.path)
                    .map(|i| (t.path.clone(), i.clone(), t.uv_scale))
            });
            let (name, pixels_per_unit) =
                mesh_density(mesh, override_image.as_ref().map(|(_, i, s)| (&**i, *s)))?;
            Some(SurfaceDensity {
                texture: override_image.map_or(name, |(p, _, _)| p),
                pixels_per_unit: pixels_per_unit / scale,
            })
        }
        _ => {
            let t = material.texture.as_ref()?;
            assets.texture(&t.path)?;
            let uv = (t.uv_scale.x * t.uv_scale.y).sqrt();
            Some(SurfaceDensity {
                texture: t.path.clone(),
                pixels_per_unit: t.density * uv / scale,
            })
        }
    }
}

/// Texture pixels per object-space unit over a mesh's textured triangles, and the first
/// texture's name: `sqrt(Σ pixel area / Σ world area)`. `image` (with its UV scale), when
/// given, replaces the mesh's own textures.
pub fn mesh_density(mesh: &TriMesh, image: Option<(&Image, glam::Vec2)>) -> Option<(String, f32)> {
    if mesh.uvs.is_empty() {
        return None;
    }
    let (mut pixel_area, mut world_area) = (0.0f64, 0.0f64);
    let mut name = None;
    for (t, tri) in mesh.indices.chunks_exact(3).enumerate() {
        let (img, uv_scale) = match image {
            Some(i) => i,
            None => {
                let Some(part) = mesh.part_of(t as u32) else {
                    continue;
                };
                let Some(albedo) = &part.maps.albedo else {
                    continue;
                };
                (&*albedo.image, part.maps.uv_scale)
            }
        };
        name.get_or_insert_with(|| img.name.clone());
        let [a, b, c] = [0, 1, 2].map(|k| tri[k] as usize);
        let p: [Vec3; 3] = [a, b, c].map(|i| mesh.positions[i]);
        let area = 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).length();
        let uv = [a, b, c].map(|i| mesh.uv(i) * uv_scale);
        let uv_area = 0.5 * (uv[1] - uv[0]).perp_dot(uv[2] - uv[0]).abs();
        let pixels = uv_area * img.width as f32 * img.height as f32;
        if area.is_finite() && pixels.is_finite() {
            world_area += f64::from(area);
            pixel_area += f64::from(pixels);
        }
    }
    if world_area <= 0.0 || pixel_area <= 0.0 {
        return None;
    }
    Some((name?, (pixel_area / world_area).sqrt() as f32))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::components::TextureMap;
    use glam::Vec2;

    #[test]
    fn a_unit_quad_with_a_whole_16_pixel_image_has_density_16() {
        let mut mesh = crate::primitives::plane(Vec2::ONE);
        // Plane UVs are world units: one unit = the whole image once.
        let img = Image::solid("t", 16, 16, [255; 4]);
        let (_, d) = mesh_density(&mesh, Some((&img, Vec2::ONE))).unwrap();
        assert!((d - 16.0).abs() < 1e-4, "{d}");
        let (_, d) = mesh_density(&mesh, Some((&img, Vec2::splat(2.0)))).unwrap();
        assert!((d - 32.0).abs() < 1e-4, "{d}");
        mesh.uvs.clear();
        assert!(mesh_density(&mesh, Some((&img, Vec2::ONE))).is_none());
    }

    #[test]
    fn primitives_take_the_material_density_over_the_scale() {
        let material = Material {
            texture: Some(TextureMap {
                density: 8.0,
                ..TextureMap::new("a.png")
            }),
            ..Default::default()
        };
        let t = Transform {
            scale: Vec3::splat(2.0),
            ..Default::default()
        };
        let g = Geometry::Box { size: Vec3::ONE };
        // Not loaded: no density.
        let mut assets = AssetLibrary::default();
        assert!(surface_density(&g, &material, &t, &assets).is_none());
        assets.insert_texture(
            "a.png",
            std::sync::Arc::new(Image::solid("a", 4, 4, [0; 4])),
        );
        let d = surface_density(&g, &material, &t, &assets).unwrap();
        assert_eq!((d.texture.as_str(), d.pixels_per_unit()), ("a.png", 4.0));
        assert!(surface_density(&g, &Material::default(), &t, &assets).is_none());
    }
}
