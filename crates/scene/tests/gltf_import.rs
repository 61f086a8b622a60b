//! Integration tests for `texel_scene::gltf_import`: the project's own meshes in `assets/meshes/`
//! (made by `assets/meshes/make_meshes.py`) and the broken files in `tests/data/gltf/` (made by
//! `tests/data/gltf/make_broken.py`). The expected numbers below come from those generators.

use std::path::{Path, PathBuf};

use std::sync::Arc;

use glam::{Vec2, Vec3};
use proptest::prelude::*;
use texel_geom::texture::{Filter, Image, Wrap};
use texel_scene::TriMesh;
use texel_scene::gltf_import::{
    GltfError, GltfImport, GltfLimits, load_gltf, load_gltf_report, load_gltf_report_with,
    load_gltf_slice,
};
use texel_scene::texture::encode_png;

const EPS: f32 = 1e-4;

fn asset(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../assets/meshes")
        .join(name)
}

fn broken(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/gltf")
        .join(name)
}

fn load(path: &Path) -> TriMesh {
    load_gltf(path).unwrap_or_else(|e| panic!("{e}"))
}

fn triangles(mesh: &TriMesh) -> impl Iterator<Item = [usize; 3]> + '_ {
    mesh.indices
        .chunks_exact(3)
        .map(|t| [t[0] as usize, t[1] as usize, t[2] as usize])
}

fn corners(mesh: &TriMesh, tri: [usize; 3]) -> [Vec3; 3] {
    tri.map(|i| mesh.positions[i])
}

/// Unit normal of the counter-clockwise triangle.
fn face_normal([a, b, c]: [Vec3; 3]) -> Vec3 {
    (b - a).cross(c - a).normalize()
}

fn assert_bounds(mesh: &TriMesh, min: Vec3, max: Vec3) {
    let (lo, hi) = mesh.bounds().expect("mesh has vertices");
    assert!(
        lo.abs_diff_eq(min, EPS) && hi.abs_diff_eq(max, EPS),
        "bounds {lo}..{hi}, expected {min}..{max}"
    );
}

fn assert_well_formed(mesh: &TriMesh) {
    let n = mesh.positions.len();
    assert_eq!(mesh.normals.len(), n);
    assert_eq!(mesh.colors.len(), n);
    assert_eq!(mesh.indices.len() % 3, 0);
    assert!(mesh.indices.iter().all(|&i| (i as usize) < n));
    for (i, normal) in mesh.normals.iter().enumerate() {
        assert!((normal.length() - 1.0).abs() < EPS, "normal {i} = {normal}");
    }
}

/// Volume by the divergence theorem; exact for closed meshes wound counter-clockwise outward
/// (inverted faces make it wrong).
fn signed_volume(mesh: &TriMesh) -> f32 {
    triangles(mesh)
        .map(|t| {
            let [a, b, c] = corners(mesh, t);
            a.dot(b.cross(c)) / 6.0
        })
        .sum()
}

// ---- obelisk.gltf: external .bin, normals, grey material, TRS parent node --------------------

#[test]
fn obelisk_has_24_triangles() {
    let mesh = load(&asset("obelisk.gltf"));
    assert_eq!(mesh.triangle_count(), 24);
    assert_eq!(
        mesh.positions.len(),
        52,
        "file's own vertices, not regenerated"
    );
    assert_well_formed(&mesh);
}

#[test]
fn obelisk_bounds_include_the_node_hierarchy() {
    // Local x, z in [-0.7, 0.7], y in [0, 3.8]; child +0.5 y; parent scale (2, 1.5, 1), then 90°
    // about +Y ((x, y, z) -> (z, y, -x)), then translation (10, 0, -4). The unused scene's copy at
    // x = 100 must not be loaded.
    let mesh = load(&asset("obelisk.gltf"));
    assert_bounds(
        &mesh,
        Vec3::new(9.3, 0.75, -5.4),
        Vec3::new(10.7, 6.45, -2.6),
    );
}

#[test]
fn obelisk_file_normals_follow_the_transformed_faces() {
    // With the non-uniform parent scale only inverse-transpose normals stay perpendicular to the
    // faces; a winding flip would point them inward.
    let mesh = load(&asset("obelisk.gltf"));
    for tri in triangles(&mesh) {
        let geometric = face_normal(corners(&mesh, tri));
        for i in tri {
            let agreement = mesh.normals[i].dot(geometric);
            assert!(
                agreement > 0.999,
                "vertex {i}: {} vs {geometric}",
                mesh.normals[i]
            );
        }
    }
}

