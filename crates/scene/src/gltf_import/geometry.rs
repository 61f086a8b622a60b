//! Geometry: triangle lists from strips and fans, flat shading.

use glam::{Vec2, Vec3};
use gltf::mesh::Mode;

use crate::mesh::TriMesh;

/// Converts a triangle-mode index sequence to a triangle list (counter-clockwise kept).
pub(super) fn triangle_list(mode: Mode, corners: &[u32]) -> Result<Vec<u32>, String> {
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

/// Flat shading: three fresh vertices per triangle with its face normal, colours and UVs
/// (`uvs` is one per position, or empty for none); zero-area triangles (which have no
/// normal) are dropped. Indices must be in range.
pub(super) fn flat_shaded(
    positions: &[Vec3],
    colors: &[[f32; 4]],
    uvs: &[Vec2],
    indices: &[u32],
) -> TriMesh {
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
        if !uvs.is_empty() {
            out.uvs.extend(corners.map(|i| uvs[i]));
        }
        out.indices.extend([base, base + 1, base + 2]);
    }
    out
}
