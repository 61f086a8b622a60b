//! Cross-crate integration tests for Texel live in this package's `tests/` folder; this
//! library holds what they share: repository paths, golden-image comparison, and a small
//! harness that plays a level through the runtime's frame driver on the GPU.

use std::path::{Path, PathBuf};

use glam::UVec2;
use texel_render::context::GpuContext;
use texel_render::frame::Renderer;
use texel_render::input::{Camera, FrameInput, Schedule};
use texel_render::stats::FrameStats;
use texel_runtime::load::load_level;
use texel_runtime::session::{FrameRequest, Session, set_face_resolution};

/// The repository root (the folder that holds `assets/` and `shaders/`).
pub fn repo_root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .map(PathBuf::from)
        .unwrap_or_default()
}

/// Compares an RGBA8 image with `tests/golden/<name>.png`.
///
/// Pixel art is flat colour, so the comparison is near-exact: a pixel differs if any channel
/// is off by more than 2, and at most `max_diff_fraction` of the pixels may differ. A missing
/// reference fails (set `TEXEL_UPDATE_GOLDEN=1` to write it); a failure writes
/// `<name>_actual.png` and `<name>_diff.png` beside the reference (ignored by git).
pub fn check_golden(name: &str, pixels: &[u8], size: UVec2, max_diff_fraction: f64) {
    let dir = repo_root().join("tests/golden");
    let reference = dir.join(format!("{name}.png"));
    let save = |path: &Path, px: &[u8]| {
        image::save_buffer(path, px, size.x, size.y, image::ColorType::Rgba8)
            .unwrap_or_else(|e| panic!("writing {}: {e}", path.display()))
    };
    if std::env::var_os("TEXEL_UPDATE_GOLDEN").is_some() {
        std::fs::create_dir_all(&dir).expect("tests/golden");
        save(&reference, pixels);
        return;
    }
    let Ok(golden) = image::open(&reference) else {
        panic!(
            "missing golden image {}; run with TEXEL_UPDATE_GOLDEN=1 to create it",
            reference.display()
        );
    };
    let golden = golden.to_rgba8();
    assert_eq!(
        (golden.width(), golden.height()),
        (size.x, size.y),
        "{name}: size differs from the golden image"
    );
    let mut diff = vec![0u8; pixels.len()];
    let mut differing = 0usize;
    for (i, (a, b)) in pixels.chunks(4).zip(golden.as_raw().chunks(4)).enumerate() {
        let off = a.iter().zip(b).take(3).any(|(x, y)| x.abs_diff(*y) > 2);
        if off {
            differing += 1;
            diff[i * 4..i * 4 + 4].copy_from_slice(&[255, 0, 255, 255]);
        } else {
            diff[i * 4..i * 4 + 4].copy_from_slice(&[a[0] / 3, a[1] / 3, a[2] / 3, 255]);
        }
    }
    let fraction = differing as f64 / (size.x * size.y) as f64;
    if fraction > max_diff_fraction {
        save(&dir.join(format!("{name}_actual.png")), pixels);
        save(&dir.join(format!("{name}_diff.png")), &diff);
        panic!(
            "{name}: {differing} pixels ({:.3}%) differ from {} (allowed {:.3}%); see {name}_actual.png and {name}_diff.png",
            fraction * 100.0,
            reference.display(),
            max_diff_fraction * 100.0
        );
    }
}

/// A level played through a runtime session on a headless GPU.
pub struct Harness {
    /// The GPU.
    pub ctx: GpuContext,
    /// The session (frame driver and renderer).
    pub session: Session,
    size: UVec2,
}

impl Harness {
    /// Loads `level` (relative to the repository) for an output of `size` with faces of
    /// `face_res` texels; `None` only when there is no GPU and `TEXEL_ALLOW_NO_GPU` is set.
    pub fn new(level: &str, size: UVec2, face_res: u32) -> Option<Harness> {
        let ctx = texel_render::context::test_context()?;
        let mut loaded = load_level(&repo_root().join(level)).expect("level loads");
        set_face_resolution(&mut loaded, face_res).expect("a valid face resolution");
        let session = Session::headless(&ctx, &loaded, size, 60f32.to_radians()).expect("session");
        Some(Harness { ctx, session, size })
    }

    /// The renderer.
    pub fn renderer(&self) -> &Renderer {
        self.session.renderer()
    }

    /// Plans and renders one frame of our schedule; returns its input, stats and RGBA8
    /// pixels.
    pub fn frame(&mut self, camera: Camera, dt: f32) -> (FrameInput, FrameStats, Vec<u8>) {
        self.frame_with(camera, dt, Schedule::Ours)
    }

