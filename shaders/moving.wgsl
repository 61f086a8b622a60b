// Moving: draws the animated objects straight into the frame, after the splats and before
// the background, depth-tested against them. They are never captured into the probes (no
// ghosts in the cache, no holes when they leave), and their art pixels are carried with
// them: each surface is cut into square cells on a grid fixed to the object (its base
// transform's rigid frame, the two axes its plane spreads along most), and every pixel of a
// cell takes the cell's one colour, lit at the cell's centre where the object is now. So a
// moving object's pixels move rigidly with it, and a still one's do not change while the
// camera moves inside a probe cell: the cell size is the grid probe's texel at the object's
// distance from the grid probe's origin (as terrain pixels are), rounded up to a power of two.
// crates/render/src/passes/moving.rs.

#include "lib/common.wgsl"
#include "lib/view.wgsl"
#include "lib/texture.wgsl"
#include "lib/bvh.wgsl"
#include "lib/lighting.wgsl"
#include "lib/raster.wgsl"
#include "lib/motion.wgsl"

// What lib/lighting.wgsl reads, and the level's posterization.
struct LightGlobals {
    suns: array<Sun, 4>,
    ambient: vec4<f32>,
    sun_count: u32,
    point_count: u32,
    bands: u32,
    _pad: u32,
}

@group(0) @binding(0) var<uniform> view: ViewGlobals;
@group(0) @binding(1) var<storage, read> objects: array<Object>;
@group(1) @binding(0) var<uniform> globals: LightGlobals;
@group(1) @binding(1) var<storage, read> points: array<PointLight>;
fn point_record(i: u32) -> PointLight {
    return points[i];
}
@group(1) @binding(2) var<storage, read> motions: array<Motion>;
@group(2) @binding(0) var<storage, read> bvh_nodes: array<BvhNode>;
@group(2) @binding(1) var<storage, read> bvh_triangles: array<BvhTriangle>;
@group(2) @binding(2) var<storage, read> bvh_instances: array<BvhInstance>;
@group(2) @binding(3) var<uniform> bvh_fields: BvhFields;
@group(2) @binding(4) var bvh_field_data: texture_2d_array<f32>;

@vertex
fn vs(v: SceneVertex) -> VsOut {
    let m = motions[objects[v.object].flags >> 8u];
    // `world` stays the base-pose point: the cells are cut there.
    return raster_vertex(v, view.view_proj * m.to_now);
}

struct FsOut {
    @location(0) colour: vec4<f32>,
    @location(1) key: u32,
}

// The centre of the object cell of size `s` holding point `q` (rigid frame) on the plane
// through `q` with unit normal `n`: the cells are squares on the two axes the plane spreads
// along most, and the centre is lifted back onto the plane along the third.
fn cell_centre(q: vec3<f32>, n: vec3<f32>, s: f32) -> vec3<f32> {
    let a = abs(n);
    if a.x >= a.y && a.x >= a.z {
        let c = (floor(q.yz / s) + 0.5) * s;
        return vec3(q.x - (n.y * (c.x - q.y) + n.z * (c.y - q.z)) / n.x, c.x, c.y);
    }
    if a.y >= a.z {
        let c = (floor(q.xz / s) + 0.5) * s;
        return vec3(c.x, q.y - (n.x * (c.x - q.x) + n.z * (c.y - q.z)) / n.y, c.y);
    }
    let c = (floor(q.xy / s) + 0.5) * s;
    return vec3(c.x, c.y, q.z - (n.x * (c.x - q.x) + n.y * (c.y - q.y)) / n.z);
}

// The two rigid-frame axes a cell spans on a plane of normal `n`, each `s` long.
fn cell_axes(n: vec3<f32>, s: f32) -> mat2x3<f32> {
    let a = abs(n);
    if a.x >= a.y && a.x >= a.z {
        return mat2x3(vec3(0.0, s, 0.0), vec3(0.0, 0.0, s));
    }
    if a.y >= a.z {
        return mat2x3(vec3(s, 0.0, 0.0), vec3(0.0, 0.0, s));
    }
    return mat2x3(vec3(s, 0.0, 0.0), vec3(0.0, s, 0.0));
}

@fragment
fn fs(in: VsOut) -> FsOut {
    let obj = objects[in.object];
    let m = motions[obj.flags >> 8u];
    let grid = view.slots[view.grid_slot];
    let centre_now = (m.to_now * vec4(m.centre.xyz, 1.0)).xyz;
    let dist = max(distance(centre_now, grid.origin), 1.0e-3);
    let s = exp2(ceil(log2(max(2.0 * dist / f32(max(grid.n, 1u)), 1.0e-4))));

    let plane = surface_plane_normal(in);
    let q = (m.frame * vec4(in.world, 1.0)).xyz;
    let nq = normalize((m.frame * vec4(plane, 0.0)).xyz);
    let cq = cell_centre(q, nq, s);
    let to_cell = (m.frame_inv * vec4(cq - q, 0.0)).xyz;
    let c0 = in.world + to_cell;
    let c_now = (m.to_now * vec4(c0, 1.0)).xyz;

    // The surface at the cell's centre: its texture coordinates, its footprint one cell.
    var at = in;
    at.uv = in.uv + vec2(dot(in.grad_u, to_cell), dot(in.grad_v, to_cell));
    let axes = cell_axes(nq, s);
    let fx = (m.frame_inv * vec4(axes[0], 0.0)).xyz;
    let fy = (m.frame_inv * vec4(axes[1], 0.0)).xyz;
    let t = surface_uv(at, fx, fy);
    let surface = surfaces[in.surface];
    let albedo = surface_albedo(obj, in.colour, surface_texture_colour(surface, t));
    var colour: vec3<f32>;
    if (obj.flags & FLAG_EMISSIVE) != 0u {
        colour = obj.emissive;
    } else {
        // The mesh's own normal (as the probes store it), normal-mapped, turned with the
        // object.
        let n0 = surface_shading_normal(surface, surface_normal(in.normal), in.grad_u, in.grad_v, t);
        let n_now = normalize((m.normal_now * vec4(n0, 0.0)).xyz);
        colour = albedo.rgb * lighting(c_now, n_now, max(SHADOW_OFFSET, 0.1 * s));
    }
    let lit = posterize(colour, globals.bands, 0.0);
    var out: FsOut;
    out.colour = vec4(linear_to_srgb(hazed(lit, length(c_now - view.camera.xyz))), 1.0);
    // Not a probe texel: the object's index under the moving bit (crates/render/src/readback.rs
    // `MOVING_KEY`), which the visible-texel pass skips and picking reads.
    out.key = 0x80000000u | in.object;
    return out;
}
