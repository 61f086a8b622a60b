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
    let mesh = flat_shaded(&positions, &[[1.0; 4]; 4], &[], &[0, 1, 2, 0, 1, 3]);
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

// ---- UVs, textures, warnings --------------------------------------------------------------------

use std::sync::Arc;

use glam::Vec2;
use texel_geom::texture::{Filter, Image, Wrap};

use crate::texture::{encode_jpeg, encode_png};

const UV_QUAD: [[f32; 2]; 4] = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]];

/// The UVs of the flat-shaded strip quad: triangles (0, 1, 2) and (2, 1, 3).
fn flat_quad_uvs() -> Vec<Vec2> {
    [0, 1, 2, 2, 1, 3]
        .map(|i| Vec2::from_array(UV_QUAD[i]))
        .to_vec()
}

/// A 2 × 2 PNG: red, green / blue, white.
fn png_2x2() -> Vec<u8> {
    let mut img = Image::solid("t", 2, 2, [255; 4]);
    img.pixels[..12].copy_from_slice(&[255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255]);
    encode_png(&img)
}

fn data_uri(mime: &str, bytes: &[u8]) -> String {
    format!("data:{mime};base64,{}", base64(bytes))
}

/// `primitives` strip quads (no scenes) sharing one data: URI buffer, primitive `i` with the
/// attributes and members of `prims[i]` (e.g. `,"material":0`); a primitive with `uv` has
/// `TEXCOORD_0` (accessor 1, float). `members` adds top-level JSON members (materials,
/// textures, images ...), each starting with a comma.
fn textured_json(prims: &[(bool, &str)], members: &str) -> String {
    let mut bytes: Vec<u8> = QUAD
        .iter()
        .flatten()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    bytes.extend(UV_QUAD.iter().flatten().flat_map(|v| v.to_le_bytes()));
    let primitives: Vec<String> = prims
        .iter()
        .map(|(uv, extra)| {
            let uv = if *uv { r#","TEXCOORD_0":1"# } else { "" };
            format!(r#"{{"attributes":{{"POSITION":0{uv}}},"mode":5{extra}}}"#)
        })
        .collect();
    format!(
        r#"{{"asset":{{"version":"2.0"}},
        "meshes":[{{"primitives":[{}]}}],
        "accessors":[
            {{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3",
              "min":[0,0,0],"max":[1,1,0]}},
            {{"bufferView":1,"componentType":5126,"count":4,"type":"VEC2"}}],
        "bufferViews":[{{"buffer":0,"byteLength":48}},
                       {{"buffer":0,"byteOffset":48,"byteLength":32}}],
        "buffers":[{{"byteLength":{},"uri":"{}"}}]{members}}}"#,
        primitives.join(","),
        bytes.len(),
        data_uri("application/octet-stream", &bytes)
    )
}

/// One material with a base-colour texture from image 0, a data: URI of `png`.
fn albedo_members(png: &[u8], sampler: &str) -> String {
    format!(
        r#","materials":[{{"pbrMetallicRoughness":{{"baseColorTexture":{{"index":0}}}}}}],
        "textures":[{{"source":0{sampler}}}],
        "images":[{{"uri":"{}"}}]"#,
        data_uri("image/png", png)
    )
}

fn import_json(json: &str) -> Result<GltfImport, GltfError> {
    import(
        json.as_bytes(),
        None,
        name(),
        &GltfLimits::default(),
        DEFAULT_MAX_IMAGE_BYTES,
    )
}

