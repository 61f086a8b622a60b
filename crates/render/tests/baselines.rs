//! The baseline methods on the GPU: Raster is a plausible reference, the reference G-buffer
//! agrees with it and reprojects exactly, Naive is blocky at the art-pixel size, Snap under
//! a whole-texel orthographic pan shifts by whole pixels, and the Cubemap agrees with Raster.

use crate::common;

use std::sync::Arc;

use glam::{Mat4, UVec2, Vec3, Vec4};
use texel_render::baselines::{
    Baseline, BaselineFrame, BaselineRenderer, BaselineView, art_pixel_height, low_res_size,
    snap_plan,
};
use texel_render::context::{GpuContext, test_context};
use texel_render::frame::RenderError;
use texel_render::input::{Camera, MaterialInput, ObjectInput, PointLightInput, SceneInput};
use texel_scene::primitives::{box_mesh, cylinder};

/// A ring of standing stones on grass around a glowing altar, lit by a sun and a point light.
fn stone_circle() -> SceneInput {
    let mut scene = common::boxes_scene();
    scene.objects.truncate(1);
    let stone = Arc::new(box_mesh(Vec3::new(0.9, 2.6, 0.5)));
    for i in 0..8 {
        let a = (i as f32 + 0.5) * std::f32::consts::TAU / 8.0;
        let at = Mat4::from_translation(Vec3::new(4.0 * a.sin(), 1.3, -6.0 + 4.0 * a.cos()))
            * Mat4::from_rotation_y(a);
        let mut o = common::object(box_mesh(Vec3::ONE), at, Vec3::new(0.55, 0.55, 0.6), 10 + i);
        o.mesh = stone.clone();
        scene.objects.push(o);
    }
    scene.objects.push(ObjectInput {
        mesh: Arc::new(cylinder(0.6, 0.8, 12)),
        transform: Mat4::from_translation(Vec3::new(0.0, 0.4, -6.0)),
        material: MaterialInput {
            albedo: Vec3::ONE,
            emissive: Vec3::new(1.0, 0.6, 0.2),
            casts_shadows: true,
            outlined: true,
            ..Default::default()
        },
        id: 30,
    });
    scene.points.push(PointLightInput {
        position: Vec3::new(0.0, 1.5, -6.0),
        colour: Vec3::new(2.0, 1.2, 0.5),
        radius: 6.0,
    });
    scene
}

fn camera() -> Camera {
    Camera::looking(Vec3::new(0.3, 1.6, 3.0), Vec3::new(0.0, -0.25, -1.0))
}

fn view(camera: Camera, size: UVec2, face_res: u32) -> BaselineView {
    BaselineView {
        camera,
        size,
        face_res,
        look: common::look(),
    }
}

fn renderer(ctx: &GpuContext, scene: &SceneInput) -> BaselineRenderer {
    let mut r = BaselineRenderer::new(ctx).expect("baseline pipelines build");
    r.set_scene(ctx, scene).expect("scene");
    r
}

fn rgb(f: &BaselineFrame, size: UVec2, x: u32, y: u32) -> [u8; 3] {
    let i = ((y * size.x + x) * 4) as usize;
    [f.pixels[i], f.pixels[i + 1], f.pixels[i + 2]]
}

/// Sky (blue, id 0) along the top row, ground (green, id 1) along the bottom row.
fn assert_sky_and_ground(f: &BaselineFrame, size: UVec2, what: &str) {
    assert_eq!(f.pixels.len(), (size.x * size.y * 4) as usize, "{what}");
    assert_eq!(f.ids.len(), (size.x * size.y) as usize, "{what}");
    for x in (0..size.x).step_by(7) {
        let sky = rgb(f, size, x, 0);
        assert!(
            sky[2] > sky[0] && sky[2] > 150,
            "{what}: sky at {x}: {sky:?}"
        );
        assert_eq!(f.ids[x as usize], 0, "{what}: sky id at {x}");
        let bottom = size.y - 1;
        let ground = rgb(f, size, x, bottom);
        assert!(
            ground[1] > ground[0] && ground[1] > ground[2],
            "{what}: ground at {x}: {ground:?}"
        );
        assert_eq!(
            f.ids[(bottom * size.x + x) as usize],
            1,
            "{what}: ground id"
        );
    }
}

#[test]
fn raster_shows_sky_above_ground_and_counts_pixels() {
    let Some(ctx) = test_context() else { return };
    let mut r = renderer(&ctx, &common::boxes_scene());
    let size = UVec2::new(160, 90);
    let f = r
        .render(&ctx, Baseline::Raster, &view(camera(), size, 32))
        .unwrap();
    common::save_png("baseline_raster_boxes.png", &f.pixels, size);
    assert_sky_and_ground(&f, size, "raster");
    assert!(f.ids.iter().any(|&i| (2..=4).contains(&i)), "boxes visible");
    assert_eq!(f.stats.counters.texels_shaded, 160 * 90);
    assert_eq!(f.stats.counters.faces_captured, 0);
    assert_eq!(f.stats.passes.len(), 3, "{:?}", f.stats.passes);
}

