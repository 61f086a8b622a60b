//! Sprites through the sprite pass and the G-buffer: drawn where their quad is, named in the
//! key and id targets, relief self-shadowed as the CPU reference says, the written depth
//! meeting geometry where the CPU says, refraction that leaves the background alone at index
//! ratio 1 and inverts it through a sphere.

use crate::common;

use std::sync::Arc;

use glam::{Mat4, UVec2, Vec2, Vec3};
use texel_geom::texture::Image;
use texel_render::baselines::BaselineRenderer;
use texel_render::context::test_context;
use texel_render::frame::Renderer;
use texel_render::input::{Camera, SceneInput, Schedule, SpriteBillboard, SpriteInput};
use texel_scene::primitives::box_mesh;

const SPRITE_ID: u32 = 50;

fn image(name: &str, n: u32, f: impl Fn(u32, u32) -> [u8; 4]) -> Arc<Image> {
    let mut pixels = Vec::with_capacity((n * n * 4) as usize);
    for y in 0..n {
        for x in 0..n {
            pixels.extend_from_slice(&f(x, y));
        }
    }
    Arc::new(Image {
        name: name.into(),
        width: n,
        height: n,
        pixels,
    })
}

/// A fixed sprite facing +Z at `at`, `size` wide, centred on its position.
fn sprite(sheet: Arc<Image>, at: Vec3, size: f32) -> SpriteInput {
    let n = sheet.width;
    SpriteInput {
        id: SPRITE_ID,
        position: at,
        rotation: glam::Quat::IDENTITY,
        size: Some(Vec2::splat(size)),
        pivot: Vec2::splat(0.5),
        billboard: SpriteBillboard::Fixed,
        sheet,
        frame_size: UVec2::splat(n),
        eight_directions: false,
        normal_map: None,
        relief: None,
        refraction: None,
        outlined: false,
        casts_shadows: false,
        frame: 0,
    }
}

/// One frame with both probes at the camera, faces of 128 texels (finer than the sprites'
/// texels at these distances, so each sprite texel is drawn as itself).
fn render(scene: &SceneInput, camera: Camera, size: UVec2) -> Option<(Vec<u8>, Vec<u32>)> {
    let ctx = test_context()?;
    let mut r = Renderer::headless(&ctx).expect("renderer");
    r.set_scene(&ctx, scene).expect("scene");
    let input = common::frame(camera, camera.position, 128, size, Schedule::Ours);
    let (_, pixels) = r.render_offscreen(&ctx, &input).expect("frame");
    let ids = r.read_frame_ids(&ctx).expect("ids").entity;
    Some((pixels, ids))
}

#[test]
fn sprites_are_drawn_and_named_by_the_pass_and_the_reference() {
    let Some(ctx) = test_context() else {
        return;
    };
    let mut scene = common::boxes_scene();
    // A white square with a transparent left column.
    let sheet = image("square", 8, |x, _| if x == 0 { [0; 4] } else { [255; 4] });
    scene
        .sprites
        .push(sprite(sheet, Vec3::new(0.0, 1.0, -1.0), 1.0));
    let camera = Camera::looking(Vec3::new(0.0, 1.0, 2.0), -Vec3::Z);
    let size = UVec2::new(96, 64);
    let (_, ids) = render(&scene, camera, size).expect("gpu");
    let centre = (32 * 96 + 48) as usize;
    assert_eq!(ids[centre], SPRITE_ID, "the pass names its sprite");
    let mut baselines = BaselineRenderer::new(&ctx).expect("baselines");
    baselines.set_scene(&ctx, &scene).expect("scene");
    let g = baselines
        .reference_gbuffer(&ctx, &camera, size, (camera.position, 128))
        .expect("gbuffer");
    assert_eq!(g.id[centre], SPRITE_ID, "the reference names its sprite");
    let hit = Vec3::from(g.world[centre]);
    assert!((hit.z + 1.0).abs() < 1e-3, "on the quad: {hit}");
    // The transparent column is not the sprite in either.
    let both = (0..ids.len())
        .filter(|&i| ids[i] == SPRITE_ID && g.id[i] == SPRITE_ID)
        .count();
    let either = (0..ids.len())
        .filter(|&i| ids[i] == SPRITE_ID || g.id[i] == SPRITE_ID)
        .count();
    // The same quad, snapped to the same probe texels: only the rasters' edge rules differ.
    eprintln!("{both} of {either} pixels are the sprite in both");
    assert!(both as f64 > 0.95 * either as f64, "{both} of {either}");
}

