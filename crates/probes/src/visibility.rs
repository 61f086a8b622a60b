//! Which cube faces of a probe can contribute to the camera's view.
//!
//! A face of a probe at `o` covers the pyramid of points whose direction from `o` falls in
//! that face, out to the capture range. Splat quads of border texels reach a little past
//! the face edge, so the pyramid is widened to `|u|, |v| <= extent` ([`splat_extent`]).
//! A face is needed when this truncated pyramid intersects the camera frustum (near..far).
//!
//! The test is a full separating-axis test between the two convex bodies (face normals of
//! both and the cross products of their edge directions), with a small slack that keeps
//! touching pairs: it never culls a face that intersects the frustum, and culls every face
//! that is clearly apart from it. Probe origin and camera may differ (grid and previous
//! probes).

use std::fmt;

use glam::Vec3;

use crate::cube::{Face, FaceMask, direction_from_face_uv};

/// Largest splat-quad half-size, in texels, that visibility allows for.
pub const MAX_QUAD_HALF_SIZE_TEXELS: f32 = 2.5;

/// Slack, world units, before a vertex counts as outside a plane (keeps the test
/// conservative under rounding).
const PLANE_EPSILON: f32 = 1e-4;

/// Half-size in face coordinates of a face pyramid widened so that splat quads of
/// half-size up to [`MAX_QUAD_HALF_SIZE_TEXELS`] stay inside: `1 + 4 / n`.
pub fn splat_extent(face_resolution: u32) -> f32 {
    let n = face_resolution.max(1) as f32;
    1.0 + (2.0 * MAX_QUAD_HALF_SIZE_TEXELS - 1.0) / n
}

/// A camera as far as visibility is concerned.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraView {
    /// Camera position.
    pub position: Vec3,
    /// View direction (any length > 0).
    pub forward: Vec3,
    /// Up hint (not parallel to `forward`).
    pub up: Vec3,
    /// Vertical field of view, radians, in `(0, π)`.
    pub fov_y: f32,
    /// Width / height (> 0).
    pub aspect: f32,
    /// Near plane distance (> 0).
    pub near: f32,
    /// Far plane distance (> near).
    pub far: f32,
}

/// A [`CameraView`] that does not describe a frustum.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ViewError {
    /// A field is NaN or infinite.
    NonFinite,
    /// `forward` is zero or `up` is parallel to it.
    DegenerateBasis,
    /// `fov_y` is outside `(0, π)`.
    FieldOfView(f32),
    /// `aspect` is not positive.
    Aspect(f32),
    /// Not `0 < near < far`.
    ClipRange {
        /// Near distance.
        near: f32,
        /// Far distance.
        far: f32,
    },
}

impl fmt::Display for ViewError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ViewError::NonFinite => write!(f, "camera has a non-finite field"),
            ViewError::DegenerateBasis => write!(f, "camera forward is zero or parallel to up"),
            ViewError::FieldOfView(v) => write!(f, "fov_y {v} must be in (0, pi)"),
            ViewError::Aspect(v) => write!(f, "aspect {v} must be > 0"),
            ViewError::ClipRange { near, far } => {
                write!(f, "need 0 < near < far, got near {near}, far {far}")
            }
        }
    }
}

impl std::error::Error for ViewError {}

/// A plane `normal · p + d = 0`; the inside is `normal · p + d >= 0`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    /// Unit normal pointing inside.
    pub normal: Vec3,
    /// Offset.
    pub d: f32,
}

impl Plane {
    /// The plane through `point` with inward `normal` (normalized here).
    pub fn through(point: Vec3, normal: Vec3) -> Plane {
        let normal = normal.normalize();
        Plane {
            normal,
            d: -normal.dot(point),
        }
    }

    /// Signed distance of `p` (positive inside).
    pub fn distance(&self, p: Vec3) -> f32 {
        self.normal.dot(p) + self.d
    }
}

