//! A terrain's shadows through its heightfield (`bvh/field`) against the same terrain's
//! triangles in the BVH: a hilly terrain under a low sun, rendered with the terrain walked as
//! a field and again with it the ninth terrain (past `MAX_FIELDS`, so its triangles go into
//! the tree), must light the grid probe's texels alike and find the same silhouette edges
//! (except where the field's terrain goes on, which is not searched).

use crate::common;

use std::sync::Arc;

use glam::{Mat4, UVec2, Vec2, Vec3};
use texel_probes::probe_set::Slot;
use texel_render::bvh::field::MAX_FIELDS;
use texel_render::context::test_context;
use texel_render::frame::Renderer;
use texel_render::gpu_scene::GpuScene;
use texel_render::input::{
    Camera, MaterialInput, ObjectInput, SceneInput, Schedule, SunInput, TerrainInput,
};
use texel_scene::terrain::Heightfield;

/// A terrain of `n` × `n` samples over `size`, centred at `at`, with heights from `h`, as
/// the runtime builds one (translation-only transform, level-0 mesh from `lod_mesh`).
fn terrain(
    at: Vec3,
    size: f32,
    n: u32,
    id: u32,
    index: usize,
    h: impl Fn(f32, f32) -> f32,
) -> (ObjectInput, TerrainInput) {
    let heights: Vec<f32> = (0..n * n)
        .map(|i| {
            h(
                (i % n) as f32 / (n - 1) as f32,
                (i / n) as f32 / (n - 1) as f32,
            )
        })
        .collect();
    let field = Heightfield {
        width: n,
        depth: n,
        heights: heights.clone(),
    };
    let mesh = Arc::new(field.lod_mesh(Vec2::splat(size), 1.0));
    let object = ObjectInput {
        mesh,
        transform: Mat4::from_translation(at),
        material: MaterialInput {
            albedo: Vec3::ONE,
            terrain: Some(index),
            ..Default::default()
        },
        id,
    };
    let input = TerrainInput {
        corner: at - Vec3::new(0.5 * size, 0.0, 0.5 * size),
        size: Vec2::splat(size),
        samples: UVec2::splat(n),
        heights: Arc::new(heights),
        max_height: 4.0,
        gradient: vec![
            (0.0, Vec3::new(0.3, 0.5, 0.2)),
            (1.0, Vec3::new(0.7, 0.7, 0.6)),
        ],
        displacement: None,
        paint: None,
        pixel_density: 4.0,
        band_distance: 8.0,
        band_transition: 0.3,
    };
    (object, input)
}

/// Hills under a low sun; `decoys` small flat terrains first (far below, out of sight), so
/// the hills are terrain `decoys`.
fn hills_scene(decoys: usize) -> SceneInput {
    let mut scene = SceneInput {
        suns: vec![SunInput {
            direction: Vec3::new(-0.8, -0.35, -0.2),
            colour: Vec3::splat(1.2),
        }],
        ..Default::default()
    };
    for i in 0..decoys {
        let at = Vec3::new(i as f32 * 10.0, -500.0, 0.0);
        let (o, t) = terrain(at, 4.0, 3, 100 + i as u32, i, |_, _| 0.0);
        scene.objects.push(o);
        scene.terrains.push(t);
    }
    let (o, t) = terrain(Vec3::ZERO, 40.0, 65, 1, decoys, |u, v| {
        let (x, z) = (u * 12.0, v * 12.0);
        2.0 + 1.5 * (x.sin() * z.cos()) + 0.8 * (0.7 * x + 1.3 * z).sin()
    });
    scene.objects.push(o);
    scene.terrains.push(t);
    scene
}

/// One frame over the hills from above their slope (192×108, faces of 64), the grid probe
/// at the camera: every face of the eye and the grid probe captured.
fn hills_frame() -> texel_render::input::FrameInput {
    let at = Vec3::new(-6.0, 7.0, 12.0);
    let cam = Camera::looking(at, Vec3::new(0.4, -0.45, -1.0));
    common::frame(cam, at, 64, UVec2::new(192, 108), Schedule::Ours)
}

