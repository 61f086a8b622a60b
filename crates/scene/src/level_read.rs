//! Reading a level file of any version the build knows: the current version parses at
//! once, an older one ([`OLDEST_VERSION`] on) goes through [`crate::migrate`]. Errors name
//! the file, line and column ([`LevelError::Parse`]) in words a level author understands.
//! The level format itself, its checks and its writing are [`crate::level`]'s.

use std::path::Path;

use serde::Deserialize;

use crate::level::{
    CURRENT_VERSION, ErrorKind, Level, LevelError, OLDEST_VERSION, parse_error, ron_options,
};
use crate::read::{FileKind, ReadError, read_bounded};

/// Just the version, read before the rest so older files can be migrated.
#[derive(Deserialize)]
#[serde(rename = "Level")]
struct VersionProbe {
    #[serde(deserialize_with = "de_version")]
    version: u32,
}

fn de_version<'de, D: serde::Deserializer<'de>>(d: D) -> Result<u32, D::Error> {
    let v = u32::deserialize(d)?;
    if (OLDEST_VERSION..=CURRENT_VERSION).contains(&v) {
        Ok(v)
    } else {
        Err(serde::de::Error::custom(format!(
            "unknown level version {v} (this build reads versions {OLDEST_VERSION} to {CURRENT_VERSION})"
        )))
    }
}

impl Level {
    /// Reads a level from RON text; `path` is only used to name the file in errors.
    pub fn from_ron_str(text: &str, path: &Path) -> Result<Level, LevelError> {
        if text.trim().is_empty() {
            return Err(parse_error(path, 1, 1, ErrorKind::Syntax, "empty file"));
        }
        // One pass for files of the current version (the common case); the version alone
        // is read only when that fails or the file is older.
        let first = ron_options().from_str::<Level>(text);
        if let Ok(level) = &first
            && level.version == CURRENT_VERSION
        {
            let level = first.map_err(|e| spanned(path, e))?;
            level.check_parents(path)?;
            return Ok(level);
        }
        let probe: VersionProbe = ron_options().from_str(text).map_err(|e| spanned(path, e))?;
        let level = match first {
            Ok(level) if probe.version == CURRENT_VERSION => level,
            Err(e) if probe.version == CURRENT_VERSION => return Err(spanned(path, e)),
            _ => crate::migrate::from_old(text, probe.version).map_err(|e| spanned(path, e))?,
        };
        level.check_parents(path)?;
        Ok(level)
    }

    /// Reads a level file: a regular file of at most [`FileKind::Level`]'s cap
    /// (see [`crate::read`]).
    pub fn load(path: &Path) -> Result<Level, LevelError> {
        let bytes = read_bounded(path, FileKind::Level).map_err(|e| match e {
            ReadError::Io { path, source, .. } => LevelError::Io { path, source },
            other => LevelError::Read(other),
        })?;
        Level::from_ron_bytes(&bytes, path)
    }

    /// Parses a level from the bytes of a file: invalid UTF-8 is a syntax error at the line
    /// and column where the text stops being UTF-8; the rest as [`Level::from_ron_str`].
    pub fn from_ron_bytes(bytes: &[u8], path: &Path) -> Result<Level, LevelError> {
        let text = std::str::from_utf8(bytes).map_err(|e| {
            let (line, column) = line_col(&bytes[..e.valid_up_to()]);
            parse_error(
                path,
                line,
                column,
                ErrorKind::Syntax,
                "not a text file (invalid UTF-8)",
            )
        })?;
        Level::from_ron_str(text, path)
    }
}

/// 1-based line and column just after `prefix`.
fn line_col(prefix: &[u8]) -> (usize, usize) {
    let line = 1 + prefix.iter().filter(|&&b| b == b'\n').count();
    let line_start = prefix
        .iter()
        .rposition(|&b| b == b'\n')
        .map_or(0, |i| i + 1);
    let column = 1 + String::from_utf8_lossy(&prefix[line_start..])
        .chars()
        .count();
    (line, column)
}

/// Turns ron's error into ours, with a message a level author understands.
fn spanned(path: &Path, e: ron::error::SpannedError) -> LevelError {
    use ron::Error as R;
    let (kind, message) = match &e.code {
        R::NoSuchStructField {
            found,
            outer,
            expected,
        } if outer.as_deref() == Some("Entity") => (
            ErrorKind::UnknownComponent,
            format!(
                "unknown component `{found}` (known components: {})",
                expected.join(", ")
            ),
        ),
        R::NoSuchStructField {
            found,
            outer,
            expected,
        } => (
            ErrorKind::UnknownField,
            format!(
                "unknown field `{found}` in {} (expected one of: {})",
                outer.as_deref().unwrap_or("this value"),
                expected.join(", ")
            ),
        ),
        R::MissingStructField { field, outer } => (
            ErrorKind::MissingField,
            format!(
                "missing field `{field}` in {}",
                outer.as_deref().unwrap_or("this value")
            ),
        ),
        R::NoSuchEnumVariant {
            found, expected, ..
        } => (
            ErrorKind::UnknownField,
            format!(
                "unknown kind `{found}` (expected one of: {})",
                expected.join(", ")
            ),
        ),
        R::Message(m) if m.starts_with("unknown level version") => {
            (ErrorKind::UnknownVersion, m.clone())
        }
        R::Message(m) => (ErrorKind::InvalidValue, m.clone()),
        R::InvalidValueForType { .. }
        | R::ExpectedDifferentLength { .. }
        | R::ExpectedArray
        | R::ExpectedBoolean
        | R::ExpectedFloat
        | R::ExpectedInteger
        | R::ExpectedString
        | R::ExpectedMap
        | R::ExpectedStructLike
        | R::ExpectedNamedStructLike(_)
        | R::ExpectedUnit
        | R::ExpectedOption
        | R::IntegerOutOfBounds => (
            ErrorKind::WrongType,
            format!("wrong type: {}", lower_first(&e.code.to_string())),
        ),
        R::Eof => (
            ErrorKind::Syntax,
            "unexpected end of file (is it truncated?)".to_owned(),
        ),
        R::ExpectedStringEnd => (
            ErrorKind::Syntax,
            "unterminated string (is the file truncated?)".to_owned(),
        ),
        code => (
            ErrorKind::Syntax,
            format!("syntax error: {}", lower_first(&code.to_string())),
        ),
    };
    parse_error(path, e.span.start.line, e.span.start.col, kind, &message)
}

fn lower_first(s: &str) -> String {
    let mut c = s.chars();
    match c.next() {
        Some(f) => f.to_lowercase().chain(c).collect(),
        None => String::new(),
    }
}
