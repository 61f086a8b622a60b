//! Orthographic probes: an orthographic camera sees along parallel rays, so its probes are
//! planes of texels on a lattice, not points ([`texel_probes::ortho`]), and the camera is
//! snapped to whole internal pixels so a pan resamples nothing.

use glam::{UVec2, Vec3};
use texel_probes::grid::{GridChoice, GridDefaults, GridError, GridOverride, resolve_grid};
use texel_probes::ortho::OrthoFrame;
use texel_render::input::{Camera, view_up};

/// The view-direction steps (yaw and pitch, degrees) at which an orthographic camera's grid
/// probe turns with it.
pub const ORTHO_TURN_STEP_DEG: f32 = 5.0;

/// Orthographic grid probes' frames remembered (a previous probe is an old grid probe).
const ORTHO_FRAMES_KEPT: usize = 4;

/// The probes of an orthographic camera (see [`texel_probes::ortho`]): one orthographic face
/// each, one texel per art pixel.
#[derive(Debug, Clone, Copy)]
pub(super) struct OrthoProbes {
    /// The grid probe: the view direction held in `ORTHO_TURN_STEP_DEG` steps, its origin on
    /// a lattice of a quarter face in its plane, so it holds while the camera pans and turns
    /// a little.
    pub(super) grid: (Vec3, OrthoFrame, u32),
    /// The eye probe: the exact view direction, its origin on the texel lattice nearest the
    /// camera, in the camera's plane: it sees what the camera sees.
    pub(super) eye: (Vec3, OrthoFrame, u32),
}

/// An orthographic camera sees along parallel rays, so its probe is not a point but a plane
/// of texels whose rays all run along the view: from there every texel meets the scene where
/// the view rays through it do, nothing is hidden from the probe that the camera sees (when
/// the directions agree), and texels are one size at every depth. Its texel is one art pixel
/// of the level's size (the size the naive and snap methods draw: `level_face_resolution ·
/// tan(fov_y / 2)` art pixels per view height), and its origin lies on a lattice of whole
/// texels in its plane, so every probe looking the same way samples the same world lines: a
/// pan changes no texel. The grid probe sits `half` behind the camera's plane, as far as a
/// texel's distance was for the cube probe this replaces (and sprites turn toward it).
pub(super) fn ortho_probes(
    camera: &Camera,
    ortho_height: f32,
    level_face_resolution: u32,
    aspect: f32,
) -> OrthoProbes {
    let art_pixels = (level_face_resolution as f32 * (camera.fov_y * 0.5).tan()).max(1.0);
    let texel = ortho_height / art_pixels;
    // The view's diagonal in texels, and faces that hold it: the eye's around the camera,
    // the grid's while the camera is up to an eighth of a face off its centre.
    let diagonal = art_pixels * (1.0 + aspect * aspect).sqrt();
    let max_n = *texel_scene::components::FACE_RESOLUTIONS.end();
    let pow2 = |t: f32| {
        (t.ceil().max(1.0) as u32)
            .next_power_of_two()
            .clamp(64, max_n)
    };
    let eye_n = pow2(diagonal + 4.0);
    let grid_n = pow2((0.5 * diagonal + 4.0) * 8.0 / 3.0);
    let snap = |v: f32, step: f32| (v / step).round() * step;
    let p = camera.position;
    // The grid's direction: the view rounded to ORTHO_TURN_STEP_DEG of yaw and pitch.
    let d = camera.forward.normalize();
    let turn = ORTHO_TURN_STEP_DEG.to_radians();
    let yaw = ((-d.x).atan2(-d.z) / turn).round() * turn;
    let pitch = (d.y.clamp(-1.0, 1.0).asin() / turn).round() * turn;
    let f = Vec3::new(
        -yaw.sin() * pitch.cos(),
        pitch.sin(),
        -yaw.cos() * pitch.cos(),
    );
    let grid = OrthoFrame::new(f, view_up(f), 0.5 * grid_n as f32 * texel);
    let step = 0.25 * grid_n as f32 * texel;
    let plane = |fr: &OrthoFrame, step: f32| {
        fr.right * snap(p.dot(fr.right), step) + fr.down * snap(p.dot(fr.down), step)
    };
    let grid_origin =
        plane(&grid, step) + grid.forward * (snap(p.dot(grid.forward), step) - step - grid.half);
    let eye = OrthoFrame::new(d, camera.up(), 0.5 * eye_n as f32 * texel);
    let eye_origin = plane(&eye, texel) + eye.forward * p.dot(eye.forward);
    OrthoProbes {
        grid: (grid_origin, grid, grid_n),
        eye: (eye_origin, eye, eye_n),
    }
}

/// An orthographic camera moved in its view plane to the nearest whole internal pixel: a pan
/// then moves every quad by whole pixels, so nothing is resampled (the probe's texels stand
/// still in the world). A perspective camera is returned as it is.
pub(super) fn pixel_snapped(camera: Camera, internal: UVec2) -> Camera {
    let Some(h) = camera.ortho_height else {
        return camera;
    };
    let pixel = h / internal.y.max(1) as f32;
    let f = camera.forward.normalize();
    let r = f.cross(camera.up()).normalize();
    let u = r.cross(f);
    let p = camera.position;
    let snap = |v: f32| (v / pixel).round() * pixel;
    Camera {
        position: p + r * (snap(p.dot(r)) - p.dot(r)) + u * (snap(p.dot(u)) - p.dot(u)),
        ..camera
    }
}

/// A grid choice for an orthographic probe at exactly `origin` (its cell's key, moved
/// there), with faces of `n` texels. No placement: the probe stands where its lattice
/// puts it, outside the scene.
pub(super) fn ortho_choice(
    origin: Vec3,
    n: u32,
    defaults: &GridDefaults,
    overrides: &[GridOverride],
) -> Result<GridChoice, GridError> {
    let mut c = resolve_grid(origin, defaults, overrides)?;
    c.key.offset = origin - c.key.cell.origin();
    c.key.face_resolution = n;
    Ok(c)
}

/// The orthographic frames of the last probes, by origin: what a capture or a view of a
/// probe at that origin is drawn with.
#[derive(Debug, Clone, Default)]
pub(super) struct OrthoFrames {
    /// The frames of the last orthographic grid probes, by origin (newest last).
    grids: Vec<(Vec3, OrthoFrame)>,
    /// This frame's orthographic eye probe: origin and frame.
    eye: Option<(Vec3, OrthoFrame)>,
}

impl OrthoFrames {
    /// The orthographic frame of the probe at `origin`, if one of the last frames' was there.
    pub(super) fn at(&self, origin: Vec3) -> Option<OrthoFrame> {
        (self.eye.iter().chain(&self.grids))
            .find(|(o, _)| *o == origin)
            .map(|(_, f)| *f)
    }

    /// Remembers this frame's probes `o`, its grid probe at `grid_origin`: keeps the frames
    /// of the stable probes that may still be drawn (grid, previous), and this frame's eye's.
    pub(super) fn remember(&mut self, grid_origin: Vec3, o: &OrthoProbes) {
        if self.at(grid_origin).is_none() {
            self.grids.push((grid_origin, o.grid.1));
        }
        let excess = self.grids.len().saturating_sub(ORTHO_FRAMES_KEPT);
        self.grids.drain(..excess);
        self.eye = Some((o.eye.0, o.eye.1));
    }
}