/// A convex body: inward face planes, corner points and edge directions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConvexHull<const P: usize, const V: usize, const E: usize> {
    /// Bounding planes, normals inward.
    pub planes: [Plane; P],
    /// Corner points.
    pub vertices: [Vec3; V],
    /// Directions of its edges (one per parallel family).
    pub edges: [Vec3; E],
}

impl<const P: usize, const V: usize, const E: usize> ConvexHull<P, V, E> {
    /// Whether `p` is inside (or on) every plane.
    pub fn contains(&self, p: Vec3) -> bool {
        self.planes
            .iter()
            .all(|pl| pl.distance(p) >= -PLANE_EPSILON)
    }

    /// Separating-axis test over both bodies' face normals and all edge-pair cross
    /// products: exact for convex bodies up to a slack of `1e-4` world units, which only ever
    /// keeps a touching pair (never drops an intersecting one).
    pub fn may_intersect<const Q: usize, const W: usize, const F: usize>(
        &self,
        other: &ConvexHull<Q, W, F>,
    ) -> bool {
        let face_axes = self.planes.iter().chain(&other.planes).map(|p| p.normal);
        let edge_axes = self
            .edges
            .iter()
            .flat_map(|a| other.edges.iter().map(move |b| a.cross(*b)))
            .filter(|axis| axis.length_squared() > 1e-10)
            .map(Vec3::normalize);
        let mut axes = face_axes.chain(edge_axes);
        !axes.any(|axis| separates(axis, &self.vertices, &other.vertices))
    }
}

/// Whether the projections of `a` and `b` on `axis` are disjoint (beyond the slack).
fn separates(axis: Vec3, a: &[Vec3], b: &[Vec3]) -> bool {
    let (a_min, a_max) = project(axis, a);
    let (b_min, b_max) = project(axis, b);
    a_max < b_min - PLANE_EPSILON || b_max < a_min - PLANE_EPSILON
}

fn project(axis: Vec3, points: &[Vec3]) -> (f32, f32) {
    points
        .iter()
        .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), p| {
            let d = axis.dot(*p);
            (lo.min(d), hi.max(d))
        })
}

/// The camera frustum: planes near, far, left, right, bottom, top; 8 corners; 6 edge
/// directions (4 side edges, right, up).
pub type Frustum = ConvexHull<6, 8, 6>;

/// A face pyramid: 4 side planes through the apex and the depth cap; apex + 4 corners;
/// 6 edge directions (4 side edges, the cap's u and v).
pub type FacePyramid = ConvexHull<5, 5, 6>;

fn validate(view: &CameraView) -> Result<(), ViewError> {
    let scalars = [view.fov_y, view.aspect, view.near, view.far];
    let finite = view.position.is_finite() && view.forward.is_finite() && view.up.is_finite();
    if !finite || scalars.iter().any(|s| !s.is_finite()) {
        return Err(ViewError::NonFinite);
    }
    if view.forward.cross(view.up).length_squared() < 1e-12 {
        return Err(ViewError::DegenerateBasis);
    }
    if !(view.fov_y > 0.0 && view.fov_y < std::f32::consts::PI) {
        return Err(ViewError::FieldOfView(view.fov_y));
    }
    if view.aspect <= 0.0 {
        return Err(ViewError::Aspect(view.aspect));
    }
    if !(view.near > 0.0 && view.far > view.near) {
        return Err(ViewError::ClipRange {
            near: view.near,
            far: view.far,
        });
    }
    Ok(())
}

