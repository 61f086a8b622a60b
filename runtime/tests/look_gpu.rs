//! Palettes and bloom (issue 61): a level that names a palette draws every pixel in one of its
//! colours, on texel splatting and on the baselines; dithering is anchored to the texel (a
//! texel keeps its colour while the camera moves inside a cell) and does dither; the
//! alternate palette swaps in; a bloom only adds light. The stone circle at 160×90, faces of
//! 64.

use std::collections::{BTreeSet, HashMap};
use std::path::{Path, PathBuf};

use glam::{UVec2, Vec3};
use texel_render::baselines::{Baseline, BaselineRenderer, BaselineView};
use texel_render::context::{GpuContext, test_context};
use texel_render::input::{Camera, Schedule};
use texel_render::passes::present::source_pixel;
use texel_render::target::read_texture_layer;
use texel_runtime::frame_plan::{level_look, level_palettes};
use texel_runtime::load::{LoadedLevel, load_level};
use texel_runtime::session::{FrameRequest, Session, set_face_resolution};
use texel_scene::Level;
use texel_scene::components::PaletteSetting;

const SIZE: UVec2 = UVec2::new(160, 90);
const DAY: &str =
    "1a1a24\n4a4e5e\n8a90a0\ndce0e8\n3d5a2a\n7fae4a\n6a4a30\nc09060\n5a7fb0\na8cce8\n";
const NIGHT: &str = "0b0d1a\n232a4d\n4b5c8a\n9aabcc\n";

/// The stone circle in `dir`, naming the day palette (and the night one as its alternate),
/// dithered at `dither`.
fn level_with_palette(dir: &Path, dither: f32) -> LoadedLevel {
    let source = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/levels/stone_circle.ron");
    let mut level = Level::load(&source).expect("stone circle");
    std::fs::write(dir.join("day.hex"), DAY).expect("write");
    std::fs::write(dir.join("night.hex"), NIGHT).expect("write");
    level.palette = Some(PaletteSetting {
        file: "day.hex".into(),
        dither,
        alternate: Some("night.hex".into()),
    });
    let path: PathBuf = dir.join("circle.ron");
    level.save(&path).expect("save");
    let mut loaded = load_level(&path).expect("load with its palette");
    set_face_resolution(&mut loaded, 64).expect("faces of 64");
    loaded
}

fn colours(text: &str) -> BTreeSet<[u8; 3]> {
    (text.lines())
        .map(|l| {
            let b = |i| u8::from_str_radix(&l[i..i + 2], 16).expect("hex");
            [b(0), b(2), b(4)]
        })
        .collect()
}

fn camera(x: f32) -> Camera {
    Camera::looking(Vec3::new(x, 1.6, 9.0), Vec3::new(0.0, -0.15, -1.0))
}

fn request(camera: Camera) -> FrameRequest {
    FrameRequest {
        camera,
        dt: 1.0 / 30.0,
        schedule: Schedule::Ours,
        size: SIZE,
    }
}

/// A settled frame at `camera`: its RGBA pixels and each output pixel's texel key (0 where
/// the eye probe drew it: the eye's texels are captured anew as the camera moves).
fn frame(ctx: &GpuContext, session: &mut Session, camera: Camera) -> (Vec<u8>, Vec<u32>) {
    let mut last = None;
    for _ in 0..8 {
        last = Some(
            session
                .draw_offscreen(ctx, &request(camera))
                .expect("frame"),
        );
    }
    let (drawn, pixels) = last.expect("a frame");
    let internal = (drawn.input.internal_size.x, drawn.input.internal_size.y);
    let keys = session.renderer().keys_texture().expect("keys");
    let raw = read_texture_layer(ctx, keys, 0, 4).expect("keys read");
    let ids = session.renderer().read_frame_ids(ctx).expect("ids");
    assert_eq!(ids.size, SIZE, "ids at the output size");
    let key = |x, y| {
        let (sx, sy) = source_pixel(x, y, internal, (SIZE.x, SIZE.y));
        let i = 4 * (sy * internal.0 + sx) as usize;
        u32::from_le_bytes([raw[i], raw[i + 1], raw[i + 2], raw[i + 3]])
    };
    let keys = (0..SIZE.y)
        .flat_map(|y| (0..SIZE.x).map(move |x| (x, y)))
        .map(|(x, y)| match ids.from_eye[(y * SIZE.x + x) as usize] {
            true => 0,
            false => key(x, y),
        })
        .collect();
    (pixels, keys)
}

