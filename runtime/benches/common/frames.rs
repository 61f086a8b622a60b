//! One bench case that times a frame (`frame(i)` draws frame number `i`, counting on from
//! where the last call stopped): criterion's samples, their median kept.

use std::time::Instant;

use criterion::BenchmarkGroup;
use criterion::measurement::WallTime;

use super::results::Samples;

/// Whether criterion measures (`cargo bench`), rather than running each case once to see it
/// works (`cargo test --benches`).
pub fn measuring() -> bool {
    std::env::args().any(|a| a == "--bench")
}

/// The frame size of a bench: 1280×720 when measuring, `small` when only run once.
pub fn frame_size(small: glam::UVec2) -> glam::UVec2 {
    if measuring() {
        glam::UVec2::new(1280, 720)
    } else {
        small
    }
}

/// Benches `label` in `group` by calling `frame(i)` for i = 0, 1, …; returns the median
/// milliseconds a frame over the last `samples` samples.
pub fn median_frame_ms(
    group: &mut BenchmarkGroup<'_, WallTime>,
    label: &str,
    samples: usize,
    mut frame: impl FnMut(u32),
) -> f64 {
    let mut i = 0;
    let mut taken = Samples::default();
    group.bench_function(label, |b| {
        b.iter_custom(|iters| {
            let t = Instant::now();
            for _ in 0..iters {
                frame(i);
                i += 1;
            }
            let elapsed = t.elapsed();
            taken.push(elapsed, iters);
            elapsed
        })
    });
    taken.median_ms(samples)
}
