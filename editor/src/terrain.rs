//! Terrain editing in the document: the terrain Add → Terrain makes, the height changes an
//! undo step keeps ([`HeightChange`]), the file a sculpted terrain's heights are saved to,
//! and 16-bit heightmap import and export. The brush math (where samples lie, the view ray's
//! hit, brushes and dabs, regions) is [`texel_scene::sculpt`], re-exported here for the
//! editor's tools. What needs the editor state (the selected terrain, an import as an undo
//! step) is `crate::terrain_edits`', so this module sits below the commands that keep its
//! changes.

use std::path::Path;
use std::sync::Arc;

use glam::{Vec2, Vec3};
use texel_scene::terrain::{GradientStop, HeightSource, Heightfield, Terrain};
use texel_scene::texture::{encode_heightmap, load_heightmap};
use texel_scene::{EntityRow, Name, Transform};

use texel_scene::sculpt::paste_region;
pub use texel_scene::sculpt::{
    BLEND_RATE, Brush, BrushKind, Dab, NOISE_RATE, Placement, RAISE_RATE, Region, copy_region, dab,
    falloff_weight, ray_hit, value_noise,
};

/// A terrain of 64 × 64 units of baked noise (an island) coloured sand, grass, forest, rock and
/// snow: what Add → Terrain makes.
pub fn default_terrain() -> Terrain {
    let stop = |at: f32, r: f32, g: f32, b: f32| GradientStop {
        at,
        colour: Vec3::new(r, g, b),
    };
    Terrain {
        size: Vec2::splat(64.0),
        heightmap: HeightSource::Noise {
            seed: 1,
            resolution: 129,
            frequency: 0.04,
            octaves: 4,
            island: 1.0,
        },
        max_height: 8.0,
        gradient: vec![
            stop(0.0, 0.55, 0.5, 0.32),
            stop(0.15, 0.25, 0.42, 0.16),
            stop(0.45, 0.16, 0.32, 0.11),
            stop(0.7, 0.4, 0.37, 0.32),
            stop(0.9, 0.92, 0.93, 0.96),
        ],
        displacement: None,
        paint: None,
        pixel_density: 6.0,
        band_distance: 8.0,
        band_transition: 0.3,
        casts_shadows: true,
        outlined: true,
    }
}

/// An entity named "Terrain" with the [`default_terrain`] centred on `at`.
pub fn terrain_row(at: Vec3) -> EntityRow {
    EntityRow {
        name: Some(Name("Terrain".into())),
        transform: Some(Transform::from_translation(at)),
        terrain: Some(default_terrain()),
        ..EntityRow::default()
    }
}

/// Where a terrain's height samples lie in the world: centred on `origin` (its transform's
#[derive(Clone, PartialEq)]
pub enum HeightChange {
    /// A stroke: the samples of `region` before and after, on a `width` × `depth` field.
    Patch {
        /// Samples along X of the field.
        width: u32,
        /// Samples along Z of the field.
        depth: u32,
        /// The samples changed.
        region: Region,
        /// Their heights before, row by row.
        before: Vec<f32>,
        /// Their heights after.
        after: Vec<f32>,
    },
    /// The whole field replaced (an import; its size may change).
    Field {
        /// The field before.
        before: Arc<Heightfield>,
        /// The field after.
        after: Arc<Heightfield>,
    },
}

impl std::fmt::Debug for HeightChange {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            HeightChange::Patch { region, .. } => write!(f, "Patch({region:?})"),
            HeightChange::Field { before, after } => write!(
                f,
                "Field({}×{} → {}×{})",
                before.width, before.depth, after.width, after.depth
            ),
        }
    }
}

impl HeightChange {
    /// A stroke's change: the samples of `region` of `before` and `after`.
    pub fn patch(before: &Heightfield, after: &Heightfield, region: Region) -> Self {
        HeightChange::Patch {
            width: before.width,
            depth: before.depth,
            region,
            before: copy_region(before, region),
            after: copy_region(after, region),
        }
    }

    /// The heights after the change (`forward`) or before it, made from `from`, the heights
    /// on the other side. An error when `from` is not the field the change was made on.
    pub fn apply(&self, from: &Heightfield, forward: bool) -> Result<Heightfield, String> {
        match self {
            HeightChange::Patch {
                width,
                depth,
                region,
                before,
                after,
            } => {
                if (from.width, from.depth) != (*width, *depth)
                    || !region.fits(*width, *depth)
                    || before.len() != region.len()
                    || after.len() != region.len()
                {
                    return Err(format!(
                        "the terrain's heights are {}×{}, the change was made on {width}×{depth}",
                        from.width, from.depth
                    ));
                }
                let mut out = from.clone();
                paste_region(&mut out, *region, if forward { after } else { before });
                Ok(out)
            }
            HeightChange::Field { before, after } => {
                let (expect, to) = if forward {
                    (before, after)
                } else {
                    (after, before)
                };
                if (from.width, from.depth) != (expect.width, expect.depth) {
                    return Err(format!(
                        "the terrain's heights are {}×{}, expected {}×{}",
                        from.width, from.depth, expect.width, expect.depth
                    ));
                }
                Ok((**to).clone())
            }
        }
    }

