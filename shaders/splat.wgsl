// Splat: draws the culled texels as world-space quads (4 vertices, indexed, corners pulled
// from the cull pass's list; a quad may span a run of texels along a face row or column).
// Eye quads are pushed back in depth so grid and previous quads win where both exist; grid
// and previous split the screen with complementary 4×4 Bayer patterns while a crossfade
// runs, each keeping behind its own the pixels of the other's it can fill (`FadeFsOut`).
// Writes the colour (sRGB-encoded, into a plain unorm target: no per-pixel encode) and the
// texel key of every pixel. A one-texel quad of a terrain shows, pixel by pixel, the terrain
// pixel its view ray meets (terrain_splat.wgsl), as the full-resolution raster does.
// crates/render/src/passes/splat.rs.

#include "lib/common.wgsl"
#include "lib/view.wgsl"

@group(0) @binding(0) var<uniform> view: ViewGlobals;
@group(0) @binding(1) var<storage, read> splats: array<Splat>;
// Each terrain quad's terrain pixels (terrain_splat.wgsl), at its splat's index.
@group(0) @binding(2) var<storage, read> terrain_splats: array<TerrainSplat>;

// Few varyings: a CPU rasterizer sets each one up per triangle.
struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(flat) colour: vec4<f32>,
    @location(1) @interpolate(flat) key: u32,
    // The run: its texels − 1 (bits 0–7), down a column (bit 8), the role (bits 9–10).
    @location(2) @interpolate(flat) run: u32,
    // Texel coordinate along a run quad (texel i spans [i, i + 1)).
    @location(3) along: f32,
    // A terrain quad's cells and sides (`terrain_sides`); zero cells for any other quad.
    @location(4) @interpolate(flat) cells: vec4<u32>,
    @location(5) sides: vec2<f32>,
}

@vertex
fn vs(@builtin(vertex_index) vi: u32, @builtin(instance_index) ii: u32) -> VsOut {
    return run_vertex(vi, ii);
}

fn run_vertex(vi: u32, ii: u32) -> VsOut {
    var out: VsOut;
    if ii >= arrayLength(&splats) {
        out.clip = vec4(0.0, 0.0, 2.0, 1.0);
        return out;
    }
    let s = splats[ii];
    let shape = bitcast<u32>(s.c2.w);
    let role = shape & 0xffu;
    let column = (shape & SPLAT_COLUMN) != 0u;
    let texels = max((shape & 0xffffu) >> 8u, 1u);
    out.clip = corner_clip(s, vi, role);
    out.colour = splat_colour(s);
    out.key = bitcast<u32>(s.c0.w);
    out.run = (texels - 1u) | (select(0u, 1u, column) << 8u) | (role << 9u);
    // Texel coordinate along the run: the first texel's centre is 0.5, the last's
    // texels − 0.5. Corners 0–3 are top-left, top-right, bottom-right, bottom-left: a row
    // run starts on the left (0, 3), a column run at the top (0, 1).
    let reach = 2.0 * unpack2x16unorm(bitcast<u32>(s.c3.w));
    let at_start = select(vi == 0u || vi == 3u, vi <= 1u, column);
    out.along = select(f32(texels) - 0.5 + reach.y, 0.5 - reach.x, at_start);
    let tq = terrain_of(s, ii);
    out.cells = tq.cells;
    out.sides = terrain_sides(tq, splat_corner(s, vi));
    return out;
}

// One texel per quad: no run to decode and no `along`.
@vertex
fn vs_texel(@builtin(vertex_index) vi: u32, @builtin(instance_index) ii: u32) -> TexelIn {
    return texel_vertex(vi, ii);
}

fn texel_vertex(vi: u32, ii: u32) -> TexelIn {
    var out: TexelIn;
    if ii >= arrayLength(&splats) {
        out.clip = vec4(0.0, 0.0, 2.0, 1.0);
        return out;
    }
    let s = splats[ii];
    let role = bitcast<u32>(s.c2.w) & 0xffu;
    out.clip = corner_clip(s, vi, role);
    out.colour = splat_colour(s);
    out.key = bitcast<u32>(s.c0.w);
    out.run = role << 9u;
    let tq = terrain_of(s, ii);
    out.cells = tq.cells;
    out.sides = terrain_sides(tq, splat_corner(s, vi));
    return out;
}

