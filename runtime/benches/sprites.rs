//! The sprite paper's Table 1 (issue 16), reported, never asserted: frame rates of its five
//! scenes at 1920×1080 and 800×600, beside the paper's, as the ratios the issue asks for
//! (relief box ÷ bump sprite, 1080p ÷ 800×600), plus 10,000 animated sprites at 1280×720.
//!
//! The paper's scenes (its section 4): a bump-mapped animated sprite (a gargoyle with a
//! normal map), a relief-mapped red box (the red pyramid of its figure 4, with self-shadows),
//! a relief-mapped brick sprite, a refraction sprite (a glass ball) over a background, and
//! all of the above together, each lit by 2 directional lights. Ours, built in code on the
//! bundled `sprites.ron` (its settings and sprite sheets):
//!
//! - `bump`: the bundled walker (8 directions, normal map, its walk playing at 8 fps);
//! - `relief_box`: the bundled stepped pyramid (`ziggurat`), the paper's figure 4 object,
//!   turned to face the viewer;
//! - `relief_brick`: a brick wall tile made here (32×32: bricks at the quad, mortar 0.15
//!   behind, bevelled normals), since nothing bundled is a brick sprite;
//! - `refraction`: the bundled glass sphere (relief front, back depth, index ratio 0.67);
//!   the bundled sprites' relief depths grow with their size;
//! - `all`: the four side by side, two over two.
//!
//! Each single sprite is 2 world units tall, 4.5 units in front of the camera (about 40% of
//! the screen's height), before the same backdrop: a ground plane and a wall 2.5 units
//! behind the sprites, which the probes capture (and the refraction bends). No sprite casts
//! shadows on the world (the paper's do not). Where we differ from the paper: its second
//! light turns about Y every frame, ours stands still (turning a sun would upload the scene
//! again each frame); its box is red, ours sandstone; our sprites face the grid probe's
//! origin, are drawn at the renderer's internal size (the full size here: the level's pixel
//! size of 2.5 asks for faces of 752 at 1080 lines, 416 at 600) and are lit with BVH shadow
//! rays, posterized and outlined; and a frame is the whole renderer, the texel world around
//! the sprites included. So two rows stand beside the paper's: `backdrop`, the same frame
//! without sprites, and `no_pixels`, the bump sprite behind the camera (what the sprite
//! pass costs without drawing a pixel); and the sprite pass's own time is reported beside
//! the frame's.
//!
//! `animated_10k`: 10,000 walkers (0.3 × 0.4 units) on a 100 × 100 grid on the ground, seen
//! from above at 1280×720, their walk at 60 fps with frames of 1/60 s, so every sprite's
//! frame changes every frame through `FrameInput::sprites`.
//!
//! `cargo bench -p texel_runtime --bench sprites` measures (on whatever Vulkan driver the
//! machine has), prints the table and writes it to `target/criterion/sprites_table1.md`;
//! `cargo test --benches` runs each case once at tiny sizes as a smoke test.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};

use criterion::{Criterion, SamplingMode, criterion_group, criterion_main};
use glam::{UVec2, Vec2, Vec3};
use texel_probes::probe_set::Slot;
use texel_render::context::{GpuContext, test_context};
use texel_render::input::{Camera, Image, Schedule};
use texel_render::target::{FRAME_FORMAT, OffscreenTarget};
use texel_runtime::load::{LoadedLevel, load_level};
use texel_runtime::session::{DrawnFrame, FrameRequest, Session};
use texel_scene::sprite::{Billboard, Relief, Sprite, SpriteAnimation, SpriteSize};
use texel_scene::{DirectionalLight, EntityRow, Geometry, Material, Name, Transform};