fn off_palette(pixels: &[u8], palette: &BTreeSet<[u8; 3]>) -> usize {
    (pixels.chunks_exact(4))
        .filter(|p| !palette.contains(&[p[0], p[1], p[2]]))
        .count()
}

#[test]
fn every_pixel_is_a_palette_colour_and_the_alternate_swaps_in() {
    let Some(ctx) = test_context() else {
        return;
    };
    let dir = tempfile::tempdir().expect("tempdir");
    let level = level_with_palette(dir.path(), 0.0);
    let mut session = Session::headless(&ctx, &level, SIZE, 1.0).expect("session");
    let (pixels, _) = frame(&ctx, &mut session, camera(0.0));
    let day = colours(DAY);
    assert_eq!(off_palette(&pixels, &day), 0, "every pixel a day colour");
    let used: BTreeSet<[u8; 3]> = pixels.chunks_exact(4).map(|p| [p[0], p[1], p[2]]).collect();
    assert!(
        used.len() >= 4,
        "the picture uses several colours: {used:?}"
    );

    assert_eq!(session.swap_palette(), Some(true), "the night palette");
    let (pixels, _) = frame(&ctx, &mut session, camera(0.0));
    assert_eq!(
        off_palette(&pixels, &colours(NIGHT)),
        0,
        "every pixel a night colour"
    );
}

/// The colours each texel key shows in a frame.
fn by_key(pixels: &[u8], keys: &[u32]) -> HashMap<u32, BTreeSet<[u8; 3]>> {
    let mut out: HashMap<u32, BTreeSet<[u8; 3]>> = HashMap::new();
    for (p, &k) in pixels.chunks_exact(4).zip(keys) {
        if k != 0 && k < 0x8000_0000 {
            out.entry(k).or_default().insert([p[0], p[1], p[2]]);
        }
    }
    out
}

