//! Outlines drawn as strips measured from the edges they outline (cull.wgsl
//! `emit_outlined`): a box seen from one camera through two grid probes whose texel grids
//! lie differently on it shows its outlines over the same pixels.

use crate::common;

use glam::{Mat4, UVec2, Vec3};
use texel_render::context::test_context;
use texel_render::frame::Renderer;
use texel_render::input::{Camera, SceneInput, Schedule, SunInput};
use texel_scene::primitives::box_mesh;

/// One outlined box in the sky, lit by a sun: every face one colour, so two probes' frames
/// differ only where the box's silhouette or its outlines do.
fn lone_box() -> SceneInput {
    let mut scene = common::boxes_scene();
    scene.objects = vec![common::object(
        box_mesh(Vec3::splat(1.0)),
        Mat4::IDENTITY,
        Vec3::new(0.8, 0.55, 0.3),
        1,
    )];
    scene.suns = vec![SunInput {
        direction: Vec3::new(-0.5, -1.0, -0.2),
        colour: Vec3::splat(1.0),
    }];
    scene
}

#[test]
fn a_box_outline_covers_the_same_pixels_from_two_probe_origins() {
    let Some(ctx) = test_context() else { return };
    let mut r = Renderer::headless(&ctx).unwrap();
    r.set_scene(&ctx, &lone_box()).expect("scene");
    let size = UVec2::new(320, 240);
    let eye = Vec3::new(1.3, 1.1, 1.8);
    let cam = Camera::looking(eye, -eye);
    // Two grid probes a fraction of a texel apart in where their texel grids fall on the box.
    let origins = [
        eye + Vec3::new(0.1, 0.2, 0.1),
        eye + Vec3::new(0.27, 0.06, 0.22),
    ];
    let frames: Vec<Vec<u8>> = origins
        .iter()
        .enumerate()
        .map(|(i, &o)| {
            let input = common::frame(cam, o, 64, size, Schedule::Ours);
            let (_, px) = r.render_offscreen(&ctx, &input).unwrap();
            common::save_png(&format!("outline_strips_{i}.png"), &px, size);
            px
        })
        .collect();
    let at = |img: &[u8], i: usize| [img[4 * i], img[4 * i + 1], img[4 * i + 2]];
    let (w, h) = (size.x as usize, size.y as usize);
    let sky = at(&frames[0], 0);
    // A face's own colour is one of the box's three most common; an outline pixel is a box
    // pixel in none of them.
    let mut counts = std::collections::HashMap::<[u8; 3], usize>::new();
    for i in 0..w * h {
        let a = at(&frames[0], i);
        if a != sky {
            *counts.entry(a).or_default() += 1;
        }
    }
    let mut faces: Vec<([u8; 3], usize)> = counts.into_iter().collect();
    faces.sort_by_key(|f| std::cmp::Reverse(f.1));
    let faces: Vec<[u8; 3]> = faces.iter().take(3).map(|f| f.0).collect();
    let masks: Vec<Vec<bool>> = frames
        .iter()
        .map(|img| {
            (0..w * h)
                .map(|i| at(img, i) != sky && !faces.contains(&at(img, i)))
                .collect()
        })
        .collect();
    let boxed = (0..w * h).filter(|&i| at(&frames[0], i) != sky).count();
    // Outline pixels of one frame with none of the other's within a pixel: a strip that
    // moved, or changed width, by more than the rasterizer's rounding.
    let near = |m: &[bool], x: usize, y: usize| {
        (y.saturating_sub(1)..=(y + 1).min(h - 1))
            .any(|yy| (x.saturating_sub(1)..=(x + 1).min(w - 1)).any(|xx| m[yy * w + xx]))
    };
    let (mut outlined, mut moved) = (0usize, 0usize);
    for (a, b) in [(0, 1), (1, 0)] {
        for y in 0..h {
            for x in 0..w {
                if masks[a][y * w + x] {
                    outlined += 1;
                    if !near(&masks[b], x, y) {
                        moved += 1;
                    }
                }
            }
        }
    }
    println!("box pixels {boxed}, outline pixels {outlined} (both frames), moved {moved}");
    // Measured (2026-12-02): 58 of 4,473 on lavapipe, 219 of 4,497 on SwiftShader; with the
    // whole-texel shift the strips replaced, 539 of 7,710 and 675 of 8,013 (7.0 %, 8.4 %).
    assert!(boxed > 8000, "the box fills the view: {boxed} pixels");
    assert!(
        outlined > boxed / 10,
        "the box is outlined: {outlined} of twice {boxed} pixels"
    );
    assert!(
        moved * 50 < outlined * 3,
        "the outlines move with the probe: {moved} of {outlined} outline pixels"
    );
}

