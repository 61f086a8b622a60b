//! Levels as RON text, made for version control.
//!
//! A level file is one `Level` value: a `version`, the level-wide `settings`, and
//! `entities`, one row per entity listing its components by name. Writing is canonical:
//! fixed field order, four-space indentation, one component per line, floats in their
//! shortest round-tripping form. So loading a saved level and saving it again gives the same
//! bytes, and a one-value edit is a one-line diff.
//!
//! Reading checks every value (see [`crate::num`]) and reports the first problem as a
//! [`LevelError`] naming the file, line and column. Fields added in later versions have
//! defaults, so older files keep loading; files of an older `version` go through
//! `crate::migrate` first. Reading (`Level::load`, `Level::from_ron_str`) is
//! `crate::level_read`'s, above both this format and its migrations.

use std::path::{Path, PathBuf};

use ron::extensions::Extensions;
use ron::ser::PrettyConfig;
use serde::{Deserialize, Serialize};

use crate::components::{
    DirectionalLight, Geometry, LevelSettings, Material, Name, PaletteSetting, PlayerStart,
    PointLight, ProbeGridOverride, Transform, Validate,
};

/// The version this build writes.
pub const CURRENT_VERSION: u32 = 3;
/// The oldest version this build reads.
pub const OLDEST_VERSION: u32 = 1;

/// A whole level, as stored in a file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename = "Level", deny_unknown_fields)]
pub struct Level {
    /// Format version; always [`CURRENT_VERSION`] once loaded.
    pub version: u32,
    /// Level-wide settings.
    #[serde(default)]
    pub settings: LevelSettings,
    /// The palette the level's frames are mapped to, if any (left out of the file when
    /// none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub palette: Option<PaletteSetting>,
    /// One row per entity, in a stable order.
    #[serde(default, deserialize_with = "de_entities")]
    pub entities: Vec<EntityRow>,
}

impl Default for Level {
    fn default() -> Self {
        Self {
            version: CURRENT_VERSION,
            settings: LevelSettings::default(),
            palette: None,
            entities: Vec::new(),
        }
    }
}

/// One entity and its components, by name. Every component is optional.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(rename = "Entity", deny_unknown_fields)]
pub struct EntityRow {
    /// Name shown in the editor.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<Name>,
    /// The parent's name (unique in the level): the entity belongs to that group, and its
    /// `transform` is relative to the parent's ([`crate::hierarchy`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub parent: Option<Name>,
    /// Placement (relative to the parent's, if any).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub transform: Option<Transform>,
    /// Shape.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub geometry: Option<Geometry>,
    /// Surface.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<Material>,
    /// Sun.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub directional_light: Option<DirectionalLight>,
    /// Point light.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub point_light: Option<PointLight>,
    /// Probe-grid override volume.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub probe_grid_override: Option<ProbeGridOverride>,
    /// Player start.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub player_start: Option<PlayerStart>,
    /// Heightmap terrain.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub terrain: Option<crate::terrain::Terrain>,
    /// Motion over time (needs a transform; not on a terrain).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub animator: Option<crate::animator::Animator>,
    /// A picture from a sprite sheet (needs a transform; no geometry, no terrain).
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "crate::sprite::de_sprite"
    )]
    pub sprite: Option<crate::sprite::Sprite>,
}

/// The names of the components an entity row may hold, in file order.
pub const COMPONENT_NAMES: &[&str] = &[
    "name",
    "parent",
    "transform",
    "geometry",
    "material",
    "directional_light",
    "point_light",
    "probe_grid_override",
    "player_start",
    "terrain",
    "animator",
    "sprite",
];

/// What is wrong with a level, for callers that react to the kind.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorKind {
    /// The text is not valid RON (or not UTF-8, or empty, or cut short).
    Syntax,
    /// An entity row names a component that does not exist.
    UnknownComponent,
    /// A struct has a field it does not know.
    UnknownField,
    /// A required field is missing.
    MissingField,
    /// A value has the wrong type (a string where a number belongs, …).
    WrongType,
    /// A value is out of its allowed range: NaN, infinite, too large, zero or negative
    /// scale, a resolution the renderer cannot hold.
    InvalidValue,
    /// The `version` is not one this build reads.
    UnknownVersion,
}