/// Builds the frustum of `view`, validating it.
pub fn frustum(view: &CameraView) -> Result<Frustum, ViewError> {
    validate(view)?;
    let f = view.forward.normalize();
    let r = f.cross(view.up).normalize();
    let u = r.cross(f);
    let th = (view.fov_y * 0.5).tan();
    let tw = th * view.aspect;
    let o = view.position;
    let planes = [
        Plane::through(o + f * view.near, f),
        Plane::through(o + f * view.far, -f),
        Plane::through(o, r + f * tw),
        Plane::through(o, -r + f * tw),
        Plane::through(o, u + f * th),
        Plane::through(o, -u + f * th),
    ];
    let corner = |dist: f32, sx: f32, sy: f32| o + (f + r * (sx * tw) + u * (sy * th)) * dist;
    let mut vertices = [Vec3::ZERO; 8];
    for (i, v) in vertices.iter_mut().enumerate() {
        let dist = if i < 4 { view.near } else { view.far };
        let sx = if i & 1 == 0 { -1.0 } else { 1.0 };
        let sy = if i & 2 == 0 { -1.0 } else { 1.0 };
        *v = corner(dist, sx, sy);
    }
    let edges = [
        vertices[4] - vertices[0],
        vertices[5] - vertices[1],
        vertices[6] - vertices[2],
        vertices[7] - vertices[3],
        r,
        u,
    ];
    Ok(Frustum {
        planes,
        vertices,
        edges,
    })
}

/// The pyramid of `face` of a probe at `origin`, out to Chebyshev depth `depth_limit`,
/// widened to `|u|, |v| <= extent`.
pub fn face_pyramid(origin: Vec3, face: Face, depth_limit: f32, extent: f32) -> FacePyramid {
    let (a, s, t) = (face.axis(), face.u_axis(), face.v_axis());
    let planes = [
        Plane::through(origin, a * extent + s),
        Plane::through(origin, a * extent - s),
        Plane::through(origin, a * extent + t),
        Plane::through(origin, a * extent - t),
        Plane::through(origin + a * depth_limit, -a),
    ];
    let corner = |u: f32, v: f32| origin + direction_from_face_uv(face, u, v) * depth_limit;
    let vertices = [
        origin,
        corner(-extent, -extent),
        corner(extent, -extent),
        corner(extent, extent),
        corner(-extent, extent),
    ];
    let edges = [
        vertices[1] - origin,
        vertices[2] - origin,
        vertices[3] - origin,
        vertices[4] - origin,
        s,
        t,
    ];
    FacePyramid {
        planes,
        vertices,
        edges,
    }
}

/// Whether `face` of the probe at `origin` may contribute to `frustum`.
pub fn face_visible(
    frustum: &Frustum,
    origin: Vec3,
    face: Face,
    depth_limit: f32,
    extent: f32,
) -> bool {
    face_pyramid(origin, face, depth_limit, extent).may_intersect(frustum)
}

/// The faces of the probe at `origin` that may contribute to `frustum`.
pub fn visible_faces(frustum: &Frustum, origin: Vec3, depth_limit: f32, extent: f32) -> FaceMask {
    Face::ALL
        .into_iter()
        .filter(|&f| face_visible(frustum, origin, f, depth_limit, extent))
        .collect()
}

/// The reference's face mask for the grid and previous probes: faces whose axis lies within
/// this angle of the camera's forward direction, degrees.
pub const REFERENCE_STABLE_FACE_DEG: f32 = 103.0;
/// The reference's face mask for the eye probe, degrees.
pub const REFERENCE_EYE_FACE_DEG: f32 = 98.0;

/// The faces the public reference captures and splats: those whose axis is within
/// `max_angle_deg` of `forward` (`forward · axis ≥ cos max_angle`), whatever the field of
/// view or the probe's position. At [`REFERENCE_STABLE_FACE_DEG`] and
/// [`REFERENCE_EYE_FACE_DEG`] that is 3 to 5 faces. The paper schedule uses it, so that it
/// does the reference's work; our schedule uses [`visible_faces`].
pub fn reference_faces(forward: Vec3, max_angle_deg: f32) -> FaceMask {
    let forward = forward.normalize_or_zero();
    let min_cos = max_angle_deg.to_radians().cos();
    Face::ALL
        .into_iter()
        .filter(|f| forward.dot(f.axis()) >= min_cos)
        .collect()
}

