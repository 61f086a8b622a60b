//! A glTF mesh's thumbnail, drawn on the thumbnail thread by a small software rasterizer (no
//! GPU, so it never waits on the viewport's device): the mesh seen from above and to the side
//! (a three-quarter view, orthographic, fitted to its bounds), each triangle flat-lit by a
//! fixed light and coloured by its vertices, over a transparent background. Pixel art wants
//! hard edges, so there is no antialiasing.

use glam::{Mat3, Vec3};
use texel_scene::TriMesh;

/// The direction the preview looks along (down and to the side).
const VIEW_YAW_DEGREES: f32 = 35.0;
const VIEW_PITCH_DEGREES: f32 = -30.0;
/// The light (unit, toward it): over the viewer's shoulder.
const TO_LIGHT: Vec3 = Vec3::new(0.45, 0.8, 0.4);
/// Light everywhere (so faces turned away still show).
const AMBIENT: f32 = 0.35;
/// The share of the thumbnail's side the mesh's extent fills.
const FILL: f32 = 0.9;

/// `mesh` drawn into a `size`×`size` RGBA8 picture; `None` when it has no triangle or no
/// finite extent.
pub fn draw(mesh: &TriMesh, size: u32) -> Option<Vec<u8>> {
    let size = size.max(1);
    let turn = Mat3::from_rotation_x(-VIEW_PITCH_DEGREES.to_radians())
        * Mat3::from_rotation_y(-VIEW_YAW_DEGREES.to_radians());
    // View space: x right, y up, z toward the viewer.
    let view: Vec<Vec3> = mesh.positions.iter().map(|&p| turn * p).collect();
    let (lo, hi) = view.iter().filter(|p| p.is_finite()).fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    );
    let extent = (hi.x - lo.x).max(hi.y - lo.y);
    if mesh.indices.len() < 3 || !extent.is_finite() || !lo.is_finite() {
        return None;
    }
    let scale = FILL * size as f32 / extent.max(1e-6);
    let centre = (lo + hi) * 0.5;
    let half = size as f32 * 0.5;
    // Pixel coordinates (y down) and depth (larger is nearer).
    let screen = |p: Vec3| {
        Vec3::new(
            (p.x - centre.x) * scale + half,
            half - (p.y - centre.y) * scale,
            p.z,
        )
    };
    let light = (turn * TO_LIGHT).normalize();
    let n = size as usize;
    let mut depth = vec![f32::NEG_INFINITY; n * n];
    let mut pixels = vec![0u8; n * n * 4];
    for t in mesh.indices.chunks_exact(3) {
        let idx = [t[0] as usize, t[1] as usize, t[2] as usize];
        if idx.iter().any(|&i| i >= view.len()) {
            continue;
        }
        let [a, b, c] = idx.map(|i| view[i]);
        if !(a.is_finite() && b.is_finite() && c.is_finite()) {
            continue;
        }
        let normal = (b - a).cross(c - a).normalize_or_zero();
        // Both sides lit alike (meshes are not always closed or wound one way).
        let lit = AMBIENT + (1.0 - AMBIENT) * normal.dot(light).abs();
        let colour = idx
            .iter()
            .map(|&i| mesh.colors.get(i).copied().unwrap_or([1.0; 4]))
            .fold([0.0f32; 4], |s, c| {
                [s[0] + c[0], s[1] + c[1], s[2] + c[2], s[3] + c[3]]
            })
            .map(|v| v / 3.0);
        let rgba = [
            to_srgb8(colour[0] * lit),
            to_srgb8(colour[1] * lit),
            to_srgb8(colour[2] * lit),
            255,
        ];
        fill(
            [screen(a), screen(b), screen(c)],
            n,
            &mut depth,
            &mut pixels,
            rgba,
        );
    }
    Some(pixels)
}