#[test]
fn obelisk_colour_is_the_grey_material() {
    let mesh = load(&asset("obelisk.gltf"));
    assert!(
        mesh.colors.iter().all(|c| *c == [0.6, 0.6, 0.6, 1.0]),
        "{:?}",
        mesh.colors[0]
    );
}

#[test]
fn slice_loading_matches_file_loading() {
    let path = asset("obelisk.gltf");
    let bytes = std::fs::read(&path).unwrap();
    let from_slice = load_gltf_slice(&bytes, path.parent(), &path).unwrap();
    assert_eq!(from_slice, load(&path));
    for name in ["arch.glb", "crate.glb"] {
        let glb = asset(name);
        let bytes = std::fs::read(&glb).unwrap();
        assert_eq!(load_gltf_slice(&bytes, None, &glb).unwrap(), load(&glb));
    }
}

#[test]
fn files_without_textures_have_no_parts_or_uvs() {
    for name in ["obelisk.gltf", "arch.glb"] {
        let import = load_gltf_report(&asset(name)).unwrap();
        assert!(import.mesh.parts.is_empty(), "{name}");
        assert!(import.mesh.uvs.is_empty(), "{name}");
        assert!(import.warnings.is_empty(), "{name}: {:?}", import.warnings);
    }
}

#[test]
fn slice_without_base_dir_cannot_resolve_the_bin() {
    let path = asset("obelisk.gltf");
    let bytes = std::fs::read(&path).unwrap();
    let err = load_gltf_slice(&bytes, None, Path::new("in-memory.gltf")).unwrap_err();
    let message = err.to_string();
    assert!(
        message.starts_with("in-memory.gltf: buffer 0:"),
        "{message}"
    );
    assert!(
        message.contains("obelisk.bin") && message.contains("no base directory"),
        "{message}"
    );
}

// ---- arch.glb: binary, no normals, two materials, COLOR_0 ------------------------------------

/// The arch's boxes from make_meshes.py: left pillar, right pillar, lintel.
const ARCH_BOXES: [(Vec3, Vec3); 3] = [
    (Vec3::new(-1.4, 0.0, -0.4), Vec3::new(-0.8, 2.0, 0.4)),
    (Vec3::new(0.8, 0.0, -0.4), Vec3::new(1.4, 2.0, 0.4)),
    (Vec3::new(-1.7, 1.8, -0.3), Vec3::new(1.7, 2.4, 0.3)),
];

fn contains(&(lo, hi): &(Vec3, Vec3), p: Vec3) -> bool {
    p.cmpge(lo - EPS).all() && p.cmple(hi + EPS).all()
}

#[test]
fn arch_has_36_triangles_with_generated_normals() {
    let mesh = load(&asset("arch.glb"));
    assert_eq!(mesh.triangle_count(), 36);
    assert_eq!(
        mesh.positions.len(),
        108,
        "flat shading: 3 vertices per triangle"
    );
    assert_well_formed(&mesh);
    assert_bounds(&mesh, Vec3::new(-1.7, 0.0, -0.4), Vec3::new(1.7, 2.4, 0.4));
}

#[test]
fn arch_generated_normals_face_out_of_their_box() {
    let mesh = load(&asset("arch.glb"));
    for tri in triangles(&mesh) {
        let pts = corners(&mesh, tri);
        let owners: Vec<_> = ARCH_BOXES
            .iter()
            .filter(|b| pts.iter().all(|p| contains(b, *p)))
            .collect();
        assert_eq!(
            owners.len(),
            1,
            "triangle {pts:?} should belong to exactly one box"
        );
        let (lo, hi) = *owners[0];
        let outward = (pts[0] + pts[1] + pts[2]) / 3.0 - (lo + hi) / 2.0;
        for i in tri {
            assert!(
                mesh.normals[i].dot(outward) > 0.0,
                "{pts:?}: {}",
                mesh.normals[i]
            );
            assert!(mesh.normals[i].abs_diff_eq(face_normal(pts), EPS));
        }
    }
}