/// 60 frames a second.
const DT: f32 = 1.0 / 60.0;
/// The brick tile's sheet, normal and depth maps, as the assets know them.
const BRICK: [&str; 3] = [
    "bench/brick.png",
    "bench/brick_n.png",
    "bench/brick_depth.png",
];
/// The two sizes of the paper's table.
const SIZES: [(&str, UVec2); 2] = [
    ("1920x1080", UVec2::new(1920, 1080)),
    ("800x600", UVec2::new(800, 600)),
];
/// Where the single sprites' centres are, and the camera looking at them.
const CENTRE: Vec3 = Vec3::new(0.0, 2.2, 0.0);
const EYE: Vec3 = Vec3::new(0.0, 2.2, 4.5);

/// One of the paper's scenes: our name, its row in Table 1, its frame rates (1080p,
/// 800×600).
struct Scene {
    name: &'static str,
    paper: &'static str,
    fps: [f64; 2],
    sprites: &'static [Kind],
}

#[derive(Clone, Copy)]
enum Kind {
    Bump,
    ReliefBox,
    ReliefBrick,
    Refraction,
}

const SCENES: [Scene; 5] = [
    Scene {
        name: "bump",
        paper: "Bump mapped animated sprite",
        fps: [5000.0, 10000.0],
        sprites: &[Kind::Bump],
    },
    Scene {
        name: "relief_box",
        paper: "Relief mapped red box",
        fps: [700.0, 2500.0],
        sprites: &[Kind::ReliefBox],
    },
    Scene {
        name: "relief_brick",
        paper: "Relief mapped brick sprite",
        fps: [357.0, 1428.0],
        sprites: &[Kind::ReliefBrick],
    },
    Scene {
        name: "refraction",
        paper: "Refraction sprite with background",
        fps: [400.0, 1500.0],
        sprites: &[Kind::Refraction],
    },
    Scene {
        name: "all",
        paper: "All of the above",
        fps: [210.0, 588.0],
        sprites: &[
            Kind::Bump,
            Kind::ReliefBox,
            Kind::ReliefBrick,
            Kind::Refraction,
        ],
    },
];

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn named(name: &str) -> Option<Name> {
    Some(Name(name.to_owned()))
}

fn at(translation: Vec3) -> Option<Transform> {
    Some(Transform {
        translation,
        ..Transform::default()
    })
}

/// `sprites.ron`'s settings and sprite sheets (and the brick tile's images) with none of its
/// entities; in their place the backdrop: a ground plane, a wall behind the sprites (unless
/// `!wall`) and two suns (one from +X +Y +Z, as the paper's fixed light; one where its
/// turning light starts).
fn backdrop(wall: bool) -> LoadedLevel {
    let mut level =
        load_level(&repo().join("assets/levels/sprites.ron")).expect("bundled level loads");
    let entities: Vec<_> = level.scene.entities().collect();
    for e in entities {
        level.scene.despawn(e);
    }
    for (name, image) in BRICK.iter().zip(brick_images()) {
        level.assets.insert_texture(name, Arc::new(image));
    }
    let rows = [
        EntityRow {
            name: named("Ground"),
            transform: at(Vec3::ZERO),
            geometry: Some(Geometry::Plane {
                size: Vec2::splat(60.0),
            }),
            material: Some(Material {
                albedo: Vec3::new(0.3, 0.42, 0.2),
                ..Material::default()
            }),
            ..EntityRow::default()
        },
        EntityRow {
            name: named("Fixed light"),
            directional_light: Some(DirectionalLight {
                direction: Vec3::new(-1.0, -1.0, -1.0),
                colour: Vec3::new(1.0, 0.92, 0.8),
                intensity: 1.0,
            }),
            ..EntityRow::default()
        },
        EntityRow {
            name: named("Turning light"),
            directional_light: Some(DirectionalLight {
                direction: Vec3::new(0.8, -0.6, -0.4),
                colour: Vec3::new(0.6, 0.7, 1.0),
                intensity: 0.6,
            }),
            ..EntityRow::default()
        },
    ];
    for row in rows {
        level.scene.spawn(row);
    }
    if wall {
        level.scene.spawn(EntityRow {
            name: named("Wall"),
            transform: at(Vec3::new(0.0, 3.0, -2.5)),
            geometry: Some(Geometry::Box {
                size: Vec3::new(14.0, 6.0, 0.5),
            }),
            material: Some(Material {
                albedo: Vec3::new(0.55, 0.5, 0.45),
                ..Material::default()
            }),
            ..EntityRow::default()
        });
    }
    level
}

