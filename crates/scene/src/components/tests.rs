//! Unit tests of the components: their defaults and the values they refuse.

use super::*;

#[test]
fn transform_matrix_applies_yaw_then_pitch() {
    let t = Transform {
        translation: Vec3::new(1.0, 2.0, 3.0),
        rotation: Vec3::new(0.0, 90.0, 0.0),
        scale: Vec3::splat(2.0),
    };
    // Yaw +90° about Y turns +X into −Z (right-handed).
    let p = t.matrix().transform_point3(Vec3::X);
    assert!((p - Vec3::new(1.0, 2.0, 1.0)).length() < 1e-5, "{p}");
}

#[test]
fn validation_names_the_field() {
    let t = Transform {
        scale: Vec3::new(1.0, 0.0, 1.0),
        ..Transform::default()
    };
    assert_eq!(t.validate().unwrap_err().0, "scale");
    let p = PlayerStart {
        pitch: 120.0,
        ..PlayerStart::default()
    };
    assert_eq!(p.validate().unwrap_err().0, "pitch");
    let g = Geometry::Sphere {
        radius: 1.0,
        segments: 2,
    };
    assert_eq!(g.validate().unwrap_err().0, "segments");
    assert!(LevelSettings::default().validate().is_ok());
}
