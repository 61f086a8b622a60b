//! The crossfade between a cell's probes: ours, shorter and spread over more frames than
//! the reference's, which the paper schedule keeps.

use texel_probes::probe_set::FadeConfig;
use texel_render::input::Schedule;

/// Our crossfade at rest lasts a quarter second; the paper's schedule keeps the reference's
/// half second ([`FadeConfig::default`]). While a fade runs, each stable probe fills behind
/// the other's pixels (`shaders/splat.wgsl` `FadeFsOut`), so a short fade opens no holes; what
/// a fade costs is its screen-fixed dither sliding over the moving scene, which a shorter
/// fade shows for fewer frames (`texel-eval run --methods splat` on walk_cells: 0.5 s 0.0049,
/// 0.25 s 0.0046, 0.15 s 0.0040 mean shimmer, but worst frames grow below a quarter second).
pub const OUR_FADE_SECONDS: f32 = 0.25;

/// A fast camera's fade of ours is paced to end within half a cell of travel (the
/// reference's within one; the frames a fade waits for its grid's captures and the
/// per-frame cap below lengthen both). At the reference's pace a sprint's fades had reached
/// only 0.77–0.97 when the next crossing came (`texel-run render` on sprint_cells, stats.json
/// `fade_t`): each crossing waited, the camera left both stable probes' views behind, and
/// the eye probe filled 4.7% of the pixels; at ours each fade ends as the next begins.
/// Measured with `texel-eval run --methods splat --face-res 128 --size 320x180` on
/// stone_circle: sprint_cells 0.0134 -> 0.0107 mean shimmer (worst frame 0.084 -> 0.046,
/// eye pixels 4.7% -> 1.7%), walk_cells 0.0047 -> 0.0042; the other crossing paths within
/// ±0.0003 but textured_walk (0.0190 -> 0.0171).
pub const OUR_FADE_CELLS: f32 = 0.5;

/// No frame of our fades hands more than a third of the pixels from one probe to the other
/// (the reference's half): a fast fade then spreads a crossing's change over three frames
/// instead of two, which lowers the worst frame, and a sprint's fade still ends before the
/// next crossing. Measured as above: sprint_cells 0.0107 -> 0.0103 (worst frame 0.046 -> 0.029),
/// iso_orbit 0.0035 -> 0.0032, terrain_descent 0.0090 -> 0.0082, terrain_walk 0.0137 ->
/// 0.0131; the other crossing paths unchanged.
pub const OUR_MIN_FADE_FRAMES: u32 = 3;

/// The crossfade of `schedule`: ours, or the reference's.
pub(super) fn fade_config(schedule: Schedule) -> FadeConfig {
    match schedule {
        Schedule::Ours => FadeConfig {
            fade_seconds: OUR_FADE_SECONDS,
            fade_cells: OUR_FADE_CELLS,
            min_frames: OUR_MIN_FADE_FRAMES,
            ..FadeConfig::default()
        },
        Schedule::Paper => FadeConfig::default(),
    }
}