#[test]
fn a_terrains_shadows_through_its_heights_match_its_triangles() {
    let Some(ctx) = test_context() else { return };
    let input = hills_frame();
    let size = input.size;
    let (mut frames, mut lit, mut bits) = (Vec::new(), Vec::new(), Vec::new());
    for decoys in [0, MAX_FIELDS] {
        let scene = hills_scene(decoys);
        let gpu = GpuScene::upload(&ctx, &scene).expect("upload");
        let hills_triangles = scene.objects.last().unwrap().mesh.pieces.iter();
        let level0: u32 = hills_triangles
            .filter(|p| p.lod == 0)
            .map(|p| p.triangles)
            .sum();
        if decoys == 0 {
            assert_eq!(
                (gpu.shadow_fields, gpu.shadow_triangles),
                (1, 0),
                "the hills walked as a field"
            );
        } else {
            // The decoys are fields; the ninth terrain's level 0 is in the tree.
            assert_eq!(gpu.shadow_fields, MAX_FIELDS);
            assert_eq!(gpu.shadow_triangles, level0 as usize);
        }
        let mut r = Renderer::headless(&ctx).unwrap();
        r.set_scene(&ctx, &scene).expect("scene");
        let (_, px) = r.render_offscreen(&ctx, &input).unwrap();
        common::save_png(&format!("terrain_fields_{decoys}.png"), &px, size);
        frames.push(px);
        lit.push(r.read_lit_faces(&ctx, Slot::StableA).unwrap().1.concat());
        bits.push(r.read_lit_bits(&ctx, Slot::StableA).unwrap().1.concat());
    }
    let pixels = (size.x * size.y) as usize;
    // Shadowed and lit texels both present, so the test can fail.
    let lum: Vec<u32> = (0..pixels)
        .map(|i| {
            frames[0][i * 4..i * 4 + 3]
                .iter()
                .map(|&c| u32::from(c))
                .sum()
        })
        .collect();
    let (lo, hi) = (lum.iter().min().unwrap(), lum.iter().max().unwrap());
    assert!(hi - lo > 150, "a frame with light and shade: {lo}..{hi}");
    // The same triangles, walked two ways: the grid probe's texels lit alike (only rays that
    // graze a triangle's edge within rounding may differ).
    let texels = bits[0].len();
    let differ = (0..texels)
        .filter(|&i| lit[0][i * 4..i * 4 + 3] != lit[1][i * 4..i * 4 + 3])
        .count();
    assert!(
        differ * 1000 <= texels,
        "{differ} of {texels} texels lit differently through the field and the BVH"
    );
    // And their silhouettes' edges found alike, except where the field's terrain goes on past
    // a farther neighbour of its own (shade.wgsl `terrain_goes_on`): there nothing is searched
    // and the edge stays halfway (code 3), where the search through the tree finds where the
    // depth passes halfway, past 3/8 of the way on these slopes, which fall away from the
    // probe. A crest taken for such a slope would show as a halfway edge where the tree's
    // search found it nearer.
    let (mut same, mut crests, mut skipped, mut other) = (0, 0, 0, 0);
    for (&a, &b) in bits[0].iter().zip(&bits[1]) {
        for k in 0..4 {
            // Sides with a farther neighbour: the sky past it, or the terrain (the only thing
            // in sight).
            if (a >> (4 + k)) & 1 == 0 {
                continue;
            }
            let sky = (a >> k) & 1 == 1;
            let edge = |bits: u32| (bits >> (9 + 3 * k)) & 7;
            let (ea, eb) = (edge(a), edge(b));
            if ea == eb {
                same += usize::from(ea != 3);
                crests += usize::from(ea != 3 && !sky);
            } else if ea == 3 && eb >= 2 {
                skipped += 1;
            } else {
                other += 1;
            }
        }
    }
    // 47 crests, 459 slopes and 3 others here (a field taken to go on everywhere: no crests).
    assert!(
        crests > 20,
        "crests against farther terrain searched through both: {crests} edges off halfway"
    );
    assert!(skipped > 100, "the field's slopes not searched: {skipped}");
    assert!(
        other * 100 <= same + skipped,
        "{other} edges found differently through the field and the BVH ({same} alike, {skipped} slopes)"
    );
}

/// A 2 × 2 texture of one grey.
fn grey_texture() -> texel_geom::texture::TextureRef {
    texel_geom::texture::TextureRef {
        image: Arc::new(texel_geom::texture::Image {
            name: "grey".into(),
            width: 2,
            height: 2,
            pixels: [200u8, 200, 200, 255].repeat(4),
        }),
        sampler: Default::default(),
    }
}

