//! Unit tests of the glTF importer's internals.

use glam::Vec3;
use gltf::mesh::Mode;

use super::buffers::percent_decode;
use super::geometry::{flat_shaded, triangle_list};
use super::*;

fn name() -> &'static Path {
    Path::new("mem.gltf")
}

/// A one-primitive glTF (no scenes) whose positions and optional u16 indices are in a
/// data: URI.
fn gltf_json(positions: &[[f32; 3]], indices: Option<&[u16]>, mode: u32) -> String {
    let mut bytes: Vec<u8> = positions
        .iter()
        .flatten()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    let pos_len = bytes.len();
    let (index_ref, index_accessor, index_view) = indices
        .map(|idx| {
            bytes.extend(idx.iter().flat_map(|i| i.to_le_bytes()));
            (
                r#","indices":1"#.to_string(),
                format!(
                    r#",{{"bufferView":1,"componentType":5123,"count":{},"type":"SCALAR"}}"#,
                    idx.len()
                ),
                format!(
                    r#",{{"buffer":0,"byteOffset":{pos_len},"byteLength":{}}}"#,
                    idx.len() * 2
                ),
            )
        })
        .unwrap_or_default();
    format!(
        r#"{{"asset":{{"version":"2.0"}},
        "meshes":[{{"primitives":[
            {{"attributes":{{"POSITION":0}},"mode":{mode}{index_ref}}}]}}],
        "accessors":[{{"bufferView":0,"componentType":5126,"count":{},"type":"VEC3",
            "min":[0,0,0],"max":[1,1,1]}}{index_accessor}],
        "bufferViews":[{{"buffer":0,"byteLength":{pos_len}}}{index_view}],
        "buffers":[{{"byteLength":{},"uri":"data:application/octet-stream;base64,{}"}}]}}"#,
        positions.len(),
        bytes.len(),
        base64(&bytes)
    )
}

fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for chunk in bytes.chunks(3) {
        let n = chunk
            .iter()
            .enumerate()
            .fold(0u32, |acc, (i, &b)| acc | u32::from(b) << (16 - 8 * i));
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(ALPHABET[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

const QUAD: [[f32; 3]; 4] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [1.0, 1.0, 0.0],
];

#[test]
fn strip_alternates_winding_and_drops_degenerates() {
    let list = triangle_list(Mode::TriangleStrip, &[0, 1, 2, 3, 3, 4]).unwrap();
    // (0,1,2) (2,1,3) then (2,3,3) and (3,3,4) are degenerate.
    assert_eq!(list, vec![0, 1, 2, 2, 1, 3]);
}

#[test]
fn fan_shares_the_first_corner() {
    let list = triangle_list(Mode::TriangleFan, &[5, 6, 7, 8]).unwrap();
    assert_eq!(list, vec![5, 6, 7, 5, 7, 8]);
    assert!(triangle_list(Mode::TriangleFan, &[]).unwrap().is_empty());
}

#[test]
fn triangles_need_a_multiple_of_three() {
    let err = triangle_list(Mode::Triangles, &[0, 1, 2, 3]).unwrap_err();
    assert!(err.contains("multiple of 3"), "{err}");
}

#[test]
fn strip_quad_faces_plus_z_everywhere() {
    let json = gltf_json(&QUAD, None, 5);
    let mesh = load_gltf_slice(json.as_bytes(), None, name()).unwrap();
    assert_eq!(mesh.triangle_count(), 2);
    assert!(
        mesh.normals.iter().all(|n| n.abs_diff_eq(Vec3::Z, 1e-6)),
        "{:?}",
        mesh.normals
    );
    assert!(mesh.colors.iter().all(|c| *c == [1.0; 4]));
}

#[test]
fn flat_shading_drops_zero_area_triangles() {
    let positions = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::X * 2.0];
    let mesh = flat_shaded(&positions, &[[1.0; 4]; 4], &[0, 1, 2, 0, 1, 3]);
    assert_eq!(mesh.triangle_count(), 1);
    assert_eq!(mesh.positions, vec![Vec3::ZERO, Vec3::X, Vec3::Y]);
    assert_eq!(mesh.normals, vec![Vec3::Z; 3]);
}

#[test]
fn point_mode_is_unsupported() {
    let json = gltf_json(&QUAD[..3], None, 0);
    let err = load_gltf_slice(json.as_bytes(), None, name()).unwrap_err();
    assert!(matches!(err, GltfError::Unsupported { .. }), "{err}");
    assert!(
        err.to_string()
            .contains("unsupported primitive mode POINTS"),
        "{err}"
    );
}

#[test]
fn u16_indices_are_read_and_range_checked() {
    let json = gltf_json(&QUAD, Some(&[0, 1, 2, 2, 1, 3]), 4);
    let mesh = load_gltf_slice(json.as_bytes(), None, name()).unwrap();
    assert_eq!(mesh.triangle_count(), 2);
    let json = gltf_json(&QUAD, Some(&[0, 1, 4]), 4);
    let err = load_gltf_slice(json.as_bytes(), None, name()).unwrap_err();
    assert!(
        err.to_string()
            .contains("index 4 (element 2) is out of range"),
        "{err}"
    );
}

#[test]
fn scene_less_file_loads_every_mesh() {
    let json = gltf_json(&QUAD[..3], None, 4);
    let mesh = load_gltf_slice(json.as_bytes(), None, name()).unwrap();
    assert_eq!(mesh.bounds(), Some((Vec3::ZERO, Vec3::new(1.0, 1.0, 0.0))));
}

#[test]
fn glb_header_shorter_than_itself_is_an_error() {
    for declared in [0u32, 11, 12, 19] {
        let mut glb = b"glTF".to_vec();
        glb.extend(2u32.to_le_bytes());
        glb.extend(declared.to_le_bytes());
        glb.extend([0u8; 16]);
        let err = load_gltf_slice(&glb, None, Path::new("x.glb")).unwrap_err();
        assert!(
            matches!(err, GltfError::Container { .. }),
            "{declared}: {err}"
        );
    }
}

#[test]
fn glb_version_one_is_rejected() {
    let mut glb = b"glTF".to_vec();
    glb.extend(1u32.to_le_bytes());
    glb.extend(20u32.to_le_bytes());
    glb.extend([0u8; 8]);
    let err = load_gltf_slice(&glb, None, Path::new("x.glb")).unwrap_err();
    assert!(err.to_string().contains("binary glTF version 1"), "{err}");
}

#[test]
fn percent_decoding() {
    assert_eq!(
        percent_decode("my%20mesh.bin").as_deref(),
        Some("my mesh.bin")
    );
    assert_eq!(percent_decode("bad%2"), None);
    assert_eq!(percent_decode("bad%zz"), None);
    assert_eq!(percent_decode("bad%+1"), None);
    assert_eq!(percent_decode("%FF"), None);
}

#[test]
fn external_buffer_without_base_dir_is_an_error() {
    let json = r#"{"asset":{"version":"2.0"},"buffers":[{"uri":"a.bin","byteLength":4}]}"#;
    let err = load_gltf_slice(json.as_bytes(), None, name()).unwrap_err();
    assert!(err.to_string().contains("no base directory"), "{err}");
}

#[test]
fn bom_and_whitespace_before_json_are_accepted() {
    let json = format!("\u{feff}\n  {}", gltf_json(&QUAD[..3], None, 4));
    assert!(load_gltf_slice(json.as_bytes(), None, name()).is_ok());
}

#[test]
fn dangling_position_index_is_an_error_not_a_panic() {
    let json = r#"{"asset":{"version":"2.0"},
        "meshes":[{"primitives":[{"attributes":{"POSITION":5}}]}]}"#;
    let err = load_gltf_slice(json.as_bytes(), None, name()).unwrap_err();
    assert!(matches!(err, GltfError::Invalid { .. }), "{err}");
    assert!(
        err.to_string().contains("accessor 5 does not exist"),
        "{err}"
    );
}

#[test]
fn file_without_meshes_has_no_geometry() {
    let json = r#"{"asset":{"version":"2.0"},"scenes":[{"nodes":[0]}],"nodes":[{}]}"#;
    let err = load_gltf_slice(json.as_bytes(), None, name()).unwrap_err();
    assert!(matches!(err, GltfError::NoGeometry { .. }), "{err}");
    assert_eq!(err.path(), name());
}