#[test]
fn arch_is_closed_and_wound_outward() {
    // Each box is closed, so the divergence-theorem volume is the sum of the box volumes.
    let expected: f32 = ARCH_BOXES
        .iter()
        .map(|(lo, hi)| (*hi - *lo).element_product())
        .sum();
    let volume = signed_volume(&load(&asset("arch.glb")));
    assert!(
        (volume - expected).abs() < 1e-3,
        "volume {volume}, expected {expected}"
    );
}

#[test]
fn arch_colours_are_material_times_color_0() {
    let mesh = load(&asset("arch.glb"));
    let sandstone = [0.8, 0.7, 0.5, 1.0];
    let slate = [0.3, 0.35, 0.4, 1.0];
    let dim = 128.0 / 255.0;
    let slate_dim = [0.3 * dim, 0.35 * dim, 0.4 * dim, 1.0];
    let near = |a: &[f32; 4], b: &[f32; 4]| a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-5);
    let count = |c: &[f32; 4]| mesh.colors.iter().filter(|v| near(v, c)).count();
    assert_eq!(count(&sandstone), 72, "pillars: 24 triangles");
    assert_eq!(
        count(&slate) + count(&slate_dim),
        36,
        "lintel: 12 triangles"
    );
    assert_eq!(
        count(&slate_dim),
        18,
        "lintel bottom corners carry COLOR_0 = 128/255"
    );
    for (p, c) in mesh.positions.iter().zip(&mesh.colors) {
        if near(c, &slate_dim) {
            assert!((p.y - 1.8).abs() < EPS, "dim slate vertex at {p}");
        }
    }
}

// ---- crate.glb: TEXCOORD_0, embedded albedo and normal PNGs, NEAREST sampler, COLOR_0 -------

/// The crate's palette and lid tint from make_meshes.py.
const CRATE_BORDER: [u8; 4] = [92, 58, 30, 255];
const CRATE_FRAME: [u8; 4] = [140, 94, 52, 255];
const CRATE_BRACE: [u8; 4] = [196, 146, 86, 255];
const CRATE_SEAM: [u8; 4] = [120, 80, 44, 255];
const CRATE_PLANK: [u8; 4] = [164, 112, 62, 255];
const LID_TINT: [f32; 4] = [1.0, 0.85, 0.7, 1.0];