/// A rectangle of texels on a face: columns `x0..x1`, rows `y0..y1`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TexelRect {
    /// First column.
    pub x0: u32,
    /// First row.
    pub y0: u32,
    /// One past the last column.
    pub x1: u32,
    /// One past the last row.
    pub y1: u32,
}

impl TexelRect {
    /// Columns × rows.
    pub fn area(&self) -> u64 {
        u64::from(self.x1 - self.x0) * u64::from(self.y1 - self.y0)
    }
}

/// The texels of `face` (`n` per edge) of a probe at `origin` through which the box
/// `min..max` may be seen, grown by `margin` texels; `None` when none. The box is clipped to
/// the face's view pyramid first (each of its sides, a convex quad, against the pyramid's
/// four planes), so the rectangle bounds exactly what the face can see of it: a box beside
/// the probe that reaches past the face's plane covers only where it shows, not the whole
/// face. A box around the origin gets the whole face.
pub fn face_box_rect(
    face: Face,
    origin: Vec3,
    (min, max): (Vec3, Vec3),
    n: u32,
    margin: u32,
) -> Option<TexelRect> {
    if n == 0 || !(min.is_finite() && max.is_finite()) {
        return None;
    }
    let whole = TexelRect {
        x0: 0,
        y0: 0,
        x1: n,
        y1: n,
    };
    if origin.cmpge(min).all() && origin.cmple(max).all() {
        return Some(whole);
    }
    let (a, u, v) = (face.axis(), face.u_axis(), face.v_axis());
    // Corner i in the face's frame (u, v, depth): bit 0 the max x, bit 1 y, bit 2 z.
    let corners: [Vec3; 8] = std::array::from_fn(|i| {
        let c = Vec3::new(
            if i & 1 == 0 { min.x } else { max.x },
            if i & 2 == 0 { min.y } else { max.y },
            if i & 4 == 0 { min.z } else { max.z },
        ) - origin;
        Vec3::new(c.dot(u), c.dot(v), c.dot(a))
    });
    const SIDES: [[usize; 4]; 6] = [
        [0, 2, 6, 4],
        [1, 3, 7, 5],
        [0, 1, 5, 4],
        [2, 3, 7, 6],
        [0, 1, 3, 2],
        [4, 5, 7, 6],
    ];
    // Inside the pyramid: depth ≥ |u| and depth ≥ |v|.
    let planes = [
        Vec3::new(-1.0, 0.0, 1.0),
        Vec3::new(1.0, 0.0, 1.0),
        Vec3::new(0.0, -1.0, 1.0),
        Vec3::new(0.0, 1.0, 1.0),
    ];
    let scale = (max - min).abs().max_element() + (min - origin).abs().max_element();
    let (mut lo, mut hi) = (
        glam::Vec2::splat(f32::INFINITY),
        glam::Vec2::splat(f32::NEG_INFINITY),
    );
    for side in SIDES {
        let mut poly: Vec<Vec3> = side.iter().map(|&i| corners[i]).collect();
        for plane in planes {
            poly = clip_polygon(&poly, plane);
        }
        for p in poly {
            // On the pyramid's apex: the box touches the probe.
            if p.z <= 1e-6 * scale.max(1e-6) {
                return Some(whole);
            }
            let q = glam::Vec2::new(p.x, p.y) / p.z;
            lo = lo.min(q);
            hi = hi.max(q);
        }
    }
    if lo.x > hi.x {
        return None;
    }
    let to_texel = |c: f32| ((c.clamp(-1.0, 1.0) + 1.0) * 0.5 * n as f32).floor() as i64;
    let m = i64::from(margin);
    let clamp = |i: i64| i.clamp(0, i64::from(n)) as u32;
    Some(TexelRect {
        x0: clamp(to_texel(lo.x) - m),
        y0: clamp(to_texel(lo.y) - m),
        x1: clamp(to_texel(hi.x) + 1 + m),
        y1: clamp(to_texel(hi.y) + 1 + m),
    })
}