// Clip position of corner `vi` of splat `s`.
fn corner_clip(s: Splat, vi: u32, role: u32) -> vec4<f32> {
    var clip = view.view_proj * vec4(splat_corner(s, vi), 1.0);
    // Overlapping coplanar quads (tight expansion toward similar neighbours) would tie in
    // depth and be resolved by draw order, which the cull pass's atomics leave unspecified,
    // and by the rasterizer's depth rounding, which differs between drivers; a per-texel
    // push-back makes the winner a function of the texel alone. It follows the depth's
    // precision: under perspective the reversed depth is about near / distance, so a
    // relative 2^-18 to 2^-10 of it is that fraction of the distance; an orthographic depth
    // is linear, so an absolute 2^-22 to 2^-14 of the depth range. On SwiftShader an absolute
    // 1e-9 under perspective, below the depth's rounding far away, left splats under pure
    // yaw flickering 9× more than this.
    let key = bitcast<u32>(s.c0.w);
    let step = f32(1u + ((key * 2654435761u) >> 24u));
    var z = clip.z * (1.0 - step * exp2(-18.0));
    if view.ortho != 0u {
        z = clip.z - step * exp2(-22.0) * clip.w;
    }
    if role == ROLE_EYE {
        // Eye quads go further back, toward the far plane (0), so grid and previous quads
        // win wherever both exist.
        z = max(z - view.eye_bias * clip.w, 0.0);
    }
    clip.z = z;
    return clip;
}

// The sRGB-encoded colour of splat `s` (stored packed), written to the target as it is;
// alpha 1, or a dithered palette's rank (lib/common.wgsl `dither_alpha`).
fn splat_colour(s: Splat) -> vec4<f32> {
    let packed = bitcast<u32>(s.c1.w);
    let c = unpack4x8unorm(packed);
    return select(c, vec4(c.rgb, 1.0), (packed >> 24u) == SPLAT_TERRAIN_ALPHA);
}

// What terrain quad `ii` (splat `s`) shows; zero cells for any other quad.
fn terrain_of(s: Splat, ii: u32) -> TerrainSplat {
    if !is_terrain_splat(s) || ii >= arrayLength(&terrain_splats) {
        return TerrainSplat();
    }
    return terrain_splats[ii];
}

// A terrain quad's corner at `world`: on which side of its block's two inner edges (the
// lines between its cells, x = size and z = size from the block's corner) the view ray
// through `world` meets the terrain, positive past the edge. The ray meets the ground past
// an edge when it is still above the ground where it crosses the edge's vertical plane and
// runs toward it: with the ground along the edge `h = a + b·t` (`TerrainSplat::edges`),
// `(o.y + t·d.y − h) · d.x` at the crossing `t = (size − o.x) / d.x` is
// `(o.y − a − b·o.z)·d.x + (size − o.x)·(d.y − b·d.z)` (and likewise along z). Both are
// affine in `world` on the quad (the ray's origin is the camera, or `world` itself under an
// orthographic view), so interpolated across it they give each pixel's own sides
// (`pixel_colour`). They depend only on the ground along the edge, not on the texel the quad
// comes from: two probes' quads over one screen pixel pick the same terrain pixel.
fn terrain_sides(t: TerrainSplat, world: vec3<f32>) -> vec2<f32> {
    if t.cells.x == 0u {
        return vec2(0.0);
    }
    let ray = view_ray_through(world);
    let o = ray.origin - vec3(t.grid.x, 0.0, t.grid.y);
    let d = ray.dir;
    let size = t.grid.z;
    let e = t.edges;
    let along_x = (o.y - e.x - e.y * o.z) * d.x + (size - o.x) * (d.y - e.y * d.z);
    let along_z = (o.y - e.z - e.w * o.x) * d.z + (size - o.z) * (d.y - e.w * d.x);
    return vec2(along_x, along_z);
}