#[test]
fn data_uri_image_becomes_the_albedo_of_a_part() {
    let json = textured_json(
        &[(true, r#","material":0"#)],
        &albedo_members(&png_2x2(), ""),
    );
    let imported = import_json(&json).unwrap();
    let mesh = &imported.mesh;
    assert!(imported.warnings.is_empty(), "{:?}", imported.warnings);
    // No normals: flat shaded, each corner keeping its UV.
    assert_eq!(mesh.uvs, flat_quad_uvs());
    assert_eq!(mesh.parts.len(), 1);
    assert_eq!(mesh.parts[0].first_triangle, 0);
    assert_eq!(mesh.parts[0].maps.uv_scale, Vec2::ONE);
    assert!(mesh.parts[0].maps.normal.is_none());
    let albedo = mesh.parts[0].maps.albedo.as_ref().unwrap();
    assert_eq!((albedo.image.width, albedo.image.height), (2, 2));
    assert_eq!(albedo.image.pixel(0, 0), [255, 0, 0, 255]);
    assert_eq!(albedo.image.pixel(1, 0), [0, 255, 0, 255]);
    assert_eq!(albedo.image.pixel(0, 1), [0, 0, 255, 255]);
    assert_eq!(albedo.image.pixel(1, 1), [255; 4]);
    assert_eq!(albedo.image.name, "mem.gltf image 0");
    // No sampler: nearest (the pixel-art default) and repeat (the glTF default).
    assert_eq!(albedo.sampler.filter, Filter::Nearest);
    assert_eq!(albedo.sampler.wrap, [Wrap::Repeat; 2]);
}

#[test]
fn samplers_map_mag_filter_and_wraps() {
    for (sampler, filter, wrap) in [
        (
            r#"{"magFilter":9729,"wrapS":33648,"wrapT":33071}"#,
            Filter::Linear,
            [Wrap::MirroredRepeat, Wrap::ClampToEdge],
        ),
        (
            r#"{"magFilter":9728,"minFilter":9987,"wrapS":10497}"#,
            Filter::Nearest,
            [Wrap::Repeat; 2],
        ),
        // minFilter alone decides nothing.
        (r#"{"minFilter":9729}"#, Filter::Nearest, [Wrap::Repeat; 2]),
    ] {
        let members = format!(
            r#"{},"samplers":[{sampler}]"#,
            albedo_members(&png_2x2(), r#","sampler":0"#)
        );
        let json = textured_json(&[(true, r#","material":0"#)], &members);
        let mesh = import_json(&json).unwrap().mesh;
        let albedo = mesh.parts[0].maps.albedo.as_ref().unwrap();
        assert_eq!(albedo.sampler.filter, filter, "{sampler}");
        assert_eq!(albedo.sampler.wrap, wrap, "{sampler}");
    }
}

#[test]
fn one_image_is_decoded_once_for_every_use() {
    // Two textures on the same image, as albedo and normal map, on three primitives.
    let members = format!(
        r#","materials":[{{"pbrMetallicRoughness":{{"baseColorTexture":{{"index":0}}}},
            "normalTexture":{{"index":1}}}}],
        "textures":[{{"source":0}},{{"source":0,"sampler":0}}],
        "samplers":[{{"magFilter":9729}}],
        "images":[{{"uri":"{}"}}]"#,
        data_uri("image/png", &png_2x2())
    );
    let prim = (true, r#","material":0"#);
    let json = textured_json(&[prim, prim, prim], &members);
    // 16 bytes decoded: a budget of 16 is enough when the image is decoded once.
    let imported = import(json.as_bytes(), None, name(), &GltfLimits::default(), 16).unwrap();
    let parts = &imported.mesh.parts;
    assert_eq!(
        parts.iter().map(|p| p.first_triangle).collect::<Vec<_>>(),
        [0, 2, 4]
    );
    let first = parts[0].maps.albedo.as_ref().unwrap();
    for part in parts {
        let albedo = part.maps.albedo.as_ref().unwrap();
        let normal = part.maps.normal.as_ref().unwrap();
        assert!(Arc::ptr_eq(&albedo.image, &first.image));
        assert!(Arc::ptr_eq(&normal.image, &first.image));
        assert_eq!(albedo.sampler.filter, Filter::Nearest);
        assert_eq!(normal.sampler.filter, Filter::Linear);
    }
    let err = import(json.as_bytes(), None, name(), &GltfLimits::default(), 15).unwrap_err();
    assert!(matches!(err, GltfError::Budget { .. }), "{err}");
    assert!(
        err.to_string().contains("TEXEL_GLTF_MAX_IMAGE_BYTES"),
        "{err}"
    );
}

#[test]
fn primitives_without_texcoords_get_zero_uvs_only_beside_one_with() {
    let json = textured_json(&[(false, ""), (true, "")], "");
    let mesh = import_json(&json).unwrap().mesh;
    assert_eq!(mesh.uvs.len(), 12);
    assert!(mesh.uvs[..6].iter().all(|uv| *uv == Vec2::ZERO));
    assert_eq!(mesh.uvs[6..], flat_quad_uvs());
    assert!(mesh.parts.is_empty(), "no material has textures");
    let json = textured_json(&[(false, ""), (false, "")], "");
    let mesh = import_json(&json).unwrap().mesh;
    assert!(mesh.uvs.is_empty() && mesh.parts.is_empty());
}

#[test]
fn untextured_primitive_after_a_textured_one_falls_back_to_the_object() {
    let members = albedo_members(&png_2x2(), "");
    let json = textured_json(&[(true, r#","material":0"#), (true, "")], &members);
    let mesh = import_json(&json).unwrap().mesh;
    assert_eq!(mesh.parts.len(), 2);
    assert!(mesh.part_of(1).unwrap().maps.albedo.is_some());
    assert!(mesh.part_of(2).unwrap().maps.is_empty());
}

#[test]
fn flat_shading_keeps_uvs() {
    let uvs = [Vec2::ZERO, Vec2::X, Vec2::Y, Vec2::ONE];
    let positions = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::X * 2.0];
    let mesh = flat_shaded(
        &positions,
        &[[1.0; 4]; 4],
        &uvs,
        &[0, 1, 2, 0, 1, 3, 2, 1, 0],
    );
    assert_eq!(mesh.triangle_count(), 2);
    assert_eq!(
        mesh.uvs,
        [Vec2::ZERO, Vec2::X, Vec2::Y, Vec2::Y, Vec2::X, Vec2::ZERO]
    );
}

/// The quad with `TEXCOORD_0` of `component_type` (normalised or not) holding `values`.
fn integer_uv_json(component_type: u32, normalized: bool, values: &[u8]) -> String {
    let mut bytes: Vec<u8> = QUAD
        .iter()
        .flatten()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    bytes.extend(values);
    format!(
        r#"{{"asset":{{"version":"2.0"}},
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0,"TEXCOORD_0":1}},"mode":5}}]}}],
        "accessors":[
            {{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3",
              "min":[0,0,0],"max":[1,1,0]}},
            {{"bufferView":1,"componentType":{component_type},"normalized":{normalized},
              "count":4,"type":"VEC2"}}],
        "bufferViews":[{{"buffer":0,"byteLength":48}},
                       {{"buffer":0,"byteOffset":48,"byteLength":{}}}],
        "buffers":[{{"byteLength":{},"uri":"{}"}}]}}"#,
        values.len(),
        bytes.len(),
        data_uri("application/octet-stream", &bytes)
    )
}