/// The sprite of `kind`, 2 units tall, centred at its transform; the bundled sprites' relief
/// depths scaled with their size in `sprites.ron` (the pyramid's 1.2, the sphere's 0.8).
fn sprite(kind: Kind) -> Sprite {
    let sheet = |s: &str| format!("../sprites/{s}.png");
    let square = UVec2::splat(32);
    let mut s = match kind {
        Kind::Bump => {
            let mut s = Sprite::new(
                &sheet("walker"),
                UVec2::new(24, 32),
                SpriteSize::World(Vec2::new(1.5, 2.0)),
            );
            s.directions = 8;
            s.animations.push(SpriteAnimation {
                name: "walk".into(),
                frames: vec![1, 2, 3, 4],
                fps: 8.0,
            });
            s.normal_map = Some(sheet("walker_n"));
            s
        }
        Kind::ReliefBox => {
            let mut s = Sprite::new(&sheet("ziggurat"), square, SpriteSize::World(Vec2::ONE));
            s.normal_map = Some(sheet("ziggurat_n"));
            s.relief = Some(Relief {
                depth_map: sheet("ziggurat_depth"),
                depth: 0.4 * 2.0 / 1.2,
            });
            s
        }
        Kind::ReliefBrick => {
            let mut s = Sprite::new(BRICK[0], square, SpriteSize::World(Vec2::ONE));
            s.normal_map = Some(BRICK[1].to_owned());
            s.relief = Some(Relief {
                depth_map: BRICK[2].to_owned(),
                depth: 0.15,
            });
            s
        }
        Kind::Refraction => {
            let mut s = Sprite::new(&sheet("glass"), square, SpriteSize::World(Vec2::ONE));
            s.normal_map = Some(sheet("glass_n"));
            s.relief = Some(Relief {
                depth_map: sheet("glass_front"),
                depth: 2.0,
            });
            s.refraction = Some(texel_scene::sprite::Refraction {
                back_depth: sheet("glass_back"),
                index_ratio: 0.67,
            });
            s.outlined = false;
            s
        }
    };
    if let SpriteSize::World(size) = &mut s.size {
        *size *= 2.0 / size.y;
    }
    s.pivot = Vec2::splat(0.5);
    s.billboard = match kind {
        Kind::Bump => Billboard::Upright,
        _ => Billboard::Spherical,
    };
    s
}

/// The backdrop with `scene`'s sprites: one at [`CENTRE`], or four two over two around it.
fn scene_level(scene: &Scene) -> LoadedLevel {
    let mut level = backdrop(true);
    let offsets: &[Vec2] = if scene.sprites.len() == 1 {
        &[Vec2::ZERO]
    } else {
        &[
            Vec2::new(-1.05, 1.05),
            Vec2::new(1.05, 1.05),
            Vec2::new(-1.05, -1.05),
            Vec2::new(1.05, -1.05),
        ]
    };
    for (i, (&kind, off)) in scene.sprites.iter().zip(offsets).enumerate() {
        level.scene.spawn(EntityRow {
            name: named(&format!("Sprite {i}")),
            transform: at(CENTRE + off.extend(0.0)),
            sprite: Some(sprite(kind)),
            ..EntityRow::default()
        });
    }
    level
}

