//! The one cube-face convention of Texel, and the texel-splat geometry built on it.
//!
//! # Convention
//!
//! Faces follow the Vulkan / WebGPU cube-map convention (Vulkan spec, "Cube Map Face
//! Selection"), so the six layers a probe captures can be sampled through a GPU `Cube`
//! view unchanged. Face `i` is array layer `i`. A direction `r` picks the face of its
//! largest-magnitude component (the major axis, `ma = |r · axis|`); then
//! `u = (r · u_axis) / ma` and `v = (r · v_axis) / ma`, both in `[-1, 1]`. Texture
//! coordinates are `s = (u + 1) / 2` (column, left to right) and `t = (v + 1) / 2`
//! (row, **top to bottom**: `v` points down in texture space, row 0 is the top row).
//!
//! | index | face | axis (major) | `u_axis` (+u, right) | `v_axis` (+v, down) | direction of `(u, v)` |
//! |-------|------|--------------|----------------------|---------------------|------------------------|
//! | 0     | +X   | `+X`         | `-Z`                 | `-Y`                | `( 1, -v, -u)`         |
//! | 1     | -X   | `-X`         | `+Z`                 | `-Y`                | `(-1, -v,  u)`         |
//! | 2     | +Y   | `+Y`         | `+X`                 | `+Z`                | `( u,  1,  v)`         |
//! | 3     | -Y   | `-Y`         | `+X`                 | `-Z`                | `( u, -1, -v)`         |
//! | 4     | +Z   | `+Z`         | `+X`                 | `-Y`                | `( u, -v,  1)`         |
//! | 5     | -Z   | `-Z`         | `-X`                 | `-Y`                | `(-u, -v, -1)`         |
//!
//! **Handedness.** For every face `u_axis × v_axis = -axis`: each face frame is
//! left-handed, i.e. a face image seen from inside the cube (from the probe origin) is the
//! mirror of its texture layout. That is inherent to the cube-map convention, not a bug.
//! The world is right-handed (`X × Y = Z`).
//!
//! **Ties.** When two components share the largest magnitude (a direction exactly on a
//! cube edge), X wins over Y and Y over Z. Both candidate faces give the same direction
//! back (the other coordinate is exactly ±1), so round trips are unaffected.
//!
//! **Rendering a face.** [`face_view`] is a rigid right-handed view (`x = u_axis`,
//! `y = v_axis`, looking along `axis`); [`face_projection`] is a 90° perspective with depth
//! in `0..1` (as wgpu) whose Y is flipped, so NDC `(x, y) = (u, -v)` and the usual wgpu
//! viewport mapping (framebuffer row 0 at NDC `y = +1`) writes texel `(x, y)` exactly where
//! the direction mapping above reads it. The flip mirrors the image, so a triangle that is
//! counter-clockwise seen from the probe origin is **clockwise** in NDC: capture pipelines
//! cull with `front_face = Cw` (or cull nothing). View-space depth along the face axis is
//! the Chebyshev distance `||p - o||_inf` of any point inside that face's pyramid.
//!
//! # Texel splatting
//!
//! A texel stores the Chebyshev depth `d = ||p - o||_inf` of the surface it saw; the world
//! position of any face coordinate at that depth is `p = o + d / ||r||_inf * r`
//! ([`world_position`]). A splat quad evaluates it at `(u ± h, v ± h)` with one shared `d`
//! ([`quad_corners`]), so quads are world-space and independent of the camera.

use glam::{Mat4, Vec2, Vec3, Vec4};

/// One of the six cube faces, in GPU layer order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Face {
    /// Layer 0, looking along `+X`.
    PosX = 0,
    /// Layer 1, looking along `-X`.
    NegX = 1,
    /// Layer 2, looking along `+Y`.
    PosY = 2,
    /// Layer 3, looking along `-Y`.
    NegY = 3,
    /// Layer 4, looking along `+Z`.
    PosZ = 4,
    /// Layer 5, looking along `-Z`.
    NegZ = 5,
}

impl Face {
    /// All faces in layer order.
    pub const ALL: [Face; 6] = [
        Face::PosX,
        Face::NegX,
        Face::PosY,
        Face::NegY,
        Face::PosZ,
        Face::NegZ,
    ];

    /// The GPU array layer of this face (0..6).
    pub const fn index(self) -> usize {
        self as usize
    }