/// The pixel of a `size` frame from `camera` where world point `p` lands.
fn pixel_of(camera: &Camera, size: UVec2, p: Vec3) -> Option<(u32, u32)> {
    let vp = camera.projection(size.x as f32 / size.y as f32) * camera.view();
    let c = vp * p.extend(1.0);
    if c.w <= 0.0 {
        return None;
    }
    let ndc = c.truncate() / c.w;
    let x = (ndc.x * 0.5 + 0.5) * size.x as f32;
    let y = (0.5 - ndc.y * 0.5) * size.y as f32;
    (x >= 0.0 && y >= 0.0 && x < size.x as f32 && y < size.y as f32).then_some((x as u32, y as u32))
}

const N: u32 = 16;
const RELIEF: f32 = 0.25;

/// A 16×16 depth map: the base `RELIEF` deep, a raised 6×6 block in the middle at the quad.
fn block_depth(x: u32, y: u32) -> u8 {
    if (5..11).contains(&x) && (5..11).contains(&y) {
        0
    } else {
        255
    }
}

/// A white relief sprite facing +Z at (0, 1, −2), 1 unit wide, over the block.
fn relief_scene(with_wall: bool) -> SceneInput {
    let mut scene = common::boxes_scene();
    scene.objects.truncate(1);
    // The ground far below: nothing of the scene shadows the sprite.
    scene.objects[0].transform = Mat4::from_translation(Vec3::new(0.0, -20.0, 0.0));
    scene.suns[0].direction = -Vec3::new(-1.0, 0.35, 0.5).normalize();
    let mut s = sprite(
        image("white", N, |_, _| [255; 4]),
        Vec3::new(0.0, 1.0, -2.0),
        1.0,
    );
    let depth = image("block", N, |x, y| {
        let d = block_depth(x, y);
        [d, d, d, 255]
    });
    s.relief = Some((depth, RELIEF));
    scene.sprites.push(s);
    if with_wall {
        // A wall between the quad and the relief's base, 0.12 behind the quad.
        scene.objects.push(common::object(
            box_mesh(Vec3::new(3.0, 3.0, 0.02)),
            Mat4::from_translation(Vec3::new(0.0, 1.0, -2.13)),
            Vec3::new(0.2, 0.3, 0.9),
            7,
        ));
    }
    scene
}

fn relief_quad(depth: &dyn Fn(UVec2) -> f32) -> texel_render::gpu_sprites::ReliefQuad<'_> {
    texel_render::gpu_sprites::ReliefQuad {
        axes: [Vec3::X, Vec3::Y, Vec3::Z],
        size: Vec2::ONE,
        frame_px: UVec2::splat(N),
        relief_depth: RELIEF,
        depth,
    }
}

fn depth_at(t: UVec2) -> f32 {
    f32::from(block_depth(t.x, t.y)) / 255.0 * RELIEF
}

/// Each quad texel's centre, the ray from the camera (the probe's origin) through it, and
/// the CPU's hit (texels whose ray grazes an edge left out).
fn texel_rays(camera: &Camera) -> Vec<(Vec3, Option<(Vec2, f32)>)> {
    let quad = relief_quad(&depth_at);
    // The anchor (the sprite's centre) where the pass draws it: on the probe's texel grid.
    let anchor = texel_render::gpu_sprites::snap_to_probe_texel(
        Vec3::new(0.0, 1.0, -2.0),
        camera.position,
        128,
    );
    let corner = anchor + Vec3::new(-0.5, 0.5, 0.0);
    let mut out = Vec::new();
    for j in 0..N {
        for i in 0..N {
            let uv = (Vec2::new(i as f32, j as f32) + 0.5) / N as f32;
            let p = corner + Vec3::X * uv.x - Vec3::Y * uv.y;
            let dir = (p - camera.position).normalize();
            // A ray that grazes the frame's edge or a step is decided by float rounding,
            // differently on the GPU: such texels are left out.
            let e = Vec2::splat(1.0e-3);
            let near = [
                uv - e,
                uv + e,
                uv + Vec2::new(e.x, -e.y),
                uv - Vec2::new(e.x, -e.y),
            ];
            let hit = quad.hit(uv, dir);
            let sure = near.iter().all(|&u| {
                let other = quad.hit(u, dir);
                other.is_some() == hit.is_some()
                    && other.zip(hit).is_none_or(|(a, b)| (a.1 - b.1).abs() < 0.01)
            });
            if sure {
                out.push((p, hit));
            }
        }
    }
    out
}

