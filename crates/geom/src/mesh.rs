//! CPU triangle meshes: the one mesh type every geometry source (primitives, glTF) produces.

use glam::{Mat4, Vec2, Vec3};

use crate::texture::SurfaceMaps;

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
    /// Texture coordinates, one per position, or empty (every UV 0). Primitives' UVs are in
    /// world units along the surface; glTF UVs are the file's `TEXCOORD_0` (1 = one image).
    pub uvs: Vec<Vec2>,
    /// Ranges of triangles with their own textures (a glTF primitive's material), sorted by
    /// `first_triangle`; triangles before the first part, or in a part without maps, use the
    /// object's material.
    pub parts: Vec<MeshPart>,
    /// Levels of detail (terrains): when not empty, every triangle belongs to exactly one
    /// piece, and a raster draws, per chunk, only the pieces of the level it picks for its
    /// distance; a G-buffer and the shadow BVH take level 0.
    pub pieces: Vec<LodPiece>,
}

/// A run of triangles holding one chunk of a mesh at one level of detail.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LodPiece {
    /// First triangle.
    pub first_triangle: u32,
    /// Triangles in the run.
    pub triangles: u32,
    /// The chunk it draws (the same for every level of a chunk).
    pub chunk: u32,
    /// Its level (0 = full detail); each level doubles the spacing.
    pub lod: u32,
    /// The chunk's coarsest level.
    pub max_lod: u32,
    /// Object-space distance between samples at level 0.
    pub spacing: f32,
    /// The chunk's object-space bounds (the same for every level).
    pub min: Vec3,
    /// See [`LodPiece::min`].
    pub max: Vec3,
}

/// Triangles from `first_triangle` up to the next part's start share these textures.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshPart {
    /// Index of the first triangle.
    pub first_triangle: u32,
    /// The part's textures.
    pub maps: SurfaceMaps,
}

impl TriMesh {
    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// The UV of vertex `i` (0 when the mesh has none).
    pub fn uv(&self, i: usize) -> Vec2 {
        self.uvs.get(i).copied().unwrap_or(Vec2::ZERO)
    }

    /// The part triangle `t` belongs to, if any.
    pub fn part_of(&self, t: u32) -> Option<&MeshPart> {
        let after = self.parts.partition_point(|p| p.first_triangle <= t);
        after.checked_sub(1).map(|i| &self.parts[i])
    }

    /// Appends `other`, transformed by `m` (normals by its inverse transpose).
    pub fn append_transformed(&mut self, other: &TriMesh, m: Mat4) {
        let base = self.positions.len() as u32;
        if !other.uvs.is_empty() || !self.uvs.is_empty() {
            self.uvs.resize(self.positions.len(), Vec2::ZERO);
            self.uvs
                .extend((0..other.positions.len()).map(|i| other.uv(i)));
        }
        let first = self.triangle_count() as u32;
        if !other.parts.is_empty() {
            if self.parts.is_empty() && first > 0 {
                // The triangles so far keep the object's material.
                self.parts.push(MeshPart {
                    first_triangle: 0,
                    maps: SurfaceMaps::default(),
                });
            }
            self.parts.extend(other.parts.iter().map(|p| MeshPart {
                first_triangle: p.first_triangle + first,
                maps: p.maps.clone(),
            }));
        } else if !self.parts.is_empty() {
            self.parts.push(MeshPart {
                first_triangle: first,
                maps: SurfaceMaps::default(),
            });
        }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::texture::{Image, TextureRef};
    use std::sync::Arc;

    fn tri(uv: bool) -> TriMesh {
        TriMesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            normals: vec![Vec3::Z; 3],
            colors: vec![[1.0; 4]; 3],
            indices: vec![0, 1, 2],
            uvs: if uv {
                vec![Vec2::ZERO, Vec2::X, Vec2::Y]
            } else {
                Vec::new()
            },
            parts: Vec::new(),
            pieces: Vec::new(),
        }
    }

    #[test]
    fn appending_keeps_uvs_and_parts_aligned() {
        let mut textured = tri(true);
        let maps = SurfaceMaps {
            albedo: Some(TextureRef {
                image: Arc::new(Image::solid("t", 2, 2, [255; 4])),
                sampler: Default::default(),
            }),
            ..Default::default()
        };
        textured.parts.push(MeshPart {
            first_triangle: 0,
            maps: maps.clone(),
        });
        let mut m = tri(false);
        m.append_transformed(&textured, Mat4::IDENTITY);
        m.append_transformed(&tri(false), Mat4::IDENTITY);
        assert_eq!(m.uvs.len(), 9);
        assert_eq!(m.uv(4), Vec2::X);
        assert_eq!(m.uv(1), Vec2::ZERO);
        assert!(m.part_of(0).unwrap().maps.is_empty());
        assert_eq!(m.part_of(1).unwrap().maps, maps);
        assert!(m.part_of(2).unwrap().maps.is_empty());
    }
}
