// The march's step, shared by march.wgsl's two walks (through a cube probe's faces and
// through an orthographic slot's one face): what a texel tells the ray (`texel_verdict`),
// where the ray leaves the texel (`exit_before`), and the step to the next texel or the
// march's end (`march_step`).

const STATUS_HIT: u32 = 0u;
const STATUS_ESCAPED: u32 = 1u;
const STATUS_UNKNOWN: u32 = 2u;

// What a march found: its status, the texels it crossed, and the texel (face, texel) and
// ray parameter of its hit.
struct March {
    status: u32,
    steps: u32,
    face: u32,
    texel: vec2<u32>,
    t: f32,
}

// What the ray learns in a texel of depth `d`, entered at depth `entry` (ray parameter `t`)
// and left at `t_out`, reaching depth `d` at `tc` when `along` > 0 (it goes deeper). Entered
// in behind the surface through the texel's side: from a texel of the same surface (`same`:
// a floor seen at a grazing angle steps in depth from row to row) the ray crossed it; else
// within `reach` the texel's quad still covers it; beyond, the probe cannot see what the
// ray hits. STATUS_ESCAPED: nothing here, on to the next texel.
struct Verdict {
    status: u32,
    t: f32,
}

fn texel_verdict(entry: f32, d: f32, same: bool, reach: f32, t: f32, tc: f32, along: f32, t_out: f32) -> Verdict {
    if entry >= d {
        return Verdict(select(STATUS_UNKNOWN, STATUS_HIT, same || entry - d <= reach), t);
    }
    if along > 0.0 && tc <= t_out {
        return Verdict(STATUS_HIT, tc);
    }
    return Verdict(STATUS_ESCAPED, t_out);
}

// The ray's exit from its texel, `t_out` so far, lowered to a boundary it crosses at
// `crossing` after `t`.
fn exit_before(t_out: f32, crossing: f32, t: f32) -> f32 {
    if crossing > t {
        return min(t_out, crossing);
    }
    return t_out;
}

// Ends the march in texel `tx` of `face` when the ray hit it or cannot see past it
// (`verdict`), or at `t1`; else steps just past the texel's exit `t_out` into the next
// texel, remembering the depth `d` it crossed last. Whether the march ended.
fn march_step(out: ptr<function, March>, t: ptr<function, f32>, prev_d: ptr<function, f32>, verdict: Verdict, face: u32, tx: vec2<u32>, d: f32, t_out: f32, t1: f32) -> bool {
    if verdict.status != STATUS_ESCAPED {
        (*out).status = verdict.status;
        (*out).face = face;
        (*out).texel = tx;
        (*out).t = verdict.t;
        return true;
    }
    if t_out >= t1 {
        return true;
    }
    *prev_d = d;
    // Just past the boundary, into the next texel.
    *t = t_out + max(1e-5 * t_out, 1e-6);
    return false;
}
