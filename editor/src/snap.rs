//! Snapping, for the session: grid snap for the gizmo's moves (and the probe-override face
//! handles), angle snap for its turns, and whether something added lands on the surface
//! under the viewport's centre. Chosen in the viewport's snap bar; Ctrl held during a drag
//! turns each of grid and angle snap the other way for that drag (on when off, off when
//! on).

/// The grid steps offered, metres.
pub const GRID_STEPS: [f32; 5] = [0.1, 0.25, 0.5, 1.0, 2.0];
/// The angle steps offered, degrees.
pub const ANGLE_STEPS: [f32; 4] = [5.0, 15.0, 45.0, 90.0];
/// The scale factor's step while grid snap is on.
pub const SCALE_STEP: f32 = 0.1;

/// The snap settings (kept for the session, not in the level).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Snap {
    /// Whether moves snap to the grid.
    pub grid: bool,
    /// The grid step, metres.
    pub step: f32,
    /// Whether turns snap to the angle step.
    pub angle: bool,
    /// The angle step, degrees.
    pub angle_step: f32,
    /// Whether something added lands on the surface under the viewport's centre (else on
    /// the ground plane there).
    pub surface: bool,
}

impl Default for Snap {
    fn default() -> Self {
        Snap {
            grid: false,
            step: 0.5,
            angle: false,
            angle_step: 15.0,
            surface: true,
        }
    }
}

/// What one drag step snaps to: the grid step (also snapping a scale factor to
/// [`SCALE_STEP`]) and the angle step, when on.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SnapNow {
    /// Grid step, metres.
    pub grid: Option<f32>,
    /// Angle step, degrees.
    pub angle: Option<f32>,
}

impl Snap {
    /// What a drag snaps to with Ctrl held (`invert`) or not.
    pub fn now(&self, invert: bool) -> SnapNow {
        SnapNow {
            grid: (self.grid != invert).then_some(self.step),
            angle: (self.angle != invert).then_some(self.angle_step),
        }
    }
}

/// `v` rounded to the nearest multiple of `step`.
pub fn to_step(v: f32, step: f32) -> f32 {
    if step <= 0.0 {
        return v;
    }
    let s = (v / step).round() * step;
    // 0.1 steps: keep 0.3 as 0.3, not 0.30000001.
    (s * 1e4).round() / 1e4
}

/// Draws the snap settings in a row (the viewport's snap bar).
pub fn bar(ui: &mut egui::Ui, snap: &mut Snap) {
    ui.checkbox(&mut snap.grid, "Grid snap")
        .on_hover_text("Moves land on multiples of the step (Ctrl while dragging: the other way)");
    egui::ComboBox::from_id_salt("grid step")
        .width(64.0)
        .selected_text(format!("{} m", snap.step))
        .show_ui(ui, |ui| {
            for s in GRID_STEPS {
                ui.selectable_value(&mut snap.step, s, format!("{s} m"));
            }
        })
        .response
        .accessible_name("Grid step");
    ui.checkbox(&mut snap.angle, "Angle snap")
        .on_hover_text("Turns land on multiples of the step (Ctrl while dragging: the other way)");
    egui::ComboBox::from_id_salt("angle step")
        .width(56.0)
        .selected_text(format!("{}°", snap.angle_step))
        .show_ui(ui, |ui| {
            for s in ANGLE_STEPS {
                ui.selectable_value(&mut snap.angle_step, s, format!("{s}°"));
            }
        })
        .response
        .accessible_name("Angle step");
    ui.checkbox(&mut snap.surface, "Place on surface").on_hover_text(
        "Add puts new things on the surface under the viewport's centre (else on the ground plane)",
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ctrl_turns_each_snap_the_other_way() {
        let mut s = Snap::default();
        assert_eq!(s.now(false), SnapNow::default());
        assert_eq!(s.now(true).grid, Some(0.5));
        s.grid = true;
        s.step = 0.25;
        assert_eq!(s.now(false).grid, Some(0.25));
        assert_eq!(s.now(false).angle, None);
        assert_eq!(s.now(true).grid, None);
        assert_eq!(s.now(true).angle, Some(15.0));
    }

    #[test]
    fn steps_round_to_multiples() {
        assert_eq!(to_step(0.37, 0.25), 0.25);
        assert_eq!(to_step(0.38, 0.25), 0.5);
        assert_eq!(to_step(-1.26, 0.5), -1.5);
        assert_eq!(to_step(0.31, 0.1), 0.3);
        assert_eq!(to_step(52.0, 15.0), 45.0);
        assert_eq!(to_step(1.3, 0.0), 1.3);
    }
}