fn crate_import() -> GltfImport {
    load_gltf_report(&asset("crate.glb")).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn crate_has_12_triangles_with_uvs_and_no_warnings() {
    let GltfImport { mesh, warnings } = crate_import();
    assert!(warnings.is_empty(), "{warnings:?}");
    assert_eq!(mesh.triangle_count(), 12);
    assert_eq!(
        mesh.positions.len(),
        24,
        "the file's own vertices, 4 per face"
    );
    assert_eq!(mesh.uvs.len(), 24);
    assert_well_formed(&mesh);
    assert_bounds(&mesh, Vec3::new(-0.5, 0.0, -0.5), Vec3::new(0.5, 1.0, 0.5));
    assert!((signed_volume(&mesh) - 1.0).abs() < 1e-4);
    // Every face shows the whole image once: its four corners take the four UV corners.
    for face in mesh.uvs.chunks_exact(4) {
        let mut corners: Vec<_> = face.iter().map(|uv| (uv.x as i32, uv.y as i32)).collect();
        corners.sort();
        assert_eq!(corners, [(0, 0), (0, 1), (1, 0), (1, 1)], "{face:?}");
    }
    // Upright: the top of the image (V = 0) is the top of each side face; on the lid, the image's
    // top-left corner is at -X, -Z.
    for (p, (n, uv)) in mesh
        .positions
        .iter()
        .zip(mesh.normals.iter().zip(&mesh.uvs))
    {
        if n.y.abs() < 0.5 {
            assert_eq!(uv.y, 1.0 - p.y, "side vertex {p}");
        } else if n.y > 0.5 && p.x < 0.0 && p.z < 0.0 {
            assert_eq!(*uv, Vec2::ZERO, "lid vertex {p}");
        }
    }
}

#[test]
fn crate_primitives_are_parts_sharing_albedo_and_normal_images() {
    let mesh = crate_import().mesh;
    let starts: Vec<_> = mesh.parts.iter().map(|p| p.first_triangle).collect();
    assert_eq!(starts, [0, 10], "body (10 triangles), then lid (2)");
    let body = &mesh.parts[0].maps;
    let lid = &mesh.parts[1].maps;
    let (albedo, normal) = (body.albedo.as_ref().unwrap(), body.normal.as_ref().unwrap());
    assert_eq!(body.uv_scale, Vec2::ONE);
    assert!(Arc::ptr_eq(
        &albedo.image,
        &lid.albedo.as_ref().unwrap().image
    ));
    assert!(Arc::ptr_eq(
        &normal.image,
        &lid.normal.as_ref().unwrap().image
    ));
    for t in [albedo, normal] {
        assert_eq!(t.sampler.filter, Filter::Nearest);
        assert_eq!(t.sampler.wrap, [Wrap::ClampToEdge; 2]);
    }
    assert_eq!(
        albedo.image.name,
        format!("{} image 0 \"CrateAlbedo\"", asset("crate.glb").display())
    );
}

#[test]
fn crate_textures_hold_the_pixel_art() {
    let mesh = crate_import().mesh;
    let maps = &mesh.parts[0].maps;
    let albedo = &maps.albedo.as_ref().unwrap().image;
    assert_eq!((albedo.width, albedo.height), (16, 16));
    assert_eq!(albedo.pixel(0, 0), CRATE_BORDER);
    assert_eq!(albedo.pixel(15, 9), CRATE_BORDER);
    assert_eq!(albedo.pixel(1, 7), CRATE_FRAME);
    assert_eq!(albedo.pixel(7, 7), CRATE_BRACE);
    assert_eq!(albedo.pixel(8, 7), CRATE_BRACE);
    assert_eq!(albedo.pixel(3, 10), CRATE_SEAM);
    assert_eq!(albedo.pixel(12, 3), CRATE_PLANK);
    let normal = &maps.normal.as_ref().unwrap().image;
    assert_eq!((normal.width, normal.height), (16, 16));
    assert_eq!(normal.pixel(8, 8), [128, 128, 255, 255], "flat inside");
    assert_eq!(normal.pixel(8, 0), [128, 204, 230, 255], "top row leans up");
    assert_eq!(
        normal.pixel(8, 15),
        [128, 51, 230, 255],
        "bottom row leans down"
    );
    assert_eq!(
        normal.pixel(0, 8),
        [51, 128, 230, 255],
        "left column leans left"
    );
    assert_eq!(
        normal.pixel(15, 8),
        [204, 128, 230, 255],
        "right column leans right"
    );
}

#[test]
fn crate_lid_carries_color_0() {
    let mesh = crate_import().mesh;
    for (i, (p, c)) in mesh.positions.iter().zip(&mesh.colors).enumerate() {
        // The lid is the second primitive: the last 4 vertices.
        let lid = i >= 20;
        let expected = if lid { LID_TINT } else { [1.0; 4] };
        let near = c.iter().zip(expected).all(|(a, b)| (a - b).abs() < 1e-6);
        assert!(near, "vertex {i} at {p}: {c:?}");
        assert_eq!(lid, p.y == 1.0 && mesh.normals[i].y > 0.5, "vertex {i}");
    }
}

// ---- external images -------------------------------------------------------------------------

/// Writes `dir/model.gltf`: a triangle with TEXCOORD_0 (buffer `model.bin`) whose material's
/// base-colour texture is image 0 at `image_uri`; returns the glTF's path.
fn write_textured(dir: &Path, image_uri: &str) -> PathBuf {
    let values: [f32; 15] = [0., 0., 0., 1., 0., 0., 0., 1., 0., 0., 0., 1., 0., 0., 1.];
    let bin: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
    std::fs::write(dir.join("model.bin"), bin).unwrap();
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0,"TEXCOORD_0":1}},
            "material":0}}]}}],
        "materials":[{{"pbrMetallicRoughness":{{"baseColorTexture":{{"index":0}}}}}}],
        "textures":[{{"source":0}}],
        "images":[{{"uri":{image_uri:?}}}],
        "accessors":[
            {{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3",
              "min":[0,0,0],"max":[1,1,0]}},
            {{"bufferView":1,"componentType":5126,"count":3,"type":"VEC2"}}],
        "bufferViews":[{{"buffer":0,"byteLength":36}},
                       {{"buffer":0,"byteOffset":36,"byteLength":24}}],
        "buffers":[{{"byteLength":60,"uri":"model.bin"}}]}}"#
    );
    let path = dir.join("model.gltf");
    std::fs::write(&path, json).unwrap();
    path
}

