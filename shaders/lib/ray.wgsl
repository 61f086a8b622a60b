// The ray–triangle test, written once for the shaders: `ray_triangle` in
// `crates/geom/src/ray.rs` (which the shadow BVH's CPU walk and the evaluator's reference
// call) in the same operations and the same order. Its minimum distance `RAY_T_MIN` is
// generated from the Rust constant (lib/constants.wgsl).

#include "lib/constants.wgsl"

// Möller–Trumbore, both faces: whether the ray `origin + t dir` crosses the triangle with
// first vertex `v0` and edges `e1`, `e2` at t in (RAY_T_MIN, t_max).
fn ray_triangle_hit(v0: vec3<f32>, e1: vec3<f32>, e2: vec3<f32>, origin: vec3<f32>, dir: vec3<f32>, t_max: f32) -> bool {
    let p = cross(dir, e2);
    let det = dot(e1, p);
    if det == 0.0 {
        return false;
    }
    let inv = 1.0 / det;
    let s = origin - v0;
    let u = dot(s, p) * inv;
    if u < 0.0 || u > 1.0 {
        return false;
    }
    let q = cross(s, e1);
    let v = dot(dir, q) * inv;
    if v < 0.0 || u + v > 1.0 {
        return false;
    }
    let t = dot(e2, q) * inv;
    return t > RAY_T_MIN && t < t_max;
}
