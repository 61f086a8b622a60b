//! What a frame's passes work on, planned before they run: the texels to capture and light
//! (`capture_rects`, `shade_jobs`, `settle_edges`), the faces whose runs to recompute
//! (`runs_to_compute`) and the faces to splat (`drawn_faces`).

use texel_probes::cube::{Face, FaceMask};
use texel_probes::probe_set::Slot;
use texel_probes::visibility::{TexelRect, face_cone_rect};

use crate::input::{FrameInput, PartialFace, ProbeView, Schedule};
use crate::passes::cull::Visit;
use crate::passes::shade::{JobFilter, ShadeJob};
use crate::probe_store::ProbeStore;
use crate::view::ViewGlobals;

/// The stable faces whose runs to recompute: in our schedule, the faces just lit and those
/// the paper schedule lit since our schedule last drew (it draws texel by texel and leaves
/// its faces `stale`); in the paper schedule none (they are added to `stale`).
pub(super) fn runs_to_compute(
    stale: &mut [FaceMask; 3],
    schedule: Schedule,
    lit: [FaceMask; 3],
) -> [FaceMask; 3] {
    let mut out = lit;
    for (stale, lit) in stale.iter_mut().zip(&mut out) {
        if schedule == Schedule::Ours {
            *lit = lit.union(*stale);
            *stale = FaceMask::EMPTY;
        } else {
            *stale = stale.union(*lit);
            *lit = FaceMask::EMPTY;
        }
    }
    out
}

/// What to light this frame: every captured face, whole (or the part an edit changed:
/// [`FrameInput::partial`]); and the edges of each valid face
/// next to a face captured this frame but not captured itself (its seam texels looked
/// across into data that has just changed).
pub(super) fn shade_jobs(input: &FrameInput, rects: &[Option<TexelRect>]) -> Vec<ShadeJob> {
    let probes: Vec<&ProbeView> = [
        Some(&input.eye),
        Some(&input.grid),
        input.previous.as_ref(),
        input.prefetch.as_ref(),
    ]
    .into_iter()
    .flatten()
    .collect();
    let valid_of = |slot| {
        probes
            .iter()
            .find(|p| p.slot == slot)
            .map_or(FaceMask::ALL, |p| p.valid)
    };
    let mut jobs: Vec<ShadeJob> = input
        .captures
        .iter()
        .zip(rects.iter().chain(std::iter::repeat(&None)))
        .map(|(c, rect)| ShadeJob {
            slot: c.slot,
            face: c.face,
            origin: c.origin,
            valid: valid_of(c.slot),
            border: false,
            view_cull: c.slot == Slot::Eye && input.schedule == Schedule::Ours,
            rect: *rect,
            filter: None,
        })
        .collect();
    // A stable face an edit changed in part is lit only where it may have changed: where
    // its geometry may show, and where its shadows or a changed light reach, texel by
    // texel (`LightFilter`).
    for j in jobs.iter_mut() {
        if let Some(p) = partial_of(input, j.slot, j.face) {
            j.rect = Some(p.light);
            j.filter = Some(JobFilter::new(p.rect, &p.filter));
        }
    }
    // Faces lit again for a moving object's shadow: whole, unless captured anyway (stable
    // slots only: the eye's texels are lit as the view needs them).
    for r in input.relight.iter().filter(|r| r.slot != Slot::Eye) {
        let (slot, face) = (r.slot, r.face);
        let captured = (input.captures.iter()).any(|c| c.slot == slot && c.face == face);
        let Some(p) = probes.iter().find(|p| p.slot == slot) else {
            continue;
        };
        if captured
            || !p.valid.contains(face)
            || jobs.iter().any(|j| j.slot == slot && j.face == face)
        {
            continue;
        }
        jobs.push(ShadeJob {
            slot,
            face,
            origin: p.origin,
            valid: p.valid,
            border: false,
            view_cull: false,
            rect: Some(r.rect),
            filter: (r.filter.as_ref()).map(|f| JobFilter::new(EMPTY, f)),
        });
    }
    for p in &probes {
        let captured: Vec<Face> = input
            .captures
            .iter()
            .filter(|c| c.slot == p.slot)
            .map(|c| c.face)
            .collect();
        // A face captured in part changed no texel at its edges unless its rectangle
        // reaches one: its neighbours' seams read the same data.
        let seams: Vec<Face> = (input.captures.iter())
            .filter(|c| c.slot == p.slot)
            .filter(|c| {
                let part = partial_of(input, c.slot, c.face);
                part.is_none_or(|part| reaches_edge(part.rect, c.face_resolution))
            })
            .map(|c| c.face)
            .collect();
        for face in p.valid.iter() {
            let touched = seams.iter().any(|c| *c != face && c.opposite() != face);
            // Lit again whole for a moving shadow: its edges with it.
            let relit = (input.relight.iter()).any(|r| {
                r.slot == p.slot
                    && r.face == face
                    && r.filter.is_none()
                    && r.rect.area() == u64::from(p.face_resolution).pow(2)
            });
            if touched && !captured.contains(&face) && !relit {
                jobs.push(ShadeJob {
                    slot: p.slot,
                    face,
                    origin: p.origin,
                    valid: p.valid,
                    border: true,
                    view_cull: false,
                    rect: None,
                    filter: None,
                });
            }
        }
    }
    jobs
}

