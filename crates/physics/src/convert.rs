//! The crate boundary between the workspace's glam and the copy rapier was built with: every
//! conversion is component by component, in this one place.

use rapier3d::math::{Pose, Rotation, Vector};

/// Workspace vector → rapier vector.
pub(crate) fn vector(v: glam::Vec3) -> Vector {
    Vector::new(v.x, v.y, v.z)
}

/// rapier vector → workspace vector.
pub(crate) fn vec3(v: Vector) -> glam::Vec3 {
    glam::Vec3::new(v.x, v.y, v.z)
}

/// Workspace quaternion → rapier rotation.
pub(crate) fn rotation(q: glam::Quat) -> Rotation {
    Rotation::from_xyzw(q.x, q.y, q.z, q.w)
}

/// rapier rotation → workspace quaternion.
pub(crate) fn quat(q: Rotation) -> glam::Quat {
    glam::Quat::from_xyzw(q.x, q.y, q.z, q.w)
}

/// A rigid pose from a translation and a rotation.
pub(crate) fn pose(translation: glam::Vec3, rot: glam::Quat) -> Pose {
    Pose::from_parts(vector(translation), rotation(rot))
}

/// A pose's translation and rotation.
pub(crate) fn parts(p: &Pose) -> (glam::Vec3, glam::Quat) {
    (vec3(p.translation), quat(p.rotation))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn conversions_round_trip() {
        let t = glam::Vec3::new(1.0, -2.0, 3.5);
        let q = glam::Quat::from_euler(glam::EulerRot::YXZ, 0.3, -0.2, 0.1);
        let (t2, q2) = parts(&pose(t, q));
        assert_eq!(t, t2);
        assert_eq!(q, q2);
        let p = pose(t, q).transform_point(vector(glam::Vec3::X));
        assert!((vec3(p) - (q * glam::Vec3::X + t)).length() < 1e-6);
    }
}
