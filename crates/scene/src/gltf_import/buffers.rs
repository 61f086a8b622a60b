//! Buffers: the GLB binary chunk, `data:` URIs, or files next to the glTF; and the URI rules
//! images share.

use std::borrow::Cow;
use std::path::{Component, Path, PathBuf};

use gltf::Document;
use gltf::buffer::Source;

use super::GltfError;
use crate::read::{FileKind, ReadError, read_bounded};

/// Loads every buffer: the GLB binary chunk (borrowed), `data:` URIs, or files next to the glTF.
pub(super) fn load_buffers<'a>(
    doc: &Document,
    blob: Option<&'a [u8]>,
    base_dir: Option<&Path>,
    name: &Path,
    allow_any_uri: bool,
) -> Result<Vec<Cow<'a, [u8]>>, GltfError> {
    doc.buffers()
        .map(|buffer| {
            let fail = |detail| GltfError::Buffer {
                path: name.to_path_buf(),
                index: buffer.index(),
                detail,
            };
            let data = match buffer.source() {
                Source::Bin => blob.map(Cow::Borrowed).ok_or_else(|| {
                    "refers to the binary chunk of a .glb, but the file has none".to_string()
                }),
                Source::Uri(uri) => {
                    read_uri(uri, base_dir, allow_any_uri, FileKind::MeshBuffer).map(Cow::Owned)
                }
            }
            .map_err(fail)?;
            if data.len() < buffer.length() {
                return Err(fail(format!(
                    "{} is truncated: {} bytes, but the glTF declares {}",
                    source_label(buffer.source(), base_dir),
                    data.len(),
                    buffer.length()
                )));
            }
            Ok(data)
        })
        .collect()
}

/// Reads a buffer or image URI: a `data:` URI (base64), or a percent-encoded path relative to
/// `base_dir` that stays inside it (unless `allow_any`), read through [`read_bounded`] as a
/// `kind` ([`FileKind::MeshBuffer`] or [`FileKind::Texture`]).
pub(super) fn read_uri(
    uri: &str,
    base_dir: Option<&Path>,
    allow_any: bool,
    kind: FileKind,
) -> Result<Vec<u8>, String> {
    if uri.starts_with("data:") {
        return gltf::buffer::Data::from_source(Source::Uri(uri), None)
            .map(|data| data.0)
            .map_err(|e| format!("invalid data: URI: {e}"));
    }
    if uri.contains(':') {
        return Err(format!(
            "unsupported URI `{}` (only relative file paths and data: URIs are read)",
            short(uri)
        ));
    }
    let relative = percent_decode(uri)
        .ok_or_else(|| format!("URI `{}` has invalid percent-encoding", short(uri)))?;
    let base = base_dir.ok_or_else(|| {
        format!("refers to external file `{relative}`, but no base directory was given")
    })?;
    if !allow_any {
        confined(base, &relative, kind)?;
    }
    let file = base.join(&relative);
    read_bounded(&file, kind).map_err(|e| match e {
        ReadError::Io { path, source, .. } => format!("cannot read `{}`: {source}", path.display()),
        other => other.to_string(),
    })
}

/// Checks that `relative` names a file inside `base`: not absolute, no `..` leading out, and
/// (when both exist) not out of it through a symbolic link.
fn confined(base: &Path, relative: &str, kind: FileKind) -> Result<(), String> {
    let what = match kind {
        FileKind::Texture => "image",
        _ => "buffer",
    };
    let refuse = |why: &str| {
        Err(format!(
            "{what} URI `{}` {why}: only files inside the glTF file's folder are read (set \
             TEXEL_GLTF_ANY_URI=1 to allow any path)",
            short(relative)
        ))
    };
    let base = if base.as_os_str().is_empty() {
        Path::new(".")
    } else {
        base
    };
    let rel = Path::new(relative);
    if rel.is_absolute() || relative.starts_with('/') || relative.starts_with('\\') {
        return refuse("is an absolute path");
    }
    let mut depth = 0usize;
    for c in rel.components() {
        match c {
            Component::Normal(_) => depth += 1,
            Component::CurDir => {}
            Component::ParentDir if depth > 0 => depth -= 1,
            Component::ParentDir => return refuse("leads out of the folder with `..`"),
            Component::RootDir | Component::Prefix(_) => return refuse("is an absolute path"),
        }
    }
    if let (Ok(b), Ok(f)) = (base.canonicalize(), base.join(rel).canonicalize())
        && !f.starts_with(&b)
    {
        return refuse("leads out of the folder through a symbolic link");
    }
    Ok(())
}

/// Where a buffer's bytes came from, for messages.
pub(super) fn source_label(source: Source<'_>, base_dir: Option<&Path>) -> String {
    match source {
        Source::Bin => "the .glb binary chunk".into(),
        Source::Uri(uri) if uri.starts_with("data:") => "its data: URI".into(),
        Source::Uri(uri) => {
            let relative = percent_decode(uri).unwrap_or_else(|| uri.to_string());
            let file = base_dir.map_or_else(|| PathBuf::from(&relative), |b| b.join(&relative));
            format!("`{}`", file.display())
        }
    }
}

/// Decodes `%XX` escapes; `None` for a bad escape or a result that is not UTF-8.
pub(super) fn percent_decode(text: &str) -> Option<String> {
    let mut out = Vec::with_capacity(text.len());
    let mut bytes = text.bytes();
    while let Some(b) = bytes.next() {
        if b == b'%' {
            let high = char::from(bytes.next()?).to_digit(16)?;
            let low = char::from(bytes.next()?).to_digit(16)?;
            out.push((high * 16 + low) as u8);
        } else {
            out.push(b);
        }
    }
    String::from_utf8(out).ok()
}

/// The first 60 characters of `text`, for messages.
pub(super) fn short(text: &str) -> String {
    const MAX: usize = 60;
    match text.char_indices().nth(MAX) {
        Some((end, _)) => format!("{}...", &text[..end]),
        None => text.to_string(),
    }
}