#[test]
fn reference_gbuffer_agrees_with_raster_and_reprojects() {
    let Some(ctx) = test_context() else { return };
    let mut r = renderer(&ctx, &common::boxes_scene());
    let size = UVec2::new(160, 90);
    let cam = camera();
    let f = r
        .render(&ctx, Baseline::Raster, &view(cam, size, 32))
        .unwrap();
    let g = r
        .reference_gbuffer(&ctx, &cam, size, (cam.position, 64))
        .unwrap();
    assert_eq!(g.size, size);
    assert_eq!(g.id, f.ids, "G-buffer ids are Raster's ids");
    let vp = cam.projection(size.x as f32 / size.y as f32) * cam.view();
    let mut ground = 0;
    for (i, (&id, w)) in g.id.iter().zip(&g.world).enumerate() {
        let (x, y) = ((i as u32 % size.x) as f32, (i as u32 / size.x) as f32);
        if id == 0 {
            assert_eq!(g.depth[i], f32::INFINITY);
            continue;
        }
        let p = Vec3::from_array(*w);
        let clip = vp * Vec4::from((p, 1.0));
        let ndc = clip.truncate() / clip.w;
        let px = (
            (ndc.x + 1.0) * 0.5 * size.x as f32,
            (1.0 - ndc.y) * 0.5 * size.y as f32,
        );
        // The rasterizer snaps vertices to its sub-pixel grid (Vulkan asks for at least 4
        // bits: SwiftShader has 4, lavapipe 8), so a pixel's interpolated point may sit about
        // 1/16 pixel off its centre, plus rounding (SwiftShader: up to 0.07).
        assert!(
            (px.0 - x - 0.5).abs() < 0.1 && (px.1 - y - 0.5).abs() < 0.1,
            "pixel ({x}, {y}) world {p} reprojects to {px:?}"
        );
        let depth = (p - cam.position).dot(cam.forward);
        assert!(
            (g.depth[i] - depth).abs() < 1e-3 * depth.max(1.0),
            "depth at {i}"
        );
        if id == 1 {
            assert!(p.y.abs() < 1e-3, "ground point {p} is on the plane");
            ground += 1;
        }
    }
    assert!(ground > 160 * 20, "ground covers the lower part: {ground}");
}

/// Colour runs in one row: 1 + the number of horizontal colour changes.
fn runs(f: &BaselineFrame, size: UVec2, y: u32) -> u32 {
    1 + (1..size.x)
        .filter(|&x| rgb(f, size, x, y) != rgb(f, size, x - 1, y))
        .count() as u32
}

#[test]
fn naive_is_blocky_at_the_art_pixel_size() {
    let Some(ctx) = test_context() else { return };
    let mut r = renderer(&ctx, &stone_circle());
    let size = UVec2::new(160, 90);
    let v = view(camera(), size, 32);
    let low = low_res_size(size, art_pixel_height(32, v.camera.fov_y).unwrap());
    assert_eq!(low, UVec2::new(32, 18));
    let naive = r.render(&ctx, Baseline::Naive, &v).unwrap();
    let raster = r.render(&ctx, Baseline::Raster, &v).unwrap();
    common::save_png("baseline_naive_blocky.png", &naive.pixels, size);
    assert_sky_and_ground(&naive, size, "naive");
    assert_eq!(naive.stats.counters.texels_shaded, 32 * 18);
    let (mut naive_max, mut raster_max) = (0, 0);
    for y in 0..size.y {
        let n = runs(&naive, size, y);
        assert!(n <= low.x + 1, "row {y}: {n} runs for {} art pixels", low.x);
        naive_max = naive_max.max(n);
        raster_max = raster_max.max(runs(&raster, size, y));
    }
    // Rows of art pixels repeat: each screen row equals its neighbour within a block.
    let same_rows = (1..size.y)
        .filter(|&y| (0..size.x).all(|x| rgb(&naive, size, x, y) == rgb(&naive, size, x, y - 1)))
        .count() as u32;
    assert!(same_rows >= size.y - low.y - 1, "{same_rows} repeated rows");
    assert!(
        raster_max > naive_max,
        "raster {raster_max} vs naive {naive_max}"
    );
}

