//! The frame plan: turns a loaded level and a camera into what the renderer consumes (the
//! [`FrameDriver`] plans each frame).
//!
//! Once, at load (`extraction`): the hecs world becomes a [`SceneInput`](texel_render::input::SceneInput) (one object per entity with
//! geometry, its id the entity's position in the level + 1) and the level's probe-grid
//! settings. Per frame (`planning`): the camera is snapped to the grid ([`resolve_grid`](texel_probes::grid::resolve_grid)), the probe set
//! advances its crossfade ([`ProbeSet`](texel_probes::probe_set::ProbeSet)), the scheduler picks which faces to capture
//! ([`Scheduler`](texel_probes::schedule::Scheduler)), and all of it becomes a [`FrameInput`](texel_render::input::FrameInput).
//!
//! Two schedules share the probe logic. **Ours** captures what the scheduler plans: the eye
//! probe's visible faces every frame, a stable probe's faces only when they are missing (new
//! origin, newly visible), within a budget so a cell crossing is spread over frames. The
//! **paper** schedule, for comparison, re-captures and re-lights the grid probe's visible faces
//! every frame, all three probes on the crossing frame, and grid and previous on alternate
//! frames during a fade, as the reference does. Its faces are the reference's too: those
//! within 103° (98° for the eye) of the view direction ([`reference_faces`](texel_probes::visibility::reference_faces)), plus any our
//! frustum test keeps, so it never draws less than ours.
//!
//! An edit of entities is taken in without extracting the level again: an entity edited
//! alone (`edit`), added or removed (`splice`: renderer objects keep their index, a removed
//! entity's become blanks, ids follow the rows).
//!
//! Moving objects and sprites keep one clock (`animation`): a pose is a function of the
//! frame's time, and a moved object's shadow marks the stable faces it may have changed.
//! An orthographic camera's probes are planes of texels, not points (`ortho`); a crossing's
//! crossfade runs at our pace or the reference's (`fade`).

mod animation;
mod edit;
mod extraction;
mod fade;
mod ortho;
mod partial;
mod planning;
mod splice;
#[cfg(test)]
mod tests;

pub use animation::Animation;
pub use edit::{EntityEdit, NotAlone};
pub use extraction::{
    PreparedLevel, entity_id, entity_index, level_bloom, level_look, level_palettes, scene_input,
    shadow_extended, start_camera, terrain_input,
};
pub use fade::{OUR_FADE_CELLS, OUR_FADE_SECONDS, OUR_MIN_FADE_FRAMES};
pub use ortho::ORTHO_TURN_STEP_DEG;
pub use partial::{EDIT_MARGIN_TEXELS, EditArea};
pub use planning::{
    CAPTURE_FAR, CROSSING_STABLE_FACES, DriverError, FACE_BUDGET, FrameDriver,
    PREFETCH_FACES_PER_FRAME, PREFETCH_LOOKAHEAD_S, STABLE_FACES_PER_FRAME,
};
pub use splice::{RowEdit, RowsEdit};
