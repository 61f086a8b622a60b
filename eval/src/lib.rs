//! `texel_eval` measures Texel against the methods it replaces: camera paths, exact
//! stability and accuracy metrics from reference G-buffers, and the report and charts that
//! put frame cost against image stability. It exists so that every claim the product makes
//! about speed or stability comes from a command anyone can re-run.
//!
//! Modules: [`metrics`] (shimmer, coverage error, hole rate: pure CPU functions),
//! [`reference`](mod@reference) (a CPU reference G-buffer), [`meter`] (per-run accumulation), [`runner`]
//! (one method along one path, GPU-independent), [`gpu`] (the real sources), [`suite`]
//! (levels × paths × methods × resolutions), [`report`] (`report.json` and its table),
//! [`chart`] (the charts), [`tables`] (the docs' results tables, from reports), [`stamp`]
//! (when, which commit, which machine), [`compare`] (the methods side by side as an animated GIF),
//! [`survey`] (random walks through a level, for views nobody tuned for), [`scale`] and
//! [`scale_chart`] (frame cost and memory against level size).

pub mod chart;
pub mod colour;
pub mod compare;
pub mod crossings;
pub mod gpu;
pub mod meter;
pub mod metrics;
pub mod reference;
pub mod report;
pub mod runner;
pub mod scale;
pub mod scale_chart;
pub use texel_runtime::stamp;
pub mod suite;
pub mod survey;
pub mod tables;
