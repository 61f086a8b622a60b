//! Terrain band transitions on the GPU: between two density bands, the share of fine cells
//! promoted to the coarse band's pixels follows the Bayer ramp (issue 14: within 1/16).

use glam::{UVec2, Vec3};
use texel_render::input::Camera;
use texel_tests::Harness;

/// Fine pixels per world unit.
const DENSITY: f32 = 4.0;
/// Band 0 ends here (by distance, or where a probe of [`TEXEL_BOUND_N`] texels outgrows its
/// pixels); its last half is the transition.
const BAND_DISTANCE: f32 = 12.0;
/// Faces whose texel (2d/n) reaches a fine pixel at [`BAND_DISTANCE`].
const TEXEL_BOUND_N: u32 = (2.0 * BAND_DISTANCE * DENSITY) as u32;
const TRANSITION: f32 = 0.5;

/// A flat terrain whose colour tells a fine (band 0) pixel from a coarser one. The
/// displacement map is 8 pixels wide per tile of 4 fine cells, each column half a fine cell;
/// columns alternate 1, 0. A fine cell's centre falls in an odd column (0: dark), a band-1
/// cell's centre (and any coarser's) in an even one (1: white). The terrain is shifted by an
/// eighth of a cell so no centre lies on a column edge.
fn banded_level(dir: &std::path::Path, band_distance: f32) -> (std::path::PathBuf, f32) {
    let s = 1.0 / DENSITY;
    let shift = s / 8.0;
    let heights = texel_scene::texture::encode_heightmap(4, 4, &[0; 16]);
    std::fs::write(dir.join("flat.png"), heights).unwrap();
    let mut disp = image::GrayImage::new(8, 8);
    for (x, _, p) in disp.enumerate_pixels_mut() {
        p.0 = [if x % 2 == 0 { 255 } else { 0 }];
    }
    disp.save(dir.join("columns.png")).unwrap();
    let text = format!(
        "(version: 3, settings: (sky: (0.5, 0.6, 0.8), ambient: (0.0, 0.0, 0.0), bands: 256, \
         pixel_scale: FaceResolution(128), cell_size: 1.0),\n entities: [(name: \"T\", \
         transform: (translation: ({shift:?}, 0.0, {shift:?}), rotation: (0.0, 0.0, 0.0), \
         scale: (1.0, 1.0, 1.0)), \
         terrain: (size: (200.0, 200.0), heightmap: File(path: \"flat.png\"), max_height: 1.0, \
         gradient: [(at: 0.0, colour: (0.05, 0.05, 0.05)), (at: 0.5, colour: (1.0, 1.0, 1.0))], \
         displacement: (path: \"columns.png\", strength: 1.0, tile_size: {tile:?}), \
         pixel_density: {DENSITY:?}, band_distance: {band_distance:?}, \
         band_transition: {TRANSITION:?}, casts_shadows: false, outlined: false)),\n \
         (directional_light: (direction: (0.0, -1.0, 0.0), colour: (1.0, 1.0, 1.0), \
         intensity: 1.0))])\n",
        tile = 4.0 * s,
    );
    let path = dir.join("banded.ron");
    std::fs::write(&path, text).unwrap();
    (path, shift)
}

/// The share of Bayer thresholds `(k + 0.5) / 16` below `ramp`: the fraction of a band's
/// fine cells a ramp value promotes.
fn bayer_share(ramp: f32) -> f64 {
    (0..16).filter(|k| (*k as f32 + 0.5) / 16.0 < ramp).count() as f64 / 16.0
}

#[test]
fn a_band_transition_promotes_the_bayer_share_of_fine_cells() {
    let dir = tempfile::tempdir().unwrap();
    let (level, shift) = banded_level(dir.path(), BAND_DISTANCE);
    promotes_the_bayer_share(&level, shift, 128);
}

