//! Collision shapes for a level's geometry, in the entity's frame (rotation and translation
//! are the body's pose; scale is baked into the shape).
//!
//! A primitive becomes the rapier shape that is exactly it under its scale: a box stays a
//! cuboid under any scale, a sphere a ball and a cylinder a cylinder only while the scale
//! keeps them round; otherwise (and for the wedge) the convex hull of the scaled primitive
//! mesh, and failing that its triangles. A plane becomes a thin cuboid whose top face is the
//! plane, so nothing can slip through a zero-thickness sheet. glTF meshes become triangle
//! meshes and terrains heightfields. Degenerate input is refused with a message, never a
//! panic (parry asserts on some of it, so it is checked here first).

use glam::{Vec2, Vec3};
use rapier3d::geometry::{Array2, HeightFieldFlags, SharedShape, TriMeshFlags};
use rapier3d::math::{Pose, Vector};
use texel_scene::terrain::Heightfield;
use texel_scene::{Geometry, TriMesh, primitives::primitive_mesh};

use crate::convert::vector;

/// How thick the cuboid standing in for a one-sided plane is (below the plane).
pub(crate) const PLANE_THICKNESS: f32 = 0.1;

/// Smallest extent, in world units, a shape may have along any axis.
const MIN_EXTENT: f32 = 1e-5;

/// The shapes of one entity, each placed in the entity's (unscaled) frame.
#[derive(Clone)]
pub(crate) struct Shapes {
    /// `(pose in the entity's frame, shape)`.
    pub parts: Vec<(Pose, SharedShape)>,
    /// Triangles held by triangle-mesh parts.
    pub triangles: usize,
    /// Something was left out on the way (some triangles), though a collider was built.
    pub note: Option<String>,
}

impl std::fmt::Debug for Shapes {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Shapes")
            .field("parts", &self.parts.len())
            .field("triangles", &self.triangles)
            .field("note", &self.note)
            .finish()
    }
}

impl Shapes {
    fn one(shape: SharedShape) -> Self {
        Shapes {
            parts: vec![(Pose::IDENTITY, shape)],
            triangles: 0,
            note: None,
        }
    }
}

/// Whether `a` and `b` agree to a relative 1e-4 (a scale that keeps a shape round).
fn same(a: f32, b: f32) -> bool {
    (a - b).abs() <= 1e-4 * a.abs().max(b.abs())
}

fn check_extents(v: Vec3) -> Result<(), String> {
    if v.is_finite() && v.min_element() >= MIN_EXTENT {
        Ok(())
    } else {
        Err(format!(
            "degenerate size {v} after scaling (zero, negative or not finite)"
        ))
    }
}

/// The shapes of a primitive or a glTF mesh under `scale`. `mesh` is the loaded mesh of a
/// [`Geometry::Mesh`].
pub(crate) fn geometry_shapes(
    geometry: &Geometry,
    scale: Vec3,
    mesh: Option<&TriMesh>,
) -> Result<Shapes, String> {
    if !scale.is_finite() || scale.min_element() <= 0.0 {
        return Err(format!("scale {scale} is not positive and finite"));
    }
    match geometry {
        Geometry::Box { size } => {
            let h = *size * scale * 0.5;
            check_extents(h)?;
            Ok(Shapes::one(SharedShape::cuboid(h.x, h.y, h.z)))
        }
        Geometry::Plane { size } => {
            let h = Vec2::new(size.x * scale.x, size.y * scale.z) * 0.5;
            check_extents(h.extend(1.0))?;
            let t = PLANE_THICKNESS * 0.5;
            Ok(Shapes {
                parts: vec![(
                    Pose::from_translation(Vector::new(0.0, -t, 0.0)),
                    SharedShape::cuboid(h.x, t, h.y),
                )],
                triangles: 0,
                note: None,
            })
        }
        Geometry::Sphere { radius, .. } if same(scale.x, scale.y) && same(scale.x, scale.z) => {
            let r = radius * scale.x;
            check_extents(Vec3::splat(r))?;
            Ok(Shapes::one(SharedShape::ball(r)))
        }
        Geometry::Cylinder { radius, height, .. } if same(scale.x, scale.z) => {
            let (r, h) = (radius * scale.x, height * scale.y * 0.5);
            check_extents(Vec3::new(r, h, r))?;
            Ok(Shapes::one(SharedShape::cylinder(h, r)))
        }
        Geometry::Sphere { .. } | Geometry::Cylinder { .. } | Geometry::Wedge { .. } => {
            let Some(m) = primitive_mesh(geometry) else {
                return Err("no mesh for the primitive".to_owned());
            };
            convex_or_mesh(&m, scale)
        }
        Geometry::Mesh { path } => match mesh {
            Some(m) => trimesh(m, scale),
            None => Err(format!("mesh {path:?} is not loaded")),
        },
    }
}