/// A plain terrain's chunks are captured by the lean terrain pipeline (`capture.wgsl`
/// `vs_terrain`: the point and object alone, the surface read from the heightmap); the same
/// terrain with an albedo texture (which a terrain's colour replaces) goes through the full
/// one (`vs`). Both must store the same surface: the grid probe's texels lit alike (a
/// normal that rounds across a posterization step may differ: the full capture's normal is
/// the rasterizer's interpolation, which differs per driver, the lean one's is the heights').
#[test]
fn the_lean_terrain_capture_stores_what_the_full_capture_does() {
    let Some(ctx) = test_context() else { return };
    let input = hills_frame();
    let mut lit = Vec::new();
    for textured in [false, true] {
        let mut scene = hills_scene(0);
        if textured {
            let m = &mut scene.objects.last_mut().unwrap().material;
            m.maps.albedo = Some(grey_texture());
        }
        let gpu = GpuScene::upload(&ctx, &scene).expect("upload");
        let lean = gpu.ranges.iter().filter(|r| r.terrain).count();
        assert_eq!(lean > 0, !textured, "{lean} ranges drawn as plain terrain");
        let mut r = Renderer::headless(&ctx).unwrap();
        r.set_scene(&ctx, &scene).expect("scene");
        r.render_offscreen(&ctx, &input).unwrap();
        lit.push(r.read_lit_faces(&ctx, Slot::StableA).unwrap().1.concat());
    }
    let texels = lit[0].len() / 4;
    let colours: std::collections::HashSet<&[u8]> = lit[0].chunks_exact(4).collect();
    let differ = (0..texels)
        .filter(|&i| lit[0][i * 4..i * 4 + 3] != lit[1][i * 4..i * 4 + 3])
        .count();
    // Measured: 0 of 24,576 differ on lavapipe, 68 on SwiftShader; with the lean normal
    // taken as straight up, 8,029.
    assert!(colours.len() > 20, "{} colours: nothing lit", colours.len());
    assert!(
        differ * 200 <= texels,
        "{differ} of {texels} texels lit differently by the lean and the full capture"
    );
}

/// The terrain splats pass keeps each texel's terrain pixels in a cache (terrain_splat.rs),
/// stamped with the texel's point, lights and probe but not with the frame's light, colours
/// or heights: a change of ambient light, of haze, or a new scene (other colours) must show
/// on the terrain's pixels exactly as a renderer that never saw the old ones draws them.
#[test]
fn cached_terrain_pixels_follow_the_light_the_haze_and_the_scene() {
    let Some(ctx) = test_context() else { return };
    let mut input = hills_frame();
    let size = input.size;
    let fresh = |scene: &SceneInput, input: &texel_render::input::FrameInput| {
        let mut r = Renderer::headless(&ctx).unwrap();
        r.set_scene(&ctx, scene).expect("scene");
        r.render_offscreen(&ctx, input).unwrap().1
    };
    let differ = |a: &[u8], b: &[u8]| {
        (a.chunks_exact(4).zip(b.chunks_exact(4)))
            .filter(|(p, q)| p[..3] != q[..3])
            .count()
    };
    let scene = hills_scene(0);
    let mut warm = Renderer::headless(&ctx).unwrap();
    warm.set_scene(&ctx, &scene).expect("scene");
    let (_, first) = warm.render_offscreen(&ctx, &input).unwrap();
    // The same frame again comes from the cache, as it was made.
    let (_, again) = warm.render_offscreen(&ctx, &input).unwrap();
    assert_eq!(differ(&first, &again), 0, "the cached frame differs");
    input.look.ambient *= 3.0;
    let (_, brighter) = warm.render_offscreen(&ctx, &input).unwrap();
    let bright = input.clone();
    input.look.haze = 0.05;
    let (_, hazed) = warm.render_offscreen(&ctx, &input).unwrap();
    let mut other = scene.clone();
    let t = other.terrains.last_mut().unwrap();
    t.gradient = vec![
        (0.0, Vec3::new(0.6, 0.2, 0.2)),
        (1.0, Vec3::new(0.9, 0.8, 0.3)),
    ];
    warm.set_scene(&ctx, &other).expect("scene");
    let (_, recoloured) = warm.render_offscreen(&ctx, &input).unwrap();
    let pixels = (size.x * size.y) as usize;
    for (what, shown, scene, look, was) in [
        ("ambient", &brighter, &scene, &bright, &first),
        ("haze", &hazed, &scene, &input, &brighter),
        ("gradient", &recoloured, &other, &input, &hazed),
    ] {
        let changed = differ(shown, was);
        assert!(
            changed * 4 > pixels,
            "{what}: only {changed} pixels changed"
        );
        let wrong = differ(shown, &fresh(scene, look));
        assert_eq!(
            wrong, 0,
            "{what}: {wrong} pixels differ from a fresh renderer's"
        );
    }
}
