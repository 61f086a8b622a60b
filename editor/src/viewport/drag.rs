//! Dragging one of several screen-space handles (the gizmo's axes, the faces of a probe-grid
//! override volume): the handle is hit-tested where the button went down, the motion is
//! measured from there (so egui's drag threshold is not lost), and the drag ends on release.
//! What a drag does to the document is the caller's: it gets the drag back each frame it
//! continues.

use egui::{Color32, PointerButton, Pos2, Response, Ui, Vec2};

/// Colours of the X, Y and Z handles.
pub const AXIS_COLOURS: [Color32; 3] = [
    Color32::from_rgb(230, 70, 70),
    Color32::from_rgb(80, 210, 80),
    Color32::from_rgb(80, 120, 240),
];

/// A drag in progress.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HandleDrag<S> {
    /// Which handle is dragged.
    pub handle: usize,
    /// What the handle edits, as it was when the drag began.
    pub start: S,
    /// Pointer motion since the button went down, pixels.
    pub moved: Vec2,
}

/// The primary button's part of one frame's pointer input over the viewport.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Pointer {
    /// Where the pointer is (while it interacts or hovers).
    pub at: Option<Pos2>,
    /// Where the button went down.
    pub pressed: Option<Pos2>,
    /// A primary-button drag started this frame.
    pub started: bool,
    /// A primary-button drag continues this frame.
    pub held: bool,
    /// Pointer motion this frame (used when the press position is unknown).
    pub delta: Vec2,
}

impl Pointer {
    /// Reads the pointer from egui.
    pub fn read(ui: &Ui, response: &Response) -> Self {
        Pointer {
            at: response.interact_pointer_pos().or(response.hover_pos()),
            pressed: ui.input(|i| i.pointer.press_origin()),
            started: response.drag_started_by(PointerButton::Primary),
            held: response.dragged_by(PointerButton::Primary),
            delta: response.drag_delta(),
        }
    }
}

/// What one frame did to a set of handles.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DragFrame<S> {
    /// The handle to highlight: the one dragged, else the one under the pointer.
    pub highlight: Option<usize>,
    /// Whether the pointer is on a handle or drags one (so a click there is not a pick).
    pub used: bool,
    /// The drag, when it continued this frame: the caller applies it.
    pub dragged: Option<HandleDrag<S>>,
}

/// Starts, continues or ends `drag` for this frame's `pointer`. `hit` names the handle at a
/// screen position; `start` is what a drag starting now begins from.
pub fn update<S: Copy>(
    drag: &mut Option<HandleDrag<S>>,
    pointer: &Pointer,
    hit: impl Fn(Pos2) -> Option<usize>,
    start: S,
) -> DragFrame<S> {
    let hot = pointer.at.and_then(&hit);
    if pointer.started
        && let Some(handle) = pointer.pressed.and_then(&hit)
    {
        *drag = Some(HandleDrag {
            handle,
            start,
            moved: Vec2::ZERO,
        });
    }
    let mut used = hot.is_some();
    if let Some(d) = drag {
        used = true;
        if pointer.held {
            d.moved = match (pointer.at, pointer.pressed) {
                (Some(now), Some(from)) => now - from,
                _ => d.moved + pointer.delta,
            };
        } else {
            *drag = None;
        }
    }
    DragFrame {
        highlight: drag.map(|d| d.handle).or(hot),
        used,
        dragged: *drag,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Handle 0 at (10, 0), handle 1 at (0, 10), each 3 pixels wide.
    fn hit(p: Pos2) -> Option<usize> {
        [Pos2::new(10.0, 0.0), Pos2::new(0.0, 10.0)]
            .iter()
            .position(|h| (*h - p).length() < 3.0)
    }

    #[test]
    fn a_drag_starts_where_the_button_went_down_and_ends_on_release() {
        let mut drag = None;
        let hover = Pointer {
            at: Some(Pos2::new(0.0, 11.0)),
            ..Pointer::default()
        };
        let f = update(&mut drag, &hover, hit, 7);
        assert_eq!((f.highlight, f.used, f.dragged), (Some(1), true, None));
        // The drag is recognised a few pixels away from the press, off the handle.
        let start = Pointer {
            at: Some(Pos2::new(0.0, 20.0)),
            pressed: Some(Pos2::new(0.0, 10.0)),
            started: true,
            held: true,
            delta: Vec2::new(0.0, 2.0),
        };
        let f = update(&mut drag, &start, hit, 7);
        let d = f.dragged.expect("dragging");
        assert_eq!((d.handle, d.start, d.moved), (1, 7, Vec2::new(0.0, 10.0)));
        assert_eq!((f.highlight, f.used), (Some(1), true));
        // Without a press position the motion accumulates.
        let on = Pointer {
            at: None,
            pressed: None,
            started: false,
            held: true,
            delta: Vec2::new(1.0, 0.0),
        };
        let f = update(&mut drag, &on, hit, 8);
        assert_eq!(
            f.dragged.map(|d| (d.start, d.moved)),
            Some((7, Vec2::new(1.0, 10.0)))
        );
        let released = Pointer::default();
        let f = update(&mut drag, &released, hit, 8);
        assert_eq!((f.highlight, f.dragged), (None, None));
        assert!(f.used, "the release frame still belongs to the drag");
        assert_eq!(drag, None);
    }

    #[test]
    fn a_press_off_every_handle_starts_nothing() {
        let mut drag: Option<HandleDrag<u8>> = None;
        let p = Pointer {
            at: Some(Pos2::new(50.0, 50.0)),
            pressed: Some(Pos2::new(40.0, 40.0)),
            started: true,
            held: true,
            delta: Vec2::ZERO,
        };
        let f = update(&mut drag, &p, hit, 0);
        assert_eq!((f.highlight, f.used, f.dragged), (None, false, None));
    }
}
