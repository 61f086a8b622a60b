//! `texel_eval` measures Texel against the methods it replaces: camera paths, exact
//! stability and accuracy metrics from reference G-buffers, and the report and charts that
//! put frame cost against image stability. It exists so that every claim the product makes
//! about speed or stability comes from a command anyone can re-run.