/// The level of the case `name` (a row of [`rows`]) and the number of sprites it holds.
fn case_level(name: &str) -> (LoadedLevel, usize) {
    match SCENES.iter().find(|s| s.name == name) {
        Some(scene) => (scene_level(scene), scene.sprites.len()),
        None if name == "no_pixels" => {
            // The bump sprite behind the camera: what the sprite pass costs with no pixel.
            let mut level = backdrop(true);
            level.scene.spawn(EntityRow {
                name: named("Sprite behind"),
                transform: at(2.0 * EYE - CENTRE),
                sprite: Some(sprite(Kind::Bump)),
                ..EntityRow::default()
            });
            (level, 1)
        }
        None => (backdrop(true), 0),
    }
}

/// The backdrop without its wall and with `n` small walkers on a square grid on the ground,
/// their walk at 60 fps (a new frame every frame of [`DT`]).
fn crowd_level(n: usize) -> LoadedLevel {
    let mut level = backdrop(false);
    let side = (n as f32).sqrt().ceil() as usize;
    let spacing = 24.0 / side as f32;
    for i in 0..n {
        let (col, row) = ((i % side) as f32, (i / side) as f32);
        let mut s = sprite(Kind::Bump);
        s.size = SpriteSize::World(Vec2::new(0.3, 0.4));
        s.pivot = Vec2::new(0.5, 1.0);
        s.animations[0].fps = 60.0;
        level.scene.spawn(EntityRow {
            name: named(&format!("Walker {i}")),
            transform: Some(Transform {
                translation: Vec3::new(
                    -12.0 + (col + 0.5) * spacing,
                    0.0,
                    -1.5 - (row + 0.5) * spacing,
                ),
                rotation: Vec3::new(0.0, (i * 37 % 360) as f32, 0.0),
                ..Transform::default()
            }),
            sprite: Some(s),
            ..EntityRow::default()
        });
    }
    level
}

/// A 32×32 brick tile in running bond: sheet, normal map, depth map (bricks at the quad,
/// their edges bevelled back, mortar at full depth).
fn brick_images() -> [Image; 3] {
    const N: u32 = 32;
    let height = |x: u32, y: u32| -> f32 {
        let (row, v) = (y / 8, y % 8);
        let u = (x + if row % 2 == 1 { 8 } else { 0 }) % 16;
        let edge = u.min(15 - u).min(v.min(7 - v));
        match edge {
            0 => 0.0,
            1 => 0.7,
            _ => 1.0,
        }
    };
    let (mut sheet, mut normal, mut depth) = (Vec::new(), Vec::new(), Vec::new());
    for y in 0..N {
        for x in 0..N {
            let h = height(x, y);
            let tone = ((x / 16 + y / 8 * 3) % 4) as u8 * 10;
            sheet.extend(if h == 0.0 {
                [150, 146, 138, 255]
            } else {
                [150 + tone, 62 + tone / 2, 44, 255]
            });
            let d = (255.0 * (1.0 - h)).round() as u8;
            depth.extend([d, d, d, 255]);
            let hx = |dx: i32| height((x as i32 + dx).clamp(0, N as i32 - 1) as u32, y);
            let hy = |dy: i32| height(x, (y as i32 + dy).clamp(0, N as i32 - 1) as u32);
            let n = Vec3::new(-(hx(1) - hx(-1)), -(hy(-1) - hy(1)), 1.0).normalize();
            let enc = |c: f32| ((c * 0.5 + 0.5) * 255.0).round() as u8;
            normal.extend([enc(n.x), enc(n.y), enc(n.z), 255]);
        }
    }
    let image = |name: &str, pixels| Image {
        name: name.to_owned(),
        width: N,
        height: N,
        pixels,
    };
    [
        image(BRICK[0], sheet),
        image(BRICK[1], normal),
        image(BRICK[2], depth),
    ]
}

fn request(camera: Camera, size: UVec2) -> FrameRequest {
    FrameRequest {
        camera,
        dt: DT,
        schedule: Schedule::Ours,
        size,
    }
}

