//! CPU meshes for the primitive shapes.
//!
//! Every mesh is counter-clockwise seen from outside, with unit normals pointing out of the
//! solid. Flat faces get their own vertices (hard edges suit pixel art and give the crease
//! outlines something to find); the sphere and the cylinder's side are smooth.
//!
//! UVs are in world units along the surface, so a texture's pixels have one world size on
//! every face ([`crate::Material`]'s texel density turns units into texture pixels): flat
//! faces are projected on their own plane (U horizontal, V down the face; on a floor U is X
//! and V is Z), the cylinder's side and the sphere are wrapped by arc length.

use glam::{Vec2, Vec3};

use crate::components::Geometry;
use crate::mesh::TriMesh;

/// The mesh of a primitive, or `None` for [`Geometry::Mesh`] (loaded from its file).
pub fn primitive_mesh(g: &Geometry) -> Option<TriMesh> {
    Some(match g {
        Geometry::Box { size } => box_mesh(*size),
        Geometry::Sphere { radius, segments } => sphere(*radius, *segments),
        Geometry::Cylinder {
            radius,
            height,
            segments,
        } => cylinder(*radius, *height, *segments),
        Geometry::Plane { size } => plane(*size),
        Geometry::Wedge { size } => wedge(*size),
        Geometry::Mesh { .. } => return None,
    })
}

/// The planar UV of `p` on a face with unit normal `n`, in world units: U along the
/// horizontal tangent (X on floors and ceilings), V down the face (Z on floors), so images
/// stand upright on walls.
pub fn face_uv(p: Vec3, n: Vec3) -> Vec2 {
    let t = if n.y.abs() > 0.999 {
        Vec3::X
    } else {
        Vec3::Y.cross(n).normalize()
    };
    let b = n.cross(t);
    Vec2::new(p.dot(t), -p.dot(b))
}

/// Adds a flat polygon (convex, corners counter-clockwise seen from outside).
fn add_face(m: &mut TriMesh, corners: &[Vec3]) {
    let n = (corners[1] - corners[0])
        .cross(corners[2] - corners[0])
        .normalize_or_zero();
    let base = m.positions.len() as u32;
    for &c in corners {
        m.positions.push(c);
        m.normals.push(n);
        m.colors.push([1.0; 4]);
        m.uvs.push(face_uv(c, n));
    }
    for i in 1..corners.len() as u32 - 1 {
        m.indices.extend_from_slice(&[base, base + i, base + i + 1]);
    }
}

/// An axis-aligned box of full `size`, centred on the origin.
pub fn box_mesh(size: Vec3) -> TriMesh {
    let h = size * 0.5;
    let c = |x: f32, y: f32, z: f32| Vec3::new(x * h.x, y * h.y, z * h.z);
    let mut m = TriMesh::default();
    add_face(
        &mut m,
        &[
            c(1., -1., 1.),
            c(1., -1., -1.),
            c(1., 1., -1.),
            c(1., 1., 1.),
        ],
    );
    add_face(
        &mut m,
        &[
            c(-1., -1., -1.),
            c(-1., -1., 1.),
            c(-1., 1., 1.),
            c(-1., 1., -1.),
        ],
    );
    add_face(
        &mut m,
        &[
            c(-1., 1., 1.),
            c(1., 1., 1.),
            c(1., 1., -1.),
            c(-1., 1., -1.),
        ],
    );
    add_face(
        &mut m,
        &[
            c(-1., -1., -1.),
            c(1., -1., -1.),
            c(1., -1., 1.),
            c(-1., -1., 1.),
        ],
    );
    add_face(
        &mut m,
        &[
            c(-1., -1., 1.),
            c(1., -1., 1.),
            c(1., 1., 1.),
            c(-1., 1., 1.),
        ],
    );
    add_face(
        &mut m,
        &[
            c(1., -1., -1.),
            c(-1., -1., -1.),
            c(-1., 1., -1.),
            c(1., 1., -1.),
        ],
    );
    m
}

/// A one-sided rectangle in the XZ plane facing +Y.
pub fn plane(size: Vec2) -> TriMesh {
    let (x, z) = (size.x * 0.5, size.y * 0.5);
    let mut m = TriMesh::default();
    add_face(
        &mut m,
        &[
            Vec3::new(-x, 0.0, z),
            Vec3::new(x, 0.0, z),
            Vec3::new(x, 0.0, -z),
            Vec3::new(-x, 0.0, -z),
        ],
    );
    m
}