/// Where the probe's texel ends a band (its distance bands lie far beyond the view), the
/// band's end is Bayer-promoted as a distance band's is; it had switched in one step.
#[test]
fn a_texel_bound_band_transition_promotes_the_bayer_share_too() {
    let dir = tempfile::tempdir().unwrap();
    let (level, shift) = banded_level(dir.path(), 1000.0);
    promotes_the_bayer_share(&level, shift, TEXEL_BOUND_N);
}

/// Asserts that `level`'s terrain (shifted by `shift`) drawn with faces of `n` texels holds
/// one pixel per fine cell, band 1 past [`BAND_DISTANCE`] and, inside band 0's transition,
/// the share of promoted cells the Bayer ramp predicts.
fn promotes_the_bayer_share(level: &std::path::Path, shift: f32, n: u32) {
    let size = UVec2::new(128, 72);
    let Some(mut h) = Harness::new(level.to_str().unwrap(), size, n) else {
        return;
    };
    let camera = Camera::from_yaw_pitch(Vec3::new(0.3, 8.3, 0.2), 0.0, -60.0);
    let (input, n, faces) = h.grid_lit_faces(camera);
    let origin = input.grid.origin;
    let corner = -100.0 + shift;
    let s = 1.0 / DENSITY;
    // Per fine cell (band 0, inside the transition): its ramp and whether its texels are
    // white (promoted). Face −Y (index 3) sees the ground within 45° of straight down.
    let face = texel_probes::cube::Face::ALL[3];
    let mut cells: std::collections::HashMap<(i64, i64), (f32, bool)> = Default::default();
    let mut coarse_white = (0, 0);
    for y in 0..n {
        for x in 0..n {
            let texel = texel_probes::cube::Texel { face, x, y };
            let d = texel_probes::cube::texel_center_direction(texel, n);
            let p = origin + d * (origin.y / -d.y);
            let (fx, fz) = ((p.x - corner) / s, (p.z - corner) / s);
            if (fx - fx.round()).abs() < 0.05 || (fz - fz.round()).abs() < 0.05 {
                continue;
            }
            let cell = (fx.floor() as i64, fz.floor() as i64);
            let centre = Vec3::new(
                corner + (cell.0 as f32 + 0.5) * s,
                0.0,
                corner + (cell.1 as f32 + 0.5) * s,
            );
            let dist = centre.distance(origin);
            let i = ((y * n + x) * 4) as usize;
            let white = faces[3][i] > 128;
            if dist > BAND_DISTANCE {
                coarse_white.0 += white as u32;
                coarse_white.1 += 1;
                continue;
            }
            let width = TRANSITION * BAND_DISTANCE;
            let ramp = ((dist - (BAND_DISTANCE - width)) / width).clamp(0.0, 1.0);
            let seen = *cells.entry(cell).or_insert((ramp, white));
            assert_eq!(
                seen.1, white,
                "cell {cell:?} holds both a fine and a coarse pixel"
            );
        }
    }
    assert!(
        coarse_white.1 > 500 && coarse_white.0 == coarse_white.1,
        "every band-1 texel is white: {coarse_white:?}"
    );
    // Buckets of ramp values across the part of the transition the face sees.
    let buckets = [(0.3, 0.5), (0.5, 0.7), (0.7, 0.85), (0.85, 1.0)];
    for (lo, hi) in buckets {
        let inside: Vec<_> = cells
            .values()
            .filter(|(r, _)| *r >= lo && *r < hi)
            .collect();
        assert!(inside.len() > 150, "{} cells in [{lo}, {hi})", inside.len());
        let promoted = inside.iter().filter(|(_, w)| *w).count() as f64 / inside.len() as f64;
        let expected =
            inside.iter().map(|(r, _)| bayer_share(*r)).sum::<f64>() / inside.len() as f64;
        assert!(
            (promoted - expected).abs() <= 1.0 / 16.0,
            "ramp [{lo}, {hi}): {promoted:.3} of {} fine cells promoted, the Bayer ramp says \
             {expected:.3}",
            inside.len()
        );
    }
}
