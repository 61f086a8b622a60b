// Direct lighting, shared by the texel shade pass and the screen-space baselines so both
// light a surface the same way: sun and point lights (lib/lights.wgsl), BVH shadow rays,
// ambient. The includer declares `globals` (with `ambient`, `sun_count`,
// `suns: array<Sun, N>`, `point_count`) and `points: array<PointLight>`, and includes
// lib/bvh.wgsl and lib/common.wgsl.

#include "lib/lights.wgsl"

// The light reaching `p` (normal `normal`). Shadow rays start `offset` off the surface along
// its normal: at least the point's own uncertainty, so a surface does not shadow itself.
fn lighting(p: vec3<f32>, normal: vec3<f32>, offset: f32) -> vec3<f32> {
    return lighting_seen(p, normal, offset, normal, vec4(0.0)).diffuse;
}

// What reaches `p`: the diffuse light, and the highlights of `spec` (lib/common.wgsl
// `highlight`) seen along `to_eye` (unit, toward the viewer).
struct Lit {
    diffuse: vec3<f32>,
    shine: vec3<f32>,
}

fn lighting_seen(p: vec3<f32>, normal: vec3<f32>, offset: f32, to_eye: vec3<f32>, spec: vec4<f32>) -> Lit {
    var out = Lit(globals.ambient.rgb, vec3(0.0));
    let start = p + normal * offset;
    for (var i = 0u; i < light_count(); i++) {
        let r = light_ray(i, p);
        let ndl = dot(normal, r.dir);
        if ndl > 0.0 && r.reach > 0.0 && !bvh_any_hit(start, r.dir, light_reach(r, offset)) {
            let fall = r.fall * r.fall;
            out.diffuse += r.colour * ndl * fall;
            out.shine += r.colour * (fall * highlight(normal, r.dir, to_eye, spec));
        }
    }
    return out;
}
