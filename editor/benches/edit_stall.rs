//! The editor's edit stall: the first render after an edit (a stone moved, taken in alone as
//! a gizmo step is: `Session::update_entities`, the faces that may see it captured again,
//! then the frame) at the viewport's still and moving resolutions for a 1280×800 window,
//! then the frame that refines it at the still resolution, and the first frame after its
//! colour changed (the inspector). The same on a generated town
//! (`texel-run gen`'s generator) of 10,000 entities, a box beside its street moved (issue 58's
//! target: a drag step to the next finished frame within 100 ms at the moving resolution).
//! On both, the first frame after that entity is deleted or the delete undone, in turn
//! (`Session::edit_rows`: a delete blanked in place, its undo an upload).
//!
//! `cargo bench -p texel_editor --bench edit_stall` measures; `cargo test --benches` runs each
//! benchmark once as a smoke test. Without a GPU adapter it fails like the GPU tests, unless
//! `TEXEL_ALLOW_NO_GPU` is set, when it measures nothing (and says so).

use std::hint::black_box;
use std::time::{Duration, Instant};

use std::path::Path;

use criterion::{Criterion, criterion_group, criterion_main};
use glam::{UVec2, Vec2, Vec3};
use texel_editor::camera::EditorCamera;
use texel_editor::viewport::gpu::GpuView;
use texel_editor::viewport::{SCALE_MOVING, SCALE_STILL};
use texel_render::context::{GpuContext, test_context};
use texel_render::input::Schedule;
use texel_runtime::frame_plan::RowEdit;
use texel_runtime::generate::{GenOptions, STREET_HALF_WIDTH, generate, side};
use texel_runtime::load::{LoadedLevel, load_level};
use texel_scene::components::Geometry;

#[path = "../tests/support/mod.rs"]
mod support;

/// What one benchmark renders with.
struct Bench {
    ctx: GpuContext,
    gpu: GpuView,
    level: LoadedLevel,
    revision: u64,
    /// The row the edits move, and where the camera looks.
    row: usize,
    camera: EditorCamera,
    /// The row deleted, while it is ([`Bench::delete_or_restore`]).
    deleted: Option<texel_scene::EntityRow>,
}

impl Bench {
    /// Moves a stone (as a gizmo step does): a new document revision, that entity alone.
    fn edit(&mut self) {
        self.revision += 1;
        self.gpu.use_entities(Some(vec![self.row]));
        let scene = &mut self.level.scene;
        let e = scene.entities().nth(self.row).expect("the moved entity");
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

    /// Changes the stone's colour (as the inspector does): its material alone.
    fn recolour(&mut self) {
        self.revision += 1;
        self.gpu.use_entities(Some(vec![self.row]));
        let scene = &mut self.level.scene;
        let e = scene
            .entities()
            .nth(self.row)
            .expect("the recoloured entity");
        let mut row = scene.row(e).expect("row");
        let mut m = row.material.unwrap_or_default();
        m.albedo.x = if self.revision.is_multiple_of(2) {
            0.8
        } else {
            0.3
        };
        row.material = Some(m);
        scene.set_row(e, row).expect("set row");
    }

    /// Deletes the edited entity, or puts it back when it is deleted (an undo): a new
    /// document revision, that row's removal or insertion alone.
    fn delete_or_restore(&mut self) {
        self.revision += 1;
        let scene = &mut self.level.scene;
        let edit = match self.deleted.take() {
            Some(row) => {
                scene.spawn_at(self.row, row);
                RowEdit::Insert(self.row)
            }
            None => {
                let e = scene.entities().nth(self.row).expect("the deleted entity");
                self.deleted = scene.despawn(e);
                RowEdit::Remove(self.row)
            }
        };
        self.gpu.use_rows(Some(vec![edit]));
    }

    /// Renders the current revision at `size` and waits for the GPU.
    fn render(&mut self, size: UVec2) {
        let camera = self.camera.camera();
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
        row: 1,
        camera: support::camera(),
        deleted: None,
    };
    stall_cases(c, "edit_stall", &mut b);
    // A town of 10,000 when measuring; of 100 when each case only runs once.
    let measuring = std::env::args().any(|a| a == "--bench");
    let dir = tempfile::tempdir().expect("a temporary folder");
    let (level, row, camera) = town(dir.path(), if measuring { 10_000 } else { 100 });
    b.level = level;
    b.row = row;
    b.camera = camera;
    // Opened as the editor opens a level: taken in whole, its first frame drawn.
    b.revision += 1;
    b.gpu.use_entities(None);
    let panel = Vec2::new(730.0, 750.0);
    b.render((panel * SCALE_STILL).as_uvec2());
    stall_cases(c, "edit_stall_town", &mut b);
}

/// A generated town of `count` entities (the bundled crate and arch repeated) saved in `dir`
/// and loaded as the editor opens it; the row of the box nearest the street's far end, and
/// a camera on the street looking at it.
fn town(dir: &Path, count: usize) -> (LoadedLevel, usize, EditorCamera) {
    let assets = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/meshes");
    let file = dir.join("town.ron");
    let options = GenOptions {
        count,
        meshes: ["crate.glb", "arch.glb"]
            .map(|m| texel_scene::assets::relative_path(&file, &assets.join(m)))
            .to_vec(),
        ..GenOptions::default()
    };
    generate(&options)
        .expect("a town")
        .save(&file)
        .expect("saved");
    let level = load_level(&file).expect("the town loads");
    let half = side(count, options.density) / 2.0;
    let target = Vec3::new(STREET_HALF_WIDTH + 2.0, 1.0, half - 12.0);
    let scene = &level.scene;
    let row = (scene.entities().enumerate())
        .filter_map(|(i, e)| {
            let r = scene.row(e)?;
            let boxed = matches!(r.geometry, Some(Geometry::Box { .. }));
            let at = r.transform?.translation;
            boxed.then(|| (i, at.distance_squared(target)))
        })
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .expect("a box")
        .0;
    let mut camera = EditorCamera::default();
    camera.focus(target, 8.0);
    (level, row, camera)
}

/// The three cases on `b`'s level, in `group`.
fn stall_cases(c: &mut Criterion, group: &str, b: &mut Bench) {
    // The central panel of a 1280×800 window is about 730×750 points.
    let panel = Vec2::new(730.0, 750.0);
    let still = (panel * SCALE_STILL).as_uvec2();
    let moving = (panel * SCALE_MOVING).as_uvec2();
    let mut group = c.benchmark_group(group);
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
    group.bench_function("first frame after a colour change, moving", |bench| {
        bench.iter(|| {
            b.recolour();
            b.render(moving);
        })
    });
    group.bench_function("first frame after a delete or its undo, moving", |bench| {
        bench.iter(|| {
            b.delete_or_restore();
            b.render(moving);
        })
    });
    if b.deleted.is_some() {
        b.delete_or_restore();
        b.render(moving);
    }
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
