//! glTF 2.0 import: turns a `.gltf` (JSON with external `.bin` files or `data:` URIs) or a `.glb`
//! (binary glTF) into one [`TriMesh`] in the file's own space, plus warnings about what the file
//! uses that is not imported ([`GltfImport`]).
//!
//! What is imported:
//!
//! * every mesh primitive reachable from the default scene, or from the root nodes of all scenes
//!   when no default is set, or every mesh (untransformed) when the file has no scenes at all;
//! * node transforms through the whole hierarchy (TRS or matrix), normals by the inverse transpose;
//! * `POSITION` (required), `NORMAL` (optional), `COLOR_0` (optional) and `TEXCOORD_0` (optional;
//!   float, or normalized u8/u16) attributes;
//! * vertex colour = the material's base colour factor × `COLOR_0` (white when both are absent);
//! * UVs = `TEXCOORD_0` as in the file (V grows down the image). [`TriMesh::uvs`] stays empty when
//!   no imported primitive has `TEXCOORD_0`; otherwise primitives without it get UV 0;
//! * the material's base-colour texture and normal texture: each primitive with either becomes a
//!   [`MeshPart`](crate::mesh::MeshPart) from its first triangle, with
//!   [`SurfaceMaps`](texel_geom::texture::SurfaceMaps) at UV scale 1. Images come from a buffer
//!   view (`.glb`), a base64 `data:` URI or an external file (same rules as buffers, below), PNG
//!   or JPEG recognised from the bytes (`mimeType` is not checked), decoded by
//!   [`decode_texture`](crate::texture::decode_texture) once per file, however many primitives
//!   use them (they share one [`Image`](texel_geom::texture::Image));
//! * samplers: `magFilter` NEAREST → [`Filter::Nearest`](texel_geom::texture::Filter), LINEAR →
//!   linear, absent → nearest (the pixel-art default, where glTF leaves it to the renderer);
//!   `minFilter` is not read (the one filter serves magnification and minification); `wrapS` /
//!   `wrapT` → the wrap along U / V;
//! * primitive modes `TRIANGLES`, `TRIANGLE_STRIP` and `TRIANGLE_FAN` (strips and fans become
//!   triangle lists with the spec's winding; strip triangles with a repeated index are dropped).
//!
//! Normals are always unit length: when a primitive has no `NORMAL` attribute, or one of its
//! normals cannot be normalised, the primitive is flat shaded (one vertex per triangle corner,
//! normal = the counter-clockwise face normal, colour and UV of the corner) and zero-area
//! triangles are dropped.
//!
//! Reported, once per file each ([`GltfImport::warnings`]; the mesh still imports):
//! metallic-roughness, occlusion and emissive textures; textures on `TEXCOORD_1` or above (not
//! applied); a normal texture `scale` other than 1 (applied at 1); a textured primitive without
//! `TEXCOORD_0`; morph targets (base shape kept); skins (placed by the node transforms,
//! unposed); animations; cameras; every extension in `extensionsUsed` (none is implemented:
//! `KHR_texture_transform`, `KHR_lights_punctual`, `KHR_materials_*` ... are all ignored). For
//! materials, textures and morph targets only what imported primitives use is checked.
//!
//! Not imported, silently: other material properties (metallic, roughness, alpha mode, double
//! sidedness), `TANGENT` (normal maps are defined along the UVs, see `SurfaceMaps::normal`),
//! `TEXCOORD_1` and above, `COLOR_1` and above, joint and weight attributes. Primitives under a
//! node whose world transform is singular (e.g. scale 0, a common way to hide something)
//! contribute nothing.
//!
//! Rejected with a [`GltfError`] (never a panic): unreadable files, empty or non-glTF bytes,
//! truncated `.glb` files or buffers, JSON syntax or schema errors (with line and column),
//! documents that fail glTF validation, any `extensionsRequired` entry (no extension is
//! implemented), point and line primitive modes, sparse accessors, accessors out of their buffer's
//! bounds or of the wrong type, indices past the last vertex, NaN or infinite positions, colours
//! or texture coordinates, integer `TEXCOORD_0` that is not normalized, node hierarchies that are
//! not trees (cycles), files that yield no triangle at all, and an image an imported primitive's
//! base-colour or normal texture uses that is missing, unreadable, refused (URI rules below), not
//! PNG or JPEG, corrupt, or larger than [`MAX_TEXTURE_SIZE`](texel_geom::texture::MAX_TEXTURE_SIZE)
//! on a side ([`GltfError::Image`], naming the image's index and, for a file, its path).
//!
//! Untrusted files are bounded ([`GltfLimits`]): the file and each external buffer or image are
//! read through [`crate::read`] (regular files only, size caps); a document with more nodes, mesh
//! instances (primitives placed by the node graph) or triangles than the limits is refused
//! before its triangles are built ([`GltfError::Budget`]), and so is one whose images decode to
//! more than [`max_image_bytes`] in all (checked as each is decoded); buffer and image URIs must
//! be relative paths inside the glTF file's own folder (no absolute paths, no `..` or symlink
//! leading out of it) unless [`GltfLimits::allow_any_uri`] is set. Images no imported primitive
//! uses are never read.