/// Strips on both silhouette sides of a thin pillar (cull.wgsl `emit_outlined`): where they
/// would leave the body between them narrower than half a strip, the body is left out and
/// the strips meet, so no sliver a fraction of a pixel wide flickers in and out as the view
/// turns (the stone circle's pure yaw, 320×180 at faces of 128: mean shimmer 0.00039 ->
/// 0.00021 on lavapipe, 0.00050 -> 0.00033 on SwiftShader). The pillar is seen head-on from
/// its grid probe's origin at 16 offsets across one texel, about 20 pixels per texel: every
/// run of the body's colour between two strips is at least a quarter texel wide (2-pixel
/// runs before the change, none after).
#[test]
fn a_thin_pillar_keeps_no_body_sliver_between_its_strips() {
    let Some(ctx) = test_context() else { return };
    let mut r = Renderer::headless(&ctx).unwrap();
    let mut scene = common::boxes_scene();
    let albedo = Vec3::new(0.8, 0.55, 0.3);
    // The pillar, 1.1 texels wide at faces of 32 from its front `front` units away (so its
    // strips, half a texel each, would leave a tenth of a texel between them), and, in the
    // same material and facing the same way, a wide box whose front shows the body's colour.
    let n = 32;
    let (eye_z, front, wide_at) = (3.0, 2.85, -1.6);
    let texel = 2.0 * front / n as f32;
    scene.objects = vec![
        common::object(
            box_mesh(Vec3::new(1.1 * texel, 3.0, 0.3)),
            Mat4::IDENTITY,
            albedo,
            1,
        ),
        common::object(
            box_mesh(Vec3::new(0.6, 3.0, 0.3)),
            Mat4::from_translation(Vec3::new(wide_at, 0.0, 0.0)),
            albedo,
            2,
        ),
    ];
    scene.suns = vec![SunInput {
        direction: Vec3::new(0.3, -1.0, -0.6),
        colour: Vec3::splat(1.0),
    }];
    r.set_scene(&ctx, &scene).expect("scene");
    let size = UVec2::new(480, 360);
    let (w, h) = (size.x as usize, size.y as usize);
    let tan_half = 30f32.to_radians().tan();
    let px_per_texel = texel / (2.0 * front * tan_half / h as f32);
    let at = |img: &[u8], x: usize, y: usize| {
        let i = 4 * (y * w + x);
        [img[i], img[i + 1], img[i + 2]]
    };
    let mut shortest = usize::MAX;
    let mut slivers = 0;
    let mut strip_pixels = 0;
    for step in 0..16 {
        let eye = Vec3::new(texel * step as f32 / 16.0, 0.0, eye_z);
        let cam = Camera::looking(eye, Vec3::NEG_Z);
        let input = common::frame(cam, eye, n, size, Schedule::Ours);
        let (_, px) = r.render_offscreen(&ctx, &input).unwrap();
        if step == 0 {
            common::save_png("thin_pillar.png", &px, size);
        }
        let sky = at(&px, 0, 0);
        // The middle pixel of the wide box's front, left of the view's middle.
        let ndc_x = (wide_at - eye.x) / front / (tan_half * w as f32 / h as f32);
        let wide_x = ((ndc_x + 1.0) * 0.5 * w as f32) as usize;
        let body = at(&px, wide_x, h / 2);
        assert_ne!(body, sky, "the wide box is in view at x {wide_x}");
        for y in h / 2 - 40..h / 2 + 40 {
            // Runs of the body's colour in the pillar's part of the row (its middle third),
            // with box pixels of another colour (strips) on both sides.
            let row: Vec<u8> = (w / 3..2 * w / 3)
                .map(|x| {
                    let c = at(&px, x, y);
                    if c == sky {
                        0
                    } else if c == body {
                        1
                    } else {
                        2
                    }
                })
                .collect();
            strip_pixels += row.iter().filter(|&&c| c == 2).count();
            let mut x = 0;
            while x < row.len() {
                if row[x] != 1 {
                    x += 1;
                    continue;
                }
                let start = x;
                while x < row.len() && row[x] == 1 {
                    x += 1;
                }
                if start > 0 && x < row.len() && row[start - 1] == 2 && row[x] == 2 {
                    slivers += 1;
                    shortest = shortest.min(x - start);
                }
            }
        }
    }
    println!(
        "{px_per_texel:.1} pixels per texel; {strip_pixels} strip pixels; \
         {slivers} body runs between strips, shortest {shortest}"
    );
    // 16 frames of 80 rows, the pillar about 21 pixels wide: it is there, and outlined.
    assert!(
        strip_pixels > 16 * 80 * 10,
        "the pillar shows its strips: {strip_pixels} pixels"
    );
    assert!(
        slivers == 0 || shortest as f32 >= 0.25 * px_per_texel - 1.0,
        "a body {shortest} pixels wide between two strips ({px_per_texel:.1} pixels per texel)"
    );
}

