// The shade pass's shadow and edge rays (`trace_rays` in shade.wgsl casts them): the
// silhouette edges' search, one ray at a time, and where its rays walk the still
// instances. The includer declares what these read: `sf` (its `ShadeFace`), `Texel`,
// `probe_ray`, `toward_ray`, `plane_depth` and `edge_reach` (shade.wgsl), and the BVH's
// bindings (lib/bvh.wgsl).

// A shadow or edge ray: from `origin` along `dir`, up to `t_max`.
struct CastRay {
    origin: vec3<f32>,
    dir: vec3<f32>,
    t_max: f32,
}

// The silhouette edges' search as `trace_rays` walks it: the sides left to search (bit k:
// side k), the one searched now, its bisection's interval and far limit, the corners left
// (bit j: side j's corner with `ky`), and the edges found so far (`SIMILAR_EDGE_AT`).
struct EdgeSearch {
    left: u32,
    k: u32,
    lo: f32,
    hi: f32,
    reach: f32,
    corners_left: u32,
    edges: u32,
}

// A ray three quarters of the way from the centre of `x` to the corner where the edges of
// the search's next corner side and of side `ky` meet: a slanting edge through the two
// edges' crossings passes nearer the centre (at half the way), a box's corner lies at the
// corner. Starts `skip` along the way (`trace_rays`).
fn corner_ray(e: ptr<function, EdgeSearch>, x: Texel, similar: u32, ky: u32, skip: f32) -> CastRay {
    (*e).k = firstTrailingBit((*e).corners_left);
    (*e).corners_left &= (*e).corners_left - 1u;
    let k = (*e).k;
    let at = vec2(side_edge((*e).edges, k), side_edge((*e).edges, ky));
    let toward = vec2(f32(NEIGHBOURS[k].x), f32(NEIGHBOURS[ky].y));
    let cr = probe_ray(x.fr, x.uv + toward * at * (1.5 / f32(sf.n)));
    let dir = cr.dir;
    let t_max = min(edge_reach(x.t, x.d, similar, k), edge_reach(x.t, x.d, similar, ky)) - skip;
    return CastRay(cr.start + dir * skip, dir, t_max);
}

// Step `step` of the bisection on the search's side (the next side at step 0): the ray
// through the middle of its interval, up to its far limit, or for a hidden side up to the
// plane, short of the surface itself where it is in the BVH (`offset`).
fn side_ray(e: ptr<function, EdgeSearch>, x: Texel, similar: u32, hidden: u32, step: u32, skip: f32, offset: f32) -> CastRay {
    if step == 0u {
        (*e).k = firstTrailingBit((*e).left);
        (*e).left &= (*e).left - 1u;
        (*e).lo = 0.0;
        (*e).hi = 1.0;
        (*e).reach = edge_reach(x.t, x.d, similar, (*e).k);
    }
    let k = (*e).k;
    let er = toward_ray(x.fr, x.uv, k, 0.5 * ((*e).lo + (*e).hi));
    let dir = er.dir;
    var t_max = (*e).reach - skip;
    if ((hidden >> k) & 1u) != 0u {
        t_max = plane_depth(x.me.geo.xyz, x.p, er) - skip - offset / length(dir);
    }
    return CastRay(er.start + dir * skip, dir, t_max);
}

// Narrows the search's side by one step's `hit`: on this side the ray meets this surface (a
// silhouette) or nothing before its plane (a hidden side); the last step stores the edge.
fn settle_side(e: ptr<function, EdgeSearch>, hit: bool, hidden: u32, step: u32) {
    let k = (*e).k;
    if hit != (((hidden >> k) & 1u) != 0u) {
        (*e).lo = 0.5 * ((*e).lo + (*e).hi);
    } else {
        (*e).hi = 0.5 * ((*e).lo + (*e).hi);
    }
    if step == EDGE_STEPS - 1u {
        let at = SIMILAR_EDGE_AT + 3u * k;
        let c = u32(clamp(round(4.0 * ((*e).lo + (*e).hi)), 1.0, 8.0));
        (*e).edges = ((*e).edges & ~(7u << at)) | ((c - 1u) << at);
    }
}

// Where the edge rays of `x` (`corner_ray`, `side_ray`; the searched sides `seek`, those a
// neighbour hides `hidden`) walk the still instances' top level (`bvh_statics_within`):
// below its root where one subtree holds all they may meet. Every one runs through face
// coordinates within two texels' widths of the texel's (a side ray's toward its
// neighbour's centre, short of it; a corner ray's 1.5 widths out at most), from `skip` (half
// the texel's depth) to at most its side's reach, or for a hidden side to the plane, whose
// depth along those rays lies between its depths along the texel's ray and the
// neighbour's (one over a linear function of the way, or linear); so within the box of the
// 8 points at those depths on the rays through the square's corners (the rays' points are
// linear in the face coordinates), grown far beyond the rounding of the rays and the box
// tests. A plane that some of those rays meet from behind bounds nothing: the whole level.
fn edge_statics(x: Texel, similar: u32, seek: u32, hidden: u32, skip: f32) -> u32 {
    let n = x.me.geo.xyz;
    var far = skip;
    for (var k = 0u; k < 4u; k++) {
        if ((seek >> k) & 1u) == 0u {
            continue;
        }
        if ((hidden >> k) & 1u) == 0u {
            far = max(far, edge_reach(x.t, x.d, similar, k));
            continue;
        }
        let own = toward_ray(x.fr, x.uv, k, 0.0);
        let next = toward_ray(x.fr, x.uv, k, 1.0);
        if !(dot(n, own.dir) < 0.0 && dot(n, next.dir) < 0.0) {
            return BVH_STATICS_ALL;
        }
        far = max(far, max(plane_depth(n, x.p, own), plane_depth(n, x.p, next)));
    }
    var lo = vec3(3.0e38);
    var hi = vec3(-3.0e38);
    let w = 2.0 / f32(sf.n);
    for (var c = 0u; c < 4u; c++) {
        let corner = vec2(f32(c & 1u), f32(c >> 1u)) * 2.0 - 1.0;
        let r = probe_ray(x.fr, x.uv + corner * w);
        let a = r.start + r.dir * skip;
        let b = r.start + r.dir * far;
        lo = min(lo, min(a, b));
        hi = max(hi, max(a, b));
    }
    let size = max(max(abs(lo), abs(hi)), abs(x.fr.origin));
    let pad = 1.0e-4 * (1.0 + max(max(size.x, size.y), size.z));
    return bvh_statics_within(lo - pad, hi + pad);
}
