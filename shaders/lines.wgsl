// Lines: world-space segments (the editor's ground grid) drawn over the frame right after the
// background, tested against the splat depth without writing it, alpha-blended into the
// sRGB-encoded colour target (vertex colours are sRGB-encoded too). The texel keys are masked
// off in the pipeline, so picking and the visible-texel count see through the lines.
// crates/render/src/passes/lines.rs.

#include "lib/common.wgsl"
#include "lib/view.wgsl"

@group(0) @binding(0) var<uniform> view: ViewGlobals;

// How far each vertex is pulled toward the camera, as a fraction of its distance (along its
// own view ray, so it stays where it was on screen): a line lying on a surface, as the grid
// lies on the ground, wins the depth test against that surface's quads, while one passing
// behind an object stays hidden. Probe texel quads of ground seen at a grazing angle stand
// a little in front of it: at 1% the grid on stone_circle's ground came out dashed.
const DEPTH_PULL: f32 = 0.03;

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) colour: vec4<f32>,
}

@vertex
fn vs(@location(0) position: vec3<f32>, @location(1) colour: vec4<f32>) -> VsOut {
    let p = mix(position, view.camera.xyz, DEPTH_PULL);
    var out: VsOut;
    out.clip = view.view_proj * vec4(p, 1.0);
    out.colour = colour;
    return out;
}

struct FsOut {
    @location(0) colour: vec4<f32>,
    // Not written (the pipeline masks the key target); declared to match the frame's targets.
    @location(1) key: u32,
}

@fragment
fn fs(in: VsOut) -> FsOut {
    return FsOut(in.colour, 0u);
}
