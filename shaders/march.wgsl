// March: texel marching, the paper's alternative display. Per pixel, the view ray is walked
// through a stable probe's cube faces texel by texel, across seams (on a face the ray's
// projection is a straight line, so the next texel is the nearer of two boundary crossings);
// the first texel whose surface the ray reaches gives the pixel its lit colour and texel key.
// Where the probe cannot say what the ray hits (the ray passes behind a surface the probe
// sees), the pixel falls back to the other stable probe, then the eye probe, then the sky.
// crates/render/src/passes/march.rs.
//
// A texel's surface is what its splat quad would be: the plane at the texel's Chebyshev depth
// across the texel's frustum, so marching and splatting show the same geometry.

#include "lib/common.wgsl"
#include "lib/view.wgsl"
#include "lib/fullscreen.wgsl"
#include "lib/slots.wgsl"
#include "lib/march.wgsl"

@group(0) @binding(0) var<uniform> view: ViewGlobals;
// [0] texels crossed, [1] pixels that fell back past their first probe.
@group(0) @binding(1) var<storage, read_write> counters: array<atomic<u32>, 2>;

// Texels one probe's march may cross before it gives up (the pixel falls back).
const MAX_STEPS: u32 = 512u;
// How far, in texels at its depth, a ray may pass behind a texel's surface and still hit it:
// the reach of a splat quad toward a dissimilar neighbour, so marching closes the same gaps.
const REACH_TEXELS: f32 = 1.5;

// The ray parameter where the face coordinate along `axis_uv` (a face's u or v vector)
// reaches `b`, for the ray `q0 + t rd` from the probe origin seen on the face of `axis`; the
// projection of a line is a line, so each texel boundary is crossed at most once.
fn crossing(q0: vec3<f32>, rd: vec3<f32>, axis: vec3<f32>, axis_uv: vec3<f32>, b: f32) -> f32 {
    let den = dot(rd, axis_uv) - b * dot(rd, axis);
    if abs(den) < 1e-12 {
        return 3.0e38;
    }
    return (b * dot(q0, axis) - dot(q0, axis_uv)) / den;
}

// `march` through an orthographic slot's one face (lib/common.wgsl `ProbeFrame`): in the
// face's frame the ray is a straight line in (u, v, depth), so the next texel is again the
// nearer of two boundary crossings; along the view's own direction the ray stays in one
// texel and meets its plane there. Off the face, the probe cannot say (the eye can).
fn march_ortho(s: u32, ro: vec3<f32>, rd: vec3<f32>, t0: f32, t1: f32) -> March {
    let v = view.slots[s];
    let f = slot_frame(v);
    let texel = 2.0 * f.half / f32(v.n);
    // Face coordinates in texels from the face's corner, and depth, at t = 0 and per unit t.
    let q0 = ro - f.origin;
    let a0 = vec3(dot(q0, f.right) + f.half, dot(q0, f.down) + f.half, dot(q0, f.forward));
    let da = vec3(dot(rd, f.right), dot(rd, f.down), dot(rd, f.forward));
    var out = March(STATUS_ESCAPED, 0u, 0u, vec2(0u), t1);
    var t = t0;
    var prev_d = -1.0;
    for (var i = 0u; i < MAX_STEPS; i++) {
        out.steps = i + 1u;
        let a = a0 + da * t;
        let cell = floor(a.xy / texel);
        if any(cell < vec2(0.0)) || any(cell >= vec2(f32(v.n))) {
            out.status = STATUS_UNKNOWN;
            return out;
        }
        let tx = vec2<u32>(cell);
        var t_out = t1;
        if da.x != 0.0 {
            let b = select(cell.x, cell.x + 1.0, da.x > 0.0) * texel;
            t_out = exit_before(t_out, (b - a0.x) / da.x, t);
        }
        if da.y != 0.0 {
            let b = select(cell.y, cell.y + 1.0, da.y > 0.0) * texel;
            t_out = exit_before(t_out, (b - a0.y) / da.y, t);
        }
        var d = -1.0;
        var verdict = Verdict(STATUS_ESCAPED, t_out);
        if (v.draw_mask & 1u) != 0u && load_id(s, tx, 0u) != 0u {
            d = load_geo(s, tx, 0u).w;
            let same = prev_d > 0.0 && frame_same_surface(f, prev_d, d, v.n);
            let tc = (d - a0.z) / da.z;
            verdict = texel_verdict(a.z, d, same, REACH_TEXELS * texel, t, tc, da.z, t_out);
        }
        if march_step(&out, &t, &prev_d, verdict, 0u, tx, d, t_out, t1) {
            return out;
        }
    }
    out.status = STATUS_UNKNOWN;
    return out;
}

