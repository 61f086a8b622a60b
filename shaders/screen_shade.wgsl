// Screen shade: lights a screen G-buffer once per pixel with the texel shade pass's model
// (shaders/shade.wgsl): sun and point lights with BVH shadow rays, ambient, emissive, OKLab
// posterization, silhouette (id) and crease (normal) outlines found among the four screen
// neighbours, and the draw passes' haze (lib/view.wgsl `hazed`) by distance from the eye. crates/render/src/baselines/shade.rs.

#include "lib/common.wgsl"
#include "lib/bvh.wgsl"
#include "lib/lighting.wgsl"

struct ScreenGlobals {
    suns: array<Sun, 4>,
    ambient: vec4<f32>,
    sky: vec4<f32>,
    // Camera position (xyz); w = 1 for an orthographic camera.
    eye: vec4<f32>,
    // Orthographic view axis (xyz).
    axis: vec4<f32>,
    sun_count: u32,
    point_count: u32,
    bands: u32,
    outlines: u32,
    size: vec2<u32>,
    // Haze density per world unit (0 = none).
    haze: f32,
    _pad: u32,
}

@group(0) @binding(0) var<uniform> globals: ScreenGlobals;
@group(0) @binding(1) var world_tex: texture_2d<f32>;
@group(0) @binding(2) var normal_tex: texture_2d<f32>;
@group(0) @binding(3) var id_tex: texture_2d<u32>;
@group(0) @binding(4) var lit_out: texture_storage_2d<rgba16float, write>;
@group(0) @binding(5) var<storage, read> objects: array<Object>;
@group(0) @binding(6) var<storage, read> points: array<PointLight>;
fn point_record(i: u32) -> PointLight {
    return points[i];
}
@group(1) @binding(0) var<storage, read> bvh_nodes: array<BvhNode>;
@group(1) @binding(1) var<storage, read> bvh_triangles: array<BvhTriangle>;
@group(1) @binding(2) var<storage, read> bvh_instances: array<BvhInstance>;
@group(1) @binding(3) var<uniform> bvh_fields: BvhFields;
@group(1) @binding(4) var bvh_field_data: texture_2d_array<f32>;


// The direction from the eye to `p` (the view axis for an orthographic camera).
fn view_ray(p: vec3<f32>) -> vec3<f32> {
    if globals.eye.w > 0.5 {
        return globals.axis.xyz;
    }
    return normalize(p - globals.eye.xyz);
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let t = gid.xy;
    if any(t >= globals.size) {
        return;
    }
    let ids = textureLoad(id_tex, t, 0);
    let id = ids.x;
    if id == 0u {
        textureStore(lit_out, t, vec4(posterize(globals.sky.rgb, globals.bands, 0.0), 1.0));
        return;
    }
    let world = textureLoad(world_tex, t, 0);
    let normal = textureLoad(normal_tex, t, 0).xyz;
    let alb = unpack4x8unorm(ids.y);
    let flags = u32(round(alb.a * 255.0));
    var colour: vec3<f32>;
    if (flags & FLAG_EMISSIVE) != 0u {
        colour = objects[id - 1u].emissive;
    } else {
        // Highlights as the camera sees them: the screen-space methods' own view.
        let to_eye = normalize(globals.eye.xyz - world.xyz);
        let lit = lighting_seen(world.xyz, normal, SHADOW_OFFSET, to_eye, objects[id - 1u].specular);
        colour = alb.rgb * lit.diffuse + lit.shine;
    }
    var shift = 0.0;
    if globals.outlines != 0u && (flags & FLAG_OUTLINED) != 0u {
        shift = outline_shift(t, id, world.w, normal, view_ray(world.xyz));
    }
    let lit = posterize(colour, globals.bands, shift);
    let fog = 1.0 - exp(-globals.haze * length(world.xyz - globals.eye.xyz));
    textureStore(lit_out, t, vec4(mix(lit, globals.sky.rgb, fog), 1.0));
}

// shade.wgsl's outline rule over the four screen neighbours: −1 band on the nearer side of a
// silhouette or the less-facing side of a crease, +1 band on the more-facing side.
fn outline_shift(t: vec2<u32>, id: u32, depth: f32, normal: vec3<f32>, ray: vec3<f32>) -> f32 {
    let facing = dot(normal, -ray);
    var darken = false;
    var lighten = false;
    for (var k = 0u; k < 4u; k++) {
        let q = vec2<i32>(t) + NEIGHBOURS[k];
        if any(q < vec2(0)) || any(q >= vec2<i32>(globals.size)) {
            continue;
        }
        let nb_id = textureLoad(id_tex, q, 0).r;
        if nb_id != id {
            if nb_id == 0u || depth <= textureLoad(world_tex, q, 0).w {
                darken = true;
            }
            continue;
        }
        let nb_normal = textureLoad(normal_tex, q, 0).xyz;
        if dot(normal, nb_normal) < 0.7 {
            if facing >= dot(nb_normal, -ray) {
                lighten = true;
            } else {
                darken = true;
            }
        }
    }
    if darken {
        return -1.0;
    }
    if lighten {
        return 1.0;
    }
    return 0.0;
}
