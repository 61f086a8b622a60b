// Pixel-art terrain colouring (crates/scene/src/terrain.rs; the Godot terrain seed's
// technique): the terrain is cut into a world-anchored grid of square pixels whose size
// doubles in distance bands (never below the probe texel), and each pixel takes one colour:
// the elevation gradient at its centre's height, perturbed by the displacement texture at its
// centre, with the paint layer's pixel holding that centre blended over it. Bands come from the distance to the band origin (the grid probe's origin in a
// capture, also for the eye probe; the camera in a G-buffer), so a pixel's colour does not
// change while the camera moves inside a cell. Between bands, fine pixels are promoted to the
// coarser band's by a Bayer pattern. The includer includes lib/common.wgsl and
// lib/texture.wgsl and binds `terrains` and `terrain_data` at group 0, bindings 5 and 6.

struct Terrain {
    corner: vec3<f32>,
    max_height: f32,
    size: vec2<f32>,
    samples: vec2<u32>,
    heights_at: u32,
    gradient_at: u32,
    gradient_len: u32,
    displacement: u32,
    strength: f32,
    tile_size: f32,
    pixel_density: f32,
    band_distance: f32,
    band_transition: f32,
    // Paint layer texture record (sRGB colour, alpha = cover; one level, nearest, clamped),
    // or NO_TEXTURE.
    paint: u32,
    _pad1: u32,
    _pad2: u32,
}

@group(0) @binding(5) var<storage, read> terrains: array<Terrain>;
@group(0) @binding(6) var<storage, read> terrain_data: array<f32>;

fn terrain_height_at(t: Terrain, x: i32, z: i32) -> f32 {
    let s = vec2<i32>(t.samples);
    let cx = clamp(x, 0, s.x - 1);
    let cz = clamp(z, 0, s.y - 1);
    return terrain_data[t.heights_at + u32(cz * s.x + cx)];
}

// Bilinear height at a point `q` relative to the corner (world units along X, Z).
fn terrain_height(t: Terrain, q: vec2<f32>) -> f32 {
    let g = q / t.size * vec2<f32>(t.samples - vec2(1u));
    let i = vec2<i32>(floor(g));
    let f = g - floor(g);
    let a = mix(terrain_height_at(t, i.x, i.y), terrain_height_at(t, i.x + 1, i.y), f.x);
    let b = mix(terrain_height_at(t, i.x, i.y + 1), terrain_height_at(t, i.x + 1, i.y + 1), f.x);
    return mix(a, b, f.y);
}

// The level-0 mesh's quad holding `q` (relative to the corner, along X and Z): its sample
// index, where `q` lies in it (0..1 along X and Z) and the sample spacing. crates/scene/src/
// terrain.rs `lod_mesh` splits each quad along its (1,0)-(0,1) diagonal: `f.x + f.y <= 1` is
// the triangle at sample `i`, the rest the one at `i + 1`.
struct TerrainQuad {
    i: vec2<i32>,
    f: vec2<f32>,
    step: vec2<f32>,
}

fn terrain_quad(t: Terrain, q: vec2<f32>) -> TerrainQuad {
    let cells = vec2<f32>(t.samples - vec2(1u));
    let step = t.size / cells;
    let g = clamp(q / step, vec2(0.0), cells);
    let i = vec2<i32>(min(floor(g), cells - 1.0));
    return TerrainQuad(i, g - vec2<f32>(i), step);
}

// The level-0 mesh's height at `q` and the slope (d height / d (x, z)) of its triangle there.
struct TerrainPlane {
    height: f32,
    slope: vec2<f32>,
}

fn terrain_plane(t: Terrain, q: vec2<f32>) -> TerrainPlane {
    let c = terrain_quad(t, q);
    let i = c.i;
    let f = c.f;
    let h10 = terrain_height_at(t, i.x + 1, i.y);
    let h01 = terrain_height_at(t, i.x, i.y + 1);
    if f.x + f.y <= 1.0 {
        let h00 = terrain_height_at(t, i.x, i.y);
        return TerrainPlane(h00 + f.x * (h10 - h00) + f.y * (h01 - h00), vec2(h10 - h00, h01 - h00) / c.step);
    }
    let h11 = terrain_height_at(t, i.x + 1, i.y + 1);
    return TerrainPlane(h11 + (1.0 - f.x) * (h01 - h11) + (1.0 - f.y) * (h10 - h11), vec2(h11 - h01, h11 - h10) / c.step);
}

fn terrain_vertex_normal(t: Terrain, x: i32, z: i32, step: vec2<f32>) -> vec3<f32> {
    let dx = (terrain_height_at(t, x + 1, z) - terrain_height_at(t, x - 1, z)) / (2.0 * step.x);
    let dz = (terrain_height_at(t, x, z + 1) - terrain_height_at(t, x, z - 1)) / (2.0 * step.y);
    return normalize(vec3(-dx, 1.0, -dz));
}

