use super::*;

const EPS: f32 = 1e-5;

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).abs().max_element() < EPS
}

/// The convention table of the module doc, row by row: (face, axis, u_axis, v_axis).
const TABLE: [(Face, Vec3, Vec3, Vec3); 6] = [
    (Face::PosX, Vec3::X, Vec3::NEG_Z, Vec3::NEG_Y),
    (Face::NegX, Vec3::NEG_X, Vec3::Z, Vec3::NEG_Y),
    (Face::PosY, Vec3::Y, Vec3::X, Vec3::Z),
    (Face::NegY, Vec3::NEG_Y, Vec3::X, Vec3::NEG_Z),
    (Face::PosZ, Vec3::Z, Vec3::X, Vec3::NEG_Y),
    (Face::NegZ, Vec3::NEG_Z, Vec3::NEG_X, Vec3::NEG_Y),
];

#[test]
fn table_matches_face_axes() {
    for (i, (face, axis, u, v)) in TABLE.into_iter().enumerate() {
        assert_eq!(face.index(), i);
        assert_eq!(Face::from_index(i), Some(face));
        assert_eq!(face.axis(), axis, "{face:?} axis");
        assert_eq!(face.u_axis(), u, "{face:?} u axis");
        assert_eq!(face.v_axis(), v, "{face:?} v axis");
    }
    assert_eq!(Face::from_index(6), None);
}

#[test]
fn every_face_frame_is_left_handed() {
    for face in Face::ALL {
        assert_eq!(face.u_axis().cross(face.v_axis()), -face.axis(), "{face:?}");
        assert_eq!(face.opposite().axis(), -face.axis());
    }
}

/// The Vulkan spec's face-selection table, written out independently: (sc, tc, ma) per face.
fn vulkan_sc_tc(r: Vec3) -> (Face, f32, f32) {
    let a = r.abs();
    let (face, sc, tc, ma) = if a.x >= a.y && a.x >= a.z {
        if r.x >= 0.0 {
            (Face::PosX, -r.z, -r.y, a.x)
        } else {
            (Face::NegX, r.z, -r.y, a.x)
        }
    } else if a.y >= a.z {
        if r.y >= 0.0 {
            (Face::PosY, r.x, r.z, a.y)
        } else {
            (Face::NegY, r.x, -r.z, a.y)
        }
    } else if r.z >= 0.0 {
        (Face::PosZ, r.x, -r.y, a.z)
    } else {
        (Face::NegZ, -r.x, -r.y, a.z)
    };
    (face, sc / ma, tc / ma)
}

#[test]
fn direction_mapping_matches_vulkan_table() {
    let dirs = [
        Vec3::new(1.0, 0.3, -0.2),
        Vec3::new(-2.0, 0.5, 0.7),
        Vec3::new(0.1, 3.0, -0.4),
        Vec3::new(0.6, -1.5, 0.9),
        Vec3::new(-0.3, 0.2, 0.8),
        Vec3::new(0.4, -0.45, -0.5),
    ];
    for (i, r) in dirs.into_iter().enumerate() {
        let got = face_uv_from_direction(r).unwrap();
        let (face, u, v) = vulkan_sc_tc(r);
        assert_eq!(got.face, face);
        assert_eq!(got.face.index(), i, "sample {i} lands on face {i}");
        assert!((got.u - u).abs() < EPS && (got.v - v).abs() < EPS, "{r}");
    }
}

#[test]
fn face_corners_map_to_expected_world_directions() {
    // Top-left texel corner (u, v) = (-1, -1) of +Z is up-left in world: x = -1, y = +1.
    assert_eq!(
        direction_from_face_uv(Face::PosZ, -1.0, -1.0),
        Vec3::new(-1.0, 1.0, 1.0)
    );
    // +X face: u grows toward -Z, v grows toward -Y.
    assert_eq!(
        direction_from_face_uv(Face::PosX, 0.5, 0.25),
        Vec3::new(1.0, -0.25, -0.5)
    );
    // +Y face: u grows toward +X, v toward +Z.
    assert_eq!(
        direction_from_face_uv(Face::PosY, 0.5, 0.25),
        Vec3::new(0.5, 1.0, 0.25)
    );
    assert_eq!(
        direction_from_face_uv(Face::NegZ, 0.5, 0.25),
        Vec3::new(-0.5, -0.25, -1.0)
    );
}