/// What one case measured: wall time per frame and each pass's time, ms; faces captured per
/// frame; the frame's internal size and face resolution.
#[derive(Default)]
struct Measured {
    frame_ms: Vec<f64>,
    /// Each pass's times, in pass order.
    passes: Vec<(&'static str, Vec<f64>)>,
    /// Faces captured per frame (the eye probe's).
    captured: Vec<f64>,
    internal: UVec2,
    faces: u32,
    /// The sprites' frames in the last frame drawn while settling.
    frames: Vec<u32>,
}

fn median(v: &[f64]) -> f64 {
    let mut v = v.to_vec();
    v.sort_by(f64::total_cmp);
    match v.len() {
        0 => f64::NAN,
        n if n % 2 == 1 => v[n / 2],
        n => 0.5 * (v[n / 2 - 1] + v[n / 2]),
    }
}

impl Measured {
    fn fps(&self) -> f64 {
        1e3 / median(&self.frame_ms)
    }
    fn frame(&self) -> f64 {
        median(&self.frame_ms)
    }
    fn pass(&self, name: &str) -> f64 {
        (self.passes.iter())
            .find(|(p, _)| *p == name)
            .map_or(f64::NAN, |(_, ms)| median(ms))
    }
    /// The sprites' whole cost: their texels lit (`sprite shade`) and drawn (`sprites`).
    fn sprites(&self) -> f64 {
        self.pass("sprites") + self.pass("sprite shade")
    }
}

/// A target of `size`, and `session` drawn into it at `camera` until no stable probe's face
/// is captured any more (at most 64 frames; the eye probe's are, every frame), checked to
/// reach the sprite pass exactly when `sprites` is set.
fn settle(
    ctx: &GpuContext,
    session: &mut Session,
    camera: Camera,
    size: UVec2,
    sprites: bool,
    label: &str,
) -> (OffscreenTarget, Measured) {
    let target = OffscreenTarget::with_format(ctx, size.x, size.y, FRAME_FORMAT);
    let mut quiet = 0;
    for _ in 0..64 {
        let drawn = session
            .draw(ctx, &request(camera, size), &target.view)
            .expect("frame");
        quiet = if drawn.input.captures.iter().all(|c| c.slot == Slot::Eye) {
            quiet + 1
        } else {
            0
        };
        if quiet == 3 {
            let has_pass = drawn.stats.passes.iter().any(|p| p.pass == "sprites");
            assert_eq!(
                has_pass, sprites,
                "{label}: the sprite pass ran: {has_pass} (passes {:?})",
                drawn.stats.passes
            );
            let measured = Measured {
                internal: drawn.input.internal_size,
                faces: drawn.input.grid.face_resolution,
                frames: sprite_frames(&drawn),
                ..Measured::default()
            };
            return (target, measured);
        }
    }
    panic!("{label}: the probes did not settle in 64 frames");
}

/// The frame of every sprite `drawn` changed, by sprite.
fn sprite_frames(drawn: &DrawnFrame) -> Vec<u32> {
    drawn.input.sprites.iter().map(|s| s.frame).collect()
}

/// Draws one frame into `target`, recording its times into `m`.
fn frame(
    ctx: &GpuContext,
    session: &mut Session,
    request: &FrameRequest,
    target: &OffscreenTarget,
    m: &mut Measured,
) -> DrawnFrame {
    let t = Instant::now();
    let drawn = session.draw(ctx, request, &target.view).expect("frame");
    m.frame_ms.push(t.elapsed().as_secs_f64() * 1e3);
    m.captured.push(drawn.input.captures.len() as f64);
    for p in &drawn.stats.passes {
        match m.passes.iter_mut().find(|(name, _)| *name == p.pass) {
            Some((_, ms)) => ms.push(p.ms),
            None => m.passes.push((p.pass, vec![p.ms])),
        }
    }
    drawn
}

/// The criterion group the cases are measured in: few samples, each one or more frames.
type Group<'a> = criterion::BenchmarkGroup<'a, criterion::measurement::WallTime>;

fn table1(c: &mut Criterion) {
    // Without an adapter this fails, unless TEXEL_ALLOW_NO_GPU opts out.
    let Some(ctx) = test_context() else {
        return;
    };
    // `cargo test --benches` runs each case once to see it works: there the frames are tiny
    // and the crowd is 100 walkers.
    let measuring = std::env::args().any(|a| a == "--bench");
    let size_of = |s: UVec2| if measuring { s } else { s / 10 };
    let crowd = if measuring { 10_000 } else { 100 };
    let camera = Camera::looking(EYE, CENTRE - EYE);

    let mut group = c.benchmark_group("sprites_table1");
    group
        .sample_size(10)
        .sampling_mode(SamplingMode::Flat)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(4));
    let first = backdrop(true);
    let mut session =
        Session::headless(&ctx, &first, size_of(SIZES[0].1), camera.fov_y).expect("session");
    let mut results: Vec<(&str, usize, Measured)> = Vec::new();
    for (name, _, _) in rows() {
        let (level, want) = case_level(name);
        session.set_level(&ctx, &level).expect("level uploads");
        let extracted = session.scene().sprites.len();
        assert_eq!(extracted, want, "{name}: sprites extracted");
        for (r, (res, size)) in SIZES.iter().enumerate() {
            let size = size_of(*size);
            let label = format!("{name}_{res}");
            let (target, mut m) = settle(&ctx, &mut session, camera, size, want > 0, &label);
            let req = request(camera, size);
            group.bench_function(&label, |b| {
                b.iter_custom(|iters| {
                    let t = Instant::now();
                    for _ in 0..iters {
                        frame(&ctx, &mut session, &req, &target, &mut m);
                    }
                    t.elapsed()
                })
            });
            results.push((name, r, m));
        }
    }
    let size = size_of(UVec2::new(1280, 720));
    let (crowd_m, changed) = crowd_case(&ctx, &mut session, &mut group, crowd, size);
    group.finish();