// The level-0 mesh's normal at `q`: its vertex normals (central differences of the samples)
// interpolated across the triangle, as the rasterizer interpolates them.
fn terrain_normal(t: Terrain, q: vec2<f32>) -> vec3<f32> {
    let c = terrain_quad(t, q);
    let i = c.i;
    let f = c.f;
    let n10 = terrain_vertex_normal(t, i.x + 1, i.y, c.step);
    let n01 = terrain_vertex_normal(t, i.x, i.y + 1, c.step);
    if f.x + f.y <= 1.0 {
        let n00 = terrain_vertex_normal(t, i.x, i.y, c.step);
        return normalize((1.0 - f.x - f.y) * n00 + f.x * n10 + f.y * n01);
    }
    let n11 = terrain_vertex_normal(t, i.x + 1, i.y + 1, c.step);
    return normalize((f.x + f.y - 1.0) * n11 + (1.0 - f.y) * n10 + (1.0 - f.x) * n01);
}

// Where the ray `o + dir · s` first meets the level-0 surface, searched from `s = depth` (a
// hit on a coarser level of the mesh, which lies within a few samples of it): Newton steps
// on the height above the surface along the ray (exact within one triangle). `depth` when the
// ray leaves the terrain, runs along it, or the steps do not settle within a quarter of
// `depth`.
fn terrain_level0_hit(t: Terrain, o: vec3<f32>, dir: vec3<f32>, depth: f32) -> f32 {
    var s = depth;
    for (var k = 0u; k < 8u; k++) {
        let p = o + dir * s;
        let q = p.xz - t.corner.xz;
        if any(q < vec2(0.0)) || any(q > t.size) {
            return depth;
        }
        let plane = terrain_plane(t, q);
        let above = p.y - (t.corner.y + plane.height);
        if abs(above) <= 1e-5 * max(s, 1.0) {
            return s;
        }
        let rate = dir.y - dot(plane.slope, dir.xz);
        if abs(rate) < 1e-6 {
            return depth;
        }
        s -= above / rate;
        if s <= 0.0 || abs(s - depth) > 0.25 * depth {
            return depth;
        }
    }
    return depth;
}

// Band by distance only: 0 within band_distance, one more per doubling past it.
fn terrain_distance_band(t: Terrain, d: f32) -> u32 {
    if d <= t.band_distance {
        return 0u;
    }
    return u32(max(ceil(log2(d / t.band_distance)), 0.0));
}

// What a terrain's pixels are sized for: the probe (or camera) at `origin` with `n` texels
// per face edge, whose texel at distance d is 2d/n (a huge `n`: no texel bound); or, where
// `ortho_texel` > 0, an orthographic probe, whose texels are that size at every distance, so
// its pixels are the finest no smaller than a texel, with no distance bands: on screen they
// keep one size without them.
struct BandFrom {
    origin: vec3<f32>,
    n: f32,
    ortho_texel: f32,
}

// The sizing of a probe at `origin` with `n` texels per face edge and, for an orthographic
// probe, face half-extent `half` (0 for a perspective cube).
fn band_from(origin: vec3<f32>, n: f32, half: f32) -> BandFrom {
    return BandFrom(origin, n, select(0.0, 2.0 * half / n, half > 0.0));
}

// The band at distance `d` from `sizing`'s origin: the distance band (none under an
// orthographic probe), raised until a pixel is at least the probe texel there.
fn terrain_band(t: Terrain, d: f32, sizing: BandFrom) -> u32 {
    var texel = 2.0 * d / sizing.n;
    var b = terrain_distance_band(t, d);
    if sizing.ortho_texel > 0.0 {
        texel = sizing.ortho_texel;
        b = 0u;
    }
    for (var k = 0u; k < 30u; k++) {
        if exp2(f32(b)) / t.pixel_density >= texel {
            break;
        }
        b += 1u;
    }
    return b;
}

// Where a band's distances end (band 0: band_distance; band b: band_distance · 2^b).
fn terrain_band_end(t: Terrain, b: u32) -> f32 {
    return t.band_distance * exp2(f32(b));
}

// The world point at the centre of cell `cell` of size `s` (on the surface).
fn terrain_cell_point(t: Terrain, cell: vec2<f32>, s: f32) -> vec3<f32> {
    let q = (cell + 0.5) * s;
    return vec3(t.corner.x + q.x, t.corner.y + terrain_height(t, q), t.corner.z + q.y);
}

