// Terrain splats: for each one-texel terrain quad of the cull pass's list, the terrain pixels
// it shows (lib/view.wgsl `TerrainSplat`), which the splat pass's fragments pick from by
// where their view ray meets the terrain: a terrain's pixels then follow the world rather
// than each probe's texel grid. Once per quad, between cull and splat.
// crates/render/src/passes/terrain_splat.rs.

#include "lib/common.wgsl"
#include "lib/view.wgsl"
#include "lib/texture.wgsl"
#include "lib/terrain.wgsl"
#include "lib/lights.wgsl"
#include "lib/shade_globals.wgsl"

struct DrawArgs {
    index_count: u32,
    instance_count: u32,
    first_index: u32,
    base_vertex: i32,
    first_instance: u32,
}

struct DispatchArgs {
    x: u32,
    y: u32,
    z: u32,
}

const GROUP: u32 = 64u;

@group(0) @binding(0) var<uniform> view: ViewGlobals;
// The scene's objects, textures and terrains (bindings 1-6 as in passes/raster.rs
// `scene_layout_entries`, less the surfaces), the shade pass's globals and point lights.
@group(0) @binding(1) var<storage, read> objects: array<Object>;
@group(0) @binding(7) var<uniform> globals: ShadeGlobals;
@group(0) @binding(8) var<storage, read> points: array<PointLight>;
@group(0) @binding(9) var<storage, read> splats: array<Splat>;
@group(0) @binding(10) var<storage, read> args: DrawArgs;
@group(0) @binding(11) var<storage, read_write> records: array<TerrainSplat>;
// Its own group: bound only while `size` writes it, not while `main` is dispatched by it.
@group(1) @binding(0) var<storage, read_write> dispatch: DispatchArgs;

// The dispatch of `main`: one invocation per quad of the list.
@compute @workgroup_size(1)
fn size() {
    let quads = min(args.instance_count, arrayLength(&splats));
    dispatch = DispatchArgs((quads + GROUP - 1u) / GROUP, 1u, 1u);
}

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let ii = gid.x;
    if ii >= min(args.instance_count, min(arrayLength(&splats), arrayLength(&records))) {
        return;
    }
    let s = splats[ii];
    if !is_terrain_splat(s) {
        return;
    }
    records[ii] = terrain_splat(s, bitcast<u32>(s.c2.w) & 0xffu);
}

// The terrain pixels splat `s` (drawn by a probe of `role`) shows, if it is a one-texel quad
// of a terrain (cull.wgsl). A terrain pixel is at least a probe texel, so the quad's pixels
// mostly lie in the 2 × 2 block of pixels toward which its point lies in its own pixel;
// each is coloured and lit as the shade pass would light it from its centre (its colour, the
// terrain's normal there), with the texel's shadows and outline. Pixels of the terrain
// follow the world, not each probe's texel grid: a crossfade's two probes show the same
// pixel under each screen pixel, where each had drawn its own texels' steps.
fn terrain_splat(s: Splat, role: u32) -> TerrainSplat {
    var out: TerrainSplat;
    let word = bitcast<u32>(s.c3.w);
    let obj = objects[word >> SPLAT_TERRAIN_OBJECT_AT];
    let tr = terrains[obj.flags >> 8u];
    let mid = 0.25 * (s.c0.xyz + s.c1.xyz + s.c2.xyz + s.c3.xyz);
    let q = clamp(mid.xz - tr.corner.xz, vec2(0.0), tr.size);
    let at = terrain_plane(tr, q);
    let point = vec3(tr.corner.x + q.x, tr.corner.y + at.height, tr.corner.z + q.y);
    let normal = normalize(vec3(-at.slope.x, 1.0, -at.slope.y));
    // Bands from the probe's band origin (the grid probe's for the eye, as in its capture).
    var origin = view.slots[view.grid_slot].origin;
    var n = view.slots[view.eye_slot].n;
    if role != ROLE_EYE {
        for (var k = 0u; k < 3u; k++) {
            if view.slots[k].role == role {
                origin = view.slots[k].origin;
                n = view.slots[k].n;
            }
        }
    }
    let size = terrain_pixel(tr, point, origin, f32(n)).size;
    out.plane = vec4(normal, dot(normal, point));
    // The cells the quad's pixels can meet: its corners seen from the camera on the plane
    // (their hits bound every pixel's), within the 2 × 2 block toward which the point lies
    // in its own cell; each cell the block does not need repeats its neighbour's colour.
    var lo = vec2(1e30);
    var hi = vec2(-1e30);
    for (var k = 0u; k < 4u; k++) {
        let h = view_ray_plane(out.plane, splat_corner(s, k)).xz - tr.corner.xz;
        lo = min(lo, h);
        hi = max(hi, h);
    }
    let g = q / size;
    let base = floor(g) - select(vec2(0.0), vec2(1.0), fract(g) < vec2(0.5));
    let first = clamp(floor(lo / size), base, base + 1.0) - base;
    let last = clamp(floor(hi / size), base, base + 1.0) - base;
    let shadows = word & ((1u << TERRAIN_LIGHTS) - 1u);
    let shift = f32((word >> TERRAIN_LIGHTS) & 3u) - 1.0;
    let dist = length(point - view.camera.xyz);
    for (var k = 0u; k < 4u; k++) {
        let at = clamp(vec2(f32(k & 1u), f32(k >> 1u)), first, last);
        let same = u32(at.x) + 2u * u32(at.y);
        if same < k {
            out.cells[k] = out.cells[same];
            continue;
        }
        let lit = terrain_lit_pixel(tr, obj.albedo, base + at, size, shadows, shift);
        out.cells[k] = pack4x8unorm(vec4(linear_to_srgb(hazed(lit, dist)), 1.0));
    }
    out.grid = vec4(tr.corner.xz + base * size, size, 0.0);
    return out;
}

// Terrain pixel `cell` (of size `size`) of `tr`, lit from its centre by the lights in `reach`
// (bit i: light i), posterized with `shift`.
fn terrain_lit_pixel(tr: Terrain, albedo: vec3<f32>, cell: vec2<f32>, size: f32, reach: u32, shift: f32) -> vec3<f32> {
    let px = TerrainPixel((cell + 0.5) * size, size);
    let colour = albedo * terrain_pixel_colour(tr, px);
    let centre = terrain_cell_point(tr, cell, size);
    let normal = terrain_normal(tr, px.centre);
    var light = globals.ambient.rgb;
    for (var i = 0u; i < light_count(); i++) {
        if ((reach >> i) & 1u) == 0u {
            continue;
        }
        let r = light_ray(i, centre);
        let ndl = dot(normal, r.dir);
        if ndl > 0.0 && r.reach > 0.0 {
            light += r.colour * ndl * r.fall * r.fall;
        }
    }
    return posterize(colour * light, globals.bands, shift);
}