#[test]
fn snap_under_a_whole_texel_orthographic_pan_shifts_by_whole_pixels() {
    let Some(ctx) = test_context() else { return };
    let mut r = renderer(&ctx, &stone_circle());
    // tan(fov/2) = 1/2: faces of 64 texels give 32 rows of art pixels, 3 screen pixels each.
    let size = UVec2::new(144, 96);
    let mut cam = Camera::looking(Vec3::new(0.37, 9.0, 5.0), Vec3::new(0.3, -0.8, -1.0));
    cam.fov_y = 2.0 * 0.5f32.atan();
    cam.ortho_height = Some(8.0);
    let low = low_res_size(size, art_pixel_height(64, cam.fov_y).unwrap());
    assert_eq!(low, UVec2::new(48, 32));
    let texel = 8.0 / 32.0;
    let right = cam.view().row(0).truncate();
    let a = r
        .render(&ctx, Baseline::Snap, &view(cam, size, 64))
        .unwrap();
    let mut panned = cam;
    panned.position += right * (3.0 * texel);
    let b = r
        .render(&ctx, Baseline::Snap, &view(panned, size, 64))
        .unwrap();
    common::save_png("baseline_snap_ortho_a.png", &a.pixels, size);
    common::save_png("baseline_snap_ortho_b.png", &b.pixels, size);
    assert_eq!(
        a.stats.counters.texels_shaded,
        50 * 34,
        "margin of one texel"
    );
    // Three texels are nine pixels: b at x shows what a showed at x + 9.
    let (same, total) = shifted_match(&a, &b, size, 9, 0);
    assert!(
        same as f32 >= 0.995 * total as f32,
        "{same} of {total} pixels match after the shift"
    );
    let (unshifted, _) = shifted_match(&a, &b, size, 0, 0);
    assert!(
        unshifted < same * 9 / 10,
        "the pan changed the image: {unshifted}"
    );
}

/// Pixels (colour and id) where `b` at `(x, y)` equals `a` at `(x + dx, y + dy)`, and the
/// number compared (the overlap).
fn shifted_match(
    a: &BaselineFrame,
    b: &BaselineFrame,
    size: UVec2,
    dx: i32,
    dy: i32,
) -> (u32, u32) {
    let (mut same, mut total) = (0, 0);
    for y in 0..size.y as i32 {
        for x in 0..size.x as i32 {
            let (ax, ay) = (x + dx, y + dy);
            if ax < 0 || ay < 0 || ax >= size.x as i32 || ay >= size.y as i32 {
                continue;
            }
            let (pa, pb) = (
                rgb(a, size, ax as u32, ay as u32),
                rgb(b, size, x as u32, y as u32),
            );
            let (ia, ib) = (
                (ay * size.x as i32 + ax) as usize,
                (y * size.x as i32 + x) as usize,
            );
            total += 1;
            same += u32::from(pa == pb && a.ids[ia] == b.ids[ib]);
        }
    }
    (same, total)
}

#[test]
fn snap_restores_sub_texel_motion_as_whole_pixels() {
    let Some(ctx) = test_context() else { return };
    let mut r = renderer(&ctx, &stone_circle());
    // Three screen pixels per texel, so a third of a texel of camera motion is one pixel.
    let size = UVec2::new(144, 96);
    let mut cam = Camera::looking(Vec3::new(0.0, 9.0, 5.0), Vec3::new(0.3, -0.8, -1.0));
    cam.fov_y = 2.0 * 0.5f32.atan();
    cam.ortho_height = Some(8.0);
    let (low, texel) = (UVec2::new(48, 32), 8.0 / 32.0);
    let view_m = cam.view();
    let (right, up) = (view_m.row(0).truncate(), view_m.row(1).truncate());
    // Start a quarter texel left of and below the grid, so a third of a texel stays within
    // the same snapped position and pixel centres stay away from texel edges.
    // The plan's origin is 1 + (remainder right, −remainder up).
    let o = snap_plan(&cam, low).origin - glam::Vec2::ONE;
    cam.position += right * ((-0.25 - o.x) * texel) + up * ((-0.25 + o.y) * texel);
    let o = snap_plan(&cam, low).origin - glam::Vec2::ONE;
    assert!(
        (o.x + 0.25).abs() < 1e-3 && (o.y - 0.25).abs() < 1e-3,
        "{o}"
    );
    let a = r
        .render(&ctx, Baseline::Snap, &view(cam, size, 64))
        .unwrap();
    for (step, dx, dy) in [(right, 1, 0), (up, 0, -1)] {
        let mut moved = cam;
        moved.position += step * (texel / 3.0);
        let plan = snap_plan(&moved, low);
        let still = plan.snapped.position - snap_plan(&cam, low).snapped.position;
        assert!(still.length() < 1e-4, "the snapped camera stays: {still}");
        let b = r
            .render(&ctx, Baseline::Snap, &view(moved, size, 64))
            .unwrap();
        let (same, total) = shifted_match(&a, &b, size, dx, dy);
        assert_eq!(
            same, total,
            "moving along {step} shifts the image by ({dx}, {dy}) pixels"
        );
    }
}