#[test]
fn normalized_integer_texcoords_are_read() {
    let json = integer_uv_json(5121, true, &[0, 0, 255, 0, 0, 51, 255, 255]);
    let mesh = import_json(&json).unwrap().mesh;
    // Flat shaded: corners are vertices 0, 1, 2, 2, 1, 3.
    assert_eq!(mesh.uvs[1], Vec2::X);
    assert!((mesh.uvs[2].y - 0.2).abs() < 1e-6, "{}", mesh.uvs[2]);
    assert_eq!(mesh.uvs[5], Vec2::ONE);
    let u16s: Vec<u8> = [0u16, 0, 65535, 0, 0, 65535, 65535, 32768]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    let mesh = import_json(&integer_uv_json(5123, true, &u16s))
        .unwrap()
        .mesh;
    assert_eq!(mesh.uvs[2], Vec2::Y);
    assert!((mesh.uvs[5].y - 0.5).abs() < 1e-4, "{}", mesh.uvs[5]);
    let err = import_json(&integer_uv_json(5121, false, &[0; 8])).unwrap_err();
    assert!(matches!(err, GltfError::Accessor { index: 1, .. }), "{err}");
    assert!(err.to_string().contains("must be normalized"), "{err}");
}

#[test]
fn jpeg_images_decode() {
    let members = format!(
        r#","materials":[{{"pbrMetallicRoughness":{{"baseColorTexture":{{"index":0}}}}}}],
        "textures":[{{"source":0}}],
        "images":[{{"uri":"{}"}}]"#,
        data_uri("image/jpeg", &encode_jpeg(8, 8, [40, 80, 160]))
    );
    let json = textured_json(&[(true, r#","material":0"#)], &members);
    let mesh = import_json(&json).unwrap().mesh;
    let image = &mesh.parts[0].maps.albedo.as_ref().unwrap().image;
    assert_eq!((image.width, image.height), (8, 8));
    let [r, g, b, a] = image.pixel(4, 4);
    assert!(r.abs_diff(40) <= 4 && g.abs_diff(80) <= 4 && b.abs_diff(160) <= 4 && a == 255);
}

#[test]
fn broken_images_of_used_materials_are_errors_naming_the_image() {
    let cases = [
        (
            r#"{"name":"nothing"}"#.to_owned(),
            "has neither a uri nor a bufferView",
        ),
        (
            format!(r#"{{"uri":"{}"}}"#, data_uri("image/png", b"not a png")),
            "not a PNG or JPEG",
        ),
        (
            format!(r#"{{"uri":"{}"}}"#, data_uri("image/png", &png_2x2()[..40])),
            "cannot decode PNG",
        ),
        (
            r#"{"uri":"data:image/png;base64,%%%"}"#.to_owned(),
            "invalid data: URI",
        ),
        (r#"{"uri":"albedo.png"}"#.to_owned(), "no base directory"),
        (
            r#"{"uri":"https://example.com/a.png"}"#.to_owned(),
            "unsupported URI",
        ),
    ];
    for (image, phrase) in cases {
        let members = format!(
            r#","materials":[{{"pbrMetallicRoughness":{{"baseColorTexture":{{"index":0}}}}}}],
            "textures":[{{"source":1}}],
            "images":[{{"uri":"{}"}},{image}]"#,
            data_uri("image/png", &png_2x2())
        );
        let json = textured_json(&[(true, r#","material":0"#)], &members);
        let err = import_json(&json).unwrap_err();
        assert!(matches!(err, GltfError::Image { index: 1, .. }), "{err}");
        let text = err.to_string();
        assert!(text.starts_with("mem.gltf: image 1: "), "{text}");
        assert!(text.contains(phrase), "{phrase}: {text}");
    }
}

#[test]
fn images_no_imported_primitive_uses_are_never_read() {
    // Material 1 (unused) names a missing file and an undecodable image.
    let members = format!(
        r#","materials":[{{}},{{"pbrMetallicRoughness":{{"baseColorTexture":{{"index":0}}}},
            "normalTexture":{{"index":1}}}}],
        "textures":[{{"source":0}},{{"source":1}}],
        "images":[{{"uri":"missing.png"}},{{"uri":"{}"}}]"#,
        data_uri("image/png", b"junk")
    );
    let json = textured_json(&[(true, r#","material":0"#)], &members);
    let imported = import_json(&json).unwrap();
    assert!(imported.mesh.parts.is_empty());
    assert!(imported.warnings.is_empty(), "{:?}", imported.warnings);
}

#[test]
fn unsupported_features_are_reported_once_per_file() {
    let png = data_uri("image/png", &png_2x2());
    let members = format!(
        r#","extensionsUsed":["KHR_texture_transform","KHR_materials_unlit"],
        "materials":[
            {{"pbrMetallicRoughness":{{"baseColorTexture":{{"index":0,"texCoord":1}},
                "metallicRoughnessTexture":{{"index":0}}}},
              "normalTexture":{{"index":0,"scale":2}},
              "occlusionTexture":{{"index":0}},"emissiveTexture":{{"index":0}}}},
            {{"pbrMetallicRoughness":{{"metallicRoughnessTexture":{{"index":0}}}},
              "emissiveTexture":{{"index":0}}}}],
        "textures":[{{"source":0}}],
        "images":[{{"uri":"{png}"}}],
        "nodes":[{{}}],
        "skins":[{{"joints":[0]}}],
        "cameras":[{{"type":"perspective","perspective":{{"yfov":1.0,"znear":0.1}}}}],
        "animations":[{{"channels":[],"samplers":[]}}]"#
    );
    let morph = r#","material":0,"targets":[{"POSITION":0}]"#;
    let prims = [
        (true, morph),
        (true, morph),
        (true, r#","material":1"#),
        (false, r#","material":0"#),
        (false, r#","material":0"#),
    ];
    let json = textured_json(&prims, &members);
    let imported = import_json(&json).unwrap();
    let w = &imported.warnings;
    let expected = [
        "1 skin ignored",
        "1 animation ignored",
        "1 camera ignored",
        "extension KHR_texture_transform ignored: texture offsets",
        "extension KHR_materials_unlit ignored",
        "morph targets ignored (first in mesh 0 primitive 0)",
        "metallic-roughness textures ignored (first in material 0)",
        "occlusion textures ignored (first in material 0)",
        "emissive textures ignored (first in material 0)",
        "textures on TEXCOORD_1 or above ignored (first: the base-colour texture of material 0, \
         on TEXCOORD_1)",
        "normal texture scale ignored (first 2 in material 0)",
        "mesh 0 primitive 3 has textures but no TEXCOORD_0",
    ];
    assert_eq!(w.len(), expected.len(), "{w:#?}");
    for (warning, start) in w.iter().zip(expected) {
        assert!(
            warning.starts_with(start),
            "{warning:?} should start {start:?}"
        );
    }
    // The normal map (TEXCOORD_0) still applies; the TEXCOORD_1 base colour does not.
    let maps = &imported.mesh.parts[0].maps;
    assert!(maps.albedo.is_none() && maps.normal.is_some());
}
