//! Integration tests for `texel_scene::gltf_import`: the project's own meshes in `assets/meshes/`
//! (made by `assets/meshes/make_meshes.py`) and the broken files in `tests/data/gltf/` (made by
//! `tests/data/gltf/make_broken.py`). The expected numbers below come from those generators.

use std::path::{Path, PathBuf};

use glam::Vec3;
use proptest::prelude::*;
use texel_scene::TriMesh;
use texel_scene::gltf_import::{GltfError, load_gltf, load_gltf_slice};

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
    let glb = asset("arch.glb");
    let bytes = std::fs::read(&glb).unwrap();
    assert_eq!(load_gltf_slice(&bytes, None, &glb).unwrap(), load(&glb));
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
    ) {
        let mut bytes = std::fs::read(asset("arch.glb")).unwrap();
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
