//! The part of each stable face an edit changed ([`EditedFaces`]): when the face is captured
//! again at the same origin, only those texels are lit again ([`FrameInput::partial`]).
//! Capturing the whole face again is cheap next to lighting it (shadow rays through the
//! scene's tree); what lies outside the part captures as it did, so its old light holds.

use glam::Vec3;
use texel_probes::cube::Face;
use texel_probes::probe_set::Slot;
use texel_probes::schedule::CaptureStamp;
use texel_probes::visibility::{TexelRect, face_box_rect};
use texel_render::input::{CaptureInput, FrameInput, Relight};

/// Texels around an edit's rectangle lit again too: a texel's outline, neighbour bits and
/// silhouette rays read its neighbours (one texel; one more for safety).
pub const EDIT_MARGIN_TEXELS: u32 = 2;

/// A stable face an edit marked stale, and the texels it can have changed.
#[derive(Debug, Clone, Copy, PartialEq)]
struct EditedFace {
    slot: Slot,
    face: Face,
    /// Where and at what resolution the face's data was captured.
    origin: Vec3,
    n: u32,
    rect: TexelRect,
}

/// The stable faces edits have changed in part since they were last captured.
#[derive(Debug, Clone, Default)]
pub struct EditedFaces {
    faces: Vec<EditedFace>,
}

impl EditedFaces {
    /// Forgets every face: each is captured and lit whole when it is captured again (after
    /// any other change to the scene, or frames of another schedule, which may have moved
    /// a slot's probe away and back).
    pub fn forget(&mut self) {
        self.faces.clear();
    }
}

impl EditedFaces {
    /// Notes the faces `marked` stale by an edit confined to `region` (each with the stamp
    /// of its last capture): each may change only where the region projects onto it. A face
    /// the region does not project onto in part (it reaches the probe) is dropped: it will
    /// be lit whole.
    pub fn mark(&mut self, marked: &[(Slot, Face, CaptureStamp)], region: (Vec3, Vec3)) {
        for &(slot, face, stamp) in marked {
            let (origin, n) = (stamp.origin, stamp.face_resolution);
            let old = (self.faces.iter())
                .position(|e| e.slot == slot && e.face == face)
                .map(|i| self.faces.swap_remove(i))
                .filter(|e| e.origin == origin && e.n == n);
            let rect = face_box_rect(face, origin, region, n, EDIT_MARGIN_TEXELS);
            let whole = TexelRect {
                x0: 0,
                y0: 0,
                x1: n,
                y1: n,
            };
            let rect = match (old, rect) {
                (_, None) => continue,
                (None, Some(r)) => r,
                (Some(e), Some(r)) => union(e.rect, r),
            };
            if slot == Slot::Eye || rect == whole {
                continue;
            }
            self.faces.push(EditedFace {
                slot,
                face,
                origin,
                n,
                rect,
            });
        }
    }

    /// The part of each of `captures` an edit changed, as [`FrameInput::partial`] lists them;
    /// those faces are forgotten (captured now, they are whole again), and so is every face
    /// whose slot holds another probe now (its data is not the one the part was found in).
    pub fn take(&mut self, captures: &[CaptureInput], input: &FrameInput) -> Vec<Relight> {
        let views = [
            Some(&input.grid),
            input.previous.as_ref(),
            input.prefetch.as_ref(),
        ];
        self.faces.retain(|e| {
            (views.iter().flatten())
                .any(|v| v.slot == e.slot && v.origin == e.origin && v.face_resolution == e.n)
        });
        let mut out = Vec::new();
        for c in captures {
            let found = (self.faces.iter()).position(|e| e.slot == c.slot && e.face == c.face);
            let Some(e) = found.map(|i| self.faces.swap_remove(i)) else {
                continue;
            };
            // An orthographic face is not a cube face: captured whole.
            if e.origin == c.origin && e.n == c.face_resolution && c.ortho.is_none() {
                (out).push(Relight {
                    slot: e.slot,
                    face: e.face,
                    rect: e.rect,
                });
            }
        }
        out
    }
}

/// The rectangle holding `a` and `b`.
fn union(a: TexelRect, b: TexelRect) -> TexelRect {
    TexelRect {
        x0: a.x0.min(b.x0),
        y0: a.y0.min(b.y0),
        x1: a.x1.max(b.x1),
        y1: a.y1.max(b.y1),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn stamp(origin: Vec3) -> CaptureStamp {
        CaptureStamp {
            origin,
            face_resolution: 64,
            scene_generation: 0,
        }
    }

    /// A box ahead of a face is remembered as the part of it; two edits join; a box around
    /// the probe, or one that covers the whole face, leaves the face to be lit whole.
    #[test]
    fn a_face_remembers_where_an_edit_falls_on_it() {
        let mut edited = EditedFaces::default();
        let marked = [(Slot::StableA, Face::NegZ, stamp(Vec3::ZERO))];
        let small = (Vec3::new(-0.5, -0.5, -10.5), Vec3::new(0.5, 0.5, -9.5));
        edited.mark(&marked, small);
        let first = edited.faces[0].rect;
        assert!(first.area() > 0 && first.area() < 64 * 64 / 4, "{first:?}");
        edited.mark(&marked, (small.0 + Vec3::X * 3.0, small.1 + Vec3::X * 3.0));
        assert_eq!(edited.faces.len(), 1);
        assert!(edited.faces[0].rect.area() > first.area(), "the parts join");
        edited.mark(&marked, (Vec3::splat(-1.0), Vec3::splat(1.0)));
        assert!(edited.faces.is_empty(), "a box around the probe: lit whole");
        edited.mark(&[(Slot::Eye, Face::NegZ, stamp(Vec3::ZERO))], small);
        assert!(
            edited.faces.is_empty(),
            "eye faces are captured every frame"
        );
        edited.mark(&marked, small);
        edited.forget();
        assert!(edited.faces.is_empty());
    }
}