#[test]
fn relief_shadows_itself_where_the_cpu_reference_says() {
    let scene = relief_scene(false);
    let camera = Camera::looking(
        Vec3::new(0.2, 1.3, 1.0),
        Vec3::new(-0.2, -0.3, -3.0).normalize(),
    );
    let size = UVec2::new(256, 256);
    let Some((pixels, ids)) = render(&scene, camera, size) else {
        return;
    };
    let l = -scene.suns[0].direction.normalize();
    let quad = relief_quad(&depth_at);
    let (mut agree, mut shadowed, mut tested) = (0, 0, 0);
    let mut lum = Vec::new();
    for (p, hit) in texel_rays(&camera) {
        let Some((uv, c)) = hit else { continue };
        let Some((x, y)) = pixel_of(&camera, size, p) else {
            continue;
        };
        let i = (y * size.x + x) as usize;
        assert_eq!(ids[i], SPRITE_ID, "the relief covers its texel at {p}");
        let px = &pixels[i * 4..i * 4 + 3];
        let l_gpu = u32::from(px[0]) + u32::from(px[1]) + u32::from(px[2]);
        let cpu = quad.shadowed(uv, c, l);
        lum.push((l_gpu, cpu));
        tested += 1;
        shadowed += usize::from(cpu);
    }
    // Lit texels are brighter than every shadowed one: split at the largest gap.
    let lit_min = lum
        .iter()
        .filter(|(_, s)| !s)
        .map(|(v, _)| *v)
        .min()
        .unwrap_or(0);
    for (v, cpu) in &lum {
        agree += usize::from((*v < lit_min) == *cpu || (*v >= lit_min && !cpu));
    }
    let dark = lum.iter().filter(|(v, _)| *v < lit_min).count();
    eprintln!("{tested} texels, {shadowed} shadowed on the CPU, {dark} dark on the GPU");
    assert!(tested > 200, "{tested}");
    assert!(
        shadowed > 10 && shadowed < tested / 2,
        "{shadowed} of {tested}"
    );
    assert_eq!(
        dark, shadowed,
        "the GPU's dark texels are the CPU's shadowed ones"
    );
    assert_eq!(agree, tested);
}

#[test]
fn relief_depth_meets_geometry_where_the_cpu_says() {
    let scene = relief_scene(true);
    let camera = Camera::looking(
        Vec3::new(0.2, 1.3, 1.0),
        Vec3::new(-0.2, -0.3, -3.0).normalize(),
    );
    let size = UVec2::new(256, 256);
    let Some((_, ids)) = render(&scene, camera, size) else {
        return;
    };
    // The wall's front face, 0.12 behind the quad: a texel whose surface is deeper is
    // hidden by it.
    let wall = 0.12;
    let (mut tested, mut right, mut front) = (0, 0, 0);
    for (p, hit) in texel_rays(&camera) {
        let Some((_, c)) = hit else { continue };
        if (c - wall).abs() < 0.02 {
            continue;
        }
        let Some((x, y)) = pixel_of(&camera, size, p) else {
            continue;
        };
        let want = if c < wall { SPRITE_ID } else { 7 };
        let got = ids[(y * size.x + x) as usize];
        tested += 1;
        right += usize::from(got == want);
        front += usize::from(want == SPRITE_ID);
    }
    eprintln!("{tested} texels, {front} in front of the wall, {right} as the CPU says");
    assert!(front > 20 && front < tested - 20, "{front} of {tested}");
    assert_eq!(
        right, tested,
        "the written depth meets the wall where the CPU says"
    );
}