// The sRGB-encoded colour of a pixel of a quad of `colour` (with its alpha); a terrain
// quad's (non-zero `cells`) is the colour of the cell its view ray meets
// (`terrain_sides`), alpha 1.
fn pixel_colour(colour: vec4<f32>, cells: vec4<u32>, sides: vec2<f32>) -> vec4<f32> {
    if cells.x == 0u {
        return colour;
    }
    let row = select(cells.xy, cells.zw, sides.y > 0.0);
    return vec4(unpack4x8unorm(select(row.x, row.y, sides.x > 0.0)).rgb, 1.0);
}

struct FsOut {
    @location(0) colour: vec4<f32>,
    @location(1) key: u32,
}

// A crossfade's output. A pixel handed to the other stable probe (the owner) is not
// discarded (as the paper's schedule does) but kept behind, halfway to the eye's push-back,
// where the owner cannot see its point: past something nearer (what the other probe sees
// around an occluder), or on a face the owner has not captured yet. There it fills before
// the eye does, whose texels move with the camera. Where the owner sees the sky or a farther
// surface toward the point, the point lies past the owner's silhouette, and kept it would
// only grow that silhouette: it is discarded.
struct FadeFsOut {
    @location(0) colour: vec4<f32>,
    @location(1) key: u32,
    @builtin(frag_depth) depth: f32,
}

// The depth of a crossfade's fragment at depth `z` (see `FadeFsOut`); `misses` the
// interpolated `FadeOut::owner_misses`.
fn fade_depth(z: f32, handed_over: bool, misses: f32) -> f32 {
    if !handed_over {
        return z;
    }
    if view.schedule == 1u || misses < 0.5 {
        discard;
    }
    return max(z - 0.5 * view.eye_bias, 0.0);
}

// A one-texel quad's vertex output: no `along`, so a pipeline of such quads (the paper
// schedule, or runs off) sets up no interpolated varying at all.
struct TexelIn {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(flat) colour: vec4<f32>,
    @location(1) @interpolate(flat) key: u32,
    @location(2) @interpolate(flat) run: u32,
    @location(3) @interpolate(flat) cells: vec4<u32>,
    @location(4) sides: vec2<f32>,
}

// The key of the texel under this pixel of a run quad.
fn pixel_key(in: VsOut) -> u32 {
    let last = f32(in.run & 0xffu);
    let step = select(1u, view.max_n, (in.run & 0x100u) != 0u);
    return in.key + step * u32(clamp(floor(in.along), 0.0, last));
}

// During a crossfade the vertex stage also passes whether the probe that owns a pixel can
// see the quad, and the quad's world point: toward a grid probe that misses faces, a pixel
// of the previous probe tells from it whether the grid probe has the face that would show it.
struct FadeOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(flat) colour: vec4<f32>,
    @location(1) @interpolate(flat) key: u32,
    @location(2) @interpolate(flat) run: u32,
    @location(3) along: f32,
    @location(4) world: vec3<f32>,
    // 1 where the stable probe that owns the pixel cannot see the quad (cull.wgsl
    // `owner_misses`, decided at the corners once per quad), 0 where it can.
    @location(5) owner_misses: f32,
    @location(6) @interpolate(flat) cells: vec4<u32>,
    @location(7) sides: vec2<f32>,
}

// Whether the probe that owns a crossfade's pixel cannot see corner `vi` of splat `ii`, as
// 1 or 0, as the cull pass decided it (cull.wgsl `owner_miss_bits`; always 0 under the
// paper's schedule, which discards every handed-over pixel).
fn corner_owner_misses(vi: u32, ii: u32) -> f32 {
    if ii >= arrayLength(&splats) {
        return 0.0;
    }
    let shape = bitcast<u32>(splats[ii].c2.w);
    return f32((shape >> (SPLAT_OWNER_MISSES + vi)) & 1u);
}

@vertex
fn vs_fade(@builtin(vertex_index) vi: u32, @builtin(instance_index) ii: u32) -> FadeOut {
    let v = run_vertex(vi, ii);
    let world = splat_world(vi, ii);
    return FadeOut(v.clip, v.colour, v.key, v.run, v.along, world, corner_owner_misses(vi, ii), v.cells, v.sides);
}

