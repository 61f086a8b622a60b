//! The benchmark's levels, built in code: the paper's scenes over one backdrop, and the
//! crowd of walkers.

use std::path::PathBuf;
use std::sync::Arc;

use glam::{UVec2, Vec2, Vec3};
use texel_render::input::Image;
use texel_runtime::load::{LoadedLevel, load_level};
use texel_scene::sprite::{Billboard, Relief, Sprite, SpriteAnimation, SpriteSize};
use texel_scene::{DirectionalLight, EntityRow, Geometry, Material, Name, Transform};

/// The brick tile's sheet, normal and depth maps, as the assets know them.
pub(crate) const BRICK: [&str; 3] = [
    "bench/brick.png",
    "bench/brick_n.png",
    "bench/brick_depth.png",
];
/// Where the single sprites' centres are, and the camera looking at them.
pub(crate) const CENTRE: Vec3 = Vec3::new(0.0, 2.2, 0.0);
pub(crate) const EYE: Vec3 = Vec3::new(0.0, 2.2, 4.5);

/// One of the paper's scenes: our name, its row in Table 1, its frame rates (1080p,
/// 800×600).
pub(crate) struct Scene {
    pub(crate) name: &'static str,
    pub(crate) paper: &'static str,
    pub(crate) fps: [f64; 2],
    pub(crate) sprites: &'static [Kind],
}

#[derive(Clone, Copy)]
pub(crate) enum Kind {
    Bump,
    ReliefBox,
    ReliefBrick,
    Refraction,
}

pub(crate) const SCENES: [Scene; 5] = [
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

pub(crate) fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

pub(crate) fn named(name: &str) -> Option<Name> {
    Some(Name(name.to_owned()))
}

pub(crate) fn at(translation: Vec3) -> Option<Transform> {
    Some(Transform {
        translation,
        ..Transform::default()
    })
}

/// `sprites.ron`'s settings and sprite sheets (and the brick tile's images) with none of its
/// entities; in their place the backdrop: a ground plane, a wall behind the sprites (unless
/// `!wall`) and two suns (one from +X +Y +Z, as the paper's fixed light; one where its
/// turning light starts).
pub(crate) fn backdrop(wall: bool) -> LoadedLevel {
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
pub(crate) fn sprite(kind: Kind) -> Sprite {
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
pub(crate) fn scene_level(scene: &Scene) -> LoadedLevel {
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
pub(crate) fn case_level(name: &str) -> (LoadedLevel, usize) {
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
pub(crate) fn crowd_level(n: usize) -> LoadedLevel {
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
pub(crate) fn brick_images() -> [Image; 3] {
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
