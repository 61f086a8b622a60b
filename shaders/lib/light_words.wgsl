// The shade pass's lights, read from its `light_words` buffer (`gpu_scene/light_grid.rs`):
// the point lights' records (8 words each), then the grid of which reach where, then each
// point light's caster root. The includer declares `light_words: array<u32>` and `globals`
// (`ShadeGlobals`); `BVH_STATICS_ALL` and `LIGHT_CASTERS_PAD` come with every shader's
// constants (crates/render/src/shader.rs).

fn point_record(i: u32) -> PointLight {
    let w = 8u * i;
    let f = array<f32, 8>(
        bitcast<f32>(light_words[w]), bitcast<f32>(light_words[w + 1u]),
        bitcast<f32>(light_words[w + 2u]), bitcast<f32>(light_words[w + 3u]),
        bitcast<f32>(light_words[w + 4u]), bitcast<f32>(light_words[w + 5u]),
        bitcast<f32>(light_words[w + 6u]), bitcast<f32>(light_words[w + 7u]),
    );
    return PointLight(vec3(f[0], f[1], f[2]), f[3], vec4(f[4], f[5], f[6], f[7]));
}

// The point lights that may reach `p`: the first word of their list and its length (none
// outside the grid, where no light reaches, or for a point that is not a number).
fn near_points(p: vec3<f32>) -> vec2<u32> {
    let h = 8u * max(globals.point_count, 1u);
    let size = vec2(light_words[h], light_words[h + 1u]);
    let origin = vec2(bitcast<f32>(light_words[h + 2u]), bitcast<f32>(light_words[h + 3u]));
    let c = floor((p.xz - origin) / bitcast<f32>(light_words[h + 4u]));
    if !(all(c >= vec2(0.0)) && all(c < vec2<f32>(size))) {
        return vec2(0u);
    }
    let at = h + 8u + 2u * (u32(c.y) * size.x + u32(c.x));
    return vec2(light_words[at], light_words[at + 1u]);
}

// Where a shadow ray from `offset` off its surface toward light `light` (an index among all
// lights) walks the still instances' top level: a point light's caster root
// (`gpu_scene/light_grid.rs`, after the grid's lists), if the grid has them and the ray
// starts within their ball; else the whole top level.
fn light_casters(light: u32, offset: f32) -> u32 {
    let h = 8u * max(globals.point_count, 1u);
    let roots = light_words[h + 5u];
    if light < globals.sun_count || roots == 0u || offset > LIGHT_CASTERS_PAD {
        return BVH_STATICS_ALL;
    }
    return light_words[roots + light - globals.sun_count];
}

// Light `k` of the suns and then the point lights `near` lists: its index among all lights.
fn near_light(near: vec2<u32>, k: u32) -> u32 {
    if k < globals.sun_count {
        return k;
    }
    return globals.sun_count + light_words[near.x + k - globals.sun_count];
}
