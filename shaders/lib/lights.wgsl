// Lights as rays from a point: directional suns and point lights with (1 − d/r)² falloff,
// without shadows (lib/lighting.wgsl traces those through the BVH; the terrain splats pass takes a
// terrain texel's). The includer declares `globals` (with `sun_count`,
// `suns: array<Sun, N>`, `point_count`) and `point_record(i) -> PointLight` (point light
// `i` of its `points` buffer: the shade pass reads that buffer as words, for the grid of
// which lights reach where that follows the records), and includes lib/common.wgsl.

// The least distance, in world units, a shadow ray starts off its surface.
const SHADOW_OFFSET: f32 = 0.02;


// Light `i` (the suns first, then the point lights) as seen from `p`: the unit direction
// toward it, how far a shadow ray must reach (before the surface offset is taken off), and
// its colour and falloff there (reach zero out of a point light's range). Callers with their own occluders
// (a relief sprite's self-shadow) loop over these; `lighting` is the plain case.
struct LightRay {
    dir: vec3<f32>,
    reach: f32,
    colour: vec3<f32>,
    // The point light's falloff 1 − d/r (1 for suns); its square scales the colour.
    fall: f32,
    // Whether the reach is a point light's distance (the offset is taken off it).
    point: bool,
}

fn light_count() -> u32 {
    return globals.sun_count + globals.point_count;
}

fn light_ray(i: u32, p: vec3<f32>) -> LightRay {
    if i < globals.sun_count {
        let s = globals.suns[i];
        return LightRay(s.to_light.xyz, 1.0e4, s.colour.rgb, 1.0, false);
    }
    let l = point_record(i - globals.sun_count);
    let to = l.position - p;
    let dist = length(to);
    if dist >= l.radius || dist < 1.0e-4 {
        return LightRay(vec3(0.0, 1.0, 0.0), 0.0, vec3(0.0), 0.0, true);
    }
    return LightRay(to / dist, dist, l.colour.rgb, 1.0 - dist / l.radius, true);
}

// The shadow ray's length for `r` from a start `offset` off the surface.
fn light_reach(r: LightRay, offset: f32) -> f32 {
    return select(r.reach, r.reach - offset, r.point);
}