    /// The face of layer `index`, or `None` if `index >= 6`.
    pub const fn from_index(index: usize) -> Option<Face> {
        if index < 6 {
            Some(Face::ALL[index])
        } else {
            None
        }
    }

    /// The unit major axis the face looks along.
    pub const fn axis(self) -> Vec3 {
        match self {
            Face::PosX => Vec3::X,
            Face::NegX => Vec3::NEG_X,
            Face::PosY => Vec3::Y,
            Face::NegY => Vec3::NEG_Y,
            Face::PosZ => Vec3::Z,
            Face::NegZ => Vec3::NEG_Z,
        }
    }

    /// The world direction in which `u` (texture column) increases on this face.
    pub const fn u_axis(self) -> Vec3 {
        match self {
            Face::PosX => Vec3::NEG_Z,
            Face::NegX => Vec3::Z,
            Face::PosY | Face::NegY | Face::PosZ => Vec3::X,
            Face::NegZ => Vec3::NEG_X,
        }
    }

    /// The world direction in which `v` (texture row, downward) increases on this face.
    pub const fn v_axis(self) -> Vec3 {
        match self {
            Face::PosY => Vec3::Z,
            Face::NegY => Vec3::NEG_Z,
            Face::PosX | Face::NegX | Face::PosZ | Face::NegZ => Vec3::NEG_Y,
        }
    }

    /// The face looking the opposite way.
    pub const fn opposite(self) -> Face {
        match self {
            Face::PosX => Face::NegX,
            Face::NegX => Face::PosX,
            Face::PosY => Face::NegY,
            Face::NegY => Face::PosY,
            Face::PosZ => Face::NegZ,
            Face::NegZ => Face::PosZ,
        }
    }
}

/// A set of faces, one bit per face (bit `i` = layer `i`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct FaceMask(u8);

impl FaceMask {
    /// No face.
    pub const EMPTY: FaceMask = FaceMask(0);
    /// All six faces.
    pub const ALL: FaceMask = FaceMask(0b11_1111);

    /// The set holding only `face`.
    pub const fn single(face: Face) -> FaceMask {
        FaceMask(1 << face.index())
    }

    /// The raw bits (bit `i` = layer `i`), e.g. for a GPU uniform.
    pub const fn bits(self) -> u8 {
        self.0
    }

    /// Whether `face` is in the set.
    pub const fn contains(self, face: Face) -> bool {
        self.0 & (1 << face.index()) != 0
    }

    /// Adds `face` to the set.
    pub fn insert(&mut self, face: Face) {
        self.0 |= 1 << face.index();
    }

    /// Number of faces in the set.
    pub const fn count(self) -> u32 {
        self.0.count_ones()
    }

    /// Whether the set is empty.
    pub const fn is_empty(self) -> bool {
        self.0 == 0
    }

    /// Faces in either set.
    pub const fn union(self, other: FaceMask) -> FaceMask {
        FaceMask(self.0 | other.0)
    }

    /// Faces in both sets.
    pub const fn intersection(self, other: FaceMask) -> FaceMask {
        FaceMask(self.0 & other.0)
    }

    /// Faces in `self` but not in `other`.
    pub const fn difference(self, other: FaceMask) -> FaceMask {
        FaceMask(self.0 & !other.0)
    }

    /// The faces of the set in layer order.
    pub fn iter(self) -> impl Iterator<Item = Face> {
        Face::ALL.into_iter().filter(move |f| self.contains(*f))
    }
}

impl FromIterator<Face> for FaceMask {
    fn from_iter<I: IntoIterator<Item = Face>>(iter: I) -> Self {
        let mut mask = FaceMask::EMPTY;
        for face in iter {
            mask.insert(face);
        }
        mask
    }
}

/// A direction expressed as a face and face coordinates `u, v` in `[-1, 1]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FaceUv {
    /// The face the direction points into.
    pub face: Face,
    /// Horizontal face coordinate (grows along [`Face::u_axis`]).
    pub u: f32,
    /// Vertical face coordinate (grows along [`Face::v_axis`], downward in the texture).
    pub v: f32,
}

/// One texel of a cube face: column `x` and row `y` (row 0 at the top).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Texel {
    /// The face holding the texel.
    pub face: Face,
    /// Column, `0..n`.
    pub x: u32,
    /// Row, `0..n`, top to bottom.
    pub y: u32,
}