/// The convex hull of a convex mesh under `scale`, or its triangles when the hull fails.
fn convex_or_mesh(m: &TriMesh, scale: Vec3) -> Result<Shapes, String> {
    let points: Vec<Vector> = m.positions.iter().map(|p| vector(*p * scale)).collect();
    let (lo, hi) = m.bounds().ok_or("the primitive's mesh is empty")?;
    check_extents((hi - lo) * scale)?;
    match SharedShape::convex_hull(&points) {
        Some(hull) => Ok(Shapes::one(hull)),
        None => trimesh(m, scale),
    }
}

/// A triangle mesh under `scale`: triangles with an index out of range, a position that is
/// not finite or no area are left out (with a note saying how many), and a mesh with no
/// triangle left is refused.
pub(crate) fn trimesh(m: &TriMesh, scale: Vec3) -> Result<Shapes, String> {
    let n = m.positions.len();
    let total = m.indices.len() / 3;
    let mut indices = Vec::with_capacity(total);
    for t in m.indices.chunks_exact(3) {
        let [a, b, c] = [t[0], t[1], t[2]];
        if [a, b, c].iter().any(|&i| i as usize >= n) {
            continue;
        }
        let [pa, pb, pc] = [a, b, c].map(|i| m.positions[i as usize] * scale);
        let area2 = (pb - pa).cross(pc - pa).length();
        if pa.is_finite() && pb.is_finite() && pc.is_finite() && area2 > 1e-12 {
            indices.push([a, b, c]);
        }
    }
    if indices.is_empty() {
        return Err(if total == 0 {
            "the mesh has no triangles".to_owned()
        } else {
            format!("none of the mesh's {total} triangles has an area (degenerate or not finite)")
        });
    }
    let skipped = total - indices.len();
    let kept = indices.len();
    let vertices = m
        .positions
        .iter()
        .map(|p| {
            let p = *p * scale;
            // Unused by any kept triangle if not finite; parry must not see a NaN anyway.
            vector(if p.is_finite() { p } else { Vec3::ZERO })
        })
        .collect();
    let flags = TriMeshFlags::MERGE_DUPLICATE_VERTICES
        | TriMeshFlags::DELETE_DEGENERATE_TRIANGLES
        | TriMeshFlags::FIX_INTERNAL_EDGES;
    let shape = SharedShape::trimesh_with_flags(vertices, indices, flags)
        .map_err(|e| format!("triangle mesh refused: {e}"))?;
    Ok(Shapes {
        parts: vec![(Pose::IDENTITY, shape)],
        triangles: kept,
        note: (skipped > 0).then(|| {
            format!("{skipped} of the mesh's {total} triangles skipped (no area, not finite or bad index)")
        }),
    })
}

/// Checks that `field` can be a heightfield collider.
pub(crate) fn check_heightfield(field: &Heightfield) -> Result<(), String> {
    let (w, d) = (field.width as usize, field.depth as usize);
    if w < 2 || d < 2 {
        return Err(format!("{w} × {d} samples; at least 2 × 2 are needed"));
    }
    if field.heights.len() != w.saturating_mul(d) {
        return Err(format!(
            "{} heights for {w} × {d} samples",
            field.heights.len()
        ));
    }
    if let Some(i) = field.heights.iter().position(|h| !h.is_finite()) {
        return Err(format!(
            "height {} at sample ({}, {}) is not finite",
            field.heights[i],
            i % w,
            i / w
        ));
    }
    Ok(())
}

