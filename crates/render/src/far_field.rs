//! The eye probe's far field. The eye is captured at the camera every frame, and drawing
//! everything within the capture range into each of its faces cost most of a large level's
//! frame (a town of 10,000 entities: some 2,000 objects a face). Yet what lies far away
//! looks the same from anywhere near the camera: seen from a point `δ` away, a surface `D`
//! away moves by at most `δ / D` radians. So each frame the eye draws only the objects and
//! terrain chunks that reach within `D + overlap` of it ([`FarFieldInput::distance`],
//! [`FarFieldInput::overlap`]; depth along the face's axis, by their bounds); those wholly
//! beyond `D` are drawn into far faces of its own (these textures), captured at the camera
//! too, but again only once the camera is [`REFRESH_CELLS`] of a cell away from where they
//! were (one face a frame, the farthest first; at once past [`LIMIT_CELLS`], the overlap, or
//! when the scene, the face size or the capture mode changed: of an edit in place, only the
//! faces its objects reach into, `FarField::forget_reaching`). Each frame an eye face takes
//! its part of the view and its depth from its far face, and what is near is drawn over it,
//! depth-tested against it (`passes::capture`).
//!
//! `D` is `REFRESH_CELLS × cell × n`, so far content sits at most half a texel (a texel at a
//! face's centre spans `2 / n` radians) from where the eye itself would see it when its face
//! is due again, a whole one at the limit. The split is by whole objects, so nothing near
//! the camera hides what lies behind it from a far face, and an object the eye draws is drawn
//! whole, from the eye. The overlap covers the camera's move since the far face's capture: an
//! object not in the far face reached within `D` of where it was captured, so within
//! `D + overlap` of the eye, which draws it (an object in both, near `D`, is drawn twice, a
//! little apart). A scene with nothing wholly beyond `D` draws exactly what it drew without
//! a far field; where the far faces were captured at the eye's origin, the eye holds what it
//! would drawing everything.

use glam::Vec3;
use texel_probes::cube::Face;

use crate::context::GpuContext;
use crate::gpu_scene::CaptureCull;
use crate::passes::capture::CaptureMode;
use crate::probe_store::{
    ALBEDO_FORMAT, DEPTH_FORMAT, GEO_FORMAT, ID_FORMAT, LayeredTexture, SHADING_FORMAT,
};

/// A far face is captured again once the camera is this many cells from where it was (one
/// face a frame).
pub const REFRESH_CELLS: f32 = 0.5;
/// A far face is captured again at once when the camera is this many cells from where it
/// was ([`FarFieldInput::overlap`]).
pub const LIMIT_CELLS: f32 = 1.0;

/// The far field of a frame: the size of the cell the camera is in, the unit of how far
/// the camera may move before a far face is captured again.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FarFieldInput {
    /// The camera cell's size, world units.
    pub cell: f32,
}

impl FarFieldInput {
    /// Depth beyond which an object is drawn into the far faces, on faces of `n` texels.
    pub fn distance(&self, n: u32) -> f32 {
        REFRESH_CELLS * self.cell * n as f32
    }

    /// How far the camera may be from where a far face was captured; the eye draws what
    /// reaches within `distance + overlap`.
    pub fn overlap(&self) -> f32 {
        LIMIT_CELLS * self.cell
    }
}

/// What a far face's contents depend on besides its origin.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Key {
    n: u32,
    mode: CaptureMode,
    cull: CaptureCull,
    cell: f32,
}

/// The far faces: their textures and where each was captured.
#[derive(Default)]
pub(crate) struct FarField {
    textures: Option<FarTextures>,
    captured: [Option<(Vec3, Key)>; 6],
}

/// The capture targets of the six far faces.
pub(crate) struct FarTextures {
    pub(crate) n: u32,
    pub(crate) geo: LayeredTexture,
    pub(crate) ids: LayeredTexture,
    pub(crate) albedo: LayeredTexture,
    pub(crate) shading: LayeredTexture,
    pub(crate) depth: LayeredTexture,
}

impl FarTextures {
    fn new(ctx: &GpuContext, n: u32) -> Self {
        use wgpu::TextureUsages as U;
        let gbuf = U::RENDER_ATTACHMENT | U::COPY_SRC;
        let t = |what: &str, format| {
            LayeredTexture::new(ctx, &format!("far_field::{what}"), n, format, gbuf)
        };
        FarTextures {
            n,
            geo: t("geo", GEO_FORMAT),
            ids: t("ids", ID_FORMAT),
            albedo: t("albedo", ALBEDO_FORMAT),
            shading: t("shading", SHADING_FORMAT),
            depth: t("depth", DEPTH_FORMAT),
        }
    }

    /// The four textures an eye face copies, in the order of the slot's (geo, ids, albedo,
    /// shading).
    pub(crate) fn targets(&self) -> [&LayeredTexture; 4] {
        [&self.geo, &self.ids, &self.albedo, &self.shading]
    }
}

impl FarField {
    /// Forgets every far face (the scene changed).
    pub(crate) fn forget(&mut self) {
        self.captured = [None; 6];
    }