fn albedo_of(mesh: &TriMesh) -> &Image {
    &mesh.parts[0]
        .maps
        .albedo
        .as_ref()
        .expect("an albedo texture")
        .image
}

#[test]
fn external_image_file_is_read() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("tex")).unwrap();
    let image = Image::solid("t", 3, 2, [10, 20, 30, 255]);
    std::fs::write(dir.path().join("tex/my albedo.png"), encode_png(&image)).unwrap();
    let path = write_textured(dir.path(), "tex/my%20albedo.png");
    let mesh = load(&path);
    assert_eq!(mesh.uvs, [Vec2::ZERO, Vec2::X, Vec2::Y]);
    let albedo = albedo_of(&mesh);
    assert_eq!((albedo.width, albedo.height), (3, 2));
    assert_eq!(albedo.pixel(2, 1), [10, 20, 30, 255]);
}

#[test]
fn external_jpeg_file_decodes() {
    let dir = tempfile::tempdir().unwrap();
    let mut jpeg = Vec::new();
    image::codecs::jpeg::JpegEncoder::new_with_quality(&mut jpeg, 95)
        .encode(
            &[250, 250, 250].repeat(16),
            4,
            4,
            image::ExtendedColorType::Rgb8,
        )
        .unwrap();
    // Named .png on purpose: the format is recognised from the bytes.
    std::fs::write(dir.path().join("albedo.png"), jpeg).unwrap();
    let mesh = load(&write_textured(dir.path(), "albedo.png"));
    let [r, g, b, a] = albedo_of(&mesh).pixel(1, 1);
    assert!(
        r >= 245 && g >= 245 && b >= 245 && a == 255,
        "{r} {g} {b} {a}"
    );
}

#[test]
fn image_uri_leaving_the_folder_is_refused() {
    let outer = tempfile::tempdir().unwrap();
    let dir = outer.path().join("model");
    std::fs::create_dir(&dir).unwrap();
    let outside = outer.path().join("outside.png");
    std::fs::write(&outside, encode_png(&Image::solid("t", 1, 1, [9; 4]))).unwrap();
    for (uri, why) in [
        ("../outside.png", "leads out of the folder with `..`"),
        (outside.to_str().unwrap(), "is an absolute path"),
    ] {
        let path = write_textured(&dir, uri);
        let err = load_gltf(&path).unwrap_err();
        assert!(matches!(err, GltfError::Image { index: 0, .. }), "{err}");
        let message = err.to_string();
        assert!(
            message.starts_with(&format!("{}: image 0: image URI", path.display())),
            "{message}"
        );
        assert!(
            message.contains(why) && message.contains("TEXEL_GLTF_ANY_URI=1"),
            "{message}"
        );
        let limits = GltfLimits {
            allow_any_uri: true,
            ..GltfLimits::default()
        };
        let mesh = load_gltf_report_with(&path, &limits).unwrap().mesh;
        assert_eq!(albedo_of(&mesh).pixel(0, 0), [9; 4]);
    }
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink(&outside, dir.join("link.png")).unwrap();
        let err = load_gltf(&write_textured(&dir, "link.png")).unwrap_err();
        assert!(err.to_string().contains("through a symbolic link"), "{err}");
    }
}

#[test]
fn missing_image_file_errors_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    let path = write_textured(dir.path(), "missing.png");
    let err = load_gltf(&path).unwrap_err();
    assert!(matches!(err, GltfError::Image { index: 0, .. }), "{err}");
    let message = err.to_string();
    let file = dir.path().join("missing.png");
    assert!(
        message.starts_with(&format!(
            "{}: image 0: cannot read `{}`",
            path.display(),
            file.display()
        )),
        "{message}"
    );
}

#[test]
fn undecodable_image_file_errors_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("junk.png"), "not an image").unwrap();
    let path = write_textured(dir.path(), "junk.png");
    let message = load_gltf(&path).unwrap_err().to_string();
    let file = dir.path().join("junk.png");
    assert!(
        message.contains(&format!("image 0: `{}`: not a PNG or JPEG", file.display())),
        "{message}"
    );
}

// ---- broken files ---------------------------------------------------------------------------