/// The part of the convex polygon `poly` where `plane · p >= 0` (Sutherland–Hodgman).
fn clip_polygon(poly: &[Vec3], plane: Vec3) -> Vec<Vec3> {
    let mut out = Vec::with_capacity(poly.len() + 1);
    for (i, &p) in poly.iter().enumerate() {
        let q = poly[(i + 1) % poly.len()];
        let (dp, dq) = (plane.dot(p), plane.dot(q));
        if dp >= 0.0 {
            out.push(p);
        }
        if (dp >= 0.0) != (dq >= 0.0) {
            out.push(p + (q - p) * (dp / (dp - dq)));
        }
    }
    out
}

/// The texels of `face` (`n` per edge) whose directions can come within `margin` radians of
/// the cone bounded by planes through the probe origin with inward unit `normals` (the side
/// planes of a camera at the probe: the eye probe); `None` when none can. The cone, widened
/// by the margin, meets the face plane in a convex polygon, clipped here from the face
/// square one plane at a time; the rectangle bounds it. A direction `r` within `margin` of
/// the cone has `normal · r̂ >= -margin` for every plane, so `normal · r >= -margin · √3` on
/// the face plane (where `|r| <= √3`): a linear bound, so the clip stays exact.
pub fn face_cone_rect(normals: &[Vec3], face: Face, n: u32, margin: f32) -> Option<TexelRect> {
    let (a, s, t) = (face.axis(), face.u_axis(), face.v_axis());
    let slack = margin.max(0.0) * 3f32.sqrt() + 1e-6;
    let mut poly = vec![(-1.0f32, -1.0f32), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
    for normal in normals {
        // normal · (a + u s + v t) >= -slack, linear in (u, v).
        let (cu, cv, c0) = (normal.dot(s), normal.dot(t), normal.dot(a));
        let side = |&(u, v): &(f32, f32)| cu * u + cv * v + c0 + slack;
        let mut clipped = Vec::with_capacity(poly.len() + 1);
        for (i, p) in poly.iter().enumerate() {
            let q = &poly[(i + 1) % poly.len()];
            let (dp, dq) = (side(p), side(q));
            if dp >= 0.0 {
                clipped.push(*p);
            }
            if (dp >= 0.0) != (dq >= 0.0) {
                let k = dp / (dp - dq);
                clipped.push((p.0 + (q.0 - p.0) * k, p.1 + (q.1 - p.1) * k));
            }
        }
        poly = clipped;
        if poly.is_empty() {
            return None;
        }
    }
    let (mut lo, mut hi) = ((1.0f32, 1.0f32), (-1.0f32, -1.0f32));
    for &(u, v) in &poly {
        lo = (lo.0.min(u), lo.1.min(v));
        hi = (hi.0.max(u), hi.1.max(v));
    }
    // Face coordinate c lies in texel floor((c + 1) n / 2); one more each side for rounding.
    let n_f = n as f32;
    let first = |c: f32| (((c + 1.0) * 0.5 * n_f).floor().max(0.0) as u32).saturating_sub(1);
    let end = |c: f32| ((((c + 1.0) * 0.5 * n_f).floor().max(0.0) as u32) + 2).min(n);
    Some(TexelRect {
        x0: first(lo.0).min(n),
        y0: first(lo.1).min(n),
        x1: end(hi.0),
        y1: end(hi.1),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f32::consts::FRAC_PI_3;

    fn view(forward: Vec3, fov_y: f32, aspect: f32) -> CameraView {
        CameraView {
            position: Vec3::ZERO,
            forward,
            up: Vec3::Y,
            fov_y,
            aspect,
            near: 0.1,
            far: 100.0,
        }
    }

    fn faces(v: &CameraView, origin: Vec3) -> Vec<Face> {
        let f = frustum(v).unwrap();
        visible_faces(&f, origin, 100.0, 1.0).iter().collect()
    }

    #[test]
    fn narrow_view_down_an_axis_sees_one_face() {
        // 60° vertical, 1.5 aspect: half-angles 30° and ~41°, both inside the +Z face.
        let v = view(Vec3::Z, FRAC_PI_3, 1.5);
        assert_eq!(faces(&v, Vec3::ZERO), vec![Face::PosZ]);
    }

    #[test]
    fn wide_or_diagonal_views_see_neighbours() {
        let v = view(Vec3::new(1.0, 0.0, 1.0), FRAC_PI_3, 1.5);
        assert_eq!(faces(&v, Vec3::ZERO), vec![Face::PosX, Face::PosZ]);
        let v = view(Vec3::Z, 2.0, 1.0);
        let seen = faces(&v, Vec3::ZERO);
        assert_eq!(seen.len(), 5, "{seen:?}");
        assert!(!seen.contains(&Face::NegZ));
    }

    #[test]
    fn an_offset_probe_sees_faces_the_eye_does_not() {
        // Probe 0.5 in front of the camera: its -Z face covers what lies behind it,
        // which the camera sees.
        let v = view(Vec3::Z, FRAC_PI_3, 1.5);
        let seen = faces(&v, Vec3::new(0.0, 0.0, 0.5));
        assert!(seen.contains(&Face::NegZ) && seen.contains(&Face::PosZ));
        // Probe behind and to the side: +X face of a probe far to the left is visible.
        let seen = faces(&v, Vec3::new(-5.0, 0.0, -1.0));
        assert!(seen.contains(&Face::PosX));
        assert!(!seen.contains(&Face::NegX));
    }

    #[test]
    fn the_reference_mask_keeps_three_to_five_faces() {
        let level = reference_faces(Vec3::Z, REFERENCE_STABLE_FACE_DEG);
        assert_eq!(level.count(), 5, "forward and the four side faces");
        assert!(!level.contains(Face::NegZ));
        let diagonal = reference_faces(Vec3::new(1.0, 0.0, 1.0), REFERENCE_STABLE_FACE_DEG);
        let want = [Face::PosX, Face::PosZ, Face::PosY, Face::NegY];
        assert_eq!(diagonal, want.into_iter().collect::<FaceMask>());
        let corner = reference_faces(Vec3::ONE, REFERENCE_EYE_FACE_DEG);
        assert_eq!(
            corner.count(),
            3,
            "the three faces around the corner it looks into"
        );
        // A face at exactly 90° is in, one just past the eye's 98° is out.
        let a = 99.0f32.to_radians();
        let tilted = Vec3::new(0.0, a.cos(), a.sin()); // 99° from +Y
        assert!(reference_faces(Vec3::Z, REFERENCE_EYE_FACE_DEG).contains(Face::PosY));
        assert!(!reference_faces(tilted, REFERENCE_EYE_FACE_DEG).contains(Face::PosY));
        assert!(reference_faces(tilted, REFERENCE_STABLE_FACE_DEG).contains(Face::PosY));
    }

    #[test]
    fn extent_widens_the_pyramid() {
        // Looking just past the +Z/+X edge from a probe on the axis.
        let mut v = view(Vec3::new(1.0, 0.0, 1.2), 0.05, 1.0);
        v.position = Vec3::ZERO;
        let f = frustum(&v).unwrap();
        assert!(!face_visible(&f, Vec3::ZERO, Face::PosX, 100.0, 1.0));
        assert!(face_visible(&f, Vec3::ZERO, Face::PosX, 100.0, 1.3));
        assert_eq!(splat_extent(8), 1.5);
    }

    #[test]
    fn depth_limit_truncates() {
        let mut v = view(Vec3::Z, 0.2, 1.0);
        v.position = Vec3::new(0.0, 0.0, 0.0);
        let f = frustum(&v).unwrap();
        // Probe 50 units to the side looking back at the camera axis needs range >= ~50.
        assert!(!face_visible(
            &f,
            Vec3::new(50.0, 0.0, 60.0),
            Face::NegX,
            10.0,
            1.0
        ));
        assert!(face_visible(
            &f,
            Vec3::new(50.0, 0.0, 60.0),
            Face::NegX,
            60.0,
            1.0
        ));
    }

    #[test]
    fn frustum_planes_contain_its_corners_and_axis() {
        let v = CameraView {
            position: Vec3::new(1.0, 2.0, 3.0),
            ..view(Vec3::new(0.3, -0.2, -1.0), 1.0, 1.7)
        };
        let f = frustum(&v).unwrap();
        for c in f.vertices {
            assert!(f.contains(c));
        }
        assert!(f.contains(v.position + v.forward.normalize() * 50.0));
        assert!(!f.contains(v.position - v.forward.normalize()));
    }

    #[test]
    fn rejects_degenerate_views() {
        let ok = view(Vec3::Z, 1.0, 1.0);
        let bad = |v: CameraView| frustum(&v).unwrap_err();
        assert_eq!(
            bad(CameraView { up: Vec3::Z, ..ok }),
            ViewError::DegenerateBasis
        );
        assert_eq!(
            bad(CameraView {
                forward: Vec3::ZERO,
                ..ok
            }),
            ViewError::DegenerateBasis
        );
        assert_eq!(
            bad(CameraView { fov_y: 3.2, ..ok }),
            ViewError::FieldOfView(3.2)
        );
        assert_eq!(
            bad(CameraView { aspect: 0.0, ..ok }),
            ViewError::Aspect(0.0)
        );
        assert!(matches!(
            bad(CameraView { far: 0.05, ..ok }),
            ViewError::ClipRange { .. }
        ));
        assert_eq!(
            bad(CameraView {
                near: f32::NAN,
                ..ok
            }),
            ViewError::NonFinite
        );
    }

    mod cone_rect {
        use super::*;
        use crate::cube::{Texel, texel_center_direction};
        use proptest::prelude::*;

        fn side_normals(view: &CameraView) -> Vec<Vec3> {
            let f = frustum(view).unwrap();
            f.planes[2..].iter().map(|p| p.normal).collect()
        }

        proptest! {
            /// Every texel whose centre direction is within the margin of every side plane
            /// (so every texel within the margin of the cone) lies in the rectangle.
            #[test]
            fn holds_every_texel_near_the_view(yaw in -3.2f32..3.2, pitch in -1.5f32..1.5,
                                         fov in 0.3f32..2.0, aspect in 0.5f32..2.5,
                                         margin in 0.0f32..0.3) {
                let forward = Vec3::new(yaw.sin() * pitch.cos(), pitch.sin(), -yaw.cos() * pitch.cos());
                let v = view(forward, fov, aspect);
                let normals = side_normals(&v);
                let n = 24;
                for face in Face::ALL {
                    let rect = face_cone_rect(&normals, face, n, margin);
                    for y in 0..n {
                        for x in 0..n {
                            let d = texel_center_direction(Texel { face, x, y }, n);
                            let inside = normals.iter().all(|m| m.dot(d.normalize()) >= -margin);
                            if inside {
                                let r = rect.expect("a texel in view but no rectangle");
                                prop_assert!(x >= r.x0 && x < r.x1 && y >= r.y0 && y < r.y1,
                                    "{face:?} texel ({x}, {y}) outside {r:?}");
                            }
                        }
                    }
                }
            }
        }

        #[test]
        fn a_face_behind_the_camera_has_no_rectangle_and_the_front_one_is_partial() {
            let v = view(Vec3::NEG_Z, 1.2, 16.0 / 9.0);
            let normals = side_normals(&v);
            let n = 64;
            assert_eq!(face_cone_rect(&normals, Face::PosZ, n, 0.0), None);
            let front = face_cone_rect(&normals, Face::NegZ, n, 0.0).unwrap();
            assert!(front.area() < u64::from(n * n));
            // tan(0.6) ≈ 0.684: rows within about ±0.684 of the centre, one more each side.
            let rows = front.y1 - front.y0;
            assert!((44..=48).contains(&rows), "{front:?}");
            let wider = face_cone_rect(&normals, Face::NegZ, n, 0.05).unwrap();
            assert!(wider.y1 > front.y1 && wider.y0 < front.y0, "{wider:?}");
        }
    }

    #[test]
    fn a_box_ahead_covers_its_projection_and_one_behind_none() {
        use super::face_box_rect;
        let n = 64;
        let o = Vec3::ZERO;
        // A unit box 4 ahead on +Z around the axis: its near face spans u, v of ±0.5/3.5.
        let b = (Vec3::new(-0.5, -0.5, 3.5), Vec3::new(0.5, 0.5, 4.5));
        let r = face_box_rect(Face::PosZ, o, b, n, 0).expect("in view");
        let half = 0.5 / 3.5 * 32.0;
        assert!(
            r.x0 <= (32.0 - half) as u32 && r.x1 >= (32.0 + half) as u32,
            "{r:?}"
        );
        assert!(r.area() < 12 * 12, "{r:?}");
        // Every texel whose centre ray meets the box is inside the rectangle.
        for y in 0..n {
            for x in 0..n {
                let d = crate::cube::texel_center_direction(
                    crate::cube::Texel {
                        face: Face::PosZ,
                        x,
                        y,
                    },
                    n,
                );
                let p = d * 4.0;
                if p.x.abs() <= 0.5 && p.y.abs() <= 0.5 {
                    assert!(
                        x >= r.x0 && x < r.x1 && y >= r.y0 && y < r.y1,
                        "({x}, {y}) outside {r:?}"
                    );
                }
            }
        }
        assert_eq!(
            face_box_rect(Face::NegZ, o, b, n, 0),
            None,
            "behind the face"
        );
        // A box around the origin reaches every face.
        let around = (Vec3::splat(-1.0), Vec3::splat(1.0));
        assert_eq!(
            face_box_rect(Face::PosX, o, around, n, 0).map(|r| r.area()),
            Some(64 * 64)
        );
        // The margin grows the rectangle, within the face.
        let grown = face_box_rect(Face::PosZ, o, b, n, 2).expect("in view");
        assert_eq!((grown.x0, grown.x1), (r.x0 - 2, r.x1 + 2));
    }

    /// A wide box ahead on +Z that reaches past the probe on x and y: the side faces see
    /// only the slivers of it their pyramids hold, or none, and every texel whose centre ray
    /// meets it is inside the rectangle.
    #[test]
    fn a_box_beside_the_probe_covers_only_where_each_face_sees_it() {
        use super::face_box_rect;
        let n = 64;
        let o = Vec3::ZERO;
        let b = (Vec3::new(-3.0, -4.0, 3.75), Vec3::new(2.0, 1.0, 9.0));
        assert_eq!(face_box_rect(Face::PosX, o, b, n, 0), None, "|x| < z");
        let below = face_box_rect(Face::NegY, o, b, n, 0).expect("a sliver");
        assert!(below.area() < 64 * 64 / 8, "{below:?}");
        for face in Face::ALL {
            let r = face_box_rect(face, o, b, n, 0);
            for y in 0..n {
                for x in 0..n {
                    let d =
                        crate::cube::texel_center_direction(crate::cube::Texel { face, x, y }, n)
                            .normalize();
                    // Does the centre ray meet the box? (slab test)
                    let inv = d.recip();
                    let (t0, t1) = ((b.0 - o) * inv, (b.1 - o) * inv);
                    let near = t0.min(t1).max_element().max(0.0);
                    let far = t0.max(t1).min_element();
                    if near <= far {
                        let r = r.unwrap_or_else(|| panic!("{face:?} ({x}, {y}) sees it"));
                        assert!(
                            x >= r.x0 && x < r.x1 && y >= r.y0 && y < r.y1,
                            "{face:?} ({x}, {y}) outside {r:?}"
                        );
                    }
                }
            }
        }
    }
}