    /// Renders eight frames from `camera` (enough for the grid probe to be complete at the
    /// test sizes); returns the last image and how many faces were captured on the way.
    pub fn settle(&mut self, camera: Camera) -> (Vec<u8>, u32) {
        let (mut px, mut faces) = (Vec::new(), 0);
        for _ in 0..8 {
            let (_, stats, p) = self.frame(camera, 1.0 / 30.0);
            faces += stats.counters.faces_captured;
            px = p;
        }
        (px, faces)
    }

    /// Settles at `camera`, renders one more frame and reads back its grid probe's six lit
    /// faces: the frame's input, the face resolution, the faces (sRGB8 RGBA, rows top down).
    pub fn grid_lit_faces(&mut self, camera: Camera) -> (FrameInput, u32, Vec<Vec<u8>>) {
        self.settle(camera);
        let input = self.frame(camera, 1.0 / 30.0).0;
        let (n, faces) = self
            .renderer()
            .read_lit_faces(&self.ctx, input.grid.slot)
            .expect("lit faces read back");
        (input, n, faces)
    }

    /// Captures the grid probe at `home`, leaves for each of `away` (long enough that both
    /// stable slots hold other probes), comes back to `back` in the same cell, and asserts
    /// the probe was captured again and that `faces` of it are lit texel for texel as before:
    /// nothing a capture stores may depend on where the camera was. Returns the number of
    /// distinct colours those faces hold (for the caller to check there was something to
    /// compare).
    pub fn assert_recaptured_identically(
        &mut self,
        home: Camera,
        away: &[Camera],
        back: Camera,
        faces: &[usize],
    ) -> usize {
        let (first, n, before) = self.grid_lit_faces(home);
        for &c in away {
            self.settle(c);
        }
        let (_, recaptured) = self.settle(back);
        assert!(
            recaptured >= 6,
            "the probe was captured again ({recaptured} faces)"
        );
        let (again, _, after) = self.grid_lit_faces(back);
        assert_eq!(
            again.grid.origin, first.grid.origin,
            "back in the same cell"
        );
        let mut colours = std::collections::HashSet::new();
        for &f in faces {
            let (a, b) = (&before[f], &after[f]);
            let differ = (a.chunks_exact(4).zip(b.chunks_exact(4)))
                .filter(|(x, y)| x != y)
                .count();
            assert_eq!(
                differ,
                0,
                "face {f}: {differ} of {} texels lit differently",
                n * n
            );
            colours.extend(a.chunks_exact(4).map(|c| [c[0], c[1], c[2]]));
        }
        colours.len()
    }

    /// [`Harness::frame`] with `schedule`.
    pub fn frame_with(
        &mut self,
        camera: Camera,
        dt: f32,
        schedule: Schedule,
    ) -> (FrameInput, FrameStats, Vec<u8>) {
        let request = FrameRequest {
            camera,
            dt,
            schedule,
            size: self.size,
        };
        let (frame, px) = (self.session)
            .draw_offscreen(&self.ctx, &request)
            .expect("frame renders");
        (frame.input, frame.stats, px)
    }
}

/// Two runs of one level side by side: `kept` keeps its terrain records and pixels' rays
/// from frame to frame, as a player's renderer does; `fresh` forgets them before every frame.
/// Each frame must draw the same pixels in both: a kept answer the frame should not have
/// used would show.
pub struct KeptAndFresh {
    /// The renderer that keeps what it made.
    pub kept: Harness,
    /// The renderer that makes every record afresh.
    pub fresh: Harness,
}

impl KeptAndFresh {
    /// Loads `level` twice, as [`Harness::new`] does; `None` without a GPU.
    pub fn new(level: &str, size: UVec2, face_res: u32) -> Option<KeptAndFresh> {
        Some(KeptAndFresh {
            kept: Harness::new(level, size, face_res)?,
            fresh: Harness::new(level, size, face_res)?,
        })
    }

    /// Settles both at `camera` ([`Harness::settle`]).
    pub fn settle(&mut self, camera: Camera) {
        self.kept.settle(camera);
        self.fresh.settle(camera);
    }

    /// Renders one frame in both, the fresh one after forgetting its records, and asserts
    /// they draw the same pixels (`what` names the frame in the failure). Returns the kept
    /// frame's input, both frames' stats (kept, fresh) and the kept frame's pixels.
    pub fn frame(
        &mut self,
        camera: Camera,
        dt: f32,
        what: &str,
    ) -> (FrameInput, FrameStats, FrameStats, Vec<u8>) {
        self.fresh.session.renderer_mut().forget_terrain_records();
        let (input, kept, pixels) = self.kept.frame(camera, dt);
        let (_, fresh, fresh_pixels) = self.fresh.frame(camera, dt);
        let differ = (pixels.chunks_exact(4).zip(fresh_pixels.chunks_exact(4)))
            .filter(|(p, q)| p != q)
            .count();
        assert_eq!(
            differ, 0,
            "{what}: {differ} pixels differ from a fresh cache's"
        );
        (input, kept, fresh, pixels)
    }
}