    /// The change that undoes this one.
    pub fn reversed(&self) -> HeightChange {
        match self {
            HeightChange::Patch {
                width,
                depth,
                region,
                before,
                after,
            } => HeightChange::Patch {
                width: *width,
                depth: *depth,
                region: *region,
                before: after.clone(),
                after: before.clone(),
            },
            HeightChange::Field { before, after } => HeightChange::Field {
                before: after.clone(),
                after: before.clone(),
            },
        }
    }

    /// A short description for the Undo menu.
    pub fn describe(&self) -> &'static str {
        match self {
            HeightChange::Patch { .. } => "sculpt",
            HeightChange::Field { .. } => "heightmap import",
        }
    }
}

/// Keeps letters, digits, `-` and `_` of `name` (others become `_`).
fn file_safe(name: &str) -> String {
    name.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect::<String>()
        .trim_matches('_')
        .to_owned()
}

/// The heightmap file (relative to the level) a sculpted or imported terrain's heights are
/// saved to: `<level stem>_<entity name or index>.png`, with `_2`, `_3`… appended while
/// `taken` says a name is used.
pub fn heightmap_file_name(
    level: &Path,
    entity: Option<&str>,
    index: usize,
    taken: impl Fn(&str) -> bool,
) -> String {
    level_file_name(level, entity, index, "", taken)
}

/// A PNG file beside the level for an entity's data: `<level stem>_<entity name or
/// index><suffix>.png`, with `_2`, `_3`… appended while `taken` says a name is used.
pub fn level_file_name(
    level: &Path,
    entity: Option<&str>,
    index: usize,
    suffix: &str,
    taken: impl Fn(&str) -> bool,
) -> String {
    let stem = level
        .file_stem()
        .map(|s| file_safe(&s.to_string_lossy()))
        .filter(|s| !s.is_empty())
        .unwrap_or_else(|| "level".to_owned());
    let name = entity
        .map(file_safe)
        .filter(|s| !s.is_empty())
        .unwrap_or_else(|| index.to_string());
    let base = format!("{stem}_{name}{suffix}");
    let first = format!("{base}.png");
    if !taken(&first) {
        return first;
    }
    (2..10_000)
        .map(|k| format!("{base}_{k}.png"))
        .find(|n| !taken(n))
        .unwrap_or_else(|| format!("{base}_{index}_x.png"))
}

/// Reads a 16-bit greyscale heightmap PNG (0..=65535 → 0..=`max_height`). The error says
/// why a file is refused (not a PNG, not 16-bit grey, too small or large).
pub fn read_heightmap(file: &Path, max_height: f32) -> Result<Heightfield, String> {
    let (w, h, samples) = load_heightmap(file).map_err(|e| e.to_string())?;
    Ok(Heightfield::from_u16(w, h, &samples, max_height))
}

/// `field` as a 16-bit greyscale PNG for `max_height`.
pub fn encode(field: &Heightfield, max_height: f32) -> Vec<u8> {
    encode_heightmap(field.width, field.depth, &field.to_u16(max_height))
}

/// Writes `field` to `file` as a 16-bit greyscale PNG, atomically (a failed write leaves
/// the old file as it was), creating its folder.
pub fn write_heightmap(file: &Path, field: &Heightfield, max_height: f32) -> Result<(), String> {
    if field.heights.len() != (field.width as usize) * (field.depth as usize) {
        return Err(format!(
            "{}: the heights do not fill the grid",
            file.display()
        ));
    }
    if let Some(dir) = file.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    texel_scene::save::write_atomic(file, &encode(field, max_height))
        .map_err(|e| format!("cannot write the heightmap {}: {e}", file.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flat(n: u32, h: f32) -> (Heightfield, Placement) {
        let field = Heightfield::flat(n, n, h);
        let place = Placement {
            origin: Vec3::ZERO,
            size: Vec2::splat((n - 1) as f32),
            width: n,
            depth: n,
            max_height: 10.0,
        };
        (field, place)
    }

    #[test]
    fn patches_undo_and_redo_exactly_and_refuse_other_fields() {
        let (before, place) = flat(17, 1.0);
        let mut after = before.clone();
        let noise = Brush {
            kind: BrushKind::Noise,
            strength: 1.0,
            ..Brush::default()
        };
        let d = Dab {
            centre: Vec3::new(1.0, 0.0, -2.0),
            dt: 0.5,
            invert: false,
            target: 0.0,
        };
        let region = dab(&mut after, &place, &noise, &d).expect("touched");
        assert_ne!(before, after);
        let change = HeightChange::patch(&before, &after, region);
        assert_eq!(change.apply(&before, true).expect("redo"), after);
        assert_eq!(change.apply(&after, false).expect("undo"), before);
        assert!(change.apply(&Heightfield::flat(3, 3, 0.0), true).is_err());
    }

    #[test]
    fn heightmap_names_sit_beside_the_level_and_stay_unique() {
        let level = Path::new("dir/hills.ron");
        assert_eq!(
            heightmap_file_name(level, Some("Big island!"), 2, |_| false),
            "hills_Big_island.png"
        );
        assert_eq!(
            heightmap_file_name(level, None, 2, |_| false),
            "hills_2.png"
        );
        let taken = |n: &str| n == "hills_T.png" || n == "hills_T_2.png";
        assert_eq!(
            heightmap_file_name(level, Some("T"), 0, taken),
            "hills_T_3.png"
        );
    }
}
