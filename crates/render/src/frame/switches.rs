//! The renderer's switches: what tests and measurements turn on or off to compare against
//! (runs, capture culling, the lights' grid), the debug views and the terrain splats' cache.

use super::Renderer;
use crate::passes::capture::CaptureMode;

impl Renderer {
    /// Whether the next scenes' point lights are gridded (on by default, off under
    /// `TEXEL_NO_LIGHT_GRID`): off, every texel tests every light (to compare against).
    pub fn set_light_grid(&mut self, on: bool) {
        self.light_grid = on;
    }

    /// Whether a texel's edge rays walk the still instances from a subtree that holds all
    /// they may meet (on by default, off under `TEXEL_NO_EDGE_ROOTS`): off, from the top
    /// level's root (the same frames, to compare against).
    pub fn set_edge_roots(&mut self, on: bool) {
        self.shade.edge_roots = on;
    }

    /// Caps the terrain splats' record cache at `slots` slots (at most
    /// [`crate::passes::terrain_splat::CACHE_SLOTS_MAX`]), so that a test's small faces share
    /// slots by hash as large faces' keys do; the next frame lays the cache out again, empty.
    pub fn set_terrain_cache_slots(&mut self, slots: u64) {
        self.terrain_splat.set_cache_slots_max(slots);
    }

    /// Forgets every terrain splat record and terrain pixel's shadow rays: the next frame
    /// makes and casts them all again (what a new scene does; tests compare the cache with
    /// it).
    pub fn forget_terrain_records(&mut self) {
        self.terrain_splat.forget();
    }

    /// Slots of the terrain splats' record cache as the last frame laid it out (0: none).
    pub fn terrain_cache_slots(&self) -> u64 {
        self.terrain_splat.cache_slots()
    }

    /// Whether our schedule draws each run of alike texels of a stable probe with one quad
    /// (on by default; off draws one quad per texel, for comparison).
    pub fn set_runs(&mut self, on: bool) {
        self.runs_on = on;
    }

    /// What captures leave out of each face ([`crate::gpu_scene::CaptureCull`]; by default
    /// what a face cannot see or spans less than a texel). Only faces captured from now on
    /// change.
    pub fn set_capture_cull(&mut self, cull: crate::gpu_scene::CaptureCull) {
        self.capture.cull = cull;
    }

    /// Whether a stable face captured again in part leaves out the objects lying behind what
    /// it already holds (on by default: the face comes out the same; off draws every
    /// object that may cover its rectangle, for comparison). See
    /// [`crate::passes::occlusion`].
    pub fn set_capture_occlusion(&mut self, on: bool) {
        self.capture.occlusion = on;
    }

    /// Whether an edit in place keeps the eye's far faces its objects do not reach (on by
    /// default; off forgets them all, as a new scene does, for comparison).
    pub fn set_edit_keeps_far_faces(&mut self, on: bool) {
        self.far_kept = on;
    }

    /// Whether captures store a texture-density colour instead of the albedo (a debug view:
    /// green where one texture pixel is one probe texel, blue where textures are magnified,
    /// red where minified, grey untextured). Only faces captured from now on change: start
    /// a fresh frame driver (`texel_runtime::session::Session::set_texture_density_view`).
    pub fn set_texture_density_view(&mut self, on: bool) {
        self.capture.mode = if on {
            CaptureMode::TextureDensity
        } else {
            CaptureMode::Surface
        };
    }

    /// What sprites turn toward: the probes (the default, world-locked inside a cell) or
    /// the camera (screen-space sprites, kept to compare against).
    pub fn set_sprite_facing(&mut self, facing: crate::input::SpriteFacing) {
        self.sprites.facing = facing;
    }
}