    let table = report(&results, &crowd_m, crowd, changed, ctx.timestamps);
    eprintln!("\n{table}");
    if measuring {
        write_table(&table);
    }
}

/// `n` walkers at `size`, each on a new frame every frame; returns what was measured and how
/// many sprites changed frame between consecutive frames, out of how many.
fn crowd_case(
    ctx: &GpuContext,
    session: &mut Session,
    group: &mut Group<'_>,
    n: usize,
    size: UVec2,
) -> (Measured, (usize, usize)) {
    session
        .set_level(ctx, &crowd_level(n))
        .expect("crowd uploads");
    assert_eq!(session.scene().sprites.len(), n, "crowd: sprites extracted");
    let eye = Vec3::new(0.0, 5.0, 6.0);
    let camera = Camera::looking(eye, Vec3::new(0.0, 0.0, -10.0) - eye);
    let label = format!("animated_{n}_1280x720");
    let (target, mut m) = settle(ctx, session, camera, size, true, &label);
    let req = request(camera, size);
    let mut previous = std::mem::take(&mut m.frames);
    let mut changed = (0usize, 0usize);
    group.bench_function(&label, |b| {
        b.iter_custom(|iters| {
            let t = Instant::now();
            for _ in 0..iters {
                let frames = sprite_frames(&frame(ctx, session, &req, &target, &mut m));
                changed.0 += previous.iter().zip(&frames).filter(|(a, b)| a != b).count();
                changed.1 += n;
                previous = frames;
            }
            t.elapsed()
        })
    });
    (m, changed)
}

/// Writes `table` to `target/criterion/sprites_table1.md` (or under `CARGO_TARGET_DIR`).
fn write_table(table: &str) {
    let dir = std::env::var_os("CARGO_TARGET_DIR")
        .map_or_else(|| repo().join("target"), PathBuf::from)
        .join("criterion");
    let dir = std::fs::create_dir_all(&dir)
        .and_then(|()| dir.canonicalize())
        .unwrap_or(dir);
    let path = dir.join("sprites_table1.md");
    match std::fs::write(&path, table) {
        Ok(()) => eprintln!("written to {}", path.display()),
        Err(e) => eprintln!("could not write {}: {e}", path.display()),
    }
}