// The gradient's colour at normalised elevation `e` (linear between stops, clamped).
fn terrain_gradient(t: Terrain, e: f32) -> vec3<f32> {
    var colour = vec3(
        terrain_data[t.gradient_at + 1u],
        terrain_data[t.gradient_at + 2u],
        terrain_data[t.gradient_at + 3u],
    );
    var prev_at = terrain_data[t.gradient_at];
    for (var i = 1u; i < t.gradient_len; i++) {
        let k = t.gradient_at + 4u * i;
        let at = terrain_data[k];
        let c = vec3(terrain_data[k + 1u], terrain_data[k + 2u], terrain_data[k + 3u]);
        if e >= at {
            colour = c;
            prev_at = at;
            continue;
        }
        if e > prev_at {
            colour = mix(colour, c, (e - prev_at) / max(at - prev_at, 1e-6));
        }
        break;
    }
    return colour;
}

// One terrain pixel: its centre (relative to the corner, along X and Z) and edge length.
struct TerrainPixel {
    centre: vec2<f32>,
    size: f32,
}

// The cell of the band that holds world point `p`, before the Bayer promotion toward the
// band's end (`terrain_pixel`): its band, size and index, and its centre's distance.
struct BandCell {
    band: u32,
    size: f32,
    cell: vec2<f32>,
    d: f32,
}

fn terrain_band_cell(t: Terrain, p: vec3<f32>, sizing: BandFrom) -> BandCell {
    let origin = sizing.origin;
    let q = p.xz - t.corner.xz;
    // The finest band whose own cell containing p is far enough to belong to it.
    var b = 0u;
    var s = 1.0 / t.pixel_density;
    var cell = floor(q / s);
    var d = distance(terrain_cell_point(t, cell, s), origin);
    for (var k = 0u; k < 30u; k++) {
        if terrain_band(t, d, sizing) <= b {
            break;
        }
        b += 1u;
        s = exp2(f32(b)) / t.pixel_density;
        cell = floor(q / s);
        d = distance(terrain_cell_point(t, cell, s), origin);
    }
    return BandCell(b, s, cell, d);
}

// The terrain pixel of `t` holding world point `p`, sized for `sizing`.
fn terrain_pixel(t: Terrain, p: vec3<f32>, sizing: BandFrom) -> TerrainPixel {
    return promoted_pixel(t, terrain_band_cell(t, p, sizing), sizing);
}

// The pixel that holds band cell `c`: the cell itself or, toward its band's far end, for a
// Bayer share of the cells, the next band's pixel around it. The band ends where its
// distances do or where the probe's texel (2d/n) outgrows its pixel, whichever is nearer:
// the texel's bound is a band change like the distance's.
fn promoted_pixel(t: Terrain, c: BandCell, sizing: BandFrom) -> TerrainPixel {
    var s = c.size;
    var cell = c.cell;
    let end = min(terrain_band_end(t, c.band), 0.5 * sizing.n * s);
    let start = select(end * 0.5, 0.0, c.band == 0u);
    let width = select(t.band_transition * (end - start), 0.0, sizing.ortho_texel > 0.0);
    if width > 0.0 {
        let ramp = clamp((c.d - (end - width)) / width, 0.0, 1.0);
        let i = vec2<i32>(cell);
        if ramp > bayer_threshold(vec2<u32>(i & vec2(0x3fffffff))) {
            s = 2.0 * s;
            cell = floor(0.5 * cell);
        }
    }
    return TerrainPixel((cell + 0.5) * s, s);
}

// A terrain pixel's colour: the gradient at its centre's height, perturbed by the
// displacement texture at its centre; then the paint layer's pixel that holds the centre
// (pixel i of w covers i/w..(i+1)/w of the extent), blended over it by its alpha in linear
// light.
fn terrain_pixel_colour(t: Terrain, px: TerrainPixel) -> vec3<f32> {
    var e = terrain_height(t, px.centre) / t.max_height;
    if t.displacement != NO_TEXTURE {
        let info = tex_infos[t.displacement];
        let disp = tex_level(info, 0u, (px.centre + t.corner.xz) / t.tile_size).r;
        e += (disp - 0.5) * t.strength;
    }
    let colour = terrain_gradient(t, clamp(e, 0.0, 1.0));
    if t.paint == NO_TEXTURE {
        return colour;
    }
    let paint = tex_level(tex_infos[t.paint], 0u, px.centre / t.size);
    return mix(colour, paint.rgb, paint.a);
}

// The colour of terrain `t` at world point `p` (see `terrain_pixel`).
fn terrain_colour(t: Terrain, p: vec3<f32>, sizing: BandFrom) -> vec3<f32> {
    return terrain_pixel_colour(t, terrain_pixel(t, p, sizing));
}
