//! The ray–triangle test, written once: the renderer's shadow BVH on the CPU
//! (`texel_render::bvh`), its WGSL twin (`ray_triangle_hit` in `shaders/lib/ray.wgsl`, the
//! same operations in the same order, its minimum distance generated from [`RAY_T_MIN`]) and
//! the evaluator's CPU reference all use it.

use glam::Vec3;

/// Hits closer than this along the ray are ignored: a shadow ray starts on the surface it
/// leaves, and must not find that surface again (self-shadowing). In units of the ray's
/// direction (world units for a unit direction).
pub const RAY_T_MIN: f32 = 1e-4;

/// The `t` at which the ray `origin + t * dir` crosses the triangle with first vertex `v0`
/// and edges `e1`, `e2` (to the second and third vertices), if `t` is in
/// `(RAY_T_MIN, t_max)`: Möller–Trumbore, both faces. A ray in the triangle's plane
/// (determinant exactly 0) misses; `dir` need not be unit length.
pub fn ray_triangle(
    origin: Vec3,
    dir: Vec3,
    v0: Vec3,
    e1: Vec3,
    e2: Vec3,
    t_max: f32,
) -> Option<f32> {
    let p = dir.cross(e2);
    let det = e1.dot(p);
    if det == 0.0 {
        return None;
    }
    let inv = 1.0 / det;
    let s = origin - v0;
    let u = s.dot(p) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = s.cross(e1);
    let v = dir.dot(q) * inv;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let t = e2.dot(q) * inv;
    (t > RAY_T_MIN && t < t_max).then_some(t)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit right triangle in the plane z = 0.
    const V0: Vec3 = Vec3::ZERO;
    const E1: Vec3 = Vec3::X;
    const E2: Vec3 = Vec3::Y;

    #[test]
    fn a_ray_through_the_triangle_hits_from_either_side() {
        let at = Vec3::new(0.25, 0.25, 0.0);
        let down = ray_triangle(at + Vec3::Z, -Vec3::Z, V0, E1, E2, 10.0);
        let up = ray_triangle(at - 2.0 * Vec3::Z, Vec3::Z, V0, E1, E2, 10.0);
        assert_eq!((down, up), (Some(1.0), Some(2.0)));
        // `t` is in units of `dir`.
        let long = ray_triangle(at + Vec3::Z, -4.0 * Vec3::Z, V0, E1, E2, 10.0);
        assert_eq!(long, Some(0.25));
    }

    #[test]
    fn misses_outside_the_triangle_its_plane_and_the_range() {
        let hit = |origin: Vec3, dir: Vec3, t_max| ray_triangle(origin, dir, V0, E1, E2, t_max);
        // Beyond the hypotenuse, in the plane, past t_max, and from on the surface.
        assert_eq!(hit(Vec3::new(0.75, 0.75, 1.0), -Vec3::Z, 10.0), None);
        assert_eq!(hit(Vec3::new(-1.0, 0.25, 0.0), Vec3::X, 10.0), None);
        assert_eq!(hit(Vec3::new(0.25, 0.25, 1.0), -Vec3::Z, 1.0), None);
        assert_eq!(
            hit(Vec3::new(0.25, 0.25, RAY_T_MIN / 2.0), -Vec3::Z, 1.0),
            None
        );
    }
}