/// `a / b` to two decimals, a dash where either is missing.
fn ratio(a: f64, b: f64) -> String {
    let r = a / b;
    if r.is_finite() {
        format!("{r:.2}")
    } else {
        "—".into()
    }
}

/// `ms` to two decimals, a dash where it is missing.
fn ms(ms: f64) -> String {
    if ms.is_finite() {
        format!("{ms:.2}")
    } else {
        "—".into()
    }
}

/// Our measurements by scene name and size index.
type Results<'a> = [(&'a str, usize, Measured)];

/// Our cases: the backdrop alone, the bump sprite behind the camera, the paper's scenes;
/// each with our name, the paper's row and its frame rates.
fn rows() -> impl Iterator<Item = (&'static str, &'static str, Option<[f64; 2]>)> + Clone {
    [
        ("backdrop", "(no sprites)", None),
        ("no_pixels", "(the bump sprite behind the camera)", None),
    ]
    .into_iter()
    .chain(SCENES.iter().map(|s| (s.name, s.paper, Some(s.fps))))
}

fn get<'a>(results: &'a Results<'_>, name: &str, size: usize) -> &'a Measured {
    (results.iter())
        .find(|(n, i, _)| *n == name && *i == size)
        .map(|(_, _, m)| m)
        .expect("measured")
}

/// The report: per scene and size our frame rate, frame and sprite-pass times beside the
/// paper's frame rate; the two ratios for both; the crowd; where each frame's time goes.
fn report(
    results: &Results<'_>,
    crowd: &Measured,
    n: usize,
    changed: (usize, usize),
    timestamps: bool,
) -> String {
    let mut t = String::new();
    let _ = writeln!(
        t,
        "Sprites: the paper's Table 1 on this machine (median of the measured frames; the \
         sprite pass's time from {})\n",
        if timestamps {
            "GPU timestamps"
        } else {
            "the CPU around its own submission"
        }
    );
    let _ = writeln!(
        t,
        "| scene | paper's row | size | internal | faces | ours fps | frame ms | sprite pass ms | \
         load | paper fps |"
    );
    let _ = writeln!(t, "|---|---|---|---|---:|---:|---:|---:|---:|---:|");
    // Every case captures the same backdrop (sprites never enter the probes), so the capture
    // pass's time against the quickest case's at that size tells how loaded the machine was.
    let quickest = |r: usize| {
        (results.iter())
            .filter(|(_, i, _)| *i == r)
            .map(|(_, _, m)| m.pass("capture"))
            .fold(f64::INFINITY, f64::min)
    };
    for (name, paper, fps) in rows() {
        for (r, (res, _)) in SIZES.iter().enumerate() {
            let m = get(results, name, r);
            let _ = writeln!(
                t,
                "| {name} | {paper} | {res} | {}×{} | {} | {:.1} | {:.1} | {} | {:.1}× | {} |",
                m.internal.x,
                m.internal.y,
                m.faces,
                m.fps(),
                m.frame(),
                ms(m.sprites()),
                m.pass("capture") / quickest(r),
                fps.map_or("—".into(), |f| format!("{:.0}", f[r])),
            );
        }
    }
    let _ = writeln!(
        t,
        "\n`load`: the capture pass's time (the same backdrop in every case) over the quickest \
         case's at that size; near 2× another process held one of lavapipe's cores."
    );
    ratios(&mut t, results);
    let _ = writeln!(
        t,
        "\n{n} animated sprites, 1280×720 (internal {}×{}, faces of {}): {:.2} fps, frame {:.1} \
         ms, sprite pass {} ms; {:.1}% of the sprites changed frame between consecutive frames.",
        crowd.internal.x,
        crowd.internal.y,
        crowd.faces,
        crowd.fps(),
        crowd.frame(),
        ms(crowd.sprites()),
        100.0 * changed.0 as f64 / changed.1.max(1) as f64,
    );
    passes(&mut t, results, crowd, n);
    t
}

