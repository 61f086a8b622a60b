// Direct lighting, shared by the texel shade pass and the screen-space baselines so both
// light a surface the same way: sun and point lights with (1 − d/r)² falloff, BVH shadow
// rays, ambient. The includer declares `globals` (with `ambient`, `sun_count`,
// `suns: array<Sun, N>`, `point_count`) and `points: array<PointLight>`, and includes
// lib/bvh.wgsl and lib/common.wgsl.

// The least distance, in world units, a shadow ray starts off its surface.
const SHADOW_OFFSET: f32 = 0.02;

struct Sun {
    to_light: vec4<f32>,
    colour: vec4<f32>,
}

// The light reaching `p` (normal `normal`). Shadow rays start `offset` off the surface along
// its normal: at least the point's own uncertainty, so a surface does not shadow itself.
fn lighting(p: vec3<f32>, normal: vec3<f32>, offset: f32) -> vec3<f32> {
    var light = globals.ambient.rgb;
    let start = p + normal * offset;
    for (var i = 0u; i < globals.sun_count; i++) {
        let s = globals.suns[i];
        let ndl = dot(normal, s.to_light.xyz);
        if ndl > 0.0 && !bvh_any_hit(start, s.to_light.xyz, 1.0e4) {
            light += s.colour.rgb * ndl;
        }
    }
    for (var i = 0u; i < globals.point_count; i++) {
        let l = points[i];
        let to = l.position - p;
        let dist = length(to);
        if dist >= l.radius || dist < 1.0e-4 {
            continue;
        }
        let dir = to / dist;
        let ndl = dot(normal, dir);
        if ndl > 0.0 && !bvh_any_hit(start, dir, dist - offset) {
            let fall = 1.0 - dist / l.radius;
            light += l.colour.rgb * ndl * fall * fall;
        }
    }
    return light;
}