/// A texel whose colour the camera's move inside a cell does not change (drawn without a
/// palette) keeps its dithered palette colour too: the pattern belongs to the texel, not the
/// screen. (Haze changes a texel's colour with the camera's distance, and with it, now and
/// then, the dithered choice; those texels are not steady.)
#[test]
fn a_texel_keeps_its_dithered_colour_while_the_camera_moves_inside_a_cell() {
    let Some(ctx) = test_context() else {
        return;
    };
    let dir = tempfile::tempdir().expect("tempdir");
    let (at, beside) = (camera(0.0), camera(0.2));
    let mut unmapped = level_with_palette(dir.path(), 0.0);
    unmapped.scene.palette = None;
    let mut plain = Session::headless(&ctx, &unmapped, SIZE, 1.0).expect("session");
    let (plain_a, plain_keys_a) = frame(&ctx, &mut plain, at);
    let (plain_b, plain_keys_b) = frame(&ctx, &mut plain, beside);
    let level = level_with_palette(dir.path(), 1.0);
    let mut session = Session::headless(&ctx, &level, SIZE, 1.0).expect("session");
    let (a, keys_a) = frame(&ctx, &mut session, at);
    let (b, keys_b) = frame(&ctx, &mut session, beside);
    // The same texels, but for a few pixels where runs part: texels of different dither
    // ranks are drawn one quad each (runs.wgsl joins one lit colour, the rank's bits too),
    // and where neighbouring quads overlap another texel may win (438 of 14,400 pixels
    // on lavapipe, 2026-12-07).
    for (keys, plain_keys) in [(&keys_a, &plain_keys_a), (&keys_b, &plain_keys_b)] {
        let differ = (keys.iter().zip(plain_keys))
            .filter(|(x, y)| x != y)
            .count();
        assert!(
            differ * 20 < keys.len(),
            "the same texels: {differ} pixels differ"
        );
    }
    let day = colours(DAY);
    assert_eq!(
        off_palette(&a, &day),
        0,
        "dithered pixels are palette colours too"
    );
    let mut undithered =
        Session::headless(&ctx, &level_with_palette(dir.path(), 0.0), SIZE, 1.0).expect("session");
    let (nearest, _) = frame(&ctx, &mut undithered, at);
    let changed = (a.chunks_exact(4).zip(nearest.chunks_exact(4)))
        .filter(|(x, y)| x != y)
        .count();
    assert!(changed > 20, "dithering changes pixels: {changed}");

    // The camera moved 0.2 to the side, inside its cell (cells of 1 from the origin).
    let (plain_a, plain_b) = (
        by_key(&plain_a, &plain_keys_a),
        by_key(&plain_b, &plain_keys_b),
    );
    let (a, b) = (by_key(&a, &keys_a), by_key(&b, &keys_b));
    let steady: Vec<u32> = (plain_a.iter())
        .filter(|(k, c)| c.len() == 1 && plain_b.get(k) == Some(c))
        .map(|(k, _)| *k)
        .collect();
    assert!(
        steady.len() > 500,
        "texels steady in both frames: {}",
        steady.len()
    );
    // Shown in both dithered frames too (where runs part, a texel may lose its pixels to a
    // neighbour's quad: 1 of 2,071 on lavapipe).
    let shown: Vec<&u32> = (steady.iter())
        .filter(|k| a.contains_key(k) && b.contains_key(k))
        .collect();
    assert!(
        shown.len() * 100 > 99 * steady.len(),
        "{} of {}",
        shown.len(),
        steady.len()
    );
    let moved: Vec<&&u32> = shown.iter().filter(|k| a.get(k) != b.get(k)).collect();
    assert!(
        moved.is_empty(),
        "{} of {} steady texels changed their dithered colour",
        moved.len(),
        steady.len()
    );
}

#[test]
fn the_baselines_map_to_the_palette_too() {
    let Some(ctx) = test_context() else {
        return;
    };
    let dir = tempfile::tempdir().expect("tempdir");
    let level = level_with_palette(dir.path(), 1.0);
    let scene = texel_runtime::frame_plan::scene_input(&level);
    let mut renderer = BaselineRenderer::new(&ctx).expect("baselines");
    renderer.set_scene(&ctx, &scene).expect("scene");
    renderer.set_palette(&ctx, level_palettes(&level).first());
    let day = colours(DAY);
    let look = level_look(&level.scene);
    for method in [Baseline::Raster, Baseline::Naive, Baseline::Snap] {
        let view = BaselineView {
            camera: camera(0.0),
            size: SIZE,
            face_res: 64,
            look,
        };
        let frame = renderer.render(&ctx, method, &view).expect("frame");
        assert_eq!(off_palette(&frame.pixels, &day), 0, "{method:?}");
    }
}

