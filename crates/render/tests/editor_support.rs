//! What the editor reads from and draws through the renderer: a probe slot's lit faces as
//! sRGB8 images, and world-space lines depth-tested against the splatted scene.

use crate::common;

use glam::{Mat4, UVec2, Vec3};
use texel_probes::probe_set::Slot;
use texel_render::context::{GpuContext, test_context};
use texel_render::frame::Renderer;
use texel_render::input::{Camera, SceneInput, Schedule};
use texel_render::passes::lines::LineVertex;
use texel_scene::primitives::box_mesh;

#[test]
fn lit_faces_read_back_as_srgb_images_in_face_order() {
    let Some(ctx) = test_context() else { return };
    let mut r = Renderer::headless(&ctx).unwrap();
    r.set_scene(&ctx, &common::boxes_scene()).expect("scene");
    let cam = Camera::looking(Vec3::new(0.3, 1.6, 3.0), Vec3::new(0.0, -0.25, -1.0));
    let n = 32;
    let input = common::frame(
        cam,
        Vec3::new(0.0, 2.0, 3.0),
        n,
        UVec2::new(64, 36),
        Schedule::Ours,
    );
    r.render_offscreen(&ctx, &input).unwrap();
    let (got_n, faces) = r.read_lit_faces(&ctx, Slot::StableA).unwrap();
    assert_eq!(got_n, n);
    assert_eq!(faces.len(), 6);
    assert!(faces.iter().all(|f| f.len() == (n * n * 4) as usize));
    assert!(
        faces.iter().flatten().skip(3).step_by(4).all(|&a| a == 255),
        "opaque"
    );
    // The average colour of a face, in sRGB bytes.
    let mean = |f: &[u8]| {
        let mut sum = [0u64; 3];
        for px in f.chunks_exact(4) {
            for c in 0..3 {
                sum[c] += u64::from(px[c]);
            }
        }
        sum.map(|s| s / u64::from(n * n))
    };
    // Layer 2 looks up (+Y) at the blue sky, layer 3 down (-Y) at the green ground.
    let up = mean(&faces[2]);
    let down = mean(&faces[3]);
    assert!(up[2] > up[0] && up[2] > 150, "sky is blue: {up:?}");
    assert!(
        down[1] > down[0] && down[1] > down[2],
        "ground is green: {down:?}"
    );
}

/// A grey 2×2×2 box at the origin, nothing else (the sky all around it).
fn one_box() -> SceneInput {
    let grey = Vec3::splat(0.5);
    SceneInput {
        objects: vec![common::object(
            box_mesh(Vec3::splat(2.0)),
            Mat4::IDENTITY,
            grey,
            1,
        )],
        suns: vec![],
        points: vec![],
        terrains: Vec::new(),
        animated: Vec::new(),
        sprites: Vec::new(),
    }
}

const MAGENTA: [u8; 4] = [255, 0, 255, 255];

/// A horizontal magenta segment at height `y` and depth `z`, from `x0` to `x1`.
fn segment(x0: f32, x1: f32, y: f32, z: f32) -> [LineVertex; 2] {
    [x0, x1].map(|x| LineVertex {
        position: [x, y, z],
        colour: MAGENTA,
    })
}

/// Renders the box from the camera at (0, 0, 6) with `lines`; returns the pixels and the
/// frame's entity ids.
fn render_with(ctx: &GpuContext, r: &mut Renderer, lines: &[LineVertex]) -> (Vec<u8>, Vec<u32>) {
    r.set_lines(ctx, lines);
    let cam = Camera::looking(Vec3::new(0.0, 0.0, 6.0), Vec3::NEG_Z);
    let size = UVec2::new(160, 90);
    let input = common::frame(cam, Vec3::new(0.0, 0.0, 6.0), 64, size, Schedule::Ours);
    let (_, px) = r.render_offscreen(ctx, &input).unwrap();
    let ids = r.read_frame_ids(ctx).unwrap().entity;
    (px, ids)
}

fn magenta_pixels(px: &[u8]) -> usize {
    px.chunks_exact(4).filter(|p| *p == MAGENTA).count()
}

#[test]
fn lines_are_hidden_behind_the_scene_and_drawn_in_front_of_it() {
    let Some(ctx) = test_context() else { return };
    let mut r = Renderer::headless(&ctx).unwrap();
    r.set_scene(&ctx, &one_box()).expect("scene");
    let (plain, plain_ids) = render_with(&ctx, &mut r, &[]);
    assert_eq!(magenta_pixels(&plain), 0);
    assert!(plain_ids.contains(&1), "the box is in view");

    // Behind the box (z = -3), well inside its silhouette: hidden.
    let behind = segment(-0.5, 0.5, 0.3, -3.0);
    let (px, _) = render_with(&ctx, &mut r, &behind);
    assert_eq!(magenta_pixels(&px), 0, "a line behind the box is not drawn");
    // The same depth beside the box, in front of the sky: drawn.
    let beside = segment(3.0, 4.0, 0.3, -3.0);
    let (px, _) = render_with(&ctx, &mut r, &beside);
    assert!(magenta_pixels(&px) >= 5, "{}", magenta_pixels(&px));
    // In front of the box (z = 2): drawn over it, and picking still sees the box.
    let front = segment(-0.5, 0.5, 0.3, 2.0);
    let (px, ids) = render_with(&ctx, &mut r, &front);
    assert!(magenta_pixels(&px) >= 10, "{}", magenta_pixels(&px));
    assert_eq!(ids, plain_ids, "lines leave the texel keys alone");
    // An empty list draws nothing again: the frame is the plain one.
    let (px, _) = render_with(&ctx, &mut r, &[]);
    assert_eq!(px, plain);
}
