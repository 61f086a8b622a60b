//! Convention images: tiny captures that pin the cube-face orientation and handedness, so a
//! sign error between `texel_probes::cube`, the capture matrices and the WGSL cannot hide.
//!
//! A room with a differently coloured wall on each side, and a white marker placed, for each
//! face, at face coordinates (u, v) = (−½, −½) — the top-left quadrant of that face's texture
//! by the documented convention. The captured albedo must show each wall's colour at its face
//! centre and each marker in its face's top-left quadrant, and nowhere else on that face.

use crate::common;

use glam::{Mat4, UVec2, Vec3};
use texel_probes::cube::{Face, direction_from_face_uv};
use texel_probes::probe_set::Slot;
use texel_render::context::test_context;
use texel_render::frame::Renderer;
use texel_render::input::{Camera, SceneInput, Schedule};
use texel_render::target::read_texture_layer;
use texel_scene::primitives::box_mesh;

const WALLS: [(Face, [u8; 3]); 6] = [
    (Face::PosX, [200, 40, 40]),
    (Face::NegX, [40, 200, 40]),
    (Face::PosY, [40, 40, 200]),
    (Face::NegY, [200, 200, 40]),
    (Face::PosZ, [200, 40, 200]),
    (Face::NegZ, [40, 200, 200]),
];

fn room() -> SceneInput {
    let mut objects = Vec::new();
    for (i, (face, rgb)) in WALLS.iter().enumerate() {
        let axis = face.axis();
        let size = Vec3::splat(8.0) - axis.abs() * 7.8;
        let albedo = Vec3::from(rgb.map(|c| f32::from(c) / 255.0));
        let at = Mat4::from_translation(axis * 4.0);
        objects.push(common::object(box_mesh(size), at, albedo, i as u32 + 1));
    }
    for (i, face) in Face::ALL.into_iter().enumerate() {
        let dir = direction_from_face_uv(face, -0.5, -0.5).normalize();
        let at = Mat4::from_translation(dir * 2.5);
        objects.push(common::object(
            box_mesh(Vec3::splat(0.3)),
            at,
            Vec3::ONE,
            10 + i as u32,
        ));
    }
    SceneInput {
        objects,
        suns: vec![],
        points: vec![],
        terrains: Vec::new(),
        animated: Vec::new(),
        sprites: Vec::new(),
    }
}

#[test]
fn faces_are_oriented_as_documented() {
    let Some(ctx) = test_context() else { return };
    let mut r = Renderer::headless(&ctx).unwrap();
    r.set_scene(&ctx, &room()).expect("scene");
    let n = 32;
    let cam = Camera::looking(Vec3::ZERO, -Vec3::Z);
    let input = common::frame(cam, Vec3::ZERO, n, UVec2::new(64, 64), Schedule::Ours);
    r.render_offscreen(&ctx, &input).unwrap();
    let albedo = &r.probes().slot(Slot::StableA).albedo.texture;
    let mut strip = vec![0u8; (6 * n * n * 4) as usize];
    for (face, wall) in WALLS {
        let px = read_texture_layer(&ctx, albedo, face.index() as u32, 4).unwrap();
        let at = |x: u32, y: u32| {
            let i = ((y * n + x) * 4) as usize;
            [px[i], px[i + 1], px[i + 2]]
        };
        let centre = at(n / 2, n / 2 + 3);
        assert!(
            centre.iter().zip(wall).all(|(a, b)| a.abs_diff(b) <= 2),
            "{face:?}: centre shows {centre:?}, its wall is {wall:?}"
        );
        let mut white = Vec::new();
        for y in 0..n {
            for x in 0..n {
                if at(x, y) == [255, 255, 255] {
                    white.push((x, y));
                }
            }
        }
        assert!(!white.is_empty(), "{face:?}: marker not captured");
        assert!(
            white.iter().all(|&(x, y)| x < n / 2 && y < n / 2),
            "{face:?}: marker outside the top-left quadrant: {white:?}"
        );
        // A strip of the six faces, for a person to look at.
        for y in 0..n {
            let row = ((y * 6 * n + face.index() as u32 * n) * 4) as usize;
            let src = (y * n * 4) as usize;
            strip[row..row + (n * 4) as usize].copy_from_slice(&px[src..src + (n * 4) as usize]);
        }
    }
    common::save_png("convention_faces.png", &strip, UVec2::new(6 * n, n));
}
