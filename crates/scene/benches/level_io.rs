//! Load and save of a generated 10,000-entity level (target: each under 100 ms in release).
//!
//! `cargo bench -p texel_scene --bench level_io` measures; `cargo test --benches` runs each
//! benchmark once as a smoke test.

use criterion::{Criterion, criterion_group, criterion_main};
use glam::{Vec2, Vec3};
use std::hint::black_box;
use texel_scene::*;

/// A deterministic level of `n` entities mixing every component kind.
fn generated_level(n: usize) -> Level {
    let entities = (0..n)
        .map(|i| {
            let f = i as f32;
            let t = Transform {
                translation: Vec3::new((f * 0.37).sin() * 90.0, f * 0.001, (f * 0.11).cos() * 90.0),
                rotation: Vec3::new(0.0, (f * 13.7) % 360.0, 0.0),
                scale: Vec3::new(1.0, 1.0 + (i % 7) as f32 * 0.25, 1.0),
            };
            let mut row = EntityRow {
                name: Some(Name(format!("Entity {i}"))),
                transform: Some(t),
                ..EntityRow::default()
            };
            match i % 10 {
                0 => row.point_light = Some(PointLight::default()),
                1 => row.probe_grid_override = Some(ProbeGridOverride::default()),
                _ => {
                    row.geometry = Some(match i % 4 {
                        0 => Geometry::Box {
                            size: Vec3::new(0.8, 2.5, 0.5),
                        },
                        1 => Geometry::Sphere {
                            radius: 0.5,
                            segments: 16,
                        },
                        2 => Geometry::Cylinder {
                            radius: 0.3,
                            height: 2.0,
                            segments: 12,
                        },
                        _ => Geometry::Plane {
                            size: Vec2::new(2.0, 2.0),
                        },
                    });
                    row.material = Some(Material {
                        albedo: Vec3::new(0.5, 0.45 + (i % 5) as f32 * 0.01, 0.4),
                        ..Material::default()
                    });
                }
            }
            row
        })
        .collect();
    Level {
        entities,
        ..Level::default()
    }
}

fn level_io(c: &mut Criterion) {
    let dir = std::env::temp_dir().join(format!("texel-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join("big.ron");
    let level = generated_level(10_000);
    level.save(&path).expect("save");
    let scene = Scene::from_level(&level);

    let mut g = c.benchmark_group("level_10k");
    g.sample_size(20);
    let text = std::fs::read_to_string(&path).expect("read");
    g.bench_function("parse", |b| {
        b.iter(|| black_box(Level::from_ron_str(&text, &path).expect("parse")))
    });
    g.bench_function("spawn", |b| b.iter(|| black_box(Scene::from_level(&level))));
    g.bench_function("load", |b| {
        b.iter(|| black_box(Scene::load(&path).expect("load")))
    });
    g.bench_function("save", |b| {
        b.iter(|| scene.save(black_box(&path)).expect("save"))
    });
    g.finish();
    let _ = std::fs::remove_dir_all(&dir);
}

criterion_group!(benches, level_io);
criterion_main!(benches);