mod accessors;
mod buffers;
mod container;
mod convert;
mod geometry;
mod report;
mod textures;

use std::path::{Path, PathBuf};

use crate::mesh::TriMesh;
use crate::read::{FileKind, ReadError, env_u64, read_bounded};

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
    /// The file is not a regular file, or is larger than the cap for glTF files.
    #[error(transparent)]
    Read(ReadError),
    /// The document exceeds a [`GltfLimits`] budget (nodes, mesh instances, triangles).
    #[error("{}: too large to import: {detail}", path.display())]
    Budget {
        /// The file.
        path: PathBuf,
        /// Which budget, the amount asked for and the limit (and how to raise it).
        detail: String,
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
    /// An image a used texture needs could not be loaded: missing or unreadable file, URI
    /// refused, not PNG or JPEG, corrupt, or too large.
    #[error("{}: image {index}: {detail}", path.display())]
    Image {
        /// The file.
        path: PathBuf,
        /// Index of the image in the document.
        index: usize,
        /// What went wrong (naming the image's own file, if it has one).
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
            Self::Read(e) => e.path(),
            Self::Io { path, .. }
            | Self::Budget { path, .. }
            | Self::Container { path, .. }
            | Self::Json { path, .. }
            | Self::Invalid { path, .. }
            | Self::Unsupported { path, .. }
            | Self::Buffer { path, .. }
            | Self::Image { path, .. }
            | Self::Accessor { path, .. }
            | Self::NoGeometry { path } => path,
        }
    }
}

/// Bounds on what one glTF file may make the importer do. [`GltfLimits::default`] holds the
/// built-in values; [`GltfLimits::from_env`] (what [`load_gltf`] uses) lets environment
/// variables override each.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GltfLimits {
    /// Most nodes in the document (`TEXEL_GLTF_MAX_NODES`, default 100,000).
    pub max_nodes: usize,
    /// Most primitive instances the node graph places (`TEXEL_GLTF_MAX_INSTANCES`, default
    /// 100,000): a mesh of 3 primitives under 10 nodes is 30.
    pub max_instances: usize,
    /// Most triangles in the imported mesh, over every instance (`TEXEL_GLTF_MAX_TRIANGLES`,
    /// default 4,000,000, about 500 MB of mesh at worst).
    pub max_triangles: usize,
    /// Read buffer and image URIs anywhere (absolute paths, `..`) rather than only inside the glTF
    /// file's folder (`TEXEL_GLTF_ANY_URI=1`, default off).
    pub allow_any_uri: bool,
}

impl Default for GltfLimits {
    fn default() -> Self {
        GltfLimits {
            max_nodes: 100_000,
            max_instances: 100_000,
            max_triangles: 4_000_000,
            allow_any_uri: false,
        }
    }
}

impl GltfLimits {
    /// The defaults, each overridden by its environment variable when that holds a positive
    /// number (or `1` for `TEXEL_GLTF_ANY_URI`).
    pub fn from_env() -> Self {
        let d = Self::default();
        let get = |name, default: usize| env_u64(name).map_or(default, |v| v as usize);
        GltfLimits {
            max_nodes: get("TEXEL_GLTF_MAX_NODES", d.max_nodes),
            max_instances: get("TEXEL_GLTF_MAX_INSTANCES", d.max_instances),
            max_triangles: get("TEXEL_GLTF_MAX_TRIANGLES", d.max_triangles),
            allow_any_uri: std::env::var("TEXEL_GLTF_ANY_URI").is_ok_and(|v| v.trim() == "1"),
        }
    }
}

/// The default of [`max_image_bytes`]: 1 GiB of decoded RGBA8 pixels (64 images of
/// 2048 × 2048).
pub const DEFAULT_MAX_IMAGE_BYTES: u64 = 1 << 30;

/// Most bytes the images of one glTF file may decode to, in all (RGBA8, 4 bytes a pixel):
/// `TEXEL_GLTF_MAX_IMAGE_BYTES` when it holds a positive number, else
/// [`DEFAULT_MAX_IMAGE_BYTES`]. (Each image is also bounded by
/// [`MAX_TEXTURE_SIZE`](texel_geom::texture::MAX_TEXTURE_SIZE) on a side.) Not a
/// [`GltfLimits`] field, so that code building `GltfLimits` literally keeps compiling.
pub fn max_image_bytes() -> u64 {
    env_u64("TEXEL_GLTF_MAX_IMAGE_BYTES").unwrap_or(DEFAULT_MAX_IMAGE_BYTES)
}

