// Scene rasterization shared by the probe capture (capture.wgsl) and the baselines' G-buffer
// (gbuffer.wgsl): the vertex layout of `GpuScene::vertices`, what the vertex stage passes on,
// and the surface albedo. The includer includes lib/common.wgsl (for `Object`) and
// lib/texture.wgsl.

struct SceneVertex {
    @location(0) position: vec3<f32>,
    @location(1) object: u32,
    @location(2) normal: vec3<f32>,
    // Vertex colour, RGBA8.
    @location(3) colour: u32,
    @location(4) uv: vec2<f32>,
    // Index into `surfaces` (0: untextured).
    @location(5) surface: u32,
    // World-space gradients of the triangle's U and V (the same on its three vertices).
    @location(6) grad_u: vec3<f32>,
    @location(7) grad_v: vec3<f32>,
}

// The instance record a draw places its vertices with (`GpuScene::instances`,
// crates/render/src/gpu_scene.rs `GpuInstance`): record 0 is the identity for vertices
// written in world space (object 0xffffffff: the vertex names its object); a shared mesh's
// object-space vertices are placed by their object's similarity.
struct SceneInstance {
    @location(8) m0: vec4<f32>,
    @location(9) m1: vec4<f32>,
    @location(10) m2: vec4<f32>,
    @location(11) m3: vec4<f32>,
    @location(12) object: u32,
}

// `v` placed by instance `i` in world space. A similarity's linear part L carries normals
// (up to length, which the fragment normalizes) and, divided by its squared scale, the UV
// gradients (covectors: L^-T = L / s^2). The identity record leaves the vertex untouched.
fn instance_vertex(v: SceneVertex, i: SceneInstance) -> SceneVertex {
    if i.object == 0xffffffffu {
        return v;
    }
    var w = v;
    let p = v.position;
    w.position = ((i.m0.xyz * p.x + i.m1.xyz * p.y) + i.m2.xyz * p.z) + i.m3.xyz;
    let l = mat3x3(i.m0.xyz, i.m1.xyz, i.m2.xyz);
    let n = l * v.normal;
    w.normal = select(vec3(0.0), normalize(n), dot(n, n) > 0.0);
    let s2 = dot(i.m0.xyz, i.m0.xyz);
    w.grad_u = (l * v.grad_u) / s2;
    w.grad_v = (l * v.grad_v) / s2;
    w.object = i.object;
    return w;
}

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) @interpolate(flat) object: u32,
    @location(3) colour: vec4<f32>,
    @location(4) uv: vec2<f32>,
    @location(5) @interpolate(flat) surface: u32,
    @location(6) @interpolate(flat) grad_u: vec3<f32>,
    @location(7) @interpolate(flat) grad_v: vec3<f32>,
}

fn raster_vertex(v: SceneVertex, view_proj: mat4x4<f32>) -> VsOut {
    var out: VsOut;
    out.clip = view_proj * vec4(v.position, 1.0);
    out.world = v.position;
    out.normal = v.normal;
    out.object = v.object;
    out.colour = unpack4x8unorm(v.colour);
    out.uv = v.uv;
    out.surface = v.surface;
    out.grad_u = v.grad_u;
    out.grad_v = v.grad_v;
    return out;
}

// The unit normal of the fragment's triangle plane: across its UV gradients when they span
// it, else the interpolated normal.
fn surface_plane_normal(in: VsOut) -> vec3<f32> {
    let c = cross(in.grad_u, in.grad_v);
    let l = length(c);
    if l > 1e-12 {
        return c / l;
    }
    return normalize(in.normal);
}

// Where the ray from `o` along `d` meets the plane through `p` with unit normal `n`; a ray
// parallel to the plane, or meeting it behind `o`, lands "far away" (a million units along
// `d`), so its footprint takes the coarsest mip.
fn plane_hit(p: vec3<f32>, n: vec3<f32>, o: vec3<f32>, d: vec3<f32>) -> vec3<f32> {
    let den = dot(d, n);
    let t = dot(p - o, n) / den;
    if abs(den) <= 1e-7 * length(d) || t <= 0.0 {
        return o + normalize(d) * 1.0e6;
    }
    return o + d * t;
}

// The texture coordinates of a fragment and their footprint, from the world-space steps
// `fx`, `fy` to the next texel (or pixel) along x and y on the surface: in a probe capture
// the steps are the probe texel's (the same wherever the camera is), in a G-buffer the
// screen pixel's. No screen derivatives: some rasterizers (lavapipe) give garbage in the
// helper lanes of quads that straddle a triangle edge, which drew a coarse mip, a seam, along
// every triangle edge.
fn surface_uv(in: VsOut, fx: vec3<f32>, fy: vec3<f32>) -> SurfaceUv {
    let s = surfaces[in.surface];
    let uv = in.uv * s.uv_scale;
    let dx = vec2(dot(in.grad_u, fx), dot(in.grad_v, fx)) * s.uv_scale;
    let dy = vec2(dot(in.grad_u, fy), dot(in.grad_v, fy)) * s.uv_scale;
    return SurfaceUv(uv, dx, dy);
}

// Albedo × vertex colour × texture colour (rgb) and the object flags (a, as flags / 255).
//
// The interpolated vertex colour is snapped back to the 8 bits it was stored in: even a
// constant colour does not interpolate exactly (the barycentrics sum to 1 within an ulp, and
// the error is the same along a cube face's raster row, where a floor's depth is), so
// without the snap the 8-bit albedo target rounds an albedo on a code midpoint — 0.5 × 255 =
// 127.5, as for every odd tenth — one way on some rows and the other way on the rest, and
// posterization can make that one code a whole band: long one-texel streaks (issue 17).
// Snapped, a surface of one colour stores one albedo wherever it is seen from.
fn surface_albedo(obj: Object, colour: vec4<f32>, texture: vec4<f32>) -> vec4<f32> {
    let c = round(colour.rgb * 255.0) / 255.0;
    return vec4(obj.albedo * c * texture.rgb, f32(obj.flags & 0xffu) / 255.0);
}

// The unit normal of a surface point, snapped to 1/65536 per component. The rasterizer
// interpolates a flat triangle's three equal normals with weights that sum to one only up to
// rounding, differently per pixel and per driver (SwiftShader's differs from lavapipe's), so
// a floor's texels got normals an ulp apart, and a lit colour on a posterization band's edge
// flipped between them. Snapped, a flat surface stores one normal wherever it is seen from.
fn surface_normal(n: vec3<f32>) -> vec3<f32> {
    return round(normalize(n) * 65536.0) / 65536.0;
}