// Marches the ray `ro + t rd` (|rd| = 1), t in [t0, t1], through stable slot `s`, one texel
// at a time (across face seams): in each texel the ray meets the texel's plane, or not.
fn march(s: u32, ro: vec3<f32>, rd: vec3<f32>, t0: f32, t1: f32) -> March {
    let v = view.slots[s];
    if v.half > 0.0 {
        return march_ortho(s, ro, rd, t0, t1);
    }
    let q0 = ro - v.origin;
    let step = 2.0 / f32(v.n);
    var out = March(STATUS_ESCAPED, 0u, 0u, vec2(0u), t1);
    var t = t0;
    // Depth of the texel the ray crossed last (-1: sky or a face the probe lacks).
    var prev_d = -1.0;
    for (var i = 0u; i < MAX_STEPS; i++) {
        out.steps = i + 1u;
        let q = q0 + rd * t;
        let fu = cube_face_uv(q);
        let axis = cube_dir(fu.face, 0.0, 0.0);
        let au = cube_dir(fu.face, 1.0, 0.0) - axis;
        let av = cube_dir(fu.face, 0.0, 1.0) - axis;
        let tx = texel_of_uv(fu.uv, v.n);
        // Where the ray leaves this texel: the first boundary it crosses in u or in v.
        let lo = vec2<f32>(tx) * step - 1.0;
        let qa = dot(q, axis);
        let du = dot(rd, au) * qa - dot(q, au) * dot(rd, axis);
        let dv = dot(rd, av) * qa - dot(q, av) * dot(rd, axis);
        var t_out = t1;
        if du != 0.0 {
            let tu = crossing(q0, rd, axis, au, select(lo.x, lo.x + step, du > 0.0));
            t_out = exit_before(t_out, tu, t);
        }
        if dv != 0.0 {
            let tv = crossing(q0, rd, axis, av, select(lo.y, lo.y + step, dv > 0.0));
            t_out = exit_before(t_out, tv, t);
        }
        var d = -1.0;
        var verdict = Verdict(STATUS_ESCAPED, t_out);
        if (v.draw_mask & (1u << fu.face)) != 0u && load_id(s, tx, fu.face) != 0u {
            d = load_geo(s, tx, fu.face).w;
            let same = prev_d > 0.0 && same_surface(prev_d, d, v.n);
            let reach = REACH_TEXELS * texel_world_size(d, v.n, q / qa);
            let along = dot(rd, axis);
            let tc = (d - dot(q0, axis)) / along;
            verdict = texel_verdict(qa, d, same, reach, t, tc, along, t_out);
        }
        if march_step(&out, &t, &prev_d, verdict, fu.face, tx, d, t_out, t1) {
            return out;
        }
    }
    out.status = STATUS_UNKNOWN;
    return out;
}

@vertex
fn vs(@builtin(vertex_index) vi: u32) -> FullscreenOut {
    return fullscreen(vi, NDC_FAR);
}

struct FsOut {
    @location(0) colour: vec4<f32>,
    @location(1) key: u32,
    @builtin(frag_depth) depth: f32,
}

// The pixel's colour, key and depth from texel `tx` of `face` of slot `s`, hit at `p`.
fn shown(s: u32, face: u32, tx: vec2<u32>, p: vec3<f32>) -> FsOut {
    let colour = hazed(lit_with_shift(load_lit(s, tx, face).rgb, view.bands), length(p - view.camera.xyz));
    let clip = view.view_proj * vec4(p, 1.0);
    let key = texel_key(s, face, tx, view.max_n) + 1u;
    return FsOut(vec4(linear_to_srgb(colour), 1.0), key, clamp(clip.z / clip.w, 0.0, 1.0));
}

@fragment
fn fs(in: FullscreenOut) -> FsOut {
    let near = view.inv_view_proj * vec4(in.ndc, NDC_NEAR, 1.0);
    let far = view.inv_view_proj * vec4(in.ndc, NDC_FAR, 1.0);
    let ro = near.xyz / near.w;
    let span = far.xyz / far.w - ro;
    let t1 = length(span);
    let rd = span / t1;

    // The stable probes in the order this pixel asks them: during a crossfade the Bayer
    // pattern hands the pixel to the grid or the previous probe (as the splats' dither does).
    var order = array<u32, 2>(4u, 4u);
    var count = 0u;
    var grid = 4u;
    var previous = 4u;
    for (var s = 0u; s < 3u; s++) {
        let role = view.slots[s].role;
        if role == ROLE_GRID { grid = s; }
        if role == ROLE_PREVIOUS { previous = s; }
    }
    let grid_first = previous == 4u
        || bayer_threshold(vec2<u32>(in.clip.xy)) < view.fade_t;
    if grid_first {
        order[0] = grid;
        order[1] = previous;
    } else {
        order[0] = previous;
        order[1] = grid;
    }

    var steps = 0u;
    var fell_back = false;
    var result = FsOut(vec4(0.0), 0u, NDC_FAR);
    var found = false;
    for (var k = 0u; k < 2u && !found; k++) {
        let s = order[k];
        if s > 2u || view.slots[s].draw_mask == 0u {
            continue;
        }
        let m = march(s, ro, rd, 0.0, t1);
        steps += m.steps;
        if m.status == STATUS_HIT {
            result = shown(s, m.face, m.texel, ro + rd * m.t);
            found = true;
        } else if m.status == STATUS_ESCAPED {
            // Nothing along the ray as far as the probe sees: the sky (or the eye's view).
            break;
        } else {
            fell_back = true;
        }
    }
    atomicAdd(&counters[0], steps);
    if fell_back {
        atomicAdd(&counters[1], 1u);
    }
    if found {
        return result;
    }
    // The eye probe sits at the camera (or in its plane): its texel under the pixel is exact.
    let e = eye_ray(in.ndc);
    let eye = view.slots[view.eye_slot];
    if e.face > 5u || (eye.draw_mask & (1u << e.face)) == 0u {
        return FsOut(vec4(linear_to_srgb(view.sky.rgb), 1.0), 0u, NDC_FAR);
    }
    let tx = texel_of_uv(e.uv, eye.n);
    if load_id(view.eye_slot, tx, e.face) == 0u {
        return FsOut(vec4(linear_to_srgb(load_lit(view.eye_slot, tx, e.face).rgb), 1.0), 0u, NDC_FAR);
    }
    let p = eye_point(e, load_geo(view.eye_slot, tx, e.face).w);
    if !within_view_depth(view.view_proj * vec4(p, 1.0)) {
        return FsOut(vec4(linear_to_srgb(sky_texel(view.sky.rgb, view.bands)), 1.0), 0u, NDC_FAR);
    }
    return shown(view.eye_slot, e.face, tx, p);
}
