//! `texel_probes` holds the CPU side of texel splatting: cube-face conventions, grid
//! snapping of probe origins (with probe-grid override volumes), the probe lifecycle and
//! crossfade, and per-frame update plans. It exists so that all of this math can be tested
//! without a GPU and without the scene ECS: it depends on `glam` alone.
