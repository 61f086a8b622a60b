//! What a frame cost and how much work it did.

use serde::Serialize;

/// Deterministic work counts of one frame.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct Counters {
    /// Cube faces rasterized (capture pass).
    pub faces_captured: u32,
    /// Objects and terrain chunks the captures drew, summed over the faces (each face draws
    /// those its frustum meets that span a texel: `gpu_scene::spans_a_texel`).
    pub objects_captured: u64,
    /// Their triangles, summed over the faces.
    pub triangles_captured: u64,
    /// Of `faces_captured`, the eye probe's (captured every frame).
    pub eye_faces_captured: u32,
    /// The eye's far faces captured (`texel_render::far_field`; what they draw is counted in
    /// `objects_captured` and `triangles_captured`, not in the eye's).
    pub far_faces_captured: u32,
    /// Of `objects_captured`, those the eye's faces drew (each frame; their far faces aside).
    pub eye_objects_captured: u64,
    /// Of `triangles_captured`, those the eye's faces drew.
    pub eye_triangles_captured: u64,
    /// Objects and terrain chunks the stable faces captured in part left out, lying behind
    /// what the faces held (`texel_render::passes::occlusion`; not in `objects_captured`).
    pub objects_occluded: u64,
    /// Texels lit by the shade pass.
    pub texels_shaded: u64,
    /// Of `texels_shaded`, the eye probe's (those no stable probe shows, and silhouettes).
    pub eye_texels_shaded: u64,
    /// Quads drawn by the splat pass.
    pub quads_splatted: u64,
    /// Texels and run heads the cull pass looked at to find them (every texel of a face it
    /// scans; each entry of a listed face's draw list: a run head of a stable face, an eye
    /// texel lit this frame). Its dispatch costs about this many invocations, drawn or not.
    pub cull_entries: u64,
    /// Distinct probe texels that colour at least one pixel of the final frame.
    pub screen_visible_texels: u64,
    /// Pixels whose view ray was marched (texel marching; 0 when splatting).
    pub pixels_marched: u64,
    /// Steps taken by those marches, over every pixel and probe.
    pub march_steps: u64,
    /// Marched pixels the first probe they asked could not resolve (they fell back to the
    /// other stable probe, the eye probe or the sky).
    pub march_fallbacks: u64,
    /// GPU bytes of the scene (vertices, records, lights, terrain heights).
    pub gpu_scene_bytes: u64,
    /// GPU bytes of the shadow-ray trees.
    pub gpu_bvh_bytes: u64,
    /// GPU bytes of the probe slots' faces and draw lists, and of the eye's far faces.
    pub gpu_probe_bytes: u64,
    /// GPU memory of the scene's texture atlas and sprite sheets, bytes (0 without them).
    pub texture_bytes: u64,
    /// Terrain quads whose record the terrain splats pass made (in its cache neither by
    /// texel nor by block).
    pub terrain_records_made: u64,
    /// Terrain pixels whose shadow rays the terrain splats pass cast.
    pub terrain_pixels_cast: u64,
    /// Terrain quads whose record was not kept for their texel but was found on their block
    /// (made by another probe's or texel's quad).
    pub terrain_records_shared: u64,
}

/// Time of one pass, in milliseconds.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PassTime {
    /// Pass name (`capture`, `shade`, `cull`, `splat`, …).
    pub pass: &'static str,
    /// Milliseconds.
    pub ms: f64,
}

/// Cost and work of one frame.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct FrameStats {
    /// Per-pass times, in pass order.
    pub passes: Vec<PassTime>,
    /// Whether `passes` are GPU timestamps (true) or CPU wall times around each pass.
    pub gpu_timestamps: bool,
    /// Wall time of the whole frame on the CPU, including waiting for the GPU, ms.
    pub frame_ms: f64,
    /// Work counts.
    pub counters: Counters,
}

impl FrameStats {
    /// Milliseconds of `pass`, or 0.
    pub fn pass_ms(&self, pass: &str) -> f64 {
        self.passes
            .iter()
            .filter(|p| p.pass == pass)
            .map(|p| p.ms)
            .sum()
    }
}
