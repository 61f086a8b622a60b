//! Grid snapping of the stable probe origin, with probe-grid override volumes.
//!
//! **Lattice.** Probe origins are grid *vertices*: integer multiples of the cell size `s`
//! on x, y and z, anchored at the world origin (`origin = index · s`). The camera's cell is
//! the set of points that snap to the same vertex: the cube of side `s` *centred* on the
//! vertex, so a probe always sits at the centre of the cell it serves. Snapping rounds each
//! coordinate of `position / s` to the nearest integer; exact halfway points round away
//! from zero (`f32::round`). Lattices of different cell sizes share the world origin, so a
//! lattice of `s / 2` contains every vertex of the lattice of `s`.
//!
//! **Overrides.** An override is an axis-aligned box (`min..=max`, inclusive) with its own
//! cell size, an optional face resolution and an integer priority. Of the overrides that
//! contain the camera, the highest priority wins; among equal priorities the one given
//! **later** in the slice wins (so a level lists general volumes first and refinements
//! after). Outside every override the level defaults apply.
//!
//! Every input is validated and bad values are reported as [`GridError`], never a panic.

use std::fmt;

use glam::{IVec3, Vec3};

/// Largest `|position / cell_size|` accepted: beyond 2^24 an `f32` cannot tell
/// neighbouring vertices apart.
pub const MAX_CELL_INDEX: f32 = 16_777_216.0;

/// Level-wide grid settings, used outside every override.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridDefaults {
    /// Edge length of a grid cell, world units (> 0).
    pub cell_size: f32,
    /// Face resolution of the probes, texels per face edge (> 0).
    pub face_resolution: u32,
}

/// A probe-grid override volume.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridOverride {
    /// Minimum corner of the box (inclusive).
    pub min: Vec3,
    /// Maximum corner of the box (inclusive).
    pub max: Vec3,
    /// Cell size inside the box, world units (> 0).
    pub cell_size: f32,
    /// Face resolution inside the box; `None` keeps the level default.
    pub face_resolution: Option<u32>,
    /// Higher wins when boxes overlap; ties go to the later override.
    pub priority: i32,
}

impl GridOverride {
    /// Whether `p` lies inside the box (faces included).
    pub fn contains(&self, p: Vec3) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }
}

/// One cell of a lattice: its integer vertex index and the lattice's cell size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridCell {
    /// Vertex index; the origin is `index · cell_size`.
    pub index: IVec3,
    /// Cell size of the lattice.
    pub cell_size: f32,
}

impl GridCell {
    /// World position of the cell's vertex (the probe origin).
    pub fn origin(&self) -> Vec3 {
        self.index.as_vec3() * self.cell_size
    }
}

/// What identifies a stable probe: its cell and its face resolution.
///
/// Two keys are equal exactly when a probe captured for one is valid for the other.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProbeKey {
    /// The grid cell (origin) of the probe.
    pub cell: GridCell,
    /// Texels per face edge.
    pub face_resolution: u32,
    /// Where the probe sits relative to the cell's vertex: zero, unless placement moved it
    /// off a spot that would blind it (`placement::place_probe`; a function of the cell and
    /// the scene only).
    pub offset: Vec3,
}

impl ProbeKey {
    /// World position of the probe.
    pub fn origin(&self) -> Vec3 {
        self.cell.origin() + self.offset
    }
}

/// The grid that applies at a camera position.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridChoice {
    /// The snapped probe (cell and face resolution).
    pub key: ProbeKey,
    /// Index of the override that applied, `None` for the level defaults.
    pub override_index: Option<usize>,
}

impl GridChoice {
    /// The snapped probe origin.
    pub fn origin(&self) -> Vec3 {
        self.key.origin()
    }
}