/// A terrain of extent `size` as a rapier heightfield, centred on the terrain's origin.
///
/// rapier's layout: rows advance along Z, columns along X, stored column-major, spanning
/// `[-0.5, 0.5] × scale` in X and Z with heights times `scale.y`; each cell is split along
/// the same diagonal as the terrain's render mesh (from (x + 1, z) to (x, z + 1)), so the
/// collider is exactly the surface drawn.
pub(crate) fn heightfield(size: Vec2, field: &Heightfield) -> Result<SharedShape, String> {
    check_heightfield(field)?;
    if !size.is_finite() || size.min_element() < MIN_EXTENT {
        return Err(format!("terrain size {size} is not positive and finite"));
    }
    let (w, d) = (field.width as usize, field.depth as usize);
    let mut data = Vec::with_capacity(w * d);
    for x in 0..w {
        for z in 0..d {
            data.push(field.heights[z * w + x]);
        }
    }
    Ok(SharedShape::heightfield_with_flags(
        Array2::new(d, w, data),
        Vector::new(size.x, 1.0, size.y),
        HeightFieldFlags::FIX_INTERNAL_EDGES,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_heightfield_matches_the_terrain_mesh() {
        // A tilted, bumpy 5 × 4 field over 8 × 6 units.
        let (w, d) = (5u32, 4u32);
        let heights = (0..d)
            .flat_map(|z| (0..w).map(move |x| x as f32 * 0.5 + (z * z) as f32 * 0.25))
            .collect();
        let field = Heightfield {
            width: w,
            depth: d,
            heights,
        };
        let size = Vec2::new(8.0, 6.0);
        let shape = heightfield(size, &field).unwrap();
        let mesh = field.lod_mesh(size, 0.0);
        // Every vertex of the render mesh lies on the collider.
        for p in &mesh.positions {
            let d = shape.distance_to_point(&Pose::IDENTITY, vector(*p), true);
            assert!(d < 1e-4, "{p} is {d} off the heightfield");
        }
        // And the centre of a quad, on its diagonal, too (same split).
        let c = 0.5 * (mesh.positions[1] + mesh.positions[w as usize]);
        assert!(shape.distance_to_point(&Pose::IDENTITY, vector(c), true) < 1e-4);
    }

    #[test]
    fn degenerate_input_is_refused_not_panicked_on() {
        let tiny = Heightfield::flat(1, 5, 0.0);
        assert!(heightfield(Vec2::ONE, &tiny).unwrap_err().contains("2 × 2"));
        let mut nan = Heightfield::flat(3, 3, 0.0);
        nan.heights[4] = f32::NAN;
        assert!(heightfield(Vec2::ONE, &nan).unwrap_err().contains("(1, 1)"));
        let short = Heightfield {
            width: 3,
            depth: 3,
            heights: vec![0.0; 4],
        };
        assert!(heightfield(Vec2::ONE, &short).is_err());

        let flat = TriMesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::X * 2.0],
            indices: vec![0, 1, 2, 0, 1, 7],
            ..TriMesh::default()
        };
        assert!(
            trimesh(&flat, Vec3::ONE)
                .unwrap_err()
                .contains("2 triangles")
        );
        assert!(trimesh(&TriMesh::default(), Vec3::ONE).is_err());
        let partly = TriMesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Z, Vec3::X * 2.0, Vec3::NAN],
            indices: vec![0, 2, 1, 0, 1, 3, 0, 1, 4, 0, 1, 9],
            ..TriMesh::default()
        };
        let s = trimesh(&partly, Vec3::ONE).unwrap();
        assert_eq!(s.triangles, 1);
        assert!(
            s.note
                .unwrap()
                .starts_with("3 of the mesh's 4 triangles skipped")
        );
        let b = Geometry::Box { size: Vec3::ONE };
        assert!(geometry_shapes(&b, Vec3::new(1.0, 0.0, 1.0), None).is_err());
        assert!(geometry_shapes(&b, Vec3::splat(f32::NAN), None).is_err());
        let m = Geometry::Mesh {
            path: "x.glb".into(),
        };
        assert!(
            geometry_shapes(&m, Vec3::ONE, None)
                .unwrap_err()
                .contains("not loaded")
        );
    }

    #[test]
    fn round_shapes_stay_exact_only_under_round_scales() {
        let s = Geometry::Sphere {
            radius: 1.0,
            segments: 16,
        };
        let ball = geometry_shapes(&s, Vec3::splat(2.0), None).unwrap();
        assert!(ball.parts[0].1.as_ball().is_some_and(|b| b.radius == 2.0));
        let squashed = geometry_shapes(&s, Vec3::new(2.0, 1.0, 2.0), None).unwrap();
        let hull = squashed.parts[0].1.as_convex_polyhedron().unwrap();
        let aabb = hull.local_aabb();
        assert!((aabb.maxs.y - 1.0).abs() < 1e-4 && (aabb.maxs.x - 2.0).abs() < 1e-4);
        let c = Geometry::Cylinder {
            radius: 0.5,
            height: 2.0,
            segments: 12,
        };
        let cyl = geometry_shapes(&c, Vec3::new(2.0, 3.0, 2.0), None).unwrap();
        let cyl = cyl.parts[0].1.as_cylinder().unwrap();
        assert_eq!((cyl.radius, cyl.half_height), (1.0, 3.0));
        let oval = geometry_shapes(&c, Vec3::new(1.0, 1.0, 2.0), None).unwrap();
        assert!(oval.parts[0].1.as_convex_polyhedron().is_some());
        // A plane is a thin box whose top is the plane.
        let p = Geometry::Plane {
            size: Vec2::new(4.0, 2.0),
        };
        let plane = geometry_shapes(&p, Vec3::new(1.0, 5.0, 2.0), None).unwrap();
        let (pose, shape) = &plane.parts[0];
        let aabb = shape.compute_aabb(pose);
        assert!(aabb.maxs.y.abs() < 1e-6 && (aabb.mins.y + PLANE_THICKNESS).abs() < 1e-6);
        assert!((aabb.maxs.x - 2.0).abs() < 1e-6 && (aabb.maxs.z - 2.0).abs() < 1e-6);
    }
}