#[test]
fn edge_ties_prefer_x_then_y() {
    assert_eq!(
        face_uv_from_direction(Vec3::new(1.0, 1.0, 1.0))
            .unwrap()
            .face,
        Face::PosX
    );
    assert_eq!(
        face_uv_from_direction(Vec3::new(0.0, -1.0, 1.0))
            .unwrap()
            .face,
        Face::NegY
    );
}

#[test]
fn degenerate_directions_have_no_face() {
    assert_eq!(face_uv_from_direction(Vec3::ZERO), None);
    assert_eq!(face_uv_from_direction(Vec3::new(f32::NAN, 1.0, 0.0)), None);
    assert_eq!(texel_from_direction(Vec3::X, 0), None);
    assert_eq!(texel_from_uv(Face::PosX, f32::INFINITY, 0.0, 4), None);
}

#[test]
fn texel_centres_and_indices() {
    assert!((texel_center_coord(0, 4) - -0.75).abs() < EPS);
    assert!((texel_center_coord(3, 4) - 0.75).abs() < EPS);
    let t = Texel {
        face: Face::NegY,
        x: 2,
        y: 0,
    };
    let d = texel_center_direction(t, 4);
    assert!(close(d, Vec3::new(0.25, -1.0, 0.75)));
    assert_eq!(texel_from_direction(d, 4), Some(t));
    // Outside [-1, 1] clamps to the border texel.
    assert_eq!(
        texel_from_uv(Face::PosZ, 1.5, -7.0, 8),
        Some(Texel {
            face: Face::PosZ,
            x: 7,
            y: 0
        })
    );
}

#[test]
fn chebyshev_and_world_position() {
    assert_eq!(chebyshev_norm(Vec3::new(-3.0, 2.0, 1.0)), 3.0);
    let o = Vec3::new(1.0, 2.0, 3.0);
    let p = world_position(o, Vec3::new(0.5, -1.0, 0.25), 4.0);
    assert!(close(p, o + Vec3::new(2.0, -4.0, 1.0)));
    assert_eq!(chebyshev_norm(p - o), 4.0);
    // Scaling the direction changes nothing.
    assert!(close(p, world_position(o, Vec3::new(1.0, -2.0, 0.5), 4.0)));
    assert_eq!(world_position(o, Vec3::ZERO, 4.0), o);
}

#[test]
fn exact_quads_tile_the_face_plane() {
    let o = Vec3::new(-2.0, 0.5, 7.0);
    let n = 8;
    let a = quad_corners(
        o,
        Texel {
            face: Face::PosX,
            x: 3,
            y: 5,
        },
        n,
        2.0,
        QuadHalfSizes::EXACT,
    );
    let b = quad_corners(
        o,
        Texel {
            face: Face::PosX,
            x: 4,
            y: 5,
        },
        n,
        2.0,
        QuadHalfSizes::EXACT,
    );
    // The right edge of texel 3 is the left edge of texel 4.
    assert!(close(a[1], b[0]) && close(a[2], b[3]));
    for c in a {
        assert!(
            (Face::PosX.axis().dot(c - o) - 2.0).abs() < EPS,
            "on the plane x = o.x + d"
        );
    }
}

#[test]
fn quad_corner_order_and_per_side_sizes() {
    let t = Texel {
        face: Face::PosZ,
        x: 1,
        y: 1,
    };
    let half = QuadHalfSizes {
        left: 0.5,
        right: 1.0,
        top: 0.25,
        bottom: 0.75,
    };
    let uv = quad_corner_uvs(t, 4, half);
    // Centre (-0.25, -0.25); one texel = 0.5 in uv.
    assert!((uv[0] - Vec2::new(-0.5, -0.375)).length() < EPS);
    assert!((uv[1] - Vec2::new(0.25, -0.375)).length() < EPS);
    assert!((uv[2] - Vec2::new(0.25, 0.125)).length() < EPS);
    assert!((uv[3] - Vec2::new(-0.5, 0.125)).length() < EPS);
}

#[test]
fn quads_are_counter_clockwise_seen_from_the_origin() {
    let o = Vec3::new(0.3, -1.0, 2.0);
    for face in Face::ALL {
        let c = quad_corners(o, Texel { face, x: 2, y: 5 }, 8, 3.0, QuadHalfSizes::EXACT);
        let normal = (c[1] - c[0]).cross(c[2] - c[0]);
        assert!(normal.dot(o - c[0]) > 0.0, "{face:?} faces the origin");
    }
}

