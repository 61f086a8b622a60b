//! Scene traversal: the nodes of the chosen scenes, with their world transforms, turned into
//! one [`TriMesh`]: each primitive's positions, normals, colours and UVs (read by
//! [`accessors`](super::accessors)), its triangles, flat shading where normals are missing,
//! and its material's textures (read by [`textures`](super::textures)) as a [`MeshPart`].

use std::borrow::Cow;
use std::cell::{Cell, RefCell};
use std::collections::{HashMap, HashSet};
use std::fmt;
use std::path::Path;
use std::sync::Arc;

use glam::{Mat4, Vec3};
use gltf::mesh::Mode;
use gltf::{Accessor, Document, Node, Primitive, Semantic};
use texel_geom::texture::Image;

use crate::mesh::{MeshPart, TriMesh};

use super::geometry::{flat_shaded, triangle_list};
use super::report::Warnings;
use super::{GltfError, GltfLimits};

/// A primitive's place in the document, for messages.
#[derive(Clone, Copy)]
pub(super) struct Site {
    mesh: usize,
    primitive: usize,
}

impl fmt::Display for Site {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "mesh {} primitive {}", self.mesh, self.primitive)
    }
}

/// The document and its loaded buffers, the file name errors report, the budgets, and what
/// the import has gathered so far (decoded images, warnings).
pub(super) struct Importer<'a> {
    /// What errors call the file.
    pub(super) name: &'a Path,
    /// The folder relative image URIs resolve against.
    pub(super) base_dir: Option<&'a Path>,
    /// The document.
    pub(super) document: &'a Document,
    /// Every buffer's bytes, by index.
    pub(super) buffers: Vec<Cow<'a, [u8]>>,
    /// The budgets.
    pub(super) limits: GltfLimits,
    /// Primitive instances placed so far.
    instances: Cell<usize>,
    /// Triangles (at most) imported so far.
    triangles: Cell<usize>,
    /// Most bytes of decoded images.
    pub(super) max_image_bytes: u64,
    /// Bytes of the images decoded so far.
    pub(super) image_bytes: Cell<u64>,
    /// Images decoded so far, by index in the document.
    pub(super) images: RefCell<HashMap<usize, Arc<Image>>>,
    /// What the file uses that is not imported.
    pub(super) warnings: RefCell<Warnings>,
}

impl<'a> Importer<'a> {
    pub(super) fn new(
        name: &'a Path,
        base_dir: Option<&'a Path>,
        document: &'a Document,
        buffers: Vec<Cow<'a, [u8]>>,
        limits: &GltfLimits,
        max_image_bytes: u64,
    ) -> Self {
        Importer {
            name,
            base_dir,
            document,
            buffers,
            limits: *limits,
            instances: Cell::new(0),
            triangles: Cell::new(0),
            max_image_bytes,
            image_bytes: Cell::new(0),
            images: RefCell::new(HashMap::new()),
            warnings: RefCell::new(Warnings::default()),
        }
    }

    /// The warnings raised, each distinct one once.
    pub(super) fn into_warnings(self) -> Vec<String> {
        self.warnings.into_inner().into_messages()
    }

    /// Counts one more instance of `prim` against the budgets, before any of its data is
    /// read: its triangle count comes from its accessors' declared counts (an upper bound
    /// of what it yields).
    fn charge(&self, prim: &Primitive<'_>, site: Site) -> Result<(), GltfError> {
        let budget = |detail: String| GltfError::Budget {
            path: self.name.to_path_buf(),
            detail,
        };
        let instances = self.instances.get() + 1;
        if instances > self.limits.max_instances {
            return Err(budget(format!(
                "the node graph places more than {} mesh primitive instances (at {site}; set \
                 TEXEL_GLTF_MAX_INSTANCES to raise the limit)",
                self.limits.max_instances
            )));
        }
        self.instances.set(instances);
        let corners = match prim.indices() {
            Some(a) => a.count(),
            None => prim.get(&Semantic::Positions).map_or(0, |a| a.count()),
        };
        let triangles = match prim.mode() {
            Mode::Triangles => corners / 3,
            _ => corners.saturating_sub(2),
        };
        let total = self.triangles.get().saturating_add(triangles);
        if total > self.limits.max_triangles {
            return Err(budget(format!(
                "more than {} triangles ({total} by {site}, instance {instances}; set \
                 TEXEL_GLTF_MAX_TRIANGLES to raise the limit)",
                self.limits.max_triangles
            )));
        }
        self.triangles.set(total);
        Ok(())
    }

    pub(super) fn invalid(&self, detail: String) -> GltfError {
        GltfError::Invalid {
            path: self.name.to_path_buf(),
            detail,
        }
    }

    pub(super) fn unsupported(&self, detail: String) -> GltfError {
        GltfError::Unsupported {
            path: self.name.to_path_buf(),
            detail,
        }
    }

    pub(super) fn accessor_error(&self, accessor: &Accessor<'_>, detail: String) -> GltfError {
        GltfError::Accessor {
            path: self.name.to_path_buf(),
            index: accessor.index(),
            detail,
        }
    }

    /// Default scene, else every scene, else every mesh untransformed.
    pub(super) fn scene_mesh(&self) -> Result<TriMesh, GltfError> {
        let doc = self.document;
        self.document_warnings(doc);
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
    pub(super) fn add_scene(
        &self,
        scene: &gltf::Scene<'_>,
        out: &mut TriMesh,
    ) -> Result<(), GltfError> {
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
    pub(super) fn add_mesh(
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
            self.charge(&primitive, site)?;
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

    /// Reads one primitive as a triangle list in its mesh's local space, with one part for its
    /// material's textures when it has any.
    pub(super) fn primitive_mesh(
        &self,
        prim: &Primitive<'_>,
        site: Site,
    ) -> Result<TriMesh, GltfError> {
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
        let uvs = match prim.get(&Semantic::TexCoords(0)) {
            Some(acc) => self.read_uvs(&acc, count, site)?,
            None => Vec::new(),
        };
        self.primitive_warnings(prim, site);
        let maps = self.surface_maps(&prim.material(), !uvs.is_empty(), site)?;
        let mut mesh = match self.vertex_normals(prim, count, site)? {
            Some(normals) => TriMesh {
                positions,
                normals,
                colors,
                indices,
                uvs,
                ..TriMesh::default()
            },
            None => flat_shaded(&positions, &colors, &uvs, &indices),
        };
        if !maps.is_empty() && !mesh.indices.is_empty() {
            mesh.parts.push(MeshPart {
                first_triangle: 0,
                maps,
            });
        }
        Ok(mesh)
    }

    /// Unit normals, or `None` when absent or some cannot be normalised (then: flat shading).
    pub(super) fn vertex_normals(
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
    pub(super) fn vertex_colors(
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
}

/// Pushes nodes so that they pop in document order.
pub(super) fn push_children<'a>(
    stack: &mut Vec<(Node<'a>, Mat4)>,
    nodes: impl Iterator<Item = Node<'a>>,
    parent: Mat4,
) {
    let start = stack.len();
    stack.extend(nodes.map(|n| (n, parent)));
    stack[start..].reverse();
}

pub(super) fn mode_name(mode: Mode) -> &'static str {
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