/// A grid input that cannot be used.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum GridError {
    /// The camera position has a NaN or infinite component.
    NonFiniteCamera(Vec3),
    /// The level default cell size is not finite and positive.
    InvalidDefaultCellSize(f32),
    /// The level default face resolution is zero.
    ZeroDefaultFaceResolution,
    /// An override's cell size is not finite and positive.
    InvalidOverrideCellSize {
        /// Index of the override.
        index: usize,
        /// The rejected value.
        cell_size: f32,
    },
    /// An override's box is not finite or has `min > max` on some axis.
    InvalidOverrideBounds {
        /// Index of the override.
        index: usize,
    },
    /// An override's face resolution is zero.
    ZeroOverrideFaceResolution {
        /// Index of the override.
        index: usize,
    },
    /// The position is too far from the world origin for this cell size.
    OutOfRange {
        /// The position.
        position: Vec3,
        /// The cell size.
        cell_size: f32,
    },
}

impl fmt::Display for GridError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            GridError::NonFiniteCamera(p) => write!(f, "camera position {p} is not finite"),
            GridError::InvalidDefaultCellSize(s) => {
                write!(f, "level cell_size {s} must be finite and > 0")
            }
            GridError::ZeroDefaultFaceResolution => {
                write!(f, "level face_resolution must be > 0")
            }
            GridError::InvalidOverrideCellSize { index, cell_size } => write!(
                f,
                "probe-grid override {index}: cell_size {cell_size} must be finite and > 0"
            ),
            GridError::InvalidOverrideBounds { index } => write!(
                f,
                "probe-grid override {index}: min/max must be finite with min <= max"
            ),
            GridError::ZeroOverrideFaceResolution { index } => {
                write!(
                    f,
                    "probe-grid override {index}: face_resolution must be > 0"
                )
            }
            GridError::OutOfRange {
                position,
                cell_size,
            } => write!(
                f,
                "position {position} is too far from the origin for cell size {cell_size}"
            ),
        }
    }
}

impl std::error::Error for GridError {}

fn valid_cell_size(s: f32) -> bool {
    s.is_finite() && s > 0.0
}

/// Snaps `position` to the nearest vertex of the lattice of cell size `cell_size`.
pub fn snap_to_grid(position: Vec3, cell_size: f32) -> Result<GridCell, GridError> {
    if !position.is_finite() {
        return Err(GridError::NonFiniteCamera(position));
    }
    if !valid_cell_size(cell_size) {
        return Err(GridError::InvalidDefaultCellSize(cell_size));
    }
    let scaled = (position / cell_size).round();
    if !scaled.is_finite() || scaled.abs().max_element() > MAX_CELL_INDEX {
        return Err(GridError::OutOfRange {
            position,
            cell_size,
        });
    }
    Ok(GridCell {
        index: scaled.as_ivec3(),
        cell_size,
    })
}

/// Checks the level defaults and every override, reporting the first problem.
pub fn validate(defaults: &GridDefaults, overrides: &[GridOverride]) -> Result<(), GridError> {
    if !valid_cell_size(defaults.cell_size) {
        return Err(GridError::InvalidDefaultCellSize(defaults.cell_size));
    }
    if defaults.face_resolution == 0 {
        return Err(GridError::ZeroDefaultFaceResolution);
    }
    overrides.iter().enumerate().try_for_each(validate_override)
}

fn validate_override((index, o): (usize, &GridOverride)) -> Result<(), GridError> {
    if !valid_cell_size(o.cell_size) {
        return Err(GridError::InvalidOverrideCellSize {
            index,
            cell_size: o.cell_size,
        });
    }
    if !o.min.is_finite() || !o.max.is_finite() || o.min.cmpgt(o.max).any() {
        return Err(GridError::InvalidOverrideBounds { index });
    }
    if o.face_resolution == Some(0) {
        return Err(GridError::ZeroOverrideFaceResolution { index });
    }
    Ok(())
}

/// Index of the override that governs `position`: the highest priority among those
/// containing it, ties to the later one. `None` if no override contains it.
pub fn select_override(position: Vec3, overrides: &[GridOverride]) -> Option<usize> {
    overrides
        .iter()
        .enumerate()
        .filter(|(_, o)| o.contains(position))
        // `max_by_key` returns the last of equal maxima: later wins ties.
        .max_by_key(|(_, o)| o.priority)
        .map(|(i, _)| i)
}

