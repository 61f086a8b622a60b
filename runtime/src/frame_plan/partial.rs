//! The part of each stable face an edit changed ([`EditedFaces`]): when the face is captured
//! again at the same origin, only where the edit's geometry may show is captured and lit
//! again, and of the rest only the texels whose light the edit may have changed (a shadow
//! that came or went, a changed light's reach) are lit again ([`FrameInput::partial`]).
//! Everything else keeps its capture and its light, which a capture afresh would equal.

use glam::Vec3;
use texel_probes::cube::Face;
use texel_probes::probe_set::Slot;
use texel_probes::schedule::CaptureStamp;
use texel_probes::visibility::{TexelRect, face_box_rect};
use texel_render::input::{CaptureInput, FrameInput, LightFilter, PartialFace};

/// Texels around an edit's rectangle lit again too: a texel's outline, neighbour bits and
/// silhouette rays read its neighbours (one texel; one more for safety).
pub const EDIT_MARGIN_TEXELS: u32 = 2;

/// Where an edit changed the scene ([`super::FrameDriver::level_edited`]).
#[derive(Debug, Clone, PartialEq)]
pub struct EditArea {
    /// Every face that may see this box is marked stale: where the geometry, its shadows
    /// and the light may have changed.
    pub region: (Vec3, Vec3),
    /// Where geometry or materials changed (old and new bounds together): captured and lit
    /// again. `None` when nothing drawn moved (a light alone).
    pub changed: Option<(Vec3, Vec3)>,
    /// Which texels of the region outside `changed` are lit again.
    pub filter: LightFilter,
    /// The objects (by index in the scene) rewritten in place: the rest stayed where they
    /// were ([`PartialFace::edited`]). `None`: not known (objects added or removed).
    pub objects: Option<Vec<u32>>,
}

impl EditArea {
    /// An edit anywhere in `region`: all of it captured and lit again (which objects it
    /// changed not known).
    pub fn whole(region: (Vec3, Vec3)) -> Self {
        EditArea {
            region,
            changed: Some(region),
            filter: LightFilter::default(),
            objects: None,
        }
    }

    /// Both edits in one.
    pub fn union(&self, other: &EditArea) -> EditArea {
        let join = |a: (Vec3, Vec3), b: (Vec3, Vec3)| (a.0.min(b.0), a.1.max(b.1));
        EditArea {
            region: join(self.region, other.region),
            changed: match (self.changed, other.changed) {
                (Some(a), Some(b)) => Some(join(a, b)),
                (a, b) => a.or(b),
            },
            filter: self.filter.union(&other.filter),
            objects: objects_union(&self.objects, &other.objects),
        }
    }
}

/// The objects of two edits: all of both, unless either is not known.
fn objects_union(a: &Option<Vec<u32>>, b: &Option<Vec<u32>>) -> Option<Vec<u32>> {
    let (a, b) = (a.as_ref()?, b.as_ref()?);
    let mut all: Vec<u32> = a.iter().chain(b).copied().collect();
    all.sort_unstable();
    all.dedup();
    Some(all)
}

/// A stable face an edit marked stale, and the texels it can have changed.
#[derive(Debug, Clone, PartialEq)]
struct EditedFace {
    slot: Slot,
    face: Face,
    /// Where and at what resolution the face's data was captured.
    origin: Vec3,
    n: u32,
    /// Captured and lit again (may be empty).
    rect: TexelRect,
    /// May be lit again, as `filter` says.
    light: TexelRect,
    filter: LightFilter,
    /// The objects rewritten since the face was last captured (`None`: not known).
    edited: Option<Vec<u32>>,
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
    /// Notes the faces `marked` stale by the edit `area` (each with the stamp of its last
    /// capture): each may change only where the area projects onto it. A face where the
    /// changed geometry covers the whole face or reaches the probe is dropped: it will be
    /// captured and lit whole.
    pub fn mark(&mut self, marked: &[(Slot, Face, CaptureStamp)], area: &EditArea) {
        for &(slot, face, stamp) in marked {
            let (origin, n) = (stamp.origin, stamp.face_resolution);
            let old = (self.faces.iter())
                .position(|e| e.slot == slot && e.face == face)
                .map(|i| self.faces.swap_remove(i))
                .filter(|e| e.origin == origin && e.n == n);
            let whole = TexelRect {
                x0: 0,
                y0: 0,
                x1: n,
                y1: n,
            };
            // `None`: the face cannot see the region after all; nothing to light.
            let light =
                face_box_rect(face, origin, area.region, n, EDIT_MARGIN_TEXELS).unwrap_or(EMPTY);
            // `None`: the changed box does not show on this face.
            let rect = (area.changed)
                .and_then(|b| face_box_rect(face, origin, b, n, EDIT_MARGIN_TEXELS))
                .unwrap_or(EMPTY);
            let mut edited = EditedFace {
                slot,
                face,
                origin,
                n,
                rect,
                light: union(light, rect),
                filter: area.filter.clone(),
                edited: area.objects.clone(),
            };
            if let Some(e) = old {
                edited.rect = union(e.rect, edited.rect);
                edited.light = union(e.light, edited.light);
                edited.filter = e.filter.union(&edited.filter);
                edited.edited = objects_union(&e.edited, &edited.edited);
            }
            if slot == Slot::Eye || edited.rect == whole {
                continue;
            }
            self.faces.push(edited);
        }
    }