/// A ramp of full `size`, centred on the origin: full height at the back (−Z), zero at the
/// front (+Z).
pub fn wedge(size: Vec3) -> TriMesh {
    let h = size * 0.5;
    let c = |x: f32, y: f32, z: f32| Vec3::new(x * h.x, y * h.y, z * h.z);
    let mut m = TriMesh::default();
    // Bottom, back, slope.
    add_face(
        &mut m,
        &[
            c(-1., -1., -1.),
            c(1., -1., -1.),
            c(1., -1., 1.),
            c(-1., -1., 1.),
        ],
    );
    add_face(
        &mut m,
        &[
            c(1., -1., -1.),
            c(-1., -1., -1.),
            c(-1., 1., -1.),
            c(1., 1., -1.),
        ],
    );
    add_face(
        &mut m,
        &[
            c(-1., -1., 1.),
            c(1., -1., 1.),
            c(1., 1., -1.),
            c(-1., 1., -1.),
        ],
    );
    // Triangular sides.
    add_face(&mut m, &[c(1., -1., 1.), c(1., -1., -1.), c(1., 1., -1.)]);
    add_face(
        &mut m,
        &[c(-1., -1., -1.), c(-1., -1., 1.), c(-1., 1., -1.)],
    );
    m
}

/// A point on the unit circle in XZ at step `i` of `n`, going counter-clockwise seen from +Y.
fn ring(i: u32, n: u32) -> Vec3 {
    let a = i as f32 / n as f32 * std::f32::consts::TAU;
    Vec3::new(a.cos(), 0.0, -a.sin())
}

/// A capped cylinder along Y, centred on the origin.
pub fn cylinder(radius: f32, height: f32, segments: u32) -> TriMesh {
    let n = segments.max(3);
    let hy = height * 0.5;
    let mut m = TriMesh::default();
    for i in 0..n {
        let (a, b) = (ring(i, n), ring(i + 1, n));
        let base = m.positions.len() as u32;
        let arc = |k: u32| k as f32 / n as f32 * std::f32::consts::TAU * radius;
        for (p, k, y) in [(a, i, -hy), (b, i + 1, -hy), (b, i + 1, hy), (a, i, hy)] {
            m.positions.push(p * radius + Vec3::Y * y);
            m.normals.push(p);
            m.colors.push([1.0; 4]);
            // Counter-clockwise seen from +Y is right to left seen from outside.
            m.uvs.push(Vec2::new(-arc(k), -y));
        }
        m.indices
            .extend_from_slice(&[base, base + 1, base + 2, base, base + 2, base + 3]);
    }
    let top: Vec<Vec3> = (0..n).map(|i| ring(i, n) * radius + Vec3::Y * hy).collect();
    let bottom: Vec<Vec3> = (0..n)
        .rev()
        .map(|i| ring(i, n) * radius - Vec3::Y * hy)
        .collect();
    add_face(&mut m, &top);
    add_face(&mut m, &bottom);
    m
}