/// Fills the triangle `v` (pixel x, y and depth) where it is nearer than `depth`.
fn fill(v: [Vec3; 3], n: usize, depth: &mut [f32], pixels: &mut [u8], rgba: [u8; 4]) {
    let area = edge(v[0], v[1], v[2]);
    if area.abs() < 1e-9 {
        return;
    }
    let min_x = v
        .iter()
        .map(|p| p.x)
        .fold(f32::INFINITY, f32::min)
        .floor()
        .max(0.0) as usize;
    let max_x = v
        .iter()
        .map(|p| p.x)
        .fold(f32::NEG_INFINITY, f32::max)
        .ceil();
    let min_y = v
        .iter()
        .map(|p| p.y)
        .fold(f32::INFINITY, f32::min)
        .floor()
        .max(0.0) as usize;
    let max_y = v
        .iter()
        .map(|p| p.y)
        .fold(f32::NEG_INFINITY, f32::max)
        .ceil();
    let max_x = (max_x.max(0.0) as usize).min(n);
    let max_y = (max_y.max(0.0) as usize).min(n);
    for y in min_y..max_y {
        for x in min_x..max_x {
            let p = Vec3::new(x as f32 + 0.5, y as f32 + 0.5, 0.0);
            let w = [
                edge(v[1], v[2], p),
                edge(v[2], v[0], p),
                edge(v[0], v[1], p),
            ]
            .map(|e| e / area);
            if w.iter().any(|&e| e < 0.0) {
                continue;
            }
            let z = w[0] * v[0].z + w[1] * v[1].z + w[2] * v[2].z;
            let i = y * n + x;
            if z > depth[i] {
                depth[i] = z;
                pixels[4 * i..4 * i + 4].copy_from_slice(&rgba);
            }
        }
    }
}

/// Twice the signed area of (a, b, p) in x, y.
fn edge(a: Vec3, b: Vec3, p: Vec3) -> f32 {
    (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x)
}

/// A linear colour channel as an sRGB byte.
fn to_srgb8(v: f32) -> u8 {
    let v = v.clamp(0.0, 1.0);
    let s = if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0).round() as u8
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_box_fills_the_middle_leaves_the_corners_clear_and_shows_three_shades() {
        let mesh = texel_scene::primitives::box_mesh(Vec3::new(1.0, 1.0, 1.0));
        let px = draw(&mesh, 48).expect("a picture");
        assert_eq!(px.len(), 48 * 48 * 4);
        let at = |x: usize, y: usize| &px[4 * (y * 48 + x)..4 * (y * 48 + x) + 4];
        assert_eq!(at(24, 24)[3], 255, "the middle is the box");
        assert_eq!(at(0, 0)[3], 0, "a corner is clear");
        let mut shades: Vec<[u8; 4]> = px
            .chunks(4)
            .filter(|p| p[3] == 255)
            .map(|p| [p[0], p[1], p[2], p[3]])
            .collect();
        shades.sort_unstable();
        shades.dedup();
        assert_eq!(
            shades.len(),
            3,
            "three faces seen, each its own shade: {shades:?}"
        );
    }

    #[test]
    fn nothing_to_draw_is_none_and_a_point_that_is_not_a_number_is_left_out() {
        let mut mesh = texel_scene::primitives::box_mesh(Vec3::ONE);
        mesh.indices.clear();
        assert!(draw(&mesh, 48).is_none());
        let mut mesh = texel_scene::primitives::box_mesh(Vec3::ONE);
        mesh.positions
            .iter_mut()
            .for_each(|p| *p = Vec3::splat(f32::NAN));
        assert!(draw(&mesh, 48).is_none());
        let mut mesh = texel_scene::primitives::box_mesh(Vec3::ONE);
        mesh.positions[0] = Vec3::splat(f32::NAN);
        let px = draw(&mesh, 48).expect("the rest is drawn");
        assert!(px.chunks(4).filter(|p| p[3] == 255).count() > 48 * 48 / 4);
    }
}
