//! Reshaping the terrain while playing: `texel-run play`'s raise and lower keys dab the
//! terrain under the crosshair (the view's centre ray) with the editor's brush math
//! ([`texel_scene::sculpt`]), keep the new heights in the played level (no file is written)
//! and refresh only the probe faces that may see the dab
//! ([`Session::update_level_region`]).

use std::sync::Arc;

use glam::Vec3;
use texel_render::context::GpuContext;
use texel_render::input::Camera;
use texel_scene::sculpt::{Brush, BrushKind, Dab, Region, dab, scene_ray_hit};

use crate::load::LoadedLevel;
use crate::session::{Session, SessionError};

/// Dabs per second while a key is held.
pub const DABS_PER_SECOND: f32 = 10.0;
/// Most dabs one frame catches up on after a slow frame; the rest are dropped.
pub const MAX_DABS_PER_FRAME: u32 = 3;

/// The brush of the raise (or lower) key: the editor's default brush with a radius of 3
/// units, so a dab at 10 per second moves the ground by a quarter of the terrain's height
/// range per second at its centre.
pub fn brush(raise: bool) -> Brush {
    Brush {
        kind: if raise {
            BrushKind::Raise
        } else {
            BrushKind::Lower
        },
        radius: 3.0,
        ..Brush::default()
    }
}

/// What a dab changed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dabbed {
    /// The terrain's entity.
    pub entity: hecs::Entity,
    /// Where the centre ray met the terrain (the brush's centre).
    pub centre: Vec3,
    /// The samples changed.
    pub region: Region,
    /// The world box the change may reach (the region over the terrain's height range).
    pub min: Vec3,
    /// Its far corner.
    pub max: Vec3,
    /// Probe faces marked for capture ([`Session::update_level_region`]); 0 until then.
    pub faces_marked: u32,
}

/// Applies `dabs` dabs of [`brush`]`(raise)`, each standing for 1/[`DABS_PER_SECOND`]
/// seconds, to the terrain of `level` that `camera`'s centre ray meets first, and keeps the
/// new heights in `level`'s assets. `None` when the ray meets no terrain (or the level has
/// none) or the heights did not change.
pub fn dab_level(
    level: &mut LoadedLevel,
    camera: &Camera,
    raise: bool,
    dabs: u32,
) -> Option<Dabbed> {
    let hit = scene_ray_hit(&level.scene, &level.assets, camera.position, camera.forward)?;
    let mut field = (*hit.field).clone();
    let stroke = Dab {
        centre: hit.point,
        dt: 1.0 / DABS_PER_SECOND,
        invert: false,
        target: hit.point.y - hit.place.origin.y,
    };
    let brush = brush(raise);
    let mut region: Option<Region> = None;
    for _ in 0..dabs {
        if let Some(r) = dab(&mut field, &hit.place, &brush, &stroke) {
            region = Some(region.map_or(r, |t| t.union(r)));
        }
    }
    let region = region?;
    if *hit.field == field {
        return None;
    }
    level
        .assets
        .insert_heightfield(&hit.terrain, Arc::new(field));
    let (min, max) = hit.place.region_bounds(region);
    Some(Dabbed {
        entity: hit.entity,
        centre: hit.point,
        region,
        min,
        max,
        faces_marked: 0,
    })
}

/// [`dab_level`], then `session` takes the edited level, capturing again only the probe
/// faces that may see the dab's box.
pub fn dab_at_centre(
    ctx: &GpuContext,
    session: &mut Session,
    level: &mut LoadedLevel,
    camera: &Camera,
    raise: bool,
    dabs: u32,
) -> Result<Option<Dabbed>, SessionError> {
    let Some(mut done) = dab_level(level, camera, raise, dabs) else {
        return Ok(None);
    };
    done.faces_marked = session.update_level_region(ctx, level, done.min, done.max)?;
    Ok(Some(done))
}

/// The raise and lower keys as held, turned into dabs: one at once on a press, then
/// [`DABS_PER_SECOND`] while held; both held do nothing.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SculptKeys {
    raise: bool,
    lower: bool,
    /// Seconds until the next dab.
    wait: f32,
    /// A key went down since the last [`SculptKeys::due`]: dab without waiting.
    pressed: bool,
}

impl SculptKeys {
    /// The raise (`raise`) or lower key went down (`held`) or up.
    pub fn set(&mut self, raise: bool, held: bool) {
        let before = self.direction();
        if raise {
            self.raise = held;
        } else {
            self.lower = held;
        }
        if self.direction() != before {
            self.wait = 0.0;
            self.pressed = self.direction().is_some();
        }
    }

    /// Lets go of both keys (the window lost the focus).
    pub fn release(&mut self) {
        *self = SculptKeys::default();
    }

    /// `Some(true)` while only the raise key is held, `Some(false)` while only the lower key.
    pub fn direction(&self) -> Option<bool> {
        match (self.raise, self.lower) {
            (true, false) => Some(true),
            (false, true) => Some(false),
            _ => None,
        }
    }

    /// The dabs due in a frame `dt` seconds after the last: whether they raise and how many
    /// (at most [`MAX_DABS_PER_FRAME`]), `None` when none is.
    pub fn due(&mut self, dt: f32) -> Option<(bool, u32)> {
        let raise = self.direction()?;
        let period = 1.0 / DABS_PER_SECOND;
        if !std::mem::take(&mut self.pressed) {
            self.wait -= dt.max(0.0);
        }
        // Due within a tenth of a millisecond counts as due: frame times summed in f32 land
        // a hair either side of a period.
        let due = |wait: f32| wait <= 1e-4;
        let mut n = 0;
        while due(self.wait) && n < MAX_DABS_PER_FRAME {
            n += 1;
            self.wait += period;
        }
        if due(self.wait) {
            self.wait = period;
        }
        (n > 0).then_some((raise, n))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_press_dabs_at_once_then_ten_times_a_second() {
        let mut keys = SculptKeys::default();
        assert_eq!(keys.due(0.5), None, "nothing held");
        keys.set(true, true);
        assert_eq!(
            keys.due(0.5),
            Some((true, 1)),
            "at once, whatever came before"
        );
        // Sixty frames a second for a second: ten dabs in all.
        let n: u32 = (0..60)
            .filter_map(|_| keys.due(1.0 / 60.0))
            .map(|d| d.1)
            .sum();
        assert_eq!(n, 10);
        // Key repeats change nothing.
        keys.set(true, true);
        assert_eq!(keys.due(0.01), None);
        keys.set(true, false);
        assert_eq!(keys.due(1.0), None, "released");
    }

    #[test]
    fn a_slow_frame_catches_up_on_at_most_three_dabs() {
        let mut keys = SculptKeys::default();
        keys.set(false, true);
        assert_eq!(keys.due(0.0), Some((false, 1)));
        assert_eq!(keys.due(0.25), Some((false, 2)));
        assert_eq!(keys.due(2.0), Some((false, MAX_DABS_PER_FRAME)));
        assert_eq!(
            keys.due(0.05),
            None,
            "the rest dropped, the next a period on"
        );
    }

    #[test]
    fn both_keys_held_do_nothing_and_letting_one_go_dabs_the_other() {
        let mut keys = SculptKeys::default();
        keys.set(true, true);
        keys.set(false, true);
        assert_eq!(keys.due(1.0), None);
        keys.set(true, false);
        assert_eq!(keys.due(0.0), Some((false, 1)));
        keys.release();
        assert_eq!(keys.due(1.0), None);
    }
}