@vertex
fn vs_texel_fade(@builtin(vertex_index) vi: u32, @builtin(instance_index) ii: u32) -> FadeOut {
    let v = texel_vertex(vi, ii);
    let world = splat_world(vi, ii);
    return FadeOut(v.clip, v.colour, v.key, v.run, 0.5, world, corner_owner_misses(vi, ii), v.cells, v.sides);
}

fn splat_world(vi: u32, ii: u32) -> vec3<f32> {
    if ii >= arrayLength(&splats) {
        return vec3(0.0);
    }
    return splat_corner(splats[ii], vi);
}

// Whether the grid probe draws the face that would show world point `p`.
fn grid_draws(p: vec3<f32>) -> bool {
    for (var s = 1u; s < 3u; s++) {
        let v = view.slots[s];
        if v.role == ROLE_GRID {
            return (v.draw_mask & (1u << frame_locate(slot_frame(v), p).face)) != 0u;
        }
    }
    return false;
}

// Whether a crossfade hands this pixel (at `pixel`) of a quad of `run` to the other stable
// probe: grid and previous split the pixels with complementary Bayer patterns.
fn faded_out(run: u32, pixel: vec2<f32>) -> bool {
    let role = run >> 9u;
    if role == ROLE_EYE {
        return false;
    }
    let grid_wins = bayer_threshold(vec2<u32>(pixel)) < view.fade_t;
    return (role == ROLE_GRID) != grid_wins;
}

// `faded_out` while the grid probe has not captured every face yet: where it lacks the face
// that would show world point `p`, the previous probe keeps the pixel, so the fade need not
// wait for a whole grid probe (`texel_probes::probe_set::PARTIAL_FADE_LIMIT`).
fn faded_out_partial(run: u32, pixel: vec2<f32>, p: vec3<f32>) -> bool {
    if (run >> 9u) == ROLE_PREVIOUS && !grid_draws(p) {
        return false;
    }
    return faded_out(run, pixel);
}

// Without a crossfade: no discard, so the depth test can run before the shader.
@fragment
fn fs(in: VsOut) -> FsOut {
    return FsOut(pixel_colour(in.colour, in.cells, in.sides), pixel_key(in));
}

// During a crossfade.
@fragment
fn fs_dither(in: FadeOut) -> FadeFsOut {
    let z = fade_depth(in.clip.z, faded_out(in.run, in.clip.xy), in.owner_misses);
    let v = VsOut(in.clip, in.colour, in.key, in.run, in.along, in.cells, in.sides);
    return FadeFsOut(pixel_colour(in.colour, in.cells, in.sides), pixel_key(v), z);
}

// During a crossfade toward a grid probe that misses faces.
@fragment
fn fs_dither_partial(in: FadeOut) -> FadeFsOut {
    let handed = faded_out_partial(in.run, in.clip.xy, in.world);
    let z = fade_depth(in.clip.z, handed, in.owner_misses);
    let v = VsOut(in.clip, in.colour, in.key, in.run, in.along, in.cells, in.sides);
    return FadeFsOut(pixel_colour(in.colour, in.cells, in.sides), pixel_key(v), z);
}

// One texel per quad, without a crossfade.
@fragment
fn fs_texel(in: TexelIn) -> FsOut {
    return FsOut(pixel_colour(in.colour, in.cells, in.sides), in.key);
}

// One texel per quad, during a crossfade.
@fragment
fn fs_texel_dither(in: FadeOut) -> FadeFsOut {
    let z = fade_depth(in.clip.z, faded_out(in.run, in.clip.xy), in.owner_misses);
    return FadeFsOut(pixel_colour(in.colour, in.cells, in.sides), in.key, z);
}

// One texel per quad, during a crossfade toward a grid probe that misses faces.
@fragment
fn fs_texel_dither_partial(in: FadeOut) -> FadeFsOut {
    let handed = faded_out_partial(in.run, in.clip.xy, in.world);
    let z = fade_depth(in.clip.z, handed, in.owner_misses);
    return FadeFsOut(pixel_colour(in.colour, in.cells, in.sides), in.key, z);
}