/// The eye's fill draws its strips from starts and colours worked out once per eye texel
/// (background.wgsl `strip_ends`), kept in textures of the eye's face size: a renderer that
/// drew faces of 32 and then draws faces of 64 draws what a fresh one does, and a frame with
/// no stable face drawn (the eye's quads and fill show everything) shows strips.
#[test]
fn the_fill_strips_follow_the_eye_face_size() {
    let Some(ctx) = test_context() else { return };
    let size = UVec2::new(240, 180);
    let eye = Vec3::new(1.3, 1.1, 1.8);
    let cam = Camera::looking(eye, -eye);
    let input = |n| {
        let mut input = common::frame(cam, eye + Vec3::new(0.1, 0.2, 0.1), n, size, Schedule::Ours);
        input.grid.draw = texel_probes::cube::FaceMask::EMPTY;
        input
    };
    let renderer = || {
        let mut r = Renderer::headless(&ctx).unwrap();
        r.set_scene(&ctx, &lone_box()).expect("scene");
        r
    };
    let (_, fresh) = renderer().render_offscreen(&ctx, &input(64)).unwrap();
    let mut r = renderer();
    let (_, small) = r.render_offscreen(&ctx, &input(32)).unwrap();
    let (_, again) = r.render_offscreen(&ctx, &input(64)).unwrap();
    assert_ne!(small, fresh, "faces of 32 and 64 draw differently");
    assert!(
        again == fresh,
        "faces of 64 after 32 draw as a fresh renderer's"
    );
    // Outlines: pixels of the box in none of its three faces' colours.
    let at = |i: usize| [fresh[4 * i], fresh[4 * i + 1], fresh[4 * i + 2]];
    let sky = at(0);
    let mut counts = std::collections::HashMap::<[u8; 3], usize>::new();
    for i in 0..(size.x * size.y) as usize {
        if at(i) != sky {
            *counts.entry(at(i)).or_default() += 1;
        }
    }
    let mut common_first: Vec<usize> = counts.values().copied().collect();
    common_first.sort_unstable_by(|a, b| b.cmp(a));
    let outline: usize = common_first.iter().skip(3).sum();
    assert!(
        outline > 50,
        "outline pixels {outline} of {:?}",
        common_first
    );
}
