//! The container: a `.gltf`'s JSON text or a `.glb`'s header and chunks, and the JSON parsed
//! and validated into a [`Document`].

use std::path::Path;

use gltf::{Document, Semantic};

use super::GltfError;

pub(super) const GLB_MAGIC: &[u8] = b"glTF";
pub(super) const GLB_HEADER_LEN: usize = 12;
pub(super) const UTF8_BOM: &[u8] = b"\xEF\xBB\xBF";

/// Splits the file into its JSON text and, for `.glb`, the binary chunk.
pub(super) fn split_container(bytes: &[u8]) -> Result<(&[u8], Option<&[u8]>), String> {
    if bytes.is_empty() {
        return Err("file is empty (0 bytes)".into());
    }
    if bytes.starts_with(GLB_MAGIC) {
        return split_glb(bytes);
    }
    let text = bytes.strip_prefix(UTF8_BOM).unwrap_or(bytes);
    match text.iter().find(|b| !b.is_ascii_whitespace()) {
        Some(b'{') => Ok((text, None)),
        _ => Err("not a glTF file: neither binary glTF (no `glTF` magic) nor a JSON object".into()),
    }
}

/// Parses the GLB header and chunks; unknown chunk types are skipped, as the spec asks.
pub(super) fn split_glb(bytes: &[u8]) -> Result<(&[u8], Option<&[u8]>), String> {
    let (Some(version), Some(declared)) = (le_u32(bytes, 4), le_u32(bytes, 8)) else {
        return Err(format!(
            "truncated binary glTF: {} bytes, shorter than the {GLB_HEADER_LEN}-byte header",
            bytes.len()
        ));
    };
    if version != 2 {
        return Err(format!(
            "unsupported binary glTF version {version} (only version 2 is supported)"
        ));
    }
    let declared = declared as usize;
    let body = bytes.get(GLB_HEADER_LEN..declared).ok_or_else(|| {
        if declared > bytes.len() {
            format!(
                "truncated binary glTF: the header declares {declared} bytes but the file has {}",
                bytes.len()
            )
        } else {
            format!("malformed binary glTF: the header declares a total length of {declared} bytes")
        }
    })?;
    let (kind, json, mut rest) = glb_chunk(body)?;
    if kind != *b"JSON" {
        return Err("malformed binary glTF: the first chunk is not JSON".into());
    }
    let mut blob = None;
    while !rest.is_empty() {
        let (kind, data, tail) = glb_chunk(rest)?;
        if kind == *b"BIN\0" && blob.is_none() {
            blob = Some(data);
        }
        rest = tail;
    }
    Ok((json, blob))
}

/// A GLB chunk's type and data, and the bytes after it.
pub(super) type Chunk<'a> = ([u8; 4], &'a [u8], &'a [u8]);

/// Splits one chunk off the front of `bytes`.
pub(super) fn glb_chunk(bytes: &[u8]) -> Result<Chunk<'_>, String> {
    let (Some(len), Some(kind)) = (le_u32(bytes, 0), bytes.get(4..8)) else {
        return Err(format!(
            "truncated binary glTF: {} stray bytes where an 8-byte chunk header should be",
            bytes.len()
        ));
    };
    let kind = [kind[0], kind[1], kind[2], kind[3]];
    let body = bytes.get(8..).unwrap_or_default();
    let (data, rest) = body.split_at_checked(len as usize).ok_or_else(|| {
        format!(
            "truncated binary glTF: the {} chunk declares {len} bytes but only {} remain",
            String::from_utf8_lossy(&kind).trim_end_matches('\0'),
            body.len()
        )
    })?;
    Ok((kind, data, rest))
}

pub(super) fn le_u32(bytes: &[u8], at: usize) -> Option<u32> {
    let b = bytes.get(at..at.checked_add(4)?)?;
    Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
}

// ---- document ---------------------------------------------------------------------------------

/// Deserialises and validates the JSON; rejects required extensions.
pub(super) fn parse_document(json: &[u8], name: &Path) -> Result<Document, GltfError> {
    let root: gltf::json::Root =
        gltf::json::deserialize::from_slice(json).map_err(|e| GltfError::Json {
            path: name.to_path_buf(),
            message: e.to_string(),
            line: e.line(),
            column: e.column(),
        })?;
    if !root.extensions_required.is_empty() {
        return Err(GltfError::Unsupported {
            path: name.to_path_buf(),
            detail: format!(
                "required extension `{}` (this importer implements no glTF extension)",
                root.extensions_required.join("`, `")
            ),
        });
    }
    let invalid = |detail| GltfError::Invalid {
        path: name.to_path_buf(),
        detail,
    };
    check_position_indices(&root).map_err(invalid)?;
    Document::from_json(root).map_err(|e| invalid(validation_message(e)))
}

/// gltf-json 1.4.1's validation indexes `accessors` with each `POSITION` index before checking
/// it (a panic on a dangling index), so those are checked here first.
pub(super) fn check_position_indices(root: &gltf::json::Root) -> Result<(), String> {
    let key = gltf::json::validation::Checked::Valid(Semantic::Positions);
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            match primitive.attributes.get(&key) {
                Some(index) if index.value() >= root.accessors.len() => {
                    return Err(format!(
                        "meshes[{m}].primitives[{p}].attributes.POSITION: accessor {} does not \
                         exist (there are {})",
                        index.value(),
                        root.accessors.len()
                    ));
                }
                _ => {}
            }
        }
    }
    Ok(())
}

/// Lists (the first few) validation failures as `path: problem; ...`.
pub(super) fn validation_message(error: gltf::Error) -> String {
    const SHOWN: usize = 5;
    let gltf::Error::Validation(list) = error else {
        return error.to_string();
    };
    let mut text: Vec<String> = list
        .iter()
        .take(SHOWN)
        .map(|(path, problem)| format!("{path}: {problem}"))
        .collect();
    if list.len() > SHOWN {
        text.push(format!("and {} more", list.len() - SHOWN));
    }
    text.join("; ")
}
