//! The editor's edit stall: the first render after an edit (a stone moved, taken in alone as
//! a gizmo step is: `Session::update_entities`, the faces that may see it captured again,
//! then the frame) at the viewport's still and moving resolutions for a 1280×800 window,
//! then the frame that refines it at the still resolution.
//!
//! `cargo bench -p texel_editor --bench edit_stall` measures; `cargo test --benches` runs each
//! benchmark once as a smoke test. Without a GPU adapter it fails like the GPU tests, unless
//! `TEXEL_ALLOW_NO_GPU` is set, when it measures nothing (and says so).

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{Criterion, criterion_group, criterion_main};
use glam::{UVec2, Vec2};
use texel_editor::viewport::gpu::GpuView;
use texel_editor::viewport::{SCALE_MOVING, SCALE_STILL};
use texel_render::context::{GpuContext, test_context};
use texel_render::input::Schedule;
use texel_runtime::load::LoadedLevel;

#[path = "../tests/support/mod.rs"]
mod support;

/// What one benchmark renders with.
struct Bench {
    ctx: GpuContext,
    gpu: GpuView,
    level: LoadedLevel,
    revision: u64,
}

impl Bench {
    /// Moves a stone (as a gizmo step does): a new document revision, that entity alone.
    fn edit(&mut self) {
        self.revision += 1;
        self.gpu.use_entities(Some(vec![1]));
        let scene = &mut self.level.scene;
        let e = scene.entities().nth(1).expect("a stone");
        let mut row = scene.row(e).expect("row");
        let mut t = row.transform.unwrap_or_default();
        t.translation.x += if self.revision.is_multiple_of(2) {
            0.1
        } else {
            -0.1
        };
        row.transform = Some(t);
        scene.set_row(e, row).expect("set row");
    }

    /// Renders the current revision at `size` and waits for the GPU.
    fn render(&mut self, size: UVec2) {
        let camera = support::camera().camera();
        let id = self
            .gpu
            .render(
                &self.level,
                self.revision,
                camera,
                size,
                Schedule::Ours,
                0.016,
            )
            .expect("render");
        self.ctx.wait_idle().expect("idle");
        assert_eq!(self.gpu.report.size, size);
        black_box(id);
    }
}

fn edit_stall(c: &mut Criterion) {
    let Some(ctx) = test_context() else {
        eprintln!("edit_stall: no GPU adapter, nothing measured");
        return;
    };
    let gpu = support::gpu_view(&ctx);
    let mut b = Bench {
        ctx,
        gpu,
        level: support::stone_circle(),
        revision: 0,
    };
    // The central panel of a 1280×800 window is about 730×750 points.
    let panel = Vec2::new(730.0, 750.0);
    let still = (panel * SCALE_STILL).as_uvec2();
    let moving = (panel * SCALE_MOVING).as_uvec2();
    let mut group = c.benchmark_group("edit_stall");
    group.sample_size(10);
    group.bench_function("first frame after an edit, still", |bench| {
        bench.iter(|| {
            b.edit();
            b.render(still);
        })
    });
    group.bench_function("first frame after an edit, moving", |bench| {
        bench.iter(|| {
            b.edit();
            b.render(moving);
        })
    });
    // The viewport renders an edit's first frame at the moving resolution, then refines.
    group.bench_function("refine at still after a moving first frame", |bench| {
        bench.iter_custom(|iters| {
            let mut spent = Duration::ZERO;
            for _ in 0..iters {
                b.edit();
                b.render(moving);
                let t = Instant::now();
                b.render(still);
                spent += t.elapsed();
            }
            spent
        })
    });
    group.finish();
}

criterion_group!(benches, edit_stall);
criterion_main!(benches);
