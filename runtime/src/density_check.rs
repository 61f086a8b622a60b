//! `texel-run check --density`: which textured entities of a level lay their texture pixels
//! far from one per art pixel (probe texel) at the level's reference distance.

use texel_probes::resolution::{
    one_to_one_distance, texel_world_size, texture_pixels_per_art_pixel,
};
use texel_scene::density::surface_density;
use texel_scene::{Geometry, Material, Name, Transform};

use crate::extract::{Viewport, level_face_resolution};
use crate::load::LoadedLevel;

/// Texture pixels per art pixel outside `1/FAR ..= FAR` is "far from 1:1".
pub const FAR: f32 = 2.0;

/// One textured entity's density.
#[derive(Debug, Clone, PartialEq)]
pub struct DensityLine {
    /// Index in the level.
    pub entity: usize,
    /// Its name ("unnamed" without one).
    pub name: String,
    /// The albedo texture.
    pub texture: String,
    /// Texture pixels per world unit.
    pub pixels_per_unit: f32,
    /// Texture pixels per art pixel at the reference distance.
    pub ratio: f32,
    /// Distance at which it is 1:1.
    pub one_to_one: f32,
}

impl DensityLine {
    /// Whether it is far from 1:1 (see [`FAR`]).
    pub fn is_far(&self) -> bool {
        !(1.0 / FAR..=FAR).contains(&self.ratio)
    }
}

/// The level's face resolution on `viewport` and each textured entity's density at the
/// level's reference distance, in level order.
pub fn density_report(level: &LoadedLevel, viewport: Viewport) -> (u32, Vec<DensityLine>) {
    let scene = &level.scene;
    let n = level_face_resolution(scene, viewport);
    let distance = scene.settings.reference_distance;
    let w = scene.world();
    let mut lines = Vec::new();
    for (entity, e) in scene.entities().enumerate() {
        let (Ok(g), Ok(m)) = (w.get::<&Geometry>(e), w.get::<&Material>(e)) else {
            continue;
        };
        let t = w.get::<&Transform>(e).map(|t| *t).unwrap_or_default();
        let Some(d) = surface_density(&g, &m, &t, &level.assets) else {
            continue;
        };
        let ppu = d.pixels_per_unit();
        lines.push(DensityLine {
            entity,
            name: w
                .get::<&Name>(e)
                .map_or_else(|_| "unnamed".to_owned(), |n| n.0.clone()),
            texture: d.texture,
            pixels_per_unit: ppu,
            ratio: texture_pixels_per_art_pixel(ppu, distance, n),
            one_to_one: one_to_one_distance(n, ppu).unwrap_or(f32::INFINITY),
        });
    }
    (n, lines)
}

/// The report as text: a header, the entities far from 1:1, a count.
pub fn format_report(level: &LoadedLevel, viewport: Viewport, size: (u32, u32)) -> String {
    let (n, lines) = density_report(level, viewport);
    let distance = level.scene.settings.reference_distance;
    let mut out = format!(
        "texture density at the reference distance {distance} (faces of {n} texels at {}x{}, \
         {:.0}° field of view; an art pixel spans {:.3} units there):\n",
        size.0,
        size.1,
        viewport.fov_y.to_degrees(),
        texel_world_size(distance, n)
    );
    let far: Vec<&DensityLine> = lines.iter().filter(|l| l.is_far()).collect();
    for l in &far {
        let how = if l.ratio < 1.0 {
            "magnified"
        } else {
            "minified"
        };
        out += &format!(
            "  entity {} ({}): {} at {:.1} px/unit: {:.2} texture pixels per art pixel ({how}; \
             1:1 at {:.1} units)\n",
            l.entity, l.name, l.texture, l.pixels_per_unit, l.ratio, l.one_to_one
        );
    }
    out += &format!(
        "{} of {} textured entities are far from 1:1 (outside {:.1}..{:.1} texture pixels per \
         art pixel)",
        far.len(),
        lines.len(),
        1.0 / FAR,
        FAR
    );
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_textured_level_reports_its_far_entities() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
        let level =
            crate::load::load_level(&root.join("assets/levels/textured.ron")).expect("level loads");
        let viewport = Viewport {
            height: 360,
            fov_y: 60f32.to_radians(),
        };
        let (n, lines) = density_report(&level, viewport);
        assert!(n >= 8);
        // Every textured entity is listed: nine primitives and two glTF crates.
        assert_eq!(lines.len(), 11, "{lines:#?}");
        let meadow = lines.iter().find(|l| l.name == "Meadow").expect("meadow");
        assert_eq!(meadow.pixels_per_unit, 8.0);
        let expect = 8.0 * 2.0 * level.scene.settings.reference_distance / n as f32;
        assert!((meadow.ratio - expect).abs() < 1e-5);
        assert!((meadow.one_to_one - n as f32 / 16.0).abs() < 1e-4);
        let text = format_report(&level, viewport, (640, 360));
        let far = lines.iter().filter(|l| l.is_far()).count();
        assert!(text.ends_with(&format!(
            "{far} of 11 textured entities are far from 1:1 (outside 0.5..2.0 texture pixels per art pixel)"
        )), "{text}");
    }
}
