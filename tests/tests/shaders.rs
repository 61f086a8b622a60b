//! Every WGSL shader parses and validates with naga, with no GPU: a broken shader cannot
//! slip through to a machine that only finds out when the pass is first built.

use naga::valid::{Capabilities, ValidationFlags, Validator};
use texel_render::shader::{SOURCES, assemble, pass_shaders};

#[test]
fn every_pass_shader_validates() {
    let mut checked = 0;
    for name in pass_shaders() {
        let src = assemble(name).unwrap_or_else(|e| panic!("{name}: {e}"));
        let module = naga::front::wgsl::parse_str(&src)
            .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(&src)));
        Validator::new(ValidationFlags::all(), Capabilities::empty())
            .validate(&module)
            .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(&src)));
        checked += 1;
    }
    assert!(checked >= 6, "only {checked} pass shaders found");
}

#[test]
fn every_shader_file_on_disk_is_embedded() {
    let dir = texel_tests::repo_root().join("shaders");
    let mut on_disk = Vec::new();
    for sub in ["", "lib/"] {
        for e in std::fs::read_dir(dir.join(sub)).unwrap() {
            let p = e.unwrap().path();
            if p.extension().is_some_and(|x| x == "wgsl") {
                on_disk.push(format!("{sub}{}", p.file_name().unwrap().to_string_lossy()));
            }
        }
    }
    for f in &on_disk {
        assert!(
            SOURCES.iter().any(|(n, _)| n == f),
            "shaders/{f} is not in shader::SOURCES"
        );
    }
    for (n, src) in SOURCES {
        let disk = std::fs::read_to_string(dir.join(n)).unwrap();
        assert_eq!(&disk, src, "{n} differs from the embedded copy");
    }
}

#[test]
fn rust_records_match_their_wgsl_layouts() {
    let mut checked = 0;
    for (file, name, rust_size) in texel_render::layouts::shared_layouts() {
        let src = assemble(file).unwrap();
        let module = naga::front::wgsl::parse_str(&src).unwrap();
        let mut layouter = naga::proc::Layouter::default();
        layouter.update(module.to_ctx()).unwrap();
        let (handle, _) = module
            .types
            .iter()
            .find(|(_, t)| t.name.as_deref() == Some(name))
            .unwrap_or_else(|| panic!("{file} declares no struct {name}"));
        let wgsl_size = layouter[handle].size as usize;
        assert_eq!(
            rust_size, wgsl_size,
            "{name} in {file}: Rust {rust_size} bytes, WGSL {wgsl_size}"
        );
        checked += 1;
    }
    assert!(checked >= 10);
}

/// The terrain splats' queue (`Misses`): its pixels' lights start where the pass clears them
/// and its misses where the pass sizes the buffer for them, each miss and record as big as the
/// Rust side counts.
#[test]
fn the_terrain_queue_lies_where_its_pass_clears_and_sizes_it() {
    use texel_render::passes::terrain_splat::{
        CELL_LIGHTS_BYTES, MISS_BYTES, MISSES_HEADER_BYTES, RECORD_BYTES,
    };
    let src = assemble("terrain_splat.wgsl").unwrap();
    let module = naga::front::wgsl::parse_str(&src).unwrap();
    let mut layouter = naga::proc::Layouter::default();
    layouter.update(module.to_ctx()).unwrap();
    let find = |name: &str| {
        let (handle, ty) = (module.types.iter())
            .find(|(_, t)| t.name.as_deref() == Some(name))
            .unwrap_or_else(|| panic!("no struct {name}"));
        (handle, ty.inner.clone())
    };
    let (_, misses) = find("Misses");
    let naga::TypeInner::Struct { members, .. } = misses else {
        panic!("Misses is a struct");
    };
    let offset = |name: &str| {
        let m = members.iter().find(|m| m.name.as_deref() == Some(name));
        u64::from(m.unwrap_or_else(|| panic!("no member {name}")).offset)
    };
    assert_eq!(offset("lights"), MISSES_HEADER_BYTES);
    assert_eq!(offset("at"), MISSES_HEADER_BYTES + CELL_LIGHTS_BYTES);
    let (miss, _) = find("Miss");
    assert_eq!(u64::from(layouter[miss].size), MISS_BYTES);
    let (record, _) = find("TerrainSplat");
    assert_eq!(u64::from(layouter[record].size), RECORD_BYTES);
}