/// A glass ball sprite (radius 0.5, front and back depth maps of a sphere, its normals) at
/// (0, 1, −2) before a red wall on the left and a blue one on the right, lit from the front.
fn glass_scene(index_ratio: Option<f32>) -> SceneInput {
    let mut scene = common::boxes_scene();
    scene.objects.clear();
    scene.suns[0].direction = -Vec3::new(0.2, 0.5, 1.0).normalize();
    for (x, colour, id) in [
        (-1.5, Vec3::new(0.9, 0.1, 0.1), 8),
        (1.5, Vec3::new(0.1, 0.2, 0.9), 9),
    ] {
        scene.objects.push(common::object(
            box_mesh(Vec3::new(3.0, 6.0, 0.2)),
            Mat4::from_translation(Vec3::new(x, 1.0, -6.0)),
            colour,
            id,
        ));
    }
    let Some(ratio) = index_ratio else {
        return scene;
    };
    const G: u32 = 32;
    let at = |x: u32, y: u32| {
        let u = (x as f32 + 0.5) / G as f32 * 2.0 - 1.0;
        let v = (y as f32 + 0.5) / G as f32 * 2.0 - 1.0;
        (u, v, (1.0 - u * u - v * v).max(0.0).sqrt())
    };
    let inside = |x, y| {
        let (u, v, _) = at(x, y);
        u * u + v * v < 0.9
    };
    let byte = |f: f32| (f.clamp(0.0, 1.0) * 255.0).round() as u8;
    let sheet = image(
        "glass",
        G,
        |x, y| if inside(x, y) { [255; 4] } else { [0; 4] },
    );
    let front = image("front", G, |x, y| {
        let d = byte(0.5 - 0.5 * at(x, y).2);
        [d, d, d, 255]
    });
    let back = image("back", G, |x, y| {
        let d = byte(0.5 + 0.5 * at(x, y).2);
        [d, d, d, 255]
    });
    let normal = image("normal", G, |x, y| {
        let (u, v, w) = at(x, y);
        [
            byte(u * 0.5 + 0.5),
            byte(-v * 0.5 + 0.5),
            byte(w * 0.5 + 0.5),
            255,
        ]
    });
    let mut s = sprite(sheet, Vec3::new(0.0, 1.0, -2.0), 1.0);
    s.normal_map = Some(normal);
    s.relief = Some((front, 1.0));
    s.refraction = Some((back, ratio));
    scene.sprites.push(s);
    scene
}

#[test]
fn refraction_at_ratio_one_leaves_the_background_and_a_ball_inverts_it() {
    let camera = Camera::looking(Vec3::new(0.0, 1.0, 1.0), -Vec3::Z);
    let size = UVec2::new(192, 192);
    let Some((plain, _)) = render(&glass_scene(None), camera, size) else {
        return;
    };
    let (straight, ids) = render(&glass_scene(Some(1.0)), camera, size).expect("gpu");
    let (bent, bent_ids) = render(&glass_scene(Some(0.67)), camera, size).expect("gpu");
    common::save_png("sprites_glass_bent.png", &bent, size);
    common::save_png("sprites_glass_straight.png", &straight, size);
    let sprite_px: Vec<usize> = (0..ids.len()).filter(|&i| ids[i] == SPRITE_ID).collect();
    assert!(sprite_px.len() > 1000, "{} ball pixels", sprite_px.len());
    let same = sprite_px
        .iter()
        .filter(|&&i| (0..3).all(|c| plain[i * 4 + c].abs_diff(straight[i * 4 + c]) <= 3))
        .count();
    // The walls' colours (the rim, bent out past them, shows the sky: neither).
    let red = |px: &[u8], i: usize| px[i * 4] > 150 && px[i * 4 + 2] < 150;
    let blue = |px: &[u8], i: usize| px[i * 4] < 150 && px[i * 4 + 2] > 150;
    // Behind the ball's left half the wall is red, behind its right half blue; bent by the
    // ball the two swap.
    let centre = size.x / 2;
    let (mut left, mut left_blue, mut right, mut right_red) = (0, 0, 0, 0);
    for i in (0..bent_ids.len()).filter(|&i| bent_ids[i] == SPRITE_ID) {
        let x = (i as u32) % size.x;
        if !red(&bent, i) && !blue(&bent, i) {
            continue;
        }
        if x + 8 < centre {
            assert!(red(&plain, i), "the wall behind the left half is red");
            left += 1;
            left_blue += usize::from(blue(&bent, i));
        } else if x > centre + 8 {
            assert!(blue(&plain, i), "the wall behind the right half is blue");
            right += 1;
            right_red += usize::from(red(&bent, i));
        }
    }
    eprintln!(
        "ratio 1: {same} of {} ball pixels as without it; ratio 0.67: of the wall-coloured \
         ball pixels, left {left_blue}/{left} blue, right {right_red}/{right} red",
        sprite_px.len()
    );
    assert!(left > 100 && right > 100, "{left} {right}");
    assert!(same as f64 > 0.9 * sprite_px.len() as f64);
    assert!(left_blue as f64 > 0.9 * left as f64 && right_red as f64 > 0.9 * right as f64);
}

