//! WGSL sources: one file per pass in `shaders/`, shared code in `shaders/lib/`, joined by a
//! tiny `#include "lib/name.wgsl"` resolver. Sources are embedded in the binary, so a build
//! runs from anywhere; the shader-validation test parses every one of them with naga.

use std::collections::HashSet;

/// Every shader file: (path under `shaders/`, source).
pub const SOURCES: &[(&str, &str)] = &[
    (
        "lib/common.wgsl",
        include_str!("../../../shaders/lib/common.wgsl"),
    ),
    (
        "lib/view.wgsl",
        include_str!("../../../shaders/lib/view.wgsl"),
    ),
    (
        "lib/lighting.wgsl",
        include_str!("../../../shaders/lib/lighting.wgsl"),
    ),
    (
        "lib/raster.wgsl",
        include_str!("../../../shaders/lib/raster.wgsl"),
    ),
    (
        "lib/lists.wgsl",
        include_str!("../../../shaders/lib/lists.wgsl"),
    ),
    (
        "lib/bvh.wgsl",
        include_str!("../../../shaders/lib/bvh.wgsl"),
    ),
    ("runs.wgsl", include_str!("../../../shaders/runs.wgsl")),
    ("lines.wgsl", include_str!("../../../shaders/lines.wgsl")),
    (
        "background.wgsl",
        include_str!("../../../shaders/background.wgsl"),
    ),
    (
        "capture.wgsl",
        include_str!("../../../shaders/capture.wgsl"),
    ),
    ("shade.wgsl", include_str!("../../../shaders/shade.wgsl")),
    ("cull.wgsl", include_str!("../../../shaders/cull.wgsl")),
    ("splat.wgsl", include_str!("../../../shaders/splat.wgsl")),
    (
        "visible.wgsl",
        include_str!("../../../shaders/visible.wgsl"),
    ),
    (
        "present.wgsl",
        include_str!("../../../shaders/present.wgsl"),
    ),
    (
        "gbuffer.wgsl",
        include_str!("../../../shaders/gbuffer.wgsl"),
    ),
    (
        "screen_shade.wgsl",
        include_str!("../../../shaders/screen_shade.wgsl"),
    ),
    (
        "upscale.wgsl",
        include_str!("../../../shaders/upscale.wgsl"),
    ),
    (
        "cubemap.wgsl",
        include_str!("../../../shaders/cubemap.wgsl"),
    ),
];

/// Pass shaders (entry files, not libraries).
pub fn pass_shaders() -> impl Iterator<Item = &'static str> {
    SOURCES
        .iter()
        .map(|(name, _)| *name)
        .filter(|n| !n.starts_with("lib/"))
}

/// Why a shader could not be assembled.
#[derive(Debug, thiserror::Error)]
pub enum ShaderError {
    /// A file (or an included file) is not in [`SOURCES`].
    #[error("shader `{0}` not found (included from `{1}`)")]
    Missing(String, String),
}

/// The source of `name` with its includes expanded (each library at most once).
pub fn assemble(name: &str) -> Result<String, ShaderError> {
    let mut out = String::new();
    let mut seen = HashSet::new();
    expand(name, "<root>", &mut seen, &mut out)?;
    Ok(out)
}

fn lookup(name: &str) -> Option<&'static str> {
    SOURCES.iter().find(|(n, _)| *n == name).map(|(_, s)| *s)
}

fn expand(
    name: &str,
    from: &str,
    seen: &mut HashSet<String>,
    out: &mut String,
) -> Result<(), ShaderError> {
    if !seen.insert(name.to_owned()) {
        return Ok(());
    }
    let src = lookup(name).ok_or_else(|| ShaderError::Missing(name.into(), from.into()))?;
    for line in src.lines() {
        match line.trim().strip_prefix("#include ") {
            Some(inc) => expand(inc.trim().trim_matches('"'), name, seen, out)?,
            None => {
                out.push_str(line);
                out.push('\n');
            }
        }
    }
    Ok(())
}

/// Creates a shader module from an assembled file, labelled with its name.
pub fn module(device: &wgpu::Device, name: &str) -> Result<wgpu::ShaderModule, ShaderError> {
    let src = assemble(name)?;
    Ok(device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(name),
        source: wgpu::ShaderSource::Wgsl(src.into()),
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn includes_expand_once_and_missing_files_are_named() {
        let bg = assemble("background.wgsl").unwrap();
        assert!(!bg.contains("#include"));
        assert_eq!(bg.matches("fn oklab_from_linear").count(), 1);
        let err = assemble("nope.wgsl").unwrap_err().to_string();
        assert!(err.contains("nope.wgsl"), "{err}");
    }
}