/// Loads a broken file; the message must start with its path and contain `phrase`.
fn broken_error(file: &str, phrase: &str) -> GltfError {
    let path = broken(file);
    let err = load_gltf(&path).expect_err(file);
    let message = err.to_string();
    assert!(
        message.starts_with(&path.display().to_string()),
        "{message}"
    );
    assert!(message.contains(file), "{message}");
    assert!(
        message.contains(phrase),
        "{file}: {message:?} lacks {phrase:?}"
    );
    assert_eq!(err.path(), path);
    err
}

#[test]
fn missing_file_is_an_io_error() {
    let err = broken_error("no_such_file.gltf", "cannot read file");
    assert!(matches!(err, GltfError::Io { .. }), "{err:?}");
}

#[test]
fn truncated_glb_says_truncated() {
    let err = broken_error(
        "truncated.glb",
        "truncated binary glTF: the header declares",
    );
    assert!(matches!(err, GltfError::Container { .. }), "{err:?}");
}

#[test]
fn truncated_bin_says_truncated() {
    let err = broken_error(
        "truncated_bin.gltf",
        "truncated_bin.bin` is truncated: 24 bytes",
    );
    assert!(matches!(err, GltfError::Buffer { index: 0, .. }), "{err:?}");
}

#[test]
fn missing_bin_names_the_bin() {
    let err = broken_error("missing_bin.gltf", "buffer 0: cannot read");
    assert!(err.to_string().contains("missing_bin.bin"), "{err}");
}

#[test]
fn bad_json_gives_line_and_column() {
    let err = broken_error("bad_json.gltf", "invalid glTF JSON: expected `,`");
    assert!(err.to_string().contains("at line 6 column 3"), "{err}");
    assert!(
        matches!(
            err,
            GltfError::Json {
                line: 6,
                column: 3,
                ..
            }
        ),
        "{err:?}"
    );
}

#[test]
fn garbage_is_not_gltf() {
    broken_error("garbage.glb", "not a glTF file");
}

#[test]
fn empty_file_says_empty() {
    broken_error("empty.gltf", "file is empty");
}

#[test]
fn lines_mode_is_unsupported() {
    let err = broken_error("lines_mode.gltf", "unsupported primitive mode LINES");
    assert!(matches!(err, GltfError::Unsupported { .. }), "{err:?}");
}

#[test]
fn required_extension_is_unsupported() {
    broken_error(
        "required_extension.gltf",
        "unsupported required extension `KHR_draco_mesh_compression`",
    );
}

#[test]
fn nan_position_is_rejected() {
    let err = broken_error("nan_position.gltf", "element 1 is not finite");
    assert!(err.to_string().contains("NaN"), "{err}");
    assert!(
        matches!(err, GltfError::Accessor { index: 0, .. }),
        "{err:?}"
    );
}

#[test]
fn accessor_past_its_view_is_out_of_bounds() {
    let err = broken_error(
        "bad_accessor.gltf",
        "accessor 0: out of bounds: 30 elements",
    );
    assert!(
        matches!(err, GltfError::Accessor { index: 0, .. }),
        "{err:?}"
    );
}

#[test]
fn index_past_the_last_vertex_is_out_of_range() {
    let err = broken_error("bad_index.gltf", "index 7 (element 2) is out of range");
    assert!(
        matches!(err, GltfError::Accessor { index: 1, .. }),
        "{err:?}"
    );
}

#[test]
fn node_cycle_is_rejected() {
    broken_error("cycle.gltf", "node 0 is reached more than once");
}

// ---- robustness -----------------------------------------------------------------------------

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    /// Corrupting or cutting a valid .glb gives a mesh or an error naming the file, never a panic.
    #[test]
    fn corrupted_glb_never_panics(
        edits in prop::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 1..8),
        cut in any::<prop::sample::Index>(),
        truncate in any::<bool>(),
        textured in any::<bool>(),
    ) {
        let mut bytes = std::fs::read(asset(if textured { "crate.glb" } else { "arch.glb" }))
            .unwrap();
        for (at, value) in edits {
            let i = at.index(bytes.len());
            bytes[i] = value;
        }
        if truncate {
            bytes.truncate(cut.index(bytes.len()));
        }
        if let Err(e) = load_gltf_slice(&bytes, None, Path::new("fuzzed.glb")) {
            prop_assert!(e.to_string().starts_with("fuzzed.glb: "), "{}", e);
        }
    }

    /// Same for the JSON of a .gltf with its external .bin.
    #[test]
    fn corrupted_gltf_json_never_panics(
        edits in prop::collection::vec((any::<prop::sample::Index>(), 0x20u8..0x7f), 1..4),
    ) {
        let path = asset("obelisk.gltf");
        let mut bytes = std::fs::read(&path).unwrap();
        for (at, value) in edits {
            let i = at.index(bytes.len());
            bytes[i] = value;
        }
        if let Err(e) = load_gltf_slice(&bytes, path.parent(), Path::new("fuzzed.gltf")) {
            prop_assert!(e.to_string().starts_with("fuzzed.gltf: "), "{}", e);
        }
    }
}