/// A level that could not be read, written or validated.
#[derive(Debug, thiserror::Error)]
pub enum LevelError {
    /// The file could not be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The OS error.
        source: std::io::Error,
    },
    /// The path is not a regular file, or the file is larger than a level may be
    /// (see [`crate::read`]).
    #[error(transparent)]
    Read(crate::read::ReadError),
    /// The text is wrong at a known place.
    #[error("{}:{line}:{column}: {message}", path.display())]
    Parse {
        /// The file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What kind of problem.
        kind: ErrorKind,
        /// What is wrong, for people.
        message: String,
    },
    /// An entity's `parent` names no entity (or a name two share), makes a cycle, a chain
    /// deeper than [`crate::hierarchy::MAX_DEPTH`], or names an animated entity.
    #[error("{}: entity {entity} ({name}): parent: {message}", path.display())]
    Parent {
        /// The file.
        path: PathBuf,
        /// Index of the entity row.
        entity: usize,
        /// The entity's name, or `unnamed`.
        name: String,
        /// What is wrong.
        message: String,
    },
    /// A level built in code holds a bad value (found before saving).
    #[error("{}: entity {entity} ({name}): {component}.{field}: {message}", path.display())]
    Invalid {
        /// The file being saved.
        path: PathBuf,
        /// Index of the entity row (or `settings`).
        entity: String,
        /// The entity's name, or `unnamed`.
        name: String,
        /// Component name.
        component: &'static str,
        /// Field name.
        field: &'static str,
        /// What is wrong.
        message: String,
    },
}

impl LevelError {
    /// The kind of problem, for parse errors.
    pub fn kind(&self) -> Option<ErrorKind> {
        match self {
            LevelError::Parse { kind, .. } => Some(*kind),
            LevelError::Invalid { .. } | LevelError::Parent { .. } => Some(ErrorKind::InvalidValue),
            LevelError::Io { .. } | LevelError::Read(_) => None,
        }
    }
}

pub(crate) fn ron_options() -> ron::Options {
    ron::Options::default().with_default_extension(Extensions::IMPLICIT_SOME)
}

fn pretty() -> PrettyConfig {
    PrettyConfig::new()
        .depth_limit(3)
        .indentor("    ")
        .new_line("\n")
        .separator(" ")
        .struct_names(false)
        .separate_tuple_members(false)
        .enumerate_arrays(false)
}

impl Level {
    /// The canonical RON text of this level (always written as [`CURRENT_VERSION`]).
    /// `path` names the file in errors. Fails if a value is invalid.
    pub fn to_ron_string(&self, path: &Path) -> Result<String, LevelError> {
        self.validate(path)?;
        let current = Level {
            version: CURRENT_VERSION,
            ..self.clone()
        };
        let mut text = ron_options()
            .to_string_pretty(&current, pretty())
            .map_err(|e| parse_error(path, 1, 1, ErrorKind::InvalidValue, &e.to_string()))?;
        text.push('\n');
        Ok(text)
    }

    /// Saves the level atomically: a failed save leaves the old file as it was.
    pub fn save(&self, path: &Path) -> Result<(), LevelError> {
        let text = self.to_ron_string(path)?;
        crate::save::write_atomic(path, text.as_bytes()).map_err(|source| LevelError::Io {
            path: path.to_owned(),
            source,
        })
    }

    /// Checks every value against the loader's rules.
    pub fn validate(&self, path: &Path) -> Result<(), LevelError> {
        let invalid =
            |entity: String, name: &str, component, (field, message)| LevelError::Invalid {
                path: path.to_owned(),
                entity,
                name: name.to_owned(),
                component,
                field,
                message,
            };
        self.settings
            .validate()
            .map_err(|e| invalid("settings".into(), "level", "settings", e))?;
        if let Some(p) = &self.palette {
            p.validate()
                .map_err(|e| invalid("palette".into(), "level", "palette", e))?;
        }
        for (i, row) in self.entities.iter().enumerate() {
            let name = row.display_name();
            row.validate()
                .map_err(|(c, e)| invalid(i.to_string(), name, c, e))?;
        }
        self.check_parents(path)
    }

    /// Checks every row's `parent` ([`crate::hierarchy::check_rows`]).
    pub fn check_parents(&self, path: &Path) -> Result<(), LevelError> {
        crate::hierarchy::check_rows(&self.entities).map_err(|(i, message)| LevelError::Parent {
            path: path.to_owned(),
            entity: i,
            name: self.entities[i].display_name().to_owned(),
            message,
        })
    }
}