/// The grid that applies at `camera`: the snapped probe origin, the override that chose
/// its cell size (if any) and the face resolution to use.
///
/// Validates all inputs first (see [`validate`]), so a broken override is reported even
/// while the camera is elsewhere.
pub fn resolve_grid(
    camera: Vec3,
    defaults: &GridDefaults,
    overrides: &[GridOverride],
) -> Result<GridChoice, GridError> {
    validate(defaults, overrides)?;
    if !camera.is_finite() {
        return Err(GridError::NonFiniteCamera(camera));
    }
    let override_index = select_override(camera, overrides);
    let (cell_size, face_resolution) = match override_index {
        Some(i) => (
            overrides[i].cell_size,
            overrides[i]
                .face_resolution
                .unwrap_or(defaults.face_resolution),
        ),
        None => (defaults.cell_size, defaults.face_resolution),
    };
    let cell = snap_to_grid(camera, cell_size)?;
    Ok(GridChoice {
        key: ProbeKey {
            cell,
            face_resolution,
            offset: Vec3::ZERO,
        },
        override_index,
    })
}

/// The first point on the segment `from..to` whose grid (cell and face resolution, see
/// [`resolve_grid`]) differs from the grid at `from`: where a camera moving along it
/// enters its next cell. `None` if the whole segment stays in `from`'s cell, or an input
/// is invalid.
///
/// The cell at `to` is not the answer: a camera near a corner of its cell, moving
/// diagonally, may cross one boundary within the segment and the other only past its end
/// (or never, if it slows), and then enters the cell beside its own, not the diagonal one.
pub fn first_crossing(
    from: Vec3,
    to: Vec3,
    defaults: &GridDefaults,
    overrides: &[GridOverride],
) -> Option<Vec3> {
    let start = resolve_grid(from, defaults, overrides).ok()?;
    // A point that does not resolve counts as another grid.
    let same = |p: Vec3| {
        resolve_grid(p, defaults, overrides).is_ok_and(|c| {
            c.key.cell == start.key.cell && c.key.face_resolution == start.key.face_resolution
        })
    };
    // Steps of an eighth of the smallest cell any grid here uses: a cell is never stepped
    // over, and a corner clipped by less than that is not worth prefetching.
    let finest = (overrides.iter().map(|o| o.cell_size)).fold(defaults.cell_size, f32::min);
    let length = (to - from).length();
    if !length.is_finite() || length <= 0.0 {
        return None;
    }
    let steps = ((length / (finest / 8.0)).ceil() as u32).clamp(1, MAX_CROSSING_STEPS);
    let at = |i: u32| i as f32 / steps as f32;
    let first = (1..=steps).find(|&i| !same(from.lerp(to, at(i))))?;
    // The step may have crossed two boundaries near a corner: bisect to the first, and
    // answer just past it.
    let (mut lo, mut hi) = (at(first - 1), at(first));
    for _ in 0..CROSSING_BISECTIONS {
        let mid = 0.5 * (lo + hi);
        if same(from.lerp(to, mid)) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some(from.lerp(to, hi))
}

/// Samples [`first_crossing`] tests at most along its segment.
const MAX_CROSSING_STEPS: u32 = 256;
/// Halvings of the step where [`first_crossing`] found a new grid (to 1/4096 of it).
const CROSSING_BISECTIONS: u32 = 12;

#[cfg(test)]
mod tests {
    use super::*;

    const DEFAULTS: GridDefaults = GridDefaults {
        cell_size: 1.0,
        face_resolution: 64,
    };

    fn volume(min: f32, max: f32, cell_size: f32, priority: i32) -> GridOverride {
        GridOverride {
            min: Vec3::splat(min),
            max: Vec3::splat(max),
            cell_size,
            face_resolution: None,
            priority,
        }
    }

    #[test]
    fn a_diagonal_move_near_a_corner_enters_the_side_cell_first() {
        // From (0.41, 1.6, 4.9) toward (0.53, 1.6, 4.3): z crosses 4.5 before x crosses
        // 0.5, so the cell entered is (0, 2, 4), not (1, 2, 4) where the segment ends.
        let (from, to) = (Vec3::new(0.41, 1.6, 4.9), Vec3::new(0.53, 1.6, 4.3));
        let p = first_crossing(from, to, &DEFAULTS, &[]).unwrap();
        let entered = resolve_grid(p, &DEFAULTS, &[]).unwrap();
        assert_eq!(entered.key.cell.index, IVec3::new(0, 2, 4));
        let end = resolve_grid(to, &DEFAULTS, &[]).unwrap();
        assert_eq!(end.key.cell.index, IVec3::new(1, 2, 4));
        assert!(p.z < 4.5 && p.z > 4.499, "{p}");
    }

    #[test]
    fn a_segment_inside_one_cell_crosses_nothing() {
        let from = Vec3::new(0.1, 1.9, 5.2);
        assert_eq!(
            first_crossing(from, from + Vec3::X * 0.3, &DEFAULTS, &[]),
            None
        );
        assert_eq!(first_crossing(from, from, &DEFAULTS, &[]), None);
        assert_eq!(first_crossing(from, Vec3::NAN, &DEFAULTS, &[]), None);
    }

    #[test]
    fn entering_an_override_volume_is_a_crossing() {
        // Same cell vertex (0,0,0) at both cell sizes, but the volume's face resolution
        // differs: a new probe.
        let mut v = volume(0.2, 1.0, 1.0, 0);
        v.face_resolution = Some(32);
        let p = first_crossing(Vec3::splat(0.1), Vec3::splat(0.3), &DEFAULTS, &[v]).unwrap();
        assert!(v.contains(p), "{p}");
        // A volume of finer cells is never stepped over.
        let fine = volume(0.30, 0.32, 0.02, 0);
        let from = Vec3::new(0.0, 0.31, 0.31);
        let p = first_crossing(from, from + Vec3::X * 0.45, &DEFAULTS, &[fine]).unwrap();
        assert!(fine.contains(p), "{p}");
    }

    #[test]
    fn snaps_to_nearest_vertex() {
        let c = snap_to_grid(Vec3::new(20.0, 1.6, 15.4), 1.0).unwrap();
        assert_eq!(c.index, IVec3::new(20, 2, 15));
        assert_eq!(c.origin(), Vec3::new(20.0, 2.0, 15.0));
        let c = snap_to_grid(Vec3::new(-0.74, 0.76, 1.24), 0.5).unwrap();
        assert_eq!(c.origin(), Vec3::new(-0.5, 1.0, 1.0));
    }

    #[test]
    fn halfway_rounds_away_from_zero() {
        let c = snap_to_grid(Vec3::new(0.5, -0.5, 1.5), 1.0).unwrap();
        assert_eq!(c.index, IVec3::new(1, -1, 2));
    }

    #[test]
    fn cell_is_centred_on_its_vertex() {
        let vertex = Vec3::splat(4.0);
        for offset in [-0.99, -0.5, 0.0, 0.5, 0.99] {
            let p = vertex + Vec3::new(offset, -offset, offset * 0.5);
            let c = snap_to_grid(p, 2.0).unwrap();
            assert_eq!(c.index, IVec3::splat(2), "{p}");
            assert_eq!(c.origin(), vertex);
        }
        let outside = snap_to_grid(vertex + Vec3::new(1.01, 0.0, -1.01), 2.0).unwrap();
        assert_eq!(outside.index, IVec3::new(3, 2, 1));
    }

    #[test]
    fn rejects_bad_cell_sizes() {
        for s in [0.0, -1.0, f32::NAN, f32::INFINITY] {
            assert!(matches!(
                snap_to_grid(Vec3::ZERO, s),
                Err(GridError::InvalidDefaultCellSize(_))
            ));
            let d = GridDefaults {
                cell_size: s,
                ..DEFAULTS
            };
            assert!(resolve_grid(Vec3::ZERO, &d, &[]).is_err());
            let o = [volume(-1.0, 1.0, s, 0)];
            assert!(matches!(
                resolve_grid(Vec3::splat(50.0), &DEFAULTS, &o),
                Err(GridError::InvalidOverrideCellSize { index: 0, .. })
            ));
        }
    }

    #[test]
    fn rejects_bad_camera_bounds_and_resolution() {
        let nan = Vec3::new(f32::NAN, 0.0, 0.0);
        assert!(matches!(
            resolve_grid(nan, &DEFAULTS, &[]),
            Err(GridError::NonFiniteCamera(p)) if p.y == 0.0 && p.x.is_nan()
        ));
        let inverted = [volume(1.0, -1.0, 1.0, 0)];
        assert_eq!(
            resolve_grid(Vec3::ZERO, &DEFAULTS, &inverted).unwrap_err(),
            GridError::InvalidOverrideBounds { index: 0 }
        );
        let mut zero_res = volume(-1.0, 1.0, 1.0, 0);
        zero_res.face_resolution = Some(0);
        assert_eq!(
            validate(&DEFAULTS, &[volume(-1.0, 1.0, 1.0, 0), zero_res]).unwrap_err(),
            GridError::ZeroOverrideFaceResolution { index: 1 }
        );
        let d = GridDefaults {
            face_resolution: 0,
            ..DEFAULTS
        };
        assert_eq!(validate(&d, &[]), Err(GridError::ZeroDefaultFaceResolution));
        assert!(matches!(
            snap_to_grid(Vec3::splat(1.0e9), 1.0),
            Err(GridError::OutOfRange { .. })
        ));
        assert!(
            GridError::InvalidOverrideBounds { index: 3 }
                .to_string()
                .contains('3')
        );
    }

    #[test]
    fn defaults_apply_outside_overrides() {
        let o = [volume(10.0, 20.0, 0.25, 5)];
        let c = resolve_grid(Vec3::new(0.3, 0.0, 0.0), &DEFAULTS, &o).unwrap();
        assert_eq!(c.override_index, None);
        assert_eq!(c.key.cell.cell_size, 1.0);
        assert_eq!(c.key.face_resolution, 64);
        assert_eq!(c.origin(), Vec3::ZERO);
    }

    #[test]
    fn highest_priority_wins_and_later_breaks_ties() {
        let mut fine = volume(-10.0, 10.0, 0.5, 2);
        fine.face_resolution = Some(128);
        let overrides = [
            volume(-10.0, 10.0, 2.0, 1),
            fine,
            volume(-10.0, 10.0, 0.25, 2),
            volume(-10.0, 10.0, 4.0, 0),
        ];
        let c = resolve_grid(Vec3::new(1.1, 0.0, 0.0), &DEFAULTS, &overrides).unwrap();
        assert_eq!(c.override_index, Some(2), "priority 2, later of the tie");
        assert_eq!(c.key.cell.cell_size, 0.25);
        assert_eq!(c.key.face_resolution, 64, "no resolution override: default");
        assert_eq!(c.origin(), Vec3::new(1.0, 0.0, 0.0));
        let c = resolve_grid(Vec3::ZERO, &DEFAULTS, &overrides[..2]).unwrap();
        assert_eq!(c.override_index, Some(1));
        assert_eq!(c.key.face_resolution, 128);
    }

    #[test]
    fn override_boxes_are_inclusive() {
        let o = volume(0.0, 1.0, 0.5, 0);
        assert!(o.contains(Vec3::splat(1.0)) && o.contains(Vec3::ZERO));
        assert!(!o.contains(Vec3::new(1.0001, 0.5, 0.5)));
        assert_eq!(select_override(Vec3::splat(2.0), &[o]), None);
    }
}