/// A `.glb` of `json` and `bin`.
fn glb(json: &[u8], bin: &[u8]) -> Vec<u8> {
    let pad = |data: &[u8], fill: u8| {
        let mut v = data.to_vec();
        v.resize(data.len().div_ceil(4) * 4, fill);
        v
    };
    let (json, bin) = (pad(json, b' '), pad(bin, 0));
    let mut out = b"glTF".to_vec();
    out.extend(2u32.to_le_bytes());
    out.extend((28 + json.len() as u32 + bin.len() as u32).to_le_bytes());
    out.extend((json.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(json);
    out.extend((bin.len() as u32).to_le_bytes());
    out.extend(b"BIN\0");
    out.extend(bin);
    out
}

/// The JSON and binary chunks of `crate.glb`.
fn crate_chunks() -> (Vec<u8>, Vec<u8>) {
    let bytes = std::fs::read(asset("crate.glb")).unwrap();
    let word = |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
    let json_len = word(12);
    let bin_at = 20 + json_len;
    let bin_len = word(bin_at);
    (
        bytes[20..bin_at].to_vec(),
        bytes[bin_at + 8..bin_at + 8 + bin_len].to_vec(),
    )
}

/// Byte ranges of the runs of ASCII digits in `text`.
fn number_spans(text: &[u8]) -> Vec<(usize, usize)> {
    let mut spans = Vec::new();
    let mut start = None;
    for (i, b) in text.iter().enumerate() {
        match (b.is_ascii_digit(), start) {
            (true, None) => start = Some(i),
            (false, Some(s)) => {
                spans.push((s, i));
                start = None;
            }
            _ => {}
        }
    }
    spans
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    /// Replacing numbers in valid JSON (indices, counts, offsets, lengths, modes, transforms) with
    /// awkward values gives a mesh or an error naming the file, never a panic.
    #[test]
    fn awkward_numbers_never_panic(
        swaps in prop::collection::vec(
            (any::<prop::sample::Index>(), prop::sample::select(vec![
                "0", "1", "2", "3", "4", "5", "6", "7", "12", "51", "52", "53", "255", "1392",
                "4294967295", "18446744073709551615", "99999999999999999999", "1e39", "-1", "0.5",
            ])),
            1..4,
        ),
    ) {
        let path = asset("obelisk.gltf");
        let mut text = std::fs::read(&path).unwrap();
        for (at, value) in swaps {
            let spans = number_spans(&text);
            let (start, end) = spans[at.index(spans.len())];
            text.splice(start..end, value.bytes());
        }
        if let Err(e) = load_gltf_slice(&text, path.parent(), Path::new("fuzzed.gltf")) {
            prop_assert!(e.to_string().starts_with("fuzzed.gltf: "), "{}", e);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    /// The same for crate.glb's JSON (images, textures, samplers, materials, UV accessors).
    #[test]
    fn awkward_numbers_in_a_textured_file_never_panic(
        swaps in prop::collection::vec(
            (any::<prop::sample::Index>(), prop::sample::select(vec![
                "0", "1", "2", "3", "4", "9", "10", "11", "12", "13", "16", "5121", "5123",
                "9728", "9729", "33071", "4294967295", "1e39", "-1", "0.5",
            ])),
            1..4,
        ),
    ) {
        let (mut json, bin) = crate_chunks();
        for (at, value) in swaps {
            let spans = number_spans(&json);
            let (start, end) = spans[at.index(spans.len())];
            json.splice(start..end, value.bytes());
        }
        if let Err(e) = load_gltf_slice(&glb(&json, &bin), None, Path::new("fuzzed.glb")) {
            prop_assert!(e.to_string().starts_with("fuzzed.glb: "), "{}", e);
        }
    }
}
