//! Reading levels of older format versions.
//!
//! Each older version keeps a frozen copy of just the types that changed, is parsed with
//! those (so errors still point at the right line and column of the original text), and is
//! converted to the current types in code. Saving a migrated level writes the current
//! version.
//!
//! | version | change |
//! |---|---|
//! | 1 | first draft of the format: `transform.rotation` was a quaternion `(x, y, z, w)` |
//! | 2 | `transform.rotation` is Euler angles in degrees (readable, editable by hand) |
//! | 3 | materials may name a `texture` (with sampling, density, UV scale) and a `normal_map`; a version 2 file is a version 3 file without them |
//! | 3 | (later, still 3) entities may hold a `terrain`; files without one are unchanged |
//! | 3 | (later, still 3) entities may hold an `animator`; files without one are unchanged |
//! | 3 | (later, still 3) entities may hold a `sprite`; files without one are unchanged |
//! | 3 | (later, still 3) entities may name a `parent` (their transform is then relative to it); files without one are unchanged |

use glam::{EulerRot, Quat, Vec3};
use serde::Deserialize;

use crate::components::{
    DirectionalLight, Geometry, LevelSettings, Material, Name, PlayerStart, PointLight,
    ProbeGridOverride, Transform,
};
use crate::level::{CURRENT_VERSION, EntityRow, Level};
use crate::num;

/// Parses `text`, a level of format `version` (< current), and converts it.
pub(crate) fn from_old(text: &str, version: u32) -> Result<Level, ron::error::SpannedError> {
    match version {
        1 => {
            let v1: LevelV1 = ron::Options::default()
                .with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME)
                .from_str(text)?;
            Ok(v1.into())
        }
        2 => {
            // Version 3 only added optional fields, so a version 2 file parses as one.
            let mut level: Level = crate::level::ron_options().from_str(text)?;
            level.version = CURRENT_VERSION;
            Ok(level)
        }
        _ => Err(ron::error::SpannedError {
            code: ron::Error::Message(format!("no migration from level version {version}")),
            span: ron::error::Span {
                start: ron::error::Position { line: 1, col: 1 },
                end: ron::error::Position { line: 1, col: 1 },
            },
        }),
    }
}

#[derive(Deserialize)]
#[serde(rename = "Level", deny_unknown_fields)]
struct LevelV1 {
    #[allow(dead_code)]
    version: u32,
    #[serde(default)]
    settings: LevelSettings,
    #[serde(default)]
    entities: Vec<EntityRowV1>,
}

#[derive(Deserialize)]
#[serde(rename = "Entity", deny_unknown_fields)]
struct EntityRowV1 {
    #[serde(default)]
    name: Option<Name>,
    #[serde(default)]
    transform: Option<TransformV1>,
    #[serde(default)]
    geometry: Option<Geometry>,
    #[serde(default)]
    material: Option<Material>,
    #[serde(default)]
    directional_light: Option<DirectionalLight>,
    #[serde(default)]
    point_light: Option<PointLight>,
    #[serde(default)]
    probe_grid_override: Option<ProbeGridOverride>,
    #[serde(default)]
    player_start: Option<PlayerStart>,
}

#[derive(Deserialize)]
#[serde(rename = "Transform", deny_unknown_fields)]
struct TransformV1 {
    #[serde(with = "num::vec3")]
    translation: Vec3,
    rotation: (f32, f32, f32, f32),
    #[serde(with = "num::scale3")]
    scale: Vec3,
}

impl From<TransformV1> for Transform {
    fn from(t: TransformV1) -> Self {
        let (x, y, z, w) = t.rotation;
        let q = Quat::from_xyzw(x, y, z, w);
        let q = if q.is_finite() && q.length_squared() > 1e-12 {
            q.normalize()
        } else {
            Quat::IDENTITY
        };
        let (yaw, pitch, roll) = q.to_euler(EulerRot::YXZ);
        Transform {
            translation: t.translation,
            rotation: Vec3::new(pitch, yaw, roll) * (180.0 / std::f32::consts::PI),
            scale: t.scale,
        }
    }
}

impl From<LevelV1> for Level {
    fn from(v1: LevelV1) -> Self {
        Level {
            version: CURRENT_VERSION,
            settings: v1.settings,
            palette: None,
            entities: v1
                .entities
                .into_iter()
                .map(|e| EntityRow {
                    name: e.name,
                    parent: None,
                    transform: e.transform.map(Transform::from),
                    geometry: e.geometry,
                    material: e.material,
                    directional_light: e.directional_light,
                    point_light: e.point_light,
                    probe_grid_override: e.probe_grid_override,
                    player_start: e.player_start,
                    terrain: None,
                    animator: None,
                    sprite: None,
                })
                .collect(),
        }
    }
}