type FieldError = (&'static str, String);

impl EntityRow {
    /// Checks every component; the error names the component and the field.
    pub fn validate(&self) -> Result<(), (&'static str, FieldError)> {
        fn check(
            c: &'static str,
            v: Option<&dyn Validate>,
        ) -> Result<(), (&'static str, FieldError)> {
            v.map_or(Ok(()), |v| v.validate().map_err(|e| (c, e)))
        }
        check("transform", self.transform.as_ref().map(|v| v as _))?;
        check("geometry", self.geometry.as_ref().map(|v| v as _))?;
        check("material", self.material.as_ref().map(|v| v as _))?;
        check(
            "directional_light",
            self.directional_light.as_ref().map(|v| v as _),
        )?;
        check("point_light", self.point_light.as_ref().map(|v| v as _))?;
        check(
            "probe_grid_override",
            self.probe_grid_override.as_ref().map(|v| v as _),
        )?;
        check("player_start", self.player_start.as_ref().map(|v| v as _))?;
        check("terrain", self.terrain.as_ref().map(|v| v as _))?;
        check("animator", self.animator.as_ref().map(|v| v as _))?;
        check("sprite", self.sprite.as_ref().map(|v| v as _))?;
        check_animator_row(self).map_err(|e| ("animator", e))?;
        check_sprite_row(self).map_err(|e| ("sprite", e))
    }

    /// The entity's name, or `unnamed`.
    fn display_name(&self) -> &str {
        self.name.as_ref().map_or("unnamed", |n| n.0.as_str())
    }
}

/// What an entity row must hold for its animator: a transform to move, and no terrain
/// (terrains do not move). `Err((field, message))` names the missing or forbidden component.
pub fn check_animator_row(row: &EntityRow) -> Result<(), (&'static str, String)> {
    if row.animator.is_none() {
        return Ok(());
    }
    if row.transform.is_none() {
        return Err((
            "transform",
            "an animator moves its entity's transform, and this entity has none".to_owned(),
        ));
    }
    if row.terrain.is_some() {
        return Err((
            "terrain",
            "terrains do not move: an entity with a terrain cannot have an animator".to_owned(),
        ));
    }
    Ok(())
}

/// What an entity row must hold for its sprite: a transform to place it, no geometry (a
/// sprite entity's only surface is the sprite) and no terrain. `Err((field, message))`
/// names the missing or forbidden component.
pub fn check_sprite_row(row: &EntityRow) -> Result<(), (&'static str, String)> {
    if row.sprite.is_none() {
        return Ok(());
    }
    if row.transform.is_none() {
        return Err((
            "transform",
            "a sprite is placed by its entity's transform, and this entity has none".to_owned(),
        ));
    }
    if row.geometry.is_some() {
        return Err((
            "geometry",
            "a sprite entity has no mesh: put the sprite and the geometry on separate entities"
                .to_owned(),
        ));
    }
    if row.terrain.is_some() {
        return Err((
            "terrain",
            "an entity with a terrain cannot have a sprite".to_owned(),
        ));
    }
    Ok(())
}

/// Reads the entity rows, checking each row's components against each other as it ends
/// (an animator or a sprite needs a transform, …), so the error points at the row.
fn de_entities<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Vec<EntityRow>, D::Error> {
    struct Rows;
    impl<'de> serde::de::Visitor<'de> for Rows {
        type Value = Vec<EntityRow>;
        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            f.write_str("a sequence")
        }
        fn visit_seq<A: serde::de::SeqAccess<'de>>(
            self,
            mut seq: A,
        ) -> Result<Self::Value, A::Error> {
            let mut rows = Vec::new();
            while let Some(row) = seq.next_element::<EntityRow>()? {
                if let Err((_, message)) =
                    check_animator_row(&row).and_then(|()| check_sprite_row(&row))
                {
                    return Err(serde::de::Error::custom(format!(
                        "entity {} ({}): {message}",
                        rows.len(),
                        row.display_name()
                    )));
                }
                rows.push(row);
            }
            Ok(rows)
        }
    }
    d.deserialize_seq(Rows)
}

pub(crate) fn parse_error(
    path: &Path,
    line: usize,
    column: usize,
    kind: ErrorKind,
    msg: &str,
) -> LevelError {
    LevelError::Parse {
        path: path.to_owned(),
        line,
        column,
        kind,
        message: msg.to_owned(),
    }
}