/// The part of stable face `face` of `slot` an edit changed, when it is captured in part
/// this frame (our schedule, a cube face).
fn partial_of(input: &FrameInput, slot: Slot, face: Face) -> Option<&PartialFace> {
    let captured = (input.captures.iter()).find(|c| c.slot == slot && c.face == face)?;
    let ours = input.schedule == Schedule::Ours && captured.ortho.is_none();
    (input.partial.iter()).find(|r| ours && slot != Slot::Eye && r.slot == slot && r.face == face)
}

/// No texels.
const EMPTY: TexelRect = TexelRect {
    x0: 0,
    y0: 0,
    x1: 0,
    y1: 0,
};

/// Whether `rect` (on a face of `n` texels) reaches the face's edge, or covers nothing:
/// `false` for an empty one.
fn reaches_edge(rect: TexelRect, n: u32) -> bool {
    rect.area() > 0 && (rect.x0 == 0 || rect.y0 == 0 || rect.x1 >= n || rect.y1 >= n)
}

/// Keeps `owed` (per slot, the stable faces lit without the silhouette edges' search) and,
/// when this frame searches (`edges`), adds a whole-face job for each owed face of a stable
/// probe that no job lights whole already: switching from the paper schedule (or from
/// marching) shows the same picture as splatting all along.
pub(super) fn settle_edges(
    jobs: &mut Vec<ShadeJob>,
    input: &FrameInput,
    owed: &mut [FaceMask; 3],
    edges: bool,
) {
    let whole = |j: &ShadeJob| j.slot != Slot::Eye && !j.border && j.rect.is_none();
    if !edges {
        for j in jobs.iter().filter(|j| whole(j)) {
            owed[j.slot.index()].insert(j.face);
        }
        return;
    }
    let stable = [
        Some(&input.grid),
        input.previous.as_ref(),
        input.prefetch.as_ref(),
    ];
    for p in stable.into_iter().flatten() {
        for face in owed[p.slot.index()].iter() {
            let lit = jobs
                .iter()
                .any(|j| whole(j) && j.slot == p.slot && j.face == face);
            if p.valid.contains(face) && !lit {
                jobs.push(ShadeJob {
                    slot: p.slot,
                    face,
                    origin: p.origin,
                    valid: p.valid,
                    border: false,
                    view_cull: false,
                    rect: None,
                    filter: None,
                });
            }
        }
    }
    for j in jobs.iter().filter(|j| whole(j)) {
        let o = &mut owed[j.slot.index()];
        *o = o.difference(FaceMask::single(j.face));
    }
}

/// How far past the view cone, in texels (of 2/n radians), an eye face is still captured and
/// lit: a texel is drawn when a sphere of 2.5 texels around it reaches the view
/// (`quad_in_view`), and its outline and neighbour bits read one texel further.
const EYE_CONE_MARGIN_TEXELS: f32 = 4.0;

/// Per capture, the texels to capture and light: in our schedule with a perspective camera,
/// an eye face only where the view cone meets it (the eye sits at the camera, so that is
/// exact up to the margin; an empty rectangle when it misses the face); a stable face an
/// edit changed in part ([`FrameInput::partial`]) only there; otherwise the whole face.
pub(super) fn capture_rects(
    input: &FrameInput,
    globals: &ViewGlobals,
    store: &ProbeStore,
) -> Vec<Option<TexelRect>> {
    let normals: Vec<glam::Vec3> = globals
        .side_planes()
        .iter()
        .map(|p| glam::Vec3::new(p[0], p[1], p[2]))
        .collect();
    let cone = input.camera.ortho_height.is_none() && input.schedule == Schedule::Ours;
    let partial =
        |c: &crate::input::CaptureInput| partial_of(input, c.slot, c.face).map(|r| r.rect);
    input
        .captures
        .iter()
        .map(|c| {
            let eye = (c.slot == Slot::Eye && cone).then(|| {
                let n = store.slot(c.slot).n;
                let margin = EYE_CONE_MARGIN_TEXELS * 2.0 / n as f32;
                face_cone_rect(&normals, c.face, n, margin).unwrap_or(TexelRect {
                    x0: 0,
                    y0: 0,
                    x1: 0,
                    y1: 0,
                })
            });
            eye.or_else(|| partial(c))
        })
        .collect()
}

/// The (slot, face) pairs the frame splats, and how the cull pass visits each: our
/// schedule walks the draw lists (the eye's lit texels; stable run heads, with runs on).
pub(super) fn drawn_faces(input: &FrameInput, runs: bool) -> Vec<(Slot, Face, Visit)> {
    let visit = |slot: Slot| match input.schedule {
        Schedule::Ours if slot == Slot::Eye || runs => Visit::List,
        _ => Visit::Scan,
    };
    [Some(&input.eye), Some(&input.grid), input.previous.as_ref()]
        .into_iter()
        .flatten()
        .flat_map(|p| p.draw.iter().map(move |f| (p.slot, f, visit(p.slot))))
        .collect()
}
