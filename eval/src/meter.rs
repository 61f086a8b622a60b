//! Accumulates the metrics of one run frame by frame ([`PathMeter`]), keeping only the
//! previous frame, and reduces them to the per-path scores of a report ([`Scores`]).

use serde::{Deserialize, Serialize};
use texel_render::input::Camera;

use crate::metrics::{
    Coverage, FlickerCount, FrameView, MetricError, MetricParams, Reference, Summary, coverage,
    flicker,
};

/// One frame of a method with its reference, owned.
#[derive(Debug, Clone)]
pub struct OwnedFrame {
    /// The camera of the frame.
    pub camera: Camera,
    /// The reference G-buffer at that camera.
    pub reference: Reference,
    /// The method's colour, RGBA8 sRGB.
    pub colour: Vec<u8>,
    /// The method's object id per pixel.
    pub ids: Vec<u32>,
    /// Per pixel, whether it came from the eye probe (splat methods).
    pub from_eye: Option<Vec<bool>>,
    /// The truth's colour at this camera, when a truth was rendered ([`FrameView::truth`]).
    pub truth: Option<Vec<u8>>,
}

impl OwnedFrame {
    /// A borrowed view for the metric functions.
    pub fn view(&self) -> FrameView<'_> {
        FrameView {
            camera: self.camera,
            reference: &self.reference,
            colour: &self.colour,
            ids: &self.ids,
            from_eye: self.from_eye.as_deref(),
            truth: self.truth.as_deref(),
        }
    }
}

/// Per-path scores.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Scores {
    /// Per-frame shimmer (the flicker fraction where the truth held), summarised over
    /// frames 1.. (frame 0 has no predecessor).
    pub shimmer: Summary,
    /// Shimmer of each frame after the first.
    pub shimmer_per_frame: Vec<f64>,
    /// Per-frame flicker fraction of every tested pixel, the truth's own changes included
    /// (the shimmer before intended change was left out).
    pub shimmer_all: Summary,
    /// Mean over frames of the fraction of pixels whose object id differs from the reference.
    pub coverage_error: f64,
    /// Mean over frames of the fraction of pixels where the reference shows geometry and the
    /// method shows none.
    pub hole_rate: f64,
    /// Mean over frames of the fraction of pixels taken from the eye probe (None: the method
    /// has no probes).
    pub eye_fraction: Option<f64>,
    /// Of all flickering pixels of the run, the share taken from the eye probe (None: no
    /// probes, or nothing flickered).
    pub eye_flicker_share: Option<f64>,
    /// Mean over frames of the flicker fraction of moving objects' pixels, followed with
    /// their objects (None: no moving object was seen).
    pub moving_shimmer: Option<f64>,
    /// The same over the still world's pixels of the same frames (None: nothing moved).
    pub still_shimmer: Option<f64>,
    /// Mean over frames of the flicker fraction of sprites' pixels (None: no sprite seen).
    pub sprite_shimmer: Option<f64>,
}

/// Frame-by-frame accumulator of a run's metrics.
#[derive(Debug, Default)]
pub struct PathMeter {
    params: MetricParams,
    prev: Option<OwnedFrame>,
    flicker: Vec<FlickerCount>,
    coverage: Vec<Coverage>,
    has_eye: bool,
}

impl PathMeter {
    /// An empty meter with `params`.
    pub fn new(params: MetricParams) -> Self {
        PathMeter {
            params,
            ..Default::default()
        }
    }

    /// Adds the next frame of the run.
    pub fn push(&mut self, frame: OwnedFrame) -> Result<(), MetricError> {
        let cur = frame.view();
        self.coverage.push(coverage(&cur)?);
        self.has_eye |= frame.from_eye.is_some();
        if let Some(prev) = &self.prev {
            self.flicker
                .push(flicker(&prev.view(), &cur, &self.params)?);
        }
        self.prev = Some(frame);
        Ok(())
    }

    /// Flicker counts so far, one per frame after the first.
    pub fn flicker_counts(&self) -> &[FlickerCount] {
        &self.flicker
    }

    /// The scores of the frames pushed so far.
    pub fn scores(&self) -> Scores {
        let per_frame: Vec<f64> = self.flicker.iter().map(FlickerCount::fraction).collect();
        let mean = |f: fn(&Coverage) -> f64| {
            if self.coverage.is_empty() {
                0.0
            } else {
                self.coverage.iter().map(f).sum::<f64>() / self.coverage.len() as f64
            }
        };
        let flicker: u64 = self.flicker.iter().map(|c| c.flicker).sum();
        let flicker_eye: u64 = self.flicker.iter().map(|c| c.flicker_eye).sum();
        Scores {
            shimmer: Summary::of(&per_frame),
            shimmer_per_frame: per_frame,
            shimmer_all: Summary::of(
                &(self.flicker.iter())
                    .map(FlickerCount::all_fraction)
                    .collect::<Vec<_>>(),
            ),
            coverage_error: mean(|c| c.error),
            hole_rate: mean(|c| c.holes),
            eye_fraction: self.has_eye.then(|| mean(|c| c.eye)),
            eye_flicker_share: (self.has_eye && flicker > 0)
                .then(|| flicker_eye as f64 / flicker as f64),
            moving_shimmer: mean_of(
                self.flicker
                    .iter()
                    .filter_map(FlickerCount::moving_fraction),
            ),
            still_shimmer: self
                .flicker
                .iter()
                .any(|c| c.tested_moving > 0)
                .then(|| mean_of(self.flicker.iter().filter_map(FlickerCount::still_fraction)))
                .flatten(),
            sprite_shimmer: mean_of(
                self.flicker
                    .iter()
                    .filter_map(FlickerCount::sprite_fraction),
            ),
        }
    }
}

/// The mean of `values`, `None` when there are none.
fn mean_of(values: impl Iterator<Item = f64>) -> Option<f64> {
    let (sum, n) = values.fold((0.0, 0usize), |(s, n), v| (s + v, n + 1));
    (n > 0).then(|| sum / n as f64)
}