/// A frame whose grid probe is at `grid` and whose previous probe, during a crossfade at
/// `fade_t`, is at `previous`.
fn fading_frame(
    camera: Camera,
    grid: Vec3,
    previous: Vec3,
    fade_t: f32,
    size: UVec2,
) -> texel_render::input::FrameInput {
    use texel_probes::cube::{Face, FaceMask};
    use texel_probes::probe_set::{Role, Slot};
    use texel_render::input::{CaptureInput, ProbeView};
    let mut input = common::frame(camera, grid, 128, size, Schedule::Ours);
    let prev = ProbeView {
        role: Role::Previous,
        slot: Slot::StableB,
        origin: previous,
        face_resolution: 128,
        draw: FaceMask::ALL,
        valid: FaceMask::ALL,
        ortho: None,
        near_faces: [glam::Vec4::ZERO; texel_render::input::MAX_NEAR_FACES],
    };
    input.captures.extend(Face::ALL.map(|face| CaptureInput {
        slot: Slot::StableB,
        face,
        origin: previous,
        face_resolution: 128,
        ortho: None,
    }));
    input.previous = Some(prev);
    input.fade_t = fade_t;
    input
}

#[test]
fn a_crossfade_splits_a_sprites_pixels_between_the_two_probes_by_the_bayer_pattern() {
    let Some(ctx) = test_context() else {
        return;
    };
    let mut scene = common::boxes_scene();
    scene.objects.truncate(1);
    // An upright sprite seen from two probes a unit apart sideways: turned toward each, its
    // quad (and the texels a pixel shows) differ.
    let sheet = image("checker", 8, |x, y| {
        if (x + y) % 2 == 0 {
            [230, 60, 40, 255]
        } else {
            [40, 60, 230, 255]
        }
    });
    let mut s = sprite(sheet, Vec3::new(0.0, 1.0, -1.5), 1.0);
    s.billboard = SpriteBillboard::Upright;
    scene.sprites.push(s);
    let camera = Camera::looking(Vec3::new(0.0, 1.0, 1.0), -Vec3::Z);
    let size = UVec2::new(96, 96);
    let (a, b) = (Vec3::new(-1.0, 1.0, 1.0), Vec3::new(1.0, 1.0, 1.0));
    let mut r = Renderer::headless(&ctx).expect("renderer");
    r.set_scene(&ctx, &scene).expect("scene");
    let mut draw = |fade_t: f32| {
        let input = fading_frame(camera, b, a, fade_t, size);
        // Twice: the second frame draws with both probes captured.
        r.render_offscreen(&ctx, &input).expect("frame");
        let (_, pixels) = r.render_offscreen(&ctx, &input).expect("frame");
        let ids = r.read_frame_ids(&ctx).expect("ids").entity;
        (pixels, ids)
    };
    let (grid, grid_ids) = draw(1.0);
    let (previous, previous_ids) = draw(0.0);
    let (half, half_ids) = draw(0.5);
    let (mut from_grid, mut from_previous, mut tested) = (0, 0, 0);
    for i in 0..half_ids.len() {
        // Pixels both copies cover, so each pixel's owner is the Bayer pattern's choice.
        if grid_ids[i] != SPRITE_ID || previous_ids[i] != SPRITE_ID || half_ids[i] != SPRITE_ID {
            continue;
        }
        let (x, y) = (i as u32 % size.x, i as u32 / size.x);
        let rgb = |p: &[u8]| [p[i * 4], p[i * 4 + 1], p[i * 4 + 2]];
        if rgb(&grid) == rgb(&previous) {
            continue;
        }
        tested += 1;
        if texel_probes::bayer::bayer_threshold(x, y) < 0.5 {
            from_grid += usize::from(rgb(&half) == rgb(&grid));
        } else {
            from_previous += usize::from(rgb(&half) == rgb(&previous));
        }
    }
    eprintln!(
        "{tested} pixels the two copies colour apart: {from_grid} + {from_previous} as the pattern says"
    );
    assert!(tested > 100, "{tested}");
    assert_eq!(from_grid + from_previous, tested);
}