/// A UV sphere with `segments` around Y and `segments / 2` rings.
pub fn sphere(radius: f32, segments: u32) -> TriMesh {
    let n = segments.max(3);
    let rings = (n / 2).max(2);
    let mut m = TriMesh::default();
    for r in 0..=rings {
        let theta = r as f32 / rings as f32 * std::f32::consts::PI;
        for i in 0..=n {
            let d = ring(i, n) * theta.sin() + Vec3::Y * theta.cos();
            m.positions.push(d * radius);
            m.normals.push(d.normalize());
            m.colors.push([1.0; 4]);
            let u = -(i as f32) / n as f32 * std::f32::consts::TAU * radius;
            m.uvs.push(Vec2::new(u, theta * radius));
        }
    }
    let row = n + 1;
    for r in 0..rings {
        for i in 0..n {
            let (a, b) = (r * row + i, r * row + i + 1);
            let (c, d) = (a + row, b + row);
            if r != 0 {
                m.indices.extend_from_slice(&[a, c, b]);
            }
            if r != rings - 1 {
                m.indices.extend_from_slice(&[b, c, d]);
            }
        }
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    fn all_closed() -> Vec<(&'static str, TriMesh)> {
        vec![
            ("box", box_mesh(Vec3::new(1.0, 2.0, 3.0))),
            ("wedge", wedge(Vec3::new(2.0, 1.0, 3.0))),
            ("cylinder", cylinder(0.5, 2.0, 12)),
            ("sphere", sphere(1.5, 16)),
        ]
    }

    fn tri(m: &TriMesh, t: usize) -> [Vec3; 3] {
        let i = &m.indices[t * 3..t * 3 + 3];
        [0, 1, 2].map(|k| m.positions[i[k] as usize])
    }

    /// Signed volume by the divergence theorem: positive iff triangles wind outward.
    fn volume(m: &TriMesh) -> f32 {
        (0..m.triangle_count())
            .map(|t| {
                let [a, b, c] = tri(m, t);
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }

    #[test]
    fn winding_agrees_with_normals() {
        for (name, m) in all_closed()
            .into_iter()
            .chain([("plane", plane(Vec2::ONE))])
        {
            assert_eq!(m.normals.len(), m.positions.len());
            for t in 0..m.triangle_count() {
                let [a, b, c] = tri(&m, t);
                let g = (b - a).cross(c - a);
                if g.length() < 1e-7 {
                    continue; // degenerate pole triangles carry no orientation
                }
                for k in 0..3 {
                    let n = m.normals[m.indices[t * 3 + k] as usize];
                    assert!((n.length() - 1.0).abs() < 1e-4, "{name}: normal not unit");
                    assert!(
                        g.dot(n) > 0.0,
                        "{name}: triangle {t} winds against its normal"
                    );
                }
            }
        }
    }

    #[test]
    fn closed_meshes_are_watertight_and_outward() {
        let key = |p: Vec3| (p * 1e4).round().as_ivec3().to_array();
        for (name, m) in all_closed() {
            let mut edges: HashMap<_, i32> = HashMap::new();
            for t in 0..m.triangle_count() {
                let [a, b, c] = tri(&m, t);
                for (p, q) in [(a, b), (b, c), (c, a)] {
                    if key(p) == key(q) {
                        continue;
                    }
                    *edges.entry((key(p), key(q))).or_default() += 1;
                    *edges.entry((key(q), key(p))).or_default() -= 1;
                }
            }
            assert!(
                edges.values().all(|&v| v == 0),
                "{name}: open or inconsistent edges"
            );
            assert!(volume(&m) > 0.0, "{name}: winds inward");
        }
    }

    #[test]
    fn volumes_match_the_shapes() {
        let close = |a: f32, b: f32, tol: f32| (a - b).abs() <= tol * b;
        assert!(close(
            volume(&box_mesh(Vec3::new(1.0, 2.0, 3.0))),
            6.0,
            1e-5
        ));
        assert!(close(volume(&wedge(Vec3::new(2.0, 1.0, 3.0))), 3.0, 1e-5));
        let cyl = std::f32::consts::PI * 0.25 * 2.0;
        assert!(close(volume(&cylinder(0.5, 2.0, 64)), cyl, 0.01));
        let sph = 4.0 / 3.0 * std::f32::consts::PI * 1.5f32.powi(3);
        assert!(close(volume(&sphere(1.5, 64)), sph, 0.01));
    }

    /// One world unit along a flat face is one UV unit, in both directions, on every face
    /// of every flat primitive; walls stand upright (V grows downward).
    #[test]
    fn flat_uvs_are_world_units_and_upright() {
        for m in [
            box_mesh(Vec3::new(1.0, 2.0, 3.0)),
            wedge(Vec3::new(2.0, 1.0, 3.0)),
            plane(Vec2::new(4.0, 2.0)),
        ] {
            assert_eq!(m.uvs.len(), m.positions.len());
            for t in 0..m.triangle_count() {
                let i = &m.indices[t * 3..t * 3 + 3];
                let [a, b] = [1, 2].map(|k| i[k] as usize);
                let o = i[0] as usize;
                for j in [a, b] {
                    let dp = (m.positions[j] - m.positions[o]).length();
                    let duv = (m.uvs[j] - m.uvs[o]).length();
                    assert!((dp - duv).abs() < 1e-5, "UV length {duv} for {dp} units");
                }
                let n = m.normals[o];
                if n.y.abs() < 0.5 {
                    let up = m.positions[o] + Vec3::Y;
                    assert!(face_uv(up, n).y < m.uvs[o].y, "walls upright");
                }
            }
        }
        let c = cylinder(0.5, 2.0, 16);
        let s = sphere(1.0, 16);
        assert_eq!(c.uvs.len(), c.positions.len());
        assert_eq!(s.uvs.len(), s.positions.len());
        let span = |m: &TriMesh| {
            m.uvs.iter().map(|u| u.x).fold(f32::MAX, f32::min)
                - m.uvs.iter().map(|u| u.x).fold(f32::MIN, f32::max)
        };
        assert!((span(&s).abs() - std::f32::consts::TAU).abs() < 1e-4);
    }

    #[test]
    fn plane_faces_up_and_wedge_slopes_down_to_the_front() {
        let p = plane(Vec2::new(4.0, 2.0));
        assert!(p.normals.iter().all(|n| *n == Vec3::Y));
        assert_eq!(
            p.bounds(),
            Some((Vec3::new(-2.0, 0.0, -1.0), Vec3::new(2.0, 0.0, 1.0)))
        );
        let w = wedge(Vec3::ONE);
        let front_top = w
            .positions
            .iter()
            .filter(|q| q.z > 0.4)
            .map(|q| q.y)
            .fold(f32::MIN, f32::max);
        assert!(
            front_top < -0.4,
            "the front edge of the wedge is at the bottom"
        );
    }
}