/// A bloom only adds light: every pixel is at least as bright as without it, pixels near the
/// bright sky brighter; the baselines bloom too.
#[test]
fn a_bloom_adds_light_near_bright_pixels_and_takes_none_away() {
    let Some(ctx) = test_context() else {
        return;
    };
    let dir = tempfile::tempdir().expect("tempdir");
    let mut plain = level_with_palette(dir.path(), 0.0);
    plain.scene.palette = None;
    let mut bloomed = level_with_palette(dir.path(), 0.0);
    bloomed.scene.palette = None;
    bloomed.scene.settings.bloom = Some(texel_scene::components::Bloom {
        threshold: 0.45,
        strength: 1.0,
        radius: 3,
    });
    let frame_of = |level: &LoadedLevel| {
        let mut session = Session::headless(&ctx, level, SIZE, 1.0).expect("session");
        frame(&ctx, &mut session, camera(0.0)).0
    };
    let (without, with) = (frame_of(&plain), frame_of(&bloomed));
    // (A pixel the bloom leaves alone goes through linear light and back: a byte may round.)
    let darker = (without.iter().zip(&with))
        .filter(|(a, b)| u16::from(**b) + 1 < u16::from(**a))
        .count();
    let brighter = (without.iter().zip(&with)).filter(|(a, b)| b > a).count();
    assert_eq!(darker, 0, "no channel darker");
    assert!(brighter > 200, "{brighter} channels brighter");

    let scene = texel_runtime::frame_plan::scene_input(&bloomed);
    let mut renderer = BaselineRenderer::new(&ctx).expect("baselines");
    renderer.set_scene(&ctx, &scene).expect("scene");
    let view = BaselineView {
        camera: camera(0.0),
        size: SIZE,
        face_res: 64,
        look: level_look(&bloomed.scene),
    };
    let before = renderer
        .render(&ctx, Baseline::Naive, &view)
        .expect("frame");
    renderer.set_bloom(texel_runtime::frame_plan::level_bloom(&bloomed.scene));
    let after = renderer
        .render(&ctx, Baseline::Naive, &view)
        .expect("frame");
    let darker = (before.pixels.iter().zip(&after.pixels))
        .filter(|(a, b)| b < a)
        .count();
    let brighter = (before.pixels.iter().zip(&after.pixels))
        .filter(|(a, b)| b > a)
        .count();
    assert_eq!(darker, 0, "naive: no channel darker");
    assert!(brighter > 200, "naive: {brighter} channels brighter");
}

/// Specular highlights are seen from the probe: they brighten the stones' texels; the grid
/// probe's lit texels, highlights included, stay byte for byte the same while the camera
/// moves inside its cell, and are the same whichever camera in the cell lit them (naive's
/// highlights follow its camera instead).
#[test]
fn highlights_are_cached_with_the_texel_while_the_camera_moves_inside_a_cell() {
    let Some(ctx) = test_context() else {
        return;
    };
    let dir = tempfile::tempdir().expect("tempdir");
    let mut matte = level_with_palette(dir.path(), 0.0);
    matte.scene.palette = None;
    let mut shiny = level_with_palette(dir.path(), 0.0);
    shiny.scene.palette = None;
    let entities: Vec<_> = shiny.scene.entities().collect();
    for e in entities {
        let mut row = shiny.scene.row(e).expect("row");
        if let Some(m) = &mut row.material {
            m.specular = Some(texel_scene::components::Specular {
                strength: 1.5,
                shininess: 16.0,
            });
            shiny.scene.set_row(e, row).expect("set");
        }
    }
    // The grid probe's lit faces after settling at `camera`, and the probe.
    let lit = |session: &mut Session, camera: Camera| {
        frame(&ctx, session, camera);
        let grid = (session
            .draw_offscreen(&ctx, &request(camera))
            .expect("frame")
            .0)
            .input
            .grid;
        let (_, faces) = (session.renderer())
            .read_lit_faces(&ctx, grid.slot)
            .expect("lit faces");
        (faces, grid.origin)
    };
    let mut session = Session::headless(&ctx, &shiny, SIZE, 1.0).expect("session");
    let (a, origin_a) = lit(&mut session, camera(0.0));
    let (b, origin_b) = lit(&mut session, camera(0.2));
    assert_eq!(origin_a, origin_b, "one grid probe");
    let differ = |x: &[Vec<u8>], y: &[Vec<u8>]| {
        (x.iter().zip(y))
            .map(|(f, g)| {
                f.chunks_exact(4)
                    .zip(g.chunks_exact(4))
                    .filter(|(p, q)| p != q)
                    .count()
            })
            .sum::<usize>()
    };
    assert_eq!(
        differ(&a, &b),
        0,
        "the grid probe's texels, highlights included, held"
    );
    let mut plain = Session::headless(&ctx, &matte, SIZE, 1.0).expect("session");
    let (m, _) = lit(&mut plain, camera(0.0));
    let brighter = (m.iter().zip(&a))
        .map(|(f, g)| f.iter().zip(g).filter(|(p, q)| q > p).count())
        .sum::<usize>();
    assert!(
        brighter > 200,
        "highlights brighten {brighter} texel channels"
    );
}