#[test]
fn kept_sprite_texels_follow_the_look_and_the_sprites_moves() {
    let Some(ctx) = test_context() else {
        return;
    };
    let mut scene = common::boxes_scene();
    scene.objects.truncate(1);
    scene.sprites.push(sprite(
        image("white", 8, |_, _| [255; 4]),
        Vec3::new(0.0, 1.0, -1.0),
        1.0,
    ));
    let camera = Camera::looking(Vec3::new(0.0, 1.0, 2.0), -Vec3::Z);
    let size = UVec2::new(64, 64);
    let mut r = Renderer::headless(&ctx).expect("renderer");
    r.set_scene(&ctx, &scene).expect("scene");
    let mut input = common::frame(camera, camera.position, 128, size, Schedule::Ours);
    let mut draw = |input: &texel_render::input::FrameInput| {
        let (_, pixels) = r.render_offscreen(&ctx, input).expect("frame");
        (pixels, r.read_frame_ids(&ctx).expect("ids").entity)
    };
    let (first, ids) = draw(&input);
    let centre = (32 * 64 + 32) as usize;
    assert_eq!(ids[centre], SPRITE_ID);
    // The same frame again: the kept texels are the ones lit the first time.
    assert_eq!(draw(&input).0, first);
    // Darker ambient: the sprite is lit again.
    input.look.ambient = Vec3::splat(0.05);
    let (dim, _) = draw(&input);
    let px = |p: &[u8]| [p[centre * 4], p[centre * 4 + 1], p[centre * 4 + 2]];
    assert_ne!(px(&dim), px(&first), "a new look lights the sprite again");
    // Moved aside: the centre shows what was behind it.
    input.sprites = vec![texel_render::input::SpriteState {
        sprite: 0,
        position: Vec3::new(3.0, 1.0, -1.0),
        frame: 0,
    }];
    let (_, moved) = draw(&input);
    assert_ne!(moved[centre], SPRITE_ID, "the sprite moved");
}

/// One white 8×8 sprite of matched size at `at`, the boxes' ground out of the way.
fn matched_sprite_scene(at: Vec3) -> texel_render::input::SceneInput {
    let mut scene = common::boxes_scene();
    scene.objects.truncate(1);
    scene.objects[0].transform = Mat4::from_translation(Vec3::new(0.0, -20.0, 0.0));
    let mut s = sprite(image("white", 8, |_, _| [255; 4]), at, 1.0);
    s.size = None;
    scene.sprites.push(s);
    scene
}

