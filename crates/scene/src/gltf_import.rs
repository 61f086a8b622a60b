//! glTF 2.0 import: turns a `.gltf` (JSON with external `.bin` files or `data:` URIs) or a `.glb`
//! (binary glTF) into one [`TriMesh`] in the file's own space.
//!
//! What is imported:
//!
//! * every mesh primitive reachable from the default scene, or from the root nodes of all scenes
//!   when no default is set, or every mesh (untransformed) when the file has no scenes at all;
//! * node transforms through the whole hierarchy (TRS or matrix), normals by the inverse transpose;
//! * `POSITION` (required), `NORMAL` (optional) and `COLOR_0` (optional) attributes;
//! * vertex colour = the material's base colour factor × `COLOR_0` (white when both are absent);
//! * primitive modes `TRIANGLES`, `TRIANGLE_STRIP` and `TRIANGLE_FAN` (strips and fans become
//!   triangle lists with the spec's winding; strip triangles with a repeated index are dropped).
//!
//! Normals are always unit length: when a primitive has no `NORMAL` attribute, or one of its
//! normals cannot be normalised, the primitive is flat shaded (one vertex per triangle corner,
//! normal = the counter-clockwise face normal) and zero-area triangles are dropped.
//!
//! Not imported, silently: textures and images (never read or decoded), UVs, tangents, skins,
//! morph targets, cameras, lights, animations. Primitives under a node whose world transform is
//! singular (e.g. scale 0, a common way to hide something) contribute nothing.
//!
//! Rejected with a [`GltfError`] (never a panic): unreadable files, empty or non-glTF bytes,
//! truncated `.glb` files or buffers, JSON syntax or schema errors (with line and column),
//! documents that fail glTF validation, any `extensionsRequired` entry (no extension is
//! implemented), point and line primitive modes, sparse accessors, accessors out of their buffer's
//! bounds or of the wrong type, indices past the last vertex, NaN or infinite positions or colours,
//! node hierarchies that are not trees (cycles), and files that yield no triangle at all.

mod accessors;
mod buffers;
mod container;
mod convert;
mod geometry;

use std::path::{Path, PathBuf};

use crate::mesh::TriMesh;

use buffers::load_buffers;
use container::{parse_document, split_container};
use convert::Importer;

/// Error loading a glTF file; every variant names the file, and its message starts with that
/// file's path.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum GltfError {
    /// The glTF file itself could not be read.
    #[error("{}: cannot read file: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// Why reading failed.
        source: std::io::Error,
    },
    /// The bytes are not a usable glTF container: empty, neither binary glTF nor JSON, or a
    /// truncated or malformed `.glb`.
    #[error("{}: {detail}", path.display())]
    Container {
        /// The file.
        path: PathBuf,
        /// What is wrong with the container.
        detail: String,
    },
    /// The JSON does not parse, or does not match the glTF schema's types.
    #[error("{}: invalid glTF JSON: {message}", path.display())]
    Json {
        /// The file.
        path: PathBuf,
        /// The parser's message (ends with "at line L column C" when known).
        message: String,
        /// 1-based line of the error in the JSON text (of the JSON chunk for `.glb`), 0 if unknown.
        line: usize,
        /// 1-based column of the error, 0 if unknown.
        column: usize,
    },
    /// The document parses but breaks a glTF rule (dangling index, missing property, node
    /// hierarchy that is not a tree, ...).
    #[error("{}: invalid glTF: {detail}", path.display())]
    Invalid {
        /// The file.
        path: PathBuf,
        /// Which rule is broken, and where.
        detail: String,
    },
    /// The file needs a feature this importer does not implement.
    #[error("{}: unsupported {detail}", path.display())]
    Unsupported {
        /// The file.
        path: PathBuf,
        /// The feature, and where it is used.
        detail: String,
    },
    /// A buffer could not be loaded (missing or truncated `.bin`, bad `data:` URI, ...).
    #[error("{}: buffer {index}: {detail}", path.display())]
    Buffer {
        /// The file.
        path: PathBuf,
        /// Index of the buffer in the document.
        index: usize,
        /// What went wrong.
        detail: String,
    },
    /// An accessor's data is out of its buffer's bounds, of the wrong type, not finite, or an
    /// index past the last vertex.
    #[error("{}: accessor {index}: {detail}", path.display())]
    Accessor {
        /// The file.
        path: PathBuf,
        /// Index of the accessor in the document.
        index: usize,
        /// What is wrong with its data.
        detail: String,
    },
    /// The file is valid but yields no triangles.
    #[error("{}: no triangles to import in the scene", path.display())]
    NoGeometry {
        /// The file.
        path: PathBuf,
    },
}

impl GltfError {
    /// The file the error is about.
    pub fn path(&self) -> &Path {
        match self {
            Self::Io { path, .. }
            | Self::Container { path, .. }
            | Self::Json { path, .. }
            | Self::Invalid { path, .. }
            | Self::Unsupported { path, .. }
            | Self::Buffer { path, .. }
            | Self::Accessor { path, .. }
            | Self::NoGeometry { path } => path,
        }
    }
}

/// Loads every mesh primitive of the default scene (or all scenes' root nodes if there is no
/// default; or all meshes if there are no scenes) with node transforms applied through the full
/// hierarchy, into one [`TriMesh`] in the file's space. Relative buffer URIs resolve against the
/// file's directory. See the [module docs](self) for what is imported and what is rejected.
pub fn load_gltf(path: &Path) -> Result<TriMesh, GltfError> {
    let bytes = std::fs::read(path).map_err(|source| GltfError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    load_gltf_slice(&bytes, path.parent(), path)
}

/// Same as [`load_gltf`], from the bytes of a `.gltf` or `.glb` already in memory. `base_dir`
/// resolves relative buffer URIs (external `.bin` files; with `None` they are an error); `name` is
/// what errors call the file.
pub fn load_gltf_slice(
    bytes: &[u8],
    base_dir: Option<&Path>,
    name: &Path,
) -> Result<TriMesh, GltfError> {
    let (json, blob) = split_container(bytes).map_err(|detail| GltfError::Container {
        path: name.to_path_buf(),
        detail,
    })?;
    let document = parse_document(json, name)?;
    let buffers = load_buffers(&document, blob, base_dir, name)?;
    let mesh = Importer { name, buffers }.scene_mesh(&document)?;
    if mesh.indices.is_empty() {
        return Err(GltfError::NoGeometry {
            path: name.to_path_buf(),
        });
    }
    Ok(mesh)
}

#[cfg(test)]
mod tests;