/// An imported glTF file: its mesh, and what it uses that was not imported.
#[derive(Debug, Clone, PartialEq)]
pub struct GltfImport {
    /// Every primitive of the scene, in the file's space.
    pub mesh: TriMesh,
    /// One message per feature the file uses that is not imported (see the
    /// [module docs](self)), first used first; each names where it was first seen, not the
    /// file.
    pub warnings: Vec<String>,
}

/// Loads every mesh primitive of the default scene (or all scenes' root nodes if there is no
/// default; or all meshes if there are no scenes) with node transforms applied through the full
/// hierarchy, into one [`TriMesh`] in the file's space, with UVs and textures. Relative buffer and
/// image URIs resolve against the file's directory. See the [module docs](self) for what is
/// imported, reported and rejected. Bounded by [`GltfLimits::from_env`] and
/// [`max_image_bytes`]. The warnings are dropped: [`load_gltf_report`] keeps them.
pub fn load_gltf(path: &Path) -> Result<TriMesh, GltfError> {
    load_gltf_report(path).map(|import| import.mesh)
}

/// [`load_gltf`] with explicit limits.
pub fn load_gltf_with(path: &Path, limits: &GltfLimits) -> Result<TriMesh, GltfError> {
    load_gltf_report_with(path, limits).map(|import| import.mesh)
}

/// [`load_gltf`], with the warnings about what the file uses that is not imported.
pub fn load_gltf_report(path: &Path) -> Result<GltfImport, GltfError> {
    load_gltf_report_with(path, &GltfLimits::from_env())
}

/// [`load_gltf_report`] with explicit limits.
pub fn load_gltf_report_with(path: &Path, limits: &GltfLimits) -> Result<GltfImport, GltfError> {
    let bytes = read_bounded(path, FileKind::Mesh).map_err(|e| match e {
        ReadError::Io { path, source, .. } => GltfError::Io { path, source },
        other => GltfError::Read(other),
    })?;
    load_gltf_slice_report_with(&bytes, path.parent(), path, limits)
}

/// Same as [`load_gltf`], from the bytes of a `.gltf` or `.glb` already in memory. `base_dir`
/// resolves relative buffer and image URIs (external files; with `None` they are an error);
/// `name` is what errors call the file.
pub fn load_gltf_slice(
    bytes: &[u8],
    base_dir: Option<&Path>,
    name: &Path,
) -> Result<TriMesh, GltfError> {
    load_gltf_slice_with(bytes, base_dir, name, &GltfLimits::from_env())
}

/// [`load_gltf_slice`] with explicit limits.
pub fn load_gltf_slice_with(
    bytes: &[u8],
    base_dir: Option<&Path>,
    name: &Path,
    limits: &GltfLimits,
) -> Result<TriMesh, GltfError> {
    load_gltf_slice_report_with(bytes, base_dir, name, limits).map(|import| import.mesh)
}

/// [`load_gltf_slice_with`], with the warnings.
pub fn load_gltf_slice_report_with(
    bytes: &[u8],
    base_dir: Option<&Path>,
    name: &Path,
    limits: &GltfLimits,
) -> Result<GltfImport, GltfError> {
    import(bytes, base_dir, name, limits, max_image_bytes())
}

/// The importer behind every `load_gltf*` function.
fn import(
    bytes: &[u8],
    base_dir: Option<&Path>,
    name: &Path,
    limits: &GltfLimits,
    max_image_bytes: u64,
) -> Result<GltfImport, GltfError> {
    let (json, blob) = split_container(bytes).map_err(|detail| GltfError::Container {
        path: name.to_path_buf(),
        detail,
    })?;
    let document = parse_document(json, name)?;
    let nodes = document.nodes().len();
    if nodes > limits.max_nodes {
        return Err(GltfError::Budget {
            path: name.to_path_buf(),
            detail: format!(
                "{nodes} nodes, the limit is {} (set TEXEL_GLTF_MAX_NODES to raise it)",
                limits.max_nodes
            ),
        });
    }
    let buffers = load_buffers(&document, blob, base_dir, name, limits.allow_any_uri)?;
    let importer = Importer::new(name, base_dir, &document, buffers, limits, max_image_bytes);
    let mesh = importer.scene_mesh()?;
    if mesh.indices.is_empty() {
        return Err(GltfError::NoGeometry {
            path: name.to_path_buf(),
        });
    }
    Ok(GltfImport {
        mesh,
        warnings: importer.into_warnings(),
    })
}

#[cfg(test)]
mod tests;