/// The two ratios of frame rates, ours (whole frame; the sprite pass; the sprite
/// pass less its cost without pixels, `no_pixels`) and the paper's.
fn ratios(t: &mut String, results: &Results<'_>) {
    let net = |m: &Measured, r: usize| m.sprites() - get(results, "no_pixels", r).sprites();
    let _ = writeln!(
        t,
        "\nRelief box ÷ bump sprite (ratio of frame rates; for the sprite pass, of its times):\n"
    );
    let _ = writeln!(
        t,
        "| size | ours, frame | ours, sprite pass | ours, sprite pass less no-pixel cost | paper |"
    );
    let _ = writeln!(t, "|---|---:|---:|---:|---:|");
    for (r, (res, _)) in SIZES.iter().enumerate() {
        let (b, x) = (get(results, "bump", r), get(results, "relief_box", r));
        let _ = writeln!(
            t,
            "| {res} | {} | {} | {} | {} |",
            ratio(x.fps(), b.fps()),
            ratio(b.sprites(), x.sprites()),
            ratio(net(b, r), net(x, r)),
            ratio(SCENES[1].fps[r], SCENES[0].fps[r]),
        );
    }
    let _ = writeln!(
        t,
        "\n1920×1080 ÷ 800×600 (ratio of frame rates, likewise):\n"
    );
    let _ = writeln!(
        t,
        "| scene | ours, frame | ours, sprite pass | ours, sprite pass less no-pixel cost | paper |"
    );
    let _ = writeln!(t, "|---|---:|---:|---:|---:|");
    for (name, _, fps) in rows() {
        let (hd, sd) = (get(results, name, 0), get(results, name, 1));
        let _ = writeln!(
            t,
            "| {name} | {} | {} | {} | {} |",
            ratio(hd.fps(), sd.fps()),
            ratio(sd.sprites(), hd.sprites()),
            if name == "no_pixels" {
                "—".into()
            } else {
                ratio(net(sd, 1), net(hd, 0))
            },
            fps.map_or("—".into(), |f| ratio(f[0], f[1])),
        );
    }
}

/// Median milliseconds of every pass, and the faces captured per frame, per case.
fn passes(t: &mut String, results: &Results<'_>, crowd: &Measured, n: usize) {
    let crowd_name = format!("animated_{n}");
    let cases: Vec<(String, &Measured)> = (results.iter())
        .map(|(name, r, m)| (format!("{name} {}", SIZES[*r].0), m))
        .chain([(format!("{crowd_name} 1280x720"), crowd)])
        .collect();
    // Frame order (`texel_render::frame`).
    let order = [
        "capture",
        "shade",
        "sprite shade",
        "runs",
        "cull",
        "splat",
        "moving",
        "sprites",
        "background",
        "march",
        "visible",
        "present",
    ];
    let mut names: Vec<&str> = Vec::new();
    for (_, m) in &cases {
        for (p, _) in &m.passes {
            if !names.contains(p) {
                names.push(p);
            }
        }
    }
    names.sort_by_key(|p| order.iter().position(|o| o == p).unwrap_or(order.len()));
    let _ = writeln!(
        t,
        "\nWhere a frame goes (median ms per pass; faces captured per frame):\n"
    );
    let _ = writeln!(t, "| case | faces | {} |", names.join(" | "));
    let _ = writeln!(t, "|---|---:|{}", "---:|".repeat(names.len()));
    for (case, m) in &cases {
        let cells: Vec<String> = names.iter().map(|p| ms(m.pass(p))).collect();
        let _ = writeln!(
            t,
            "| {case} | {:.0} | {} |",
            median(&m.captured),
            cells.join(" | ")
        );
    }
}

criterion_group!(benches, table1);
criterion_main!(benches);