/// The face whose major axis is the largest-magnitude component of `r` (ties: X, then Y).
fn major_face(r: Vec3) -> Face {
    let a = r.abs();
    if a.x >= a.y && a.x >= a.z {
        if r.x >= 0.0 { Face::PosX } else { Face::NegX }
    } else if a.y >= a.z {
        if r.y >= 0.0 { Face::PosY } else { Face::NegY }
    } else if r.z >= 0.0 {
        Face::PosZ
    } else {
        Face::NegZ
    }
}

/// Face and face coordinates of direction `r` (any length).
///
/// Returns `None` for the zero vector or a vector with a non-finite component.
pub fn face_uv_from_direction(r: Vec3) -> Option<FaceUv> {
    if !r.is_finite() || r == Vec3::ZERO {
        return None;
    }
    let face = major_face(r);
    let ma = r.dot(face.axis());
    Some(FaceUv {
        face,
        u: r.dot(face.u_axis()) / ma,
        v: r.dot(face.v_axis()) / ma,
    })
}

/// The (unnormalized) direction of face coordinates `(u, v)`: `axis + u·u_axis + v·v_axis`.
///
/// Its component along the face axis is exactly 1, so for `|u|, |v| <= 1` its Chebyshev
/// norm is 1. Coordinates beyond `[-1, 1]` are allowed (splat corners past a face edge).
pub fn direction_from_face_uv(face: Face, u: f32, v: f32) -> Vec3 {
    face.axis() + u * face.u_axis() + v * face.v_axis()
}

/// Face coordinate of the centre of texel column (or row) `i` on a face of `n` texels:
/// `2 (i + 0.5) / n - 1`.
pub fn texel_center_coord(i: u32, n: u32) -> f32 {
    debug_assert!(n > 0, "face resolution must be positive");
    2.0 * (i as f32 + 0.5) / n as f32 - 1.0
}

/// Face coordinates `(u, v)` of the centre of `texel` on a face of `n` texels.
pub fn texel_center_uv(texel: Texel, n: u32) -> Vec2 {
    Vec2::new(
        texel_center_coord(texel.x, n),
        texel_center_coord(texel.y, n),
    )
}

/// Direction through the centre of `texel` on a face of `n` texels (major component ±1).
pub fn texel_center_direction(texel: Texel, n: u32) -> Vec3 {
    let uv = texel_center_uv(texel, n);
    direction_from_face_uv(texel.face, uv.x, uv.y)
}

/// Column (or row) index of face coordinate `c` on a face of `n` texels, clamped to `0..n`.
fn texel_index(c: f32, n: u32) -> u32 {
    let i = ((c + 1.0) * 0.5 * n as f32).floor();
    i.clamp(0.0, (n - 1) as f32) as u32
}

/// The texel of a face of `n` texels that face coordinates `(u, v)` fall in.
///
/// Coordinates outside `[-1, 1]` clamp to the border texel. Returns `None` if `n == 0` or
/// a coordinate is not finite.
pub fn texel_from_uv(face: Face, u: f32, v: f32, n: u32) -> Option<Texel> {
    if n == 0 || !u.is_finite() || !v.is_finite() {
        return None;
    }
    Some(Texel {
        face,
        x: texel_index(u, n),
        y: texel_index(v, n),
    })
}

/// The texel of a cube of `n`×`n` faces that direction `r` falls in.
///
/// Returns `None` if `n == 0` or `r` is zero or not finite.
pub fn texel_from_direction(r: Vec3, n: u32) -> Option<Texel> {
    let fuv = face_uv_from_direction(r)?;
    texel_from_uv(fuv.face, fuv.u, fuv.v, n)
}

/// Chebyshev norm `||r||_inf = max(|x|, |y|, |z|)`: the depth a probe stores for offset `r`.
pub fn chebyshev_norm(r: Vec3) -> f32 {
    r.abs().max_element()
}

/// World position `p = o + d / ||r||_inf * r` of direction `r` at Chebyshev depth `d`.
///
/// Returns `origin` for the zero direction (which has no position).
pub fn world_position(origin: Vec3, r: Vec3, depth: f32) -> Vec3 {
    let norm = chebyshev_norm(r);
    if norm == 0.0 {
        return origin;
    }
    origin + r * (depth / norm)
}

/// Half-sizes of a splat quad, per side, in texels (0.5 = exactly the texel).
///
/// `left` extends toward `-u` (previous column), `right` toward `+u`, `top` toward `-v`
/// (previous row, up in the texture) and `bottom` toward `+v`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuadHalfSizes {
    /// Extent toward `-u`, in texels.
    pub left: f32,
    /// Extent toward `+u`, in texels.
    pub right: f32,
    /// Extent toward `-v` (up in the texture), in texels.
    pub top: f32,
    /// Extent toward `+v` (down in the texture), in texels.
    pub bottom: f32,
}