#[test]
fn corners_past_an_edge_bend_onto_the_neighbour_plane() {
    let o = Vec3::ZERO;
    // Rightmost texel of +Z with a wide right side: its right corners cross into +X.
    let half = QuadHalfSizes {
        left: 0.5,
        right: 2.5,
        top: 0.5,
        bottom: 0.5,
    };
    let c = quad_corners(
        o,
        Texel {
            face: Face::PosZ,
            x: 7,
            y: 3,
        },
        8,
        2.0,
        half,
    );
    assert!(
        (c[1].x - 2.0).abs() < EPS,
        "right corner lies on the x = d plane"
    );
    assert!(c[1].z < 2.0);
    assert!((c[0].z - 2.0).abs() < EPS, "left corner stays on z = d");
}

fn project_to_texture(m: Mat4, p: Vec3) -> (Vec2, f32) {
    let clip = m * p.extend(1.0);
    let ndc = clip.truncate() / clip.w;
    (texture_coords_from_ndc(ndc.truncate()), ndc.z)
}

#[test]
fn texel_centres_project_to_their_texel_centre() {
    let o = Vec3::new(3.0, -2.0, 0.5);
    let n = 16;
    for face in Face::ALL {
        let m = face_view_projection(o, face, 0.1, 200.0);
        for (x, y) in [(0, 0), (15, 0), (3, 11), (8, 8), (15, 15)] {
            let texel = Texel { face, x, y };
            let p = o + texel_center_direction(texel, n) * 7.5;
            let (st, z) = project_to_texture(m, p);
            let expect = Vec2::new(x as f32 + 0.5, y as f32 + 0.5) / n as f32;
            assert!(
                (st - expect).length() < 1e-5,
                "{face:?} {x},{y}: {st} vs {expect}"
            );
            assert!(z > 0.0 && z < 1.0);
        }
    }
}

#[test]
fn view_depth_is_chebyshev_and_maps_near_far_to_0_1() {
    let o = Vec3::new(1.0, 1.0, 1.0);
    for face in Face::ALL {
        let r = direction_from_face_uv(face, 0.4, -0.7);
        let view = face_view(o, face);
        let p = world_position(o, r, 5.0);
        assert!((view.transform_point3(p).z - -5.0).abs() < 1e-4, "{face:?}");
        let m = face_view_projection(o, face, 0.5, 50.0);
        assert!(project_to_texture(m, world_position(o, r, 0.5)).1.abs() < 1e-5);
        assert!((project_to_texture(m, world_position(o, r, 50.0)).1 - 1.0).abs() < 1e-5);
    }
}

#[test]
fn face_view_is_a_rigid_right_handed_transform() {
    for face in Face::ALL {
        let v = face_view(Vec3::new(4.0, 5.0, 6.0), face);
        let rot = glam::Mat3::from_mat4(v);
        assert!((rot.determinant() - 1.0).abs() < EPS, "{face:?}");
    }
}

#[test]
fn projection_flips_winding() {
    // A triangle counter-clockwise seen from the origin (its normal points at the origin).
    let o = Vec3::ZERO;
    for face in Face::ALL {
        let tri = [
            direction_from_face_uv(face, -0.5, -0.5) * 3.0,
            direction_from_face_uv(face, 0.5, -0.5) * 3.0,
            direction_from_face_uv(face, 0.5, 0.5) * 3.0,
        ];
        let n = (tri[1] - tri[0]).cross(tri[2] - tri[0]);
        assert!(n.dot(o - tri[0]) > 0.0, "CCW from the origin");
        let m = face_view_projection(o, face, 0.1, 10.0);
        let ndc = tri.map(|p| m.project_point3(p).truncate());
        let area2 = (ndc[1] - ndc[0]).perp_dot(ndc[2] - ndc[0]);
        assert!(area2 < 0.0, "{face:?}: clockwise in NDC (y up)");
    }
}

#[test]
fn face_mask_set_operations() {
    let mut m = FaceMask::EMPTY;
    m.insert(Face::PosY);
    m.insert(Face::NegZ);
    assert_eq!(m.count(), 2);
    assert!(m.contains(Face::PosY) && !m.contains(Face::PosX));
    assert_eq!(m.bits(), 0b10_0100);
    assert_eq!(m.iter().collect::<Vec<_>>(), vec![Face::PosY, Face::NegZ]);
    let other: FaceMask = [Face::NegZ, Face::PosX].into_iter().collect();
    assert_eq!(m.intersection(other), FaceMask::single(Face::NegZ));
    assert_eq!(m.difference(other), FaceMask::single(Face::PosY));
    assert_eq!(m.union(other).count(), 3);
    assert_eq!(FaceMask::ALL.count(), 6);
    assert!(FaceMask::EMPTY.is_empty() && !m.is_empty());
}