    /// The part of each of `captures` an edit changed, as [`FrameInput::partial`] lists them;
    /// those faces are forgotten (captured now, they are whole again), and so is every face
    /// whose slot holds another probe now (its data is not the one the part was found in).
    pub fn take(&mut self, captures: &[CaptureInput], input: &FrameInput) -> Vec<PartialFace> {
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
                out.push(PartialFace {
                    slot: e.slot,
                    face: e.face,
                    rect: e.rect,
                    light: e.light,
                    filter: e.filter,
                    edited: e.edited,
                });
            }
        }
        out
    }
}

/// No texels.
const EMPTY: TexelRect = TexelRect {
    x0: 0,
    y0: 0,
    x1: 0,
    y1: 0,
};

/// The rectangle holding `a` and `b` (an empty one holds nothing).
fn union(a: TexelRect, b: TexelRect) -> TexelRect {
    if a.area() == 0 {
        return b;
    }
    if b.area() == 0 {
        return a;
    }
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
        edited.mark(&marked, &EditArea::whole(small));
        let first = edited.faces[0].rect;
        assert!(first.area() > 0 && first.area() < 64 * 64 / 4, "{first:?}");
        assert_eq!(edited.faces[0].light, first);
        let moved = (small.0 + Vec3::X * 3.0, small.1 + Vec3::X * 3.0);
        edited.mark(&marked, &EditArea::whole(moved));
        assert_eq!(edited.faces.len(), 1);
        assert!(edited.faces[0].rect.area() > first.area(), "the parts join");
        let around = (Vec3::splat(-1.0), Vec3::splat(1.0));
        edited.mark(&marked, &EditArea::whole(around));
        assert!(edited.faces.is_empty(), "a box around the probe: lit whole");
        edited.mark(
            &[(Slot::Eye, Face::NegZ, stamp(Vec3::ZERO))],
            &EditArea::whole(small),
        );
        assert!(
            edited.faces.is_empty(),
            "eye faces are captured every frame"
        );
        edited.mark(&marked, &EditArea::whole(small));
        edited.forget();
        assert!(edited.faces.is_empty());
    }

    /// An object's shadows may reach around the probe: the face is still captured only
    /// where the object shows, and lit elsewhere only as its filter says; a light changed
    /// alone captures nothing.
    #[test]
    fn shadows_around_the_probe_leave_the_capture_where_the_object_shows() {
        let mut edited = EditedFaces::default();
        let marked = [(Slot::StableA, Face::NegZ, stamp(Vec3::ZERO))];
        let object = (Vec3::new(-0.5, -0.5, -10.5), Vec3::new(0.5, 0.5, -9.5));
        let filter = LightFilter {
            casters: vec![object],
            lit: Vec::new(),
        };
        let area = EditArea {
            region: (Vec3::splat(-12.0), Vec3::splat(12.0)),
            changed: Some(object),
            filter: filter.clone(),
            objects: Some(vec![3]),
        };
        edited.mark(&marked, &area);
        let e = &edited.faces[0];
        assert!(e.rect.area() > 0 && e.rect.area() < 64 * 64 / 4, "{e:?}");
        assert_eq!(e.light.area(), 64 * 64, "the shadows may fall anywhere");
        assert_eq!(e.filter, filter);
        let light = EditArea {
            changed: None,
            ..area
        };
        let mut alone = EditedFaces::default();
        alone.mark(&marked, &light);
        assert_eq!(alone.faces[0].rect.area(), 0, "nothing to capture");
        assert_eq!(alone.faces[0].light.area(), 64 * 64);
    }
}