impl QuadHalfSizes {
    /// The exact texel footprint: half a texel on every side.
    pub const EXACT: QuadHalfSizes = QuadHalfSizes::uniform(0.5);

    /// The same half-size `h` (in texels) on every side.
    pub const fn uniform(h: f32) -> QuadHalfSizes {
        QuadHalfSizes {
            left: h,
            right: h,
            top: h,
            bottom: h,
        }
    }
}

/// Face coordinates of the four corners of a splat quad, in the order of [`quad_corners`].
pub fn quad_corner_uvs(texel: Texel, n: u32, half: QuadHalfSizes) -> [Vec2; 4] {
    let c = texel_center_uv(texel, n);
    let texel_size = 2.0 / n as f32;
    let (l, r) = (c.x - half.left * texel_size, c.x + half.right * texel_size);
    let (t, b) = (c.y - half.top * texel_size, c.y + half.bottom * texel_size);
    [
        Vec2::new(l, t),
        Vec2::new(r, t),
        Vec2::new(r, b),
        Vec2::new(l, b),
    ]
}

/// World-space corners of the splat quad of `texel` (face of `n` texels) at Chebyshev
/// `depth` from the probe `origin`.
///
/// Order: top-left, top-right, bottom-right, bottom-left in texture space (`(u-l, v-t)`,
/// `(u+r, v-t)`, `(u+r, v+b)`, `(u-l, v+b)`), which is counter-clockwise seen from the
/// probe origin. All four corners share `depth`, so a quad inside its face lies in the
/// plane `axis · (p - o) = depth`; corners past a face edge bend onto the neighbour face's
/// plane. The result depends on nothing but its arguments: never on the camera.
pub fn quad_corners(
    origin: Vec3,
    texel: Texel,
    n: u32,
    depth: f32,
    half: QuadHalfSizes,
) -> [Vec3; 4] {
    quad_corner_uvs(texel, n, half).map(|uv| {
        world_position(
            origin,
            direction_from_face_uv(texel.face, uv.x, uv.y),
            depth,
        )
    })
}

/// Rigid right-handed view matrix for rendering `face` from `origin`.
///
/// View space: `x = u_axis`, `y = v_axis`, `-z = axis` (the camera looks along the face
/// axis), so view depth `-z` equals the Chebyshev distance inside the face's pyramid.
pub fn face_view(origin: Vec3, face: Face) -> Mat4 {
    let (s, t, a) = (face.u_axis(), face.v_axis(), face.axis());
    Mat4::from_cols(
        Vec4::new(s.x, t.x, -a.x, 0.0),
        Vec4::new(s.y, t.y, -a.y, 0.0),
        Vec4::new(s.z, t.z, -a.z, 0.0),
        Vec4::new(-s.dot(origin), -t.dot(origin), a.dot(origin), 1.0),
    )
}

/// 90°, square, Y-flipped perspective projection with depth `0..1` (near → 0, far → 1).
///
/// Expects the view space of [`face_view`]; NDC is `(u, -v)`. Requires `0 < near < far`.
pub fn face_projection(near: f32, far: f32) -> Mat4 {
    debug_assert!(near > 0.0 && far > near, "need 0 < near < far");
    let a = far / (near - far);
    let b = near * far / (near - far);
    Mat4::from_cols(
        Vec4::new(1.0, 0.0, 0.0, 0.0),
        Vec4::new(0.0, -1.0, 0.0, 0.0),
        Vec4::new(0.0, 0.0, a, -1.0),
        Vec4::new(0.0, 0.0, b, 0.0),
    )
}

/// `face_projection(near, far) * face_view(origin, face)`.
pub fn face_view_projection(origin: Vec3, face: Face, near: f32, far: f32) -> Mat4 {
    face_projection(near, far) * face_view(origin, face)
}

/// Texture coordinates `(s, t)` in `[0, 1]` (t down) of an NDC position (y up), as the
/// wgpu viewport maps them.
pub fn texture_coords_from_ndc(ndc: Vec2) -> Vec2 {
    Vec2::new((ndc.x + 1.0) * 0.5, (1.0 - ndc.y) * 0.5)
}

#[cfg(test)]
mod tests;
