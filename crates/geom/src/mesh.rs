//! CPU triangle meshes: the one mesh type every geometry source (primitives, glTF) produces.

use glam::{Mat4, Vec3};

/// An indexed triangle mesh in object space, counter-clockwise front faces (right-handed,
/// normals point out of the solid).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TriMesh {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Unit vertex normals, one per position.
    pub normals: Vec<Vec3>,
    /// Linear RGBA vertex colours, one per position (white when the source has none; a glTF
    /// primitive's base colour factor is multiplied in).
    pub colors: Vec<[f32; 4]>,
    /// Triangle list, three indices per triangle.
    pub indices: Vec<u32>,
}

impl TriMesh {
    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// Appends `other`, transformed by `m` (normals by its inverse transpose).
    pub fn append_transformed(&mut self, other: &TriMesh, m: Mat4) {
        let base = self.positions.len() as u32;
        let normal_m = m.inverse().transpose();
        let flip = m.determinant() < 0.0;
        self.positions
            .extend(other.positions.iter().map(|p| m.transform_point3(*p)));
        self.normals.extend(
            other
                .normals
                .iter()
                .map(|n| normal_m.transform_vector3(*n).normalize_or_zero()),
        );
        self.colors.extend_from_slice(&other.colors);
        for tri in other.indices.chunks_exact(3) {
            let (a, b, c) = (tri[0] + base, tri[1] + base, tri[2] + base);
            if flip {
                self.indices.extend_from_slice(&[a, c, b]);
            } else {
                self.indices.extend_from_slice(&[a, b, c]);
            }
        }
    }

    /// Axis-aligned bounds `(min, max)`, or `None` for an empty mesh.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        let first = *self.positions.first()?;
        Some(
            self.positions
                .iter()
                .fold((first, first), |(lo, hi), p| (lo.min(*p), hi.max(*p))),
        )
    }
}
