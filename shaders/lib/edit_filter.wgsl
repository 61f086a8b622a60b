// The shade pass's filter after a scene edit (`ShadeFace`'s `keep` and boxes;
// crates/render/src/input.rs `LightFilter`): which texels of a job the edit may have changed.
// Included by shade.wgsl only, which declares `sf`, `load`, `face_frame`, `near_points` and
// `near_light`, and includes lib/lights.wgsl.

// Whether an edit may have changed texel `t` (always, without an edit's filter): it lies
// in `keep`, or its surface stayed and its light or its silhouette edges' rays may have
// changed (see `ShadeFace`).
fn edit_wants(t: vec2<u32>) -> bool {
    if sf.boxes == 0u || (all(t >= sf.keep_min) && all(t < sf.keep_max)) {
        return true;
    }
    let me = load(sf.face, t);
    if me.id == 0u {
        return false;
    }
    let n = sf.n;
    let uv = texel_center_uv(t, n);
    let fr = face_frame();
    let ray = frame_ray(fr, sf.face, uv);
    let p = frame_point(fr, sf.face, uv, me.geo.w);
    // The shadow rays start a little off the surface along its normal (`trace_rays`), in
    // the same directions: boxes grown past that offset meet every ray that meets them.
    let grow = 2.0 * max(SHADOW_OFFSET, 0.1 * frame_texel_size(fr, me.geo.w, n, ray));
    let near = near_points(p);
    let lights = globals.sun_count + near.y;
    for (var b = 0u; b + 1u < sf.boxes; b++) {
        let lo = sf.box_corners[2u * b].xyz - vec3(grow);
        let hi = sf.box_corners[2u * b + 1u].xyz + vec3(grow);
        if ((sf.lit_mask >> b) & 1u) != 0u {
            if all(p >= lo) && all(p <= hi) {
                return true;
            }
            continue;
        }
        // The silhouette edges' rays run from halfway to the surface to at most four times
        // its depth (`edge_reach`), within a texel of the texel's own ray: a box near them
        // changes them too. Tested as three lengths of that ray, each with the box grown by
        // two texels at its far end.
        let start = frame_ray_start(fr, uv);
        let seen = length(p - start);
        if seen > 0.0 {
            let dir = (p - start) / seen;
            for (var k = 0u; k < 3u; k++) {
                let t0 = 0.5 * f32(1u << k);
                let wide = vec3(2.0 * frame_texel_size(fr, 2.0 * t0 * me.geo.w, n, ray));
                if segment_meets_box(start + dir * (t0 * seen), dir, t0 * seen, lo - wide, hi + wide) {
                    return true;
                }
            }
        }
        for (var i = 0u; i < lights; i++) {
            let r = light_ray(near_light(near, i), p);
            if r.reach > 0.0 && segment_meets_box(p, r.dir, light_reach(r, 0.0), lo, hi) {
                return true;
            }
        }
    }
    return false;
}

// Whether the segment from `o` along unit `dir` for `len` meets the box `lo..hi`.
fn segment_meets_box(o: vec3<f32>, dir: vec3<f32>, len: f32, lo: vec3<f32>, hi: vec3<f32>) -> bool {
    let inv = 1.0 / select(dir, vec3(1.0e-12), abs(dir) < vec3(1.0e-12));
    let a = (lo - o) * inv;
    let b = (hi - o) * inv;
    let t0 = max(max(min(a.x, b.x), min(a.y, b.y)), min(a.z, b.z));
    let t1 = min(min(max(a.x, b.x), max(a.y, b.y)), max(a.z, b.z));
    return t1 >= max(t0, 0.0) && t0 <= len;
}
