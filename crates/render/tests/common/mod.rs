//! Helpers shared by the renderer's GPU tests: scenes and frames built by hand.

#![allow(dead_code)]

use std::sync::Arc;

use glam::{Mat4, UVec2, Vec3};
use texel_probes::cube::{Face, FaceMask};
use texel_probes::probe_set::{Role, Slot};
use texel_render::input::*;
use texel_scene::primitives::{box_mesh, plane};

pub fn object(mesh: texel_scene::TriMesh, at: Mat4, albedo: Vec3, id: u32) -> ObjectInput {
    ObjectInput {
        mesh: Arc::new(mesh),
        transform: at,
        material: MaterialInput {
            albedo,
            emissive: Vec3::ZERO,
            casts_shadows: true,
            outlined: true,
            ..Default::default()
        },
        id,
    }
}

/// A ground plane, three coloured boxes and a sun.
pub fn boxes_scene() -> SceneInput {
    let mut objects = vec![object(
        plane(glam::Vec2::splat(40.0)),
        Mat4::IDENTITY,
        Vec3::new(0.3, 0.5, 0.25),
        1,
    )];
    let boxes = [
        (Vec3::new(-2.0, 1.0, -4.0), Vec3::new(0.8, 0.3, 0.2)),
        (Vec3::new(1.5, 0.75, -6.0), Vec3::new(0.2, 0.4, 0.8)),
        (Vec3::new(0.0, 0.5, -2.5), Vec3::new(0.9, 0.8, 0.3)),
    ];
    for (i, (p, c)) in boxes.iter().enumerate() {
        let size = Vec3::splat(p.y * 2.0);
        objects.push(object(
            box_mesh(size),
            Mat4::from_translation(*p),
            *c,
            i as u32 + 2,
        ));
    }
    SceneInput {
        objects,
        suns: vec![SunInput {
            direction: Vec3::new(-0.4, -1.0, -0.3),
            colour: Vec3::splat(1.0),
        }],
        points: vec![],
        terrains: Vec::new(),
        animated: Vec::new(),
        sprites: Vec::new(),
    }
}

pub fn look() -> Look {
    Look {
        sky: Vec3::new(0.5, 0.65, 0.9),
        ambient: Vec3::splat(0.25),
        bands: 16,
        haze: 0.0,
    }
}

/// A frame with the eye probe at the camera and the grid probe at `grid`, every face of both
/// captured and drawn.
pub fn frame(camera: Camera, grid: Vec3, n: u32, size: UVec2, schedule: Schedule) -> FrameInput {
    let probe = |role, slot, origin| ProbeView {
        role,
        slot,
        origin,
        face_resolution: n,
        draw: FaceMask::ALL,
        valid: FaceMask::ALL,
        ortho: None,
        near_faces: [glam::Vec4::ZERO; texel_render::input::MAX_NEAR_FACES],
    };
    let eye = probe(Role::Eye, Slot::Eye, camera.position);
    let grid = probe(Role::Grid, Slot::StableA, grid);
    let captures = [eye, grid]
        .iter()
        .flat_map(|p| {
            Face::ALL.map(|face| CaptureInput {
                slot: p.slot,
                face,
                origin: p.origin,
                face_resolution: n,
                ortho: None,
            })
        })
        .collect();
    FrameInput {
        camera,
        size,
        internal_size: size,
        look: look(),
        eye,
        grid,
        previous: None,
        fade_t: 1.0,
        filling_ahead: false,
        prefetch: None,
        captures,
        schedule,
        grid_complete: true,
        poses: Vec::new(),
        relight: Vec::new(),
        partial: Vec::new(),
        sprites: Vec::new(),
        far_field: None,
    }
}

/// Writes an RGBA8 image for a person to look at (under `target/test-output/`).
pub fn save_png(name: &str, pixels: &[u8], size: UVec2) {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../target/test-output");
    let _ = std::fs::create_dir_all(&dir);
    let _ = image::save_buffer(
        dir.join(name),
        pixels,
        size.x,
        size.y,
        image::ColorType::Rgba8,
    );
}

/// How many RGBA8 pixels of two frames differ.
pub fn differing_pixels(a: &[u8], b: &[u8]) -> usize {
    a.chunks(4).zip(b.chunks(4)).filter(|(p, q)| p != q).count()
}

/// `input`'s frame from a new renderer that took `scene` in whole: what an in-place edit's
/// frame must equal.
pub fn fresh_frame(
    ctx: &texel_render::context::GpuContext,
    scene: &SceneInput,
    input: &FrameInput,
) -> Vec<u8> {
    let mut fresh = texel_render::frame::Renderer::headless(ctx).unwrap();
    fresh.set_scene(ctx, scene).expect("scene");
    fresh.render_offscreen(ctx, input).unwrap().1
}