    /// Forgets the far faces an edit in place can have changed: those where some corner of
    /// one of `boxes` (each edited object's draw ranges, as they were and as they are) lies
    /// beyond the face's distance along its axis. A far face draws only the ranges whose
    /// every corner does (`CapturePass::record`), and a range lies within its object's box,
    /// so of an object whose box lies wholly within the distance it drew nothing, and draws
    /// nothing: the face is what a capture afresh would make.
    pub(crate) fn forget_reaching(&mut self, boxes: &[(Vec3, Vec3)]) {
        for (face, captured) in Face::ALL.into_iter().zip(&mut self.captured) {
            let Some((at, key)) = *captured else {
                continue;
            };
            let beyond = FarFieldInput { cell: key.cell }.distance(key.n);
            let axis = face.axis();
            let reaches = |&(lo, hi): &(Vec3, Vec3)| {
                // The box's farthest corner along the axis (a unit axis: one coordinate).
                let far = Vec3::select(axis.cmpgt(Vec3::ZERO), hi, lo);
                let depth = (far - at).dot(axis);
                depth.is_nan() || depth > beyond
            };
            if boxes.iter().any(reaches) {
                *captured = None;
            }
        }
    }

    /// The textures, once made.
    pub(crate) fn drawn(&self) -> Option<&FarTextures> {
        self.textures.as_ref()
    }

    /// GPU bytes of the far faces.
    pub(crate) fn bytes(&self) -> u64 {
        self.textures.as_ref().map_or(0, |t| {
            (t.targets().into_iter().chain([&t.depth]))
                .map(|l| crate::memory::texture_bytes(&l.texture))
                .sum()
        })
    }

    /// The textures for faces of `n` texels (made, or made again at another size).
    pub(crate) fn textures(&mut self, ctx: &GpuContext, n: u32) -> &FarTextures {
        if self.textures.as_ref().is_some_and(|t| t.n != n) {
            self.textures = None;
            self.forget();
        }
        self.textures
            .get_or_insert_with(|| FarTextures::new(ctx, n))
    }

    /// Which of the eye's `faces` (captured this frame at `origin` on faces of `n` texels)
    /// need their far face captured first, and remembers them as captured there: those never
    /// captured for this scene, size and mode, or [`LIMIT_CELLS`] away; and of the rest, the
    /// one farthest from `origin` if it is [`REFRESH_CELLS`] away.
    pub(crate) fn plan(
        &mut self,
        far: FarFieldInput,
        faces: &[Face],
        origin: Vec3,
        (n, mode, cull): (u32, CaptureMode, CaptureCull),
    ) -> Vec<Face> {
        let key = Key {
            n,
            mode,
            cull,
            cell: far.cell,
        };
        let away = |f: Face| match self.captured[f.index()] {
            Some((at, k)) if k == key => (at - origin).length(),
            _ => f32::INFINITY,
        };
        let mut due: Vec<Face> = (faces.iter().copied())
            .filter(|&f| away(f) > LIMIT_CELLS * far.cell)
            .collect();
        let stale = (faces.iter().copied())
            .filter(|f| !due.contains(f))
            .map(|f| (away(f), f))
            .filter(|&(d, _)| d > REFRESH_CELLS * far.cell)
            .max_by(|a, b| a.0.total_cmp(&b.0));
        due.extend(stale.map(|(_, f)| f));
        for &f in &due {
            self.captured[f.index()] = Some((origin, key));
        }
        due
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const FAR: FarFieldInput = FarFieldInput { cell: 1.0 };
    const AT: (u32, CaptureMode, CaptureCull) = (128, CaptureMode::Surface, CaptureCull::Footprint);

    #[test]
    fn the_split_follows_the_cell_and_the_face_size() {
        assert_eq!((FAR.distance(128), FAR.overlap()), (64.0, 1.0));
        assert_eq!(FarFieldInput { cell: 2.0 }.distance(64), 64.0);
        assert_eq!(FarFieldInput { cell: 2.0 }.overlap(), 2.0);
    }

    #[test]
    fn far_faces_are_captured_when_new_then_one_a_frame_once_stale() {
        let mut far = FarField::default();
        let faces = [Face::PosX, Face::NegZ, Face::PosY];
        let o = Vec3::ZERO;
        assert_eq!(far.plan(FAR, &faces, o, AT), faces.to_vec());
        // Nothing to do until the camera is half a cell away.
        assert!(far.plan(FAR, &faces, o + Vec3::X * 0.4, AT).is_empty());
        // Then one face a frame, until each was captured nearer.
        let o2 = o + Vec3::X * 0.6;
        let first = far.plan(FAR, &faces, o2, AT);
        assert_eq!(first.len(), 1);
        let second = far.plan(FAR, &faces, o2, AT);
        assert_eq!(second.len(), 1);
        assert_ne!(first, second);
        assert_eq!(far.plan(FAR, &faces, o2, AT).len(), 1);
        assert!(far.plan(FAR, &faces, o2, AT).is_empty());
        // A whole cell away, every face at once.
        assert_eq!(far.plan(FAR, &faces, o2 + Vec3::Z * 1.1, AT).len(), 3);
        // A new face at once, and all of them for another size or after `forget`.
        assert_eq!(far.plan(FAR, &[Face::NegY], o2, AT), vec![Face::NegY]);
        let other = (64, CaptureMode::Surface, CaptureCull::Footprint);
        assert_eq!(far.plan(FAR, &faces, o2 + Vec3::Z * 1.1, other).len(), 3);
        far.forget();
        assert_eq!(far.plan(FAR, &faces, o2 + Vec3::Z * 1.1, other).len(), 3);
    }
}
