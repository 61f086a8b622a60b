//! Fuzzes the glTF importer on `.gltf` and `.glb` bytes: any input must give a mesh or an
//! error, never a panic, a hang or an allocation past the budgets; and a mesh that imports is
//! well formed (every index in range, finite positions, one normal and colour per position).
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use texel_scene::gltf_import::{GltfLimits, load_gltf_slice_with};

fuzz_target!(|data: &[u8]| {
    // Small budgets, so a node or instance bomb is refused quickly rather than expanded.
    let limits = GltfLimits {
        max_nodes: 1_000,
        max_instances: 1_000,
        max_triangles: 100_000,
        allow_any_uri: false,
    };
    // No folder: external buffer URIs are errors, so the fuzzer never reads the disk.
    if let Ok(mesh) = load_gltf_slice_with(data, None, Path::new("fuzz.glb"), &limits) {
        let n = mesh.positions.len();
        assert!(mesh.indices.len() % 3 == 0 && !mesh.indices.is_empty());
        assert!(mesh.indices.iter().all(|&i| (i as usize) < n));
        assert!(mesh.positions.iter().all(|p| p.is_finite()));
        assert_eq!(mesh.normals.len(), n);
        assert_eq!(mesh.colors.len(), n);
        assert!(mesh.triangle_count() <= limits.max_triangles);
    }
});