#[test]
fn a_matched_sprite_pixel_is_one_probe_texel_at_its_distance() {
    let Some(ctx) = test_context() else {
        return;
    };
    let scene = matched_sprite_scene(Vec3::new(0.0, 1.0, -4.0));
    let camera = Camera::looking(Vec3::new(0.0, 1.0, 0.0), -Vec3::Z);
    let size = UVec2::new(256, 256);
    let mut baselines = BaselineRenderer::new(&ctx).expect("baselines");
    baselines.set_scene(&ctx, &scene).expect("scene");
    for n in [32u32, 64] {
        let g = baselines
            .reference_gbuffer(&ctx, &camera, size, (camera.position, n))
            .expect("gbuffer");
        let xs: Vec<f32> = (0..g.id.len())
            .filter(|&i| g.id[i] == SPRITE_ID)
            .map(|i| g.world[i][0])
            .collect();
        let width = xs.iter().copied().fold(f32::MIN, f32::max)
            - xs.iter().copied().fold(f32::MAX, f32::min);
        // 8 sprite pixels of one probe texel each: 8 × 2 × 4 / n, less a screen pixel.
        let want = 8.0 * 2.0 * 4.0 / n as f32;
        let pixel = 2.0 * 4.0 * (30f32.to_radians()).tan() / size.y as f32;
        eprintln!("faces of {n}: {width} wide, {want} wanted");
        assert!((width - want).abs() <= 2.0 * pixel, "{width} vs {want}");
    }
}

/// Under an orthographic camera drawn from orthographic probes, a matched sprite's pixel is
/// one texel of the probe's face wherever the sprite stands (the face's texels are one size
/// at every depth), and it faces back along the probe's parallel rays: a sprite of 8 pixels
/// spans 8 texels near and far.
#[test]
fn under_orthographic_probes_a_matched_sprite_pixel_is_one_face_texel_at_every_depth() {
    use texel_probes::cube::{Face, FaceMask};
    use texel_probes::ortho::OrthoFrame;
    let Some(ctx) = test_context() else {
        return;
    };
    let size = UVec2::new(256, 256);
    // A 16-unit-tall view; faces of 64 texels 32 units across: a texel is half a unit, 8
    // output pixels.
    let (n, half, height) = (64u32, 16.0f32, 16.0f32);
    let mut widths = Vec::new();
    for depth in [4.0f32, 30.0] {
        let scene = matched_sprite_scene(Vec3::new(0.0, 1.0, -depth));
        let mut camera = Camera::looking(Vec3::new(0.0, 1.0, 0.0), -Vec3::Z);
        camera.ortho_height = Some(height);
        let mut input = common::frame(camera, Vec3::ZERO, n, size, Schedule::Ours);
        let frame = OrthoFrame::new(-Vec3::Z, Vec3::Y, half);
        // The probes' planes through the camera (on the lattice of half-unit texels).
        let origin = Vec3::new(0.0, 1.0, 0.0);
        for p in [&mut input.eye, &mut input.grid] {
            p.origin = origin;
            p.ortho = Some(frame);
            p.draw = FaceMask::EMPTY;
            p.draw.insert(Face::PosX);
            p.valid = p.draw;
        }
        input.captures.retain(|c| c.face == Face::PosX);
        for c in &mut input.captures {
            c.origin = origin;
            c.ortho = Some(frame);
        }
        input.internal_size = size;
        let mut r = Renderer::headless(&ctx).expect("renderer");
        r.set_scene(&ctx, &scene).expect("scene");
        r.render_offscreen(&ctx, &input).expect("frame");
        r.render_offscreen(&ctx, &input).expect("frame");
        let ids = r.read_frame_ids(&ctx).expect("ids").entity;
        let xs: Vec<u32> = (0..ids.len() as u32)
            .filter(|&i| ids[i as usize] == SPRITE_ID)
            .map(|i| i % size.x)
            .collect();
        assert!(!xs.is_empty(), "the sprite is drawn at depth {depth}");
        let width = xs.iter().max().unwrap() - xs.iter().min().unwrap() + 1;
        widths.push(width);
    }
    // 8 sprite pixels of half a unit each, 16 output pixels a unit.
    let want = 8.0 * (2.0 * half / n as f32) * (size.y as f32 / height);
    for w in &widths {
        assert!(
            (*w as f32 - want).abs() <= 1.0,
            "width {w} px, want {want}: {widths:?}"
        );
    }
}