#[test]
fn snap_perspective_and_every_method_render_the_stone_circle() {
    let Some(ctx) = test_context() else { return };
    let mut r = renderer(&ctx, &stone_circle());
    let size = UVec2::new(320, 180);
    let v = view(camera(), size, 64);
    for method in Baseline::ALL {
        let f = r.render(&ctx, method, &v).unwrap();
        common::save_png(&format!("baseline_{}.png", method.name()), &f.pixels, size);
        assert_sky_and_ground(&f, size, method.name());
        assert!(
            f.ids.contains(&30),
            "{}: the altar is visible",
            method.name()
        );
        assert!(f.stats.frame_ms > 0.0);
    }
}

#[test]
fn cubemap_agrees_with_raster() {
    let Some(ctx) = test_context() else { return };
    let mut r = renderer(&ctx, &common::boxes_scene());
    let size = UVec2::new(160, 90);
    let v = view(camera(), size, 64);
    let cube = r.render(&ctx, Baseline::Cubemap, &v).unwrap();
    let raster = r.render(&ctx, Baseline::Raster, &v).unwrap();
    common::save_png("baseline_cubemap_boxes.png", &cube.pixels, size);
    assert_sky_and_ground(&cube, size, "cubemap");
    assert_eq!(cube.stats.counters.faces_captured, 6);
    assert_eq!(cube.stats.counters.texels_shaded, 6 * 64 * 64);
    let agree = cube.ids.iter().zip(&raster.ids).filter(|(a, b)| a == b);
    let agree = agree.count() as f32 / cube.ids.len() as f32;
    assert!(agree >= 0.9, "ids agree on {:.1}% of pixels", agree * 100.0);
}

#[test]
fn bad_views_are_errors() {
    let Some(ctx) = test_context() else { return };
    let mut r = BaselineRenderer::new(&ctx).unwrap();
    let v = view(camera(), UVec2::new(16, 16), 32);
    assert!(matches!(
        r.render(&ctx, Baseline::Raster, &v),
        Err(RenderError::NoScene)
    ));
    r.set_scene(&ctx, &common::boxes_scene()).expect("scene");
    for bad in [
        BaselineView { face_res: 0, ..v },
        BaselineView {
            size: UVec2::ZERO,
            ..v
        },
        BaselineView {
            camera: Camera::looking(Vec3::NAN, Vec3::Z),
            ..v
        },
    ] {
        let e = r.render(&ctx, Baseline::Naive, &bad);
        assert!(matches!(e, Err(RenderError::InvalidFrame(_))), "{bad:?}");
    }
}

/// Per-method frame times at 640×360 (printed; run with `--nocapture` to read them).
#[test]
fn frame_times_at_640x360() {
    let Some(ctx) = test_context() else { return };
    let mut r = renderer(&ctx, &stone_circle());
    let v = view(camera(), UVec2::new(640, 360), 96);
    for method in Baseline::ALL {
        let _warm = r.render(&ctx, method, &v).unwrap();
        let f = r.render(&ctx, method, &v).unwrap();
        let passes: Vec<String> = f
            .stats
            .passes
            .iter()
            .map(|p| format!("{} {:.2}", p.pass, p.ms))
            .collect();
        println!(
            "{:8} frame {:8.2} ms (gpu timestamps: {}) [{}] {:?}",
            method.name(),
            f.stats.frame_ms,
            f.stats.gpu_timestamps,
            passes.join(", "),
            f.stats.counters
        );
        assert!(!f.stats.passes.is_empty() && f.stats.passes.iter().all(|p| p.ms >= 0.0));
    }
}

#[test]
fn haze_fades_distant_ground_toward_the_sky() {
    let Some(ctx) = test_context() else { return };
    let mut r = renderer(&ctx, &common::boxes_scene());
    let size = UVec2::new(160, 90);
    let clear = view(camera(), size, 32);
    let mut hazy = clear;
    hazy.look.haze = 0.3;
    for method in [Baseline::Raster, Baseline::Cubemap] {
        let a = r.render(&ctx, method, &clear).unwrap();
        let b = r.render(&ctx, method, &hazy).unwrap();
        // Far ground just below the horizon, at the left edge (no box there).
        let y = (0..size.y)
            .find(|&y| a.ids[(y * size.x) as usize] == 1)
            .unwrap()
            + 1;
        let sky = rgb(&a, size, 0, 0).map(i32::from);
        let dist = |p: [u8; 3]| {
            (0..3)
                .map(|k| (i32::from(p[k]) - sky[k]).abs())
                .sum::<i32>()
        };
        let (near_a, near_b) = (dist(rgb(&a, size, 0, y)), dist(rgb(&b, size, 0, y)));
        assert!(near_b < near_a / 2, "{method:?}: {near_b} vs {near_a}");
        assert_eq!(a.ids, b.ids, "{method:?}: haze changes colours only");
    }
}
