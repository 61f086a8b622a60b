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

use std::borrow::Cow;
use std::collections::HashSet;
use std::fmt;
use std::path::{Path, PathBuf};

use glam::{Mat4, Vec3};
use gltf::accessor::{DataType, Dimensions};
use gltf::buffer::Source;
use gltf::mesh::Mode;
use gltf::{Accessor, Document, Node, Primitive, Semantic};

use crate::mesh::TriMesh;

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

// ---- container: JSON text or GLB ----------------------------------------------------------------

const GLB_MAGIC: &[u8] = b"glTF";
const GLB_HEADER_LEN: usize = 12;
const UTF8_BOM: &[u8] = b"\xEF\xBB\xBF";

/// Splits the file into its JSON text and, for `.glb`, the binary chunk.
fn split_container(bytes: &[u8]) -> Result<(&[u8], Option<&[u8]>), String> {
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
fn split_glb(bytes: &[u8]) -> Result<(&[u8], Option<&[u8]>), String> {
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
type Chunk<'a> = ([u8; 4], &'a [u8], &'a [u8]);

/// Splits one chunk off the front of `bytes`.
fn glb_chunk(bytes: &[u8]) -> Result<Chunk<'_>, String> {
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

fn le_u32(bytes: &[u8], at: usize) -> Option<u32> {
    let b = bytes.get(at..at.checked_add(4)?)?;
    Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
}

// ---- document ---------------------------------------------------------------------------------

/// Deserialises and validates the JSON; rejects required extensions.
fn parse_document(json: &[u8], name: &Path) -> Result<Document, GltfError> {
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
fn check_position_indices(root: &gltf::json::Root) -> Result<(), String> {
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
fn validation_message(error: gltf::Error) -> String {
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

// ---- buffers ----------------------------------------------------------------------------------

/// Loads every buffer: the GLB binary chunk (borrowed), `data:` URIs, or files next to the glTF.
fn load_buffers<'a>(
    doc: &Document,
    blob: Option<&'a [u8]>,
    base_dir: Option<&Path>,
    name: &Path,
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
                Source::Uri(uri) => read_uri(uri, base_dir).map(Cow::Owned),
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

/// Reads a buffer URI: a `data:` URI, or a percent-encoded path relative to `base_dir`.
fn read_uri(uri: &str, base_dir: Option<&Path>) -> Result<Vec<u8>, String> {
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
    let file = base.join(&relative);
    std::fs::read(&file).map_err(|e| format!("cannot read `{}`: {e}", file.display()))
}

/// Where a buffer's bytes came from, for messages.
fn source_label(source: Source<'_>, base_dir: Option<&Path>) -> String {
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
fn percent_decode(text: &str) -> Option<String> {
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
fn short(text: &str) -> String {
    const MAX: usize = 60;
    match text.char_indices().nth(MAX) {
        Some((end, _)) => format!("{}...", &text[..end]),
        None => text.to_string(),
    }
}

// ---- scene traversal ----------------------------------------------------------------------------

/// A primitive's place in the document, for messages.
#[derive(Clone, Copy)]
struct Site {
    mesh: usize,
    primitive: usize,
}

impl fmt::Display for Site {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "mesh {} primitive {}", self.mesh, self.primitive)
    }
}

/// The loaded buffers plus the file name errors report.
struct Importer<'a> {
    name: &'a Path,
    buffers: Vec<Cow<'a, [u8]>>,
}

impl Importer<'_> {
    fn invalid(&self, detail: String) -> GltfError {
        GltfError::Invalid {
            path: self.name.to_path_buf(),
            detail,
        }
    }

    fn unsupported(&self, detail: String) -> GltfError {
        GltfError::Unsupported {
            path: self.name.to_path_buf(),
            detail,
        }
    }

    fn accessor_error(&self, accessor: &Accessor<'_>, detail: String) -> GltfError {
        GltfError::Accessor {
            path: self.name.to_path_buf(),
            index: accessor.index(),
            detail,
        }
    }

    /// Default scene, else every scene, else every mesh untransformed.
    fn scene_mesh(&self, doc: &Document) -> Result<TriMesh, GltfError> {
        let mut out = TriMesh::default();
        if let Some(scene) = doc.default_scene() {
            self.add_scene(&scene, &mut out)?;
        } else if doc.scenes().len() > 0 {
            for scene in doc.scenes() {
                self.add_scene(&scene, &mut out)?;
            }
        } else {
            for mesh in doc.meshes() {
                self.add_mesh(&mesh, Mat4::IDENTITY, &mut out)?;
            }
        }
        Ok(out)
    }

    /// Walks the scene's node trees depth-first in document order (no recursion, so deep
    /// hierarchies cannot overflow the stack); a node reached twice means a cycle or shared child.
    fn add_scene(&self, scene: &gltf::Scene<'_>, out: &mut TriMesh) -> Result<(), GltfError> {
        let mut seen = HashSet::new();
        let mut stack: Vec<(Node<'_>, Mat4)> = Vec::new();
        push_children(&mut stack, scene.nodes(), Mat4::IDENTITY);
        while let Some((node, parent)) = stack.pop() {
            if !seen.insert(node.index()) {
                return Err(self.invalid(format!(
                    "node {} is reached more than once from scene {} (a cycle or a shared \
                     child; node hierarchies must be trees)",
                    node.index(),
                    scene.index()
                )));
            }
            let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
            if !world.is_finite() {
                return Err(self.invalid(format!("node {}: transform is not finite", node.index())));
            }
            if let Some(mesh) = node.mesh() {
                self.add_mesh(&mesh, world, out)?;
            }
            push_children(&mut stack, node.children(), world);
        }
        Ok(())
    }

    /// Appends every primitive of `mesh`, transformed by `world` (skipped if `world` is singular).
    fn add_mesh(
        &self,
        mesh: &gltf::Mesh<'_>,
        world: Mat4,
        out: &mut TriMesh,
    ) -> Result<(), GltfError> {
        let invertible = world.determinant() != 0.0 && world.inverse().is_finite();
        for primitive in mesh.primitives() {
            let site = Site {
                mesh: mesh.index(),
                primitive: primitive.index(),
            };
            let local = self.primitive_mesh(&primitive, site)?;
            if !invertible {
                continue;
            }
            let start = out.positions.len();
            out.append_transformed(&local, world);
            let overflow = out.positions[start..].iter().any(|p| !p.is_finite())
                || out.normals[start..].contains(&Vec3::ZERO);
            if overflow {
                return Err(self.invalid(format!(
                    "{site}: positions or normals overflow under the node transforms"
                )));
            }
        }
        Ok(())
    }

    // ---- one primitive ------------------------------------------------------------------------

    /// Reads one primitive as a triangle list in its mesh's local space.
    fn primitive_mesh(&self, prim: &Primitive<'_>, site: Site) -> Result<TriMesh, GltfError> {
        let mode = prim.mode();
        if !matches!(
            mode,
            Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
        ) {
            return Err(self.unsupported(format!(
                "primitive mode {} in {site} (only TRIANGLES, TRIANGLE_STRIP and TRIANGLE_FAN \
                 are imported)",
                mode_name(mode)
            )));
        }
        let Some(position_accessor) = prim.get(&Semantic::Positions) else {
            return Err(self.invalid(format!("{site} has no POSITION attribute")));
        };
        let positions = self.read_positions(&position_accessor, site)?;
        let count = positions.len();
        let corners = match prim.indices() {
            Some(accessor) => self.read_indices(&accessor, count, site)?,
            None => (0..count as u32).collect(),
        };
        let indices = triangle_list(mode, &corners)
            .map_err(|detail| self.invalid(format!("{site}: {detail}")))?;
        let colors = self.vertex_colors(prim, count, site)?;
        Ok(match self.vertex_normals(prim, count, site)? {
            Some(normals) => TriMesh {
                positions,
                normals,
                colors,
                indices,
            },
            None => flat_shaded(&positions, &colors, &indices),
        })
    }

    fn read_positions(&self, acc: &Accessor<'_>, site: Site) -> Result<Vec<Vec3>, GltfError> {
        let positions = self.read_vec3(acc, "POSITION", site, None)?;
        match positions.iter().position(|p| !p.is_finite()) {
            Some(i) => Err(self.accessor_error(
                acc,
                format!(
                    "POSITION of {site}: element {i} is not finite ({})",
                    positions[i]
                ),
            )),
            None => Ok(positions),
        }
    }

    /// Unit normals, or `None` when absent or some cannot be normalised (then: flat shading).
    fn vertex_normals(
        &self,
        prim: &Primitive<'_>,
        count: usize,
        site: Site,
    ) -> Result<Option<Vec<Vec3>>, GltfError> {
        let Some(acc) = prim.get(&Semantic::Normals) else {
            return Ok(None);
        };
        let normals = self.read_vec3(&acc, "NORMAL", site, Some(count))?;
        Ok(normals.iter().map(|n| n.try_normalize()).collect())
    }

    /// Base colour factor × `COLOR_0` (either may be absent), clamped to `[0, 1]`.
    fn vertex_colors(
        &self,
        prim: &Primitive<'_>,
        count: usize,
        site: Site,
    ) -> Result<Vec<[f32; 4]>, GltfError> {
        let factor = prim
            .material()
            .pbr_metallic_roughness()
            .base_color_factor()
            .map(|c| c.clamp(0.0, 1.0));
        let Some(acc) = prim.get(&Semantic::Colors(0)) else {
            return Ok(vec![factor; count]);
        };
        let colors = self.read_colors(&acc, count, site)?;
        Ok(colors
            .into_iter()
            .map(|c| std::array::from_fn(|k| factor[k] * c[k].clamp(0.0, 1.0)))
            .collect())
    }

    // ---- typed accessor reads -----------------------------------------------------------------

    /// Checks an accessor's shape against what its semantic allows.
    fn expect_type(
        &self,
        acc: &Accessor<'_>,
        what: &str,
        dims: &[Dimensions],
        types: &[DataType],
    ) -> Result<(), GltfError> {
        if dims.contains(&acc.dimensions()) && types.contains(&acc.data_type()) {
            return Ok(());
        }
        Err(self.accessor_error(
            acc,
            format!(
                "{what} must be {dims:?} of {types:?}, found {:?} of {:?}",
                acc.dimensions(),
                acc.data_type()
            ),
        ))
    }

    /// Checks that an attribute has one element per vertex.
    fn expect_count(
        &self,
        acc: &Accessor<'_>,
        what: &str,
        expected: Option<usize>,
    ) -> Result<(), GltfError> {
        match expected {
            Some(n) if acc.count() != n => Err(self.accessor_error(
                acc,
                format!("{what} has {} elements but POSITION has {n}", acc.count()),
            )),
            _ => Ok(()),
        }
    }

    /// Reads a float VEC3 attribute.
    fn read_vec3(
        &self,
        acc: &Accessor<'_>,
        semantic: &str,
        site: Site,
        expected: Option<usize>,
    ) -> Result<Vec<Vec3>, GltfError> {
        let what = format!("{semantic} of {site}");
        self.expect_type(acc, &what, &[Dimensions::Vec3], &[DataType::F32])?;
        self.expect_count(acc, &what, expected)?;
        let raw = self.read_raw(acc)?;
        Ok(raw
            .chunks_exact(3)
            .map(|c| {
                Vec3::new(
                    f32::from_bits(c[0]),
                    f32::from_bits(c[1]),
                    f32::from_bits(c[2]),
                )
            })
            .collect())
    }

    /// Reads `COLOR_0` (RGB or RGBA; float or normalised u8/u16) as RGBA.
    fn read_colors(
        &self,
        acc: &Accessor<'_>,
        count: usize,
        site: Site,
    ) -> Result<Vec<[f32; 4]>, GltfError> {
        let what = format!("COLOR_0 of {site}");
        let dims = [Dimensions::Vec3, Dimensions::Vec4];
        let types = [DataType::F32, DataType::U8, DataType::U16];
        self.expect_type(acc, &what, &dims, &types)?;
        self.expect_count(acc, &what, Some(count))?;
        let scale = match acc.data_type() {
            DataType::U8 => Some(255.0),
            DataType::U16 => Some(65535.0),
            _ => None,
        };
        let values: Vec<f32> = self
            .read_raw(acc)?
            .into_iter()
            .map(|bits| scale.map_or(f32::from_bits(bits), |s| bits as f32 / s))
            .collect();
        if let Some(i) = values.iter().position(|v| !v.is_finite()) {
            return Err(self.accessor_error(acc, format!("{what}: value {i} is not finite")));
        }
        let width = acc.dimensions().multiplicity();
        Ok(values
            .chunks_exact(width)
            .map(|c| [c[0], c[1], c[2], c.get(3).copied().unwrap_or(1.0)])
            .collect())
    }

    /// Reads an index accessor and checks every index is below `vertex_count`.
    fn read_indices(
        &self,
        acc: &Accessor<'_>,
        vertex_count: usize,
        site: Site,
    ) -> Result<Vec<u32>, GltfError> {
        let what = format!("indices of {site}");
        let types = [DataType::U8, DataType::U16, DataType::U32];
        self.expect_type(acc, &what, &[Dimensions::Scalar], &types)?;
        let indices = self.read_raw(acc)?;
        match indices.iter().position(|&i| i as usize >= vertex_count) {
            Some(at) => Err(self.accessor_error(
                acc,
                format!(
                    "{what}: index {} (element {at}) is out of range; there are {vertex_count} \
                     vertices",
                    indices[at]
                ),
            )),
            None => Ok(indices),
        }
    }

    /// Every component of every element as a little-endian `u32` (float bits for `F32`), after
    /// checking the accessor lies within its buffer view and the view within its buffer.
    fn read_raw(&self, acc: &Accessor<'_>) -> Result<Vec<u32>, GltfError> {
        let (region, stride) = self.accessor_region(acc)?;
        let size = acc.data_type().size();
        let width = acc.dimensions().multiplicity();
        let mut out = Vec::with_capacity(acc.count() * width);
        for element in region.chunks(stride) {
            out.extend(element.chunks_exact(size).take(width).map(le_component));
        }
        Ok(out)
    }

    /// The bytes from the accessor's first element to the end of its last, and the stride.
    fn accessor_region(&self, acc: &Accessor<'_>) -> Result<(&[u8], usize), GltfError> {
        if acc.sparse().is_some() {
            return Err(self.unsupported(format!("sparse accessor {}", acc.index())));
        }
        let Some(view) = acc.view() else {
            return Err(self.accessor_error(acc, "has no buffer view".into()));
        };
        let element = acc.size();
        let stride = view.stride().unwrap_or(element);
        if stride < element {
            return Err(self.accessor_error(
                acc,
                format!("byte stride {stride} is smaller than one element ({element} bytes)"),
            ));
        }
        let view_bytes = self.view_bytes(&view)?;
        if acc.count() == 0 {
            return Ok((&[], stride));
        }
        let end = (acc.count() - 1)
            .checked_mul(stride)
            .and_then(|n| n.checked_add(element))
            .and_then(|n| n.checked_add(acc.offset()));
        let region = end.and_then(|end| view_bytes.get(acc.offset()..end));
        let region = region.ok_or_else(|| {
            self.accessor_error(
                acc,
                format!(
                    "out of bounds: {} elements of {element} bytes (stride {stride}) from byte \
                     {} do not fit in buffer view {} ({} bytes)",
                    acc.count(),
                    acc.offset(),
                    view.index(),
                    view_bytes.len()
                ),
            )
        })?;
        Ok((region, stride))
    }

    /// A buffer view's bytes, checked against its buffer's actual length.
    fn view_bytes(&self, view: &gltf::buffer::View<'_>) -> Result<&[u8], GltfError> {
        let buffer = view.buffer().index();
        let data = self.buffers.get(buffer).map_or(&[][..], |b| &b[..]);
        let range = view.offset()..view.offset().saturating_add(view.length());
        data.get(range.clone()).ok_or_else(|| {
            self.invalid(format!(
                "buffer view {} (bytes {range:?}) is out of bounds of buffer {buffer} ({} bytes)",
                view.index(),
                data.len()
            ))
        })
    }
}

/// Pushes nodes so that they pop in document order.
fn push_children<'a>(
    stack: &mut Vec<(Node<'a>, Mat4)>,
    nodes: impl Iterator<Item = Node<'a>>,
    parent: Mat4,
) {
    let start = stack.len();
    stack.extend(nodes.map(|n| (n, parent)));
    stack[start..].reverse();
}

/// One little-endian component of 1, 2 or 4 bytes.
fn le_component(bytes: &[u8]) -> u32 {
    bytes
        .iter()
        .rev()
        .fold(0, |acc, &b| (acc << 8) | u32::from(b))
}

fn mode_name(mode: Mode) -> &'static str {
    match mode {
        Mode::Points => "POINTS",
        Mode::Lines => "LINES",
        Mode::LineLoop => "LINE_LOOP",
        Mode::LineStrip => "LINE_STRIP",
        Mode::Triangles => "TRIANGLES",
        Mode::TriangleStrip => "TRIANGLE_STRIP",
        Mode::TriangleFan => "TRIANGLE_FAN",
    }
}

// ---- geometry -----------------------------------------------------------------------------------

/// Converts a triangle-mode index sequence to a triangle list (counter-clockwise kept).
fn triangle_list(mode: Mode, corners: &[u32]) -> Result<Vec<u32>, String> {
    match mode {
        Mode::TriangleStrip => Ok(corners
            .windows(3)
            .enumerate()
            .map(|(i, w)| {
                if i % 2 == 0 {
                    [w[0], w[1], w[2]]
                } else {
                    [w[1], w[0], w[2]]
                }
            })
            .filter(|[a, b, c]| a != b && b != c && a != c)
            .flatten()
            .collect()),
        Mode::TriangleFan => Ok(corners
            .get(1..)
            .unwrap_or_default()
            .windows(2)
            .flat_map(|w| [corners[0], w[0], w[1]])
            .collect()),
        _ if !corners.len().is_multiple_of(3) => Err(format!(
            "TRIANGLES needs a multiple of 3 indices (or vertices), found {}",
            corners.len()
        )),
        _ => Ok(corners.to_vec()),
    }
}

/// Flat shading: three fresh vertices per triangle with its face normal; zero-area triangles
/// (which have no normal) are dropped. Indices must be in range.
fn flat_shaded(positions: &[Vec3], colors: &[[f32; 4]], indices: &[u32]) -> TriMesh {
    let mut out = TriMesh::default();
    for tri in indices.chunks_exact(3) {
        let corners = [tri[0], tri[1], tri[2]].map(|i| i as usize);
        let [a, b, c] = corners.map(|i| positions[i]);
        let Some(normal) = (b - a).cross(c - a).try_normalize() else {
            continue;
        };
        let base = out.positions.len() as u32;
        out.positions.extend([a, b, c]);
        out.normals.extend([normal; 3]);
        out.colors.extend(corners.map(|i| colors[i]));
        out.indices.extend([base, base + 1, base + 2]);
    }
    out
}

#[cfg(test)]
mod tests;
