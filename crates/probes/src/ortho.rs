//! The probe of an orthographic camera: one orthographic face instead of a cube.
//!
//! An orthographic camera sees along parallel rays, so the probe that serves it is not a
//! point but a plane: a square face of `n × n` texels whose centre rays all run along one
//! direction `forward` (the view direction, held in steps while the camera turns), starting
//! on the plane through the probe's `origin` spanned by `right` (texture column, `u`) and
//! `down` (texture row, `v`), `half` world units from the centre to each edge. A texel
//! `(u, v)` in `[-1, 1]²` at depth `d` is the world point
//! `origin + half · (u · right + v · down) + d · forward`.
//!
//! Its texels are one art pixel each, and the driver places `origin` on a lattice of whole
//! texels in the view plane (`texel_runtime::frame_plan`), so two orthographic probes with the
//! same direction sample exactly the same world lines: moving a probe along the lattice
//! changes no texel's content, and a pan never resamples. The face is stored as layer 0
//! (face +X) of its slot; the other five layers are unused.

use glam::{Mat4, Vec3, Vec4};

/// The frame of an orthographic probe face (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrthoFrame {
    /// World direction of texture columns (`u`).
    pub right: Vec3,
    /// World direction of texture rows (`v`, downward).
    pub down: Vec3,
    /// The direction every texel's ray runs along.
    pub forward: Vec3,
    /// World units from the face's centre to each of its edges.
    pub half: f32,
}

impl OrthoFrame {
    /// The frame looking along `forward` with `up` as its up direction (not parallel to
    /// `forward`), handed like a cube face (`right × down = −forward`, as `u × v = −axis`:
    /// seen along `forward`, `u` runs to the left), so triangles keep their winding.
    pub fn new(forward: Vec3, up: Vec3, half: f32) -> OrthoFrame {
        let forward = forward.normalize();
        let right = up.cross(forward).normalize();
        let down = right.cross(forward);
        OrthoFrame {
            right,
            down,
            forward,
            half,
        }
    }

    /// The world point of face coordinates `(u, v)` at depth `d` from `origin`'s plane.
    pub fn point(&self, origin: Vec3, u: f32, v: f32, d: f32) -> Vec3 {
        origin + self.half * (u * self.right + v * self.down) + d * self.forward
    }

    /// Face coordinates and depth of world point `p` for a probe at `origin`.
    pub fn locate(&self, origin: Vec3, p: Vec3) -> (f32, f32, f32) {
        let q = p - origin;
        (
            q.dot(self.right) / self.half,
            q.dot(self.down) / self.half,
            q.dot(self.forward),
        )
    }

    /// World size of one texel of a face of `n` texels.
    pub fn texel(&self, n: u32) -> f32 {
        2.0 * self.half / n.max(1) as f32
    }

    /// View-projection of the face from `origin`, depth `near..far` along `forward` mapped to
    /// `0..1`, NDC `(u, -v)` as a cube face's (`cube::face_projection`).
    pub fn view_projection(&self, origin: Vec3, near: f32, far: f32) -> Mat4 {
        let (s, t, a) = (self.right, self.down, self.forward);
        let view = Mat4::from_cols(
            Vec4::new(s.x, t.x, -a.x, 0.0),
            Vec4::new(s.y, t.y, -a.y, 0.0),
            Vec4::new(s.z, t.z, -a.z, 0.0),
            Vec4::new(-s.dot(origin), -t.dot(origin), a.dot(origin), 1.0),
        );
        let h = self.half;
        // View depth is −z: z_ndc = (−z − near) / (far − near).
        let k = 1.0 / (far - near);
        let projection = Mat4::from_cols(
            Vec4::new(1.0 / h, 0.0, 0.0, 0.0),
            Vec4::new(0.0, -1.0 / h, 0.0, 0.0),
            Vec4::new(0.0, 0.0, -k, 0.0),
            Vec4::new(0.0, 0.0, -near * k, 1.0),
        );
        projection * view
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_project_back_to_their_face_coordinates_and_depth() {
        let f = OrthoFrame::new(Vec3::new(-1.0, -0.8, -1.0), Vec3::Y, 12.5);
        let o = Vec3::new(40.0, 35.0, 41.0);
        let vp = f.view_projection(o, 0.1, 500.0);
        for &(u, v, d) in &[(0.0, 0.0, 1.0), (0.5, -0.25, 30.0), (-0.9, 0.9, 400.0)] {
            let p = f.point(o, u, v, d);
            let (lu, lv, ld) = f.locate(o, p);
            assert!((lu - u).abs() < 1e-5 && (lv - v).abs() < 1e-5 && (ld - d).abs() < 1e-3);
            let c = vp * p.extend(1.0);
            let ndc = c.truncate() / c.w;
            assert!((ndc.x - u).abs() < 1e-5, "{ndc} for {u}");
            assert!((ndc.y + v).abs() < 1e-5, "{ndc} for {v}");
            assert!((ndc.z - (d - 0.1) / 499.9).abs() < 1e-5, "{ndc} for {d}");
        }
        // Handed like a cube face (u × v = −axis), rows downward.
        assert!((f.right.cross(f.down) + f.forward).length() < 1e-5);
        let face = crate::cube::Face::PosZ;
        assert!((face.u_axis().cross(face.v_axis()) + face.axis()).length() < 1e-6);
        assert!(f.down.y < 0.0, "rows go down the screen");
    }
}
