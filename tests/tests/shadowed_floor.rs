//! Issue 17: a flat floor in shadow is shaded like a flat floor in light — one colour per
//! posterization band, no streaks. The grid probe's lit faces are read back and every floor
//! texel well inside the wall's shadow (or well inside the sunlight) is compared; a texel that
//! differs is reported with what the capture stored for it, so a failure says why.

use std::collections::BTreeMap;

use glam::{UVec2, Vec3};
use texel_probes::cube::{Texel, texel_center_direction, world_position};
use texel_render::bvh::BvhTriangle;
use texel_render::input::Camera;
use texel_render::probe_store::{LayeredTexture, SlotTextures};
use texel_render::target::read_texture_layer;
use texel_tests::Harness;

const LEVEL: &str = "tests/data/shadowed_floor.ron";
/// The level's first entity.
const FLOOR_ID: u32 = 1;
const N: u32 = 64;

/// One captured and lit face of a slot, read back.
struct FaceData {
    geo: Vec<[f32; 4]>,
    ids: Vec<u32>,
    albedo: Vec<[u8; 4]>,
    /// The lit colour's RGB as float bits (compared exactly).
    lit: Vec<[u32; 3]>,
}

fn read_face(h: &Harness, slot: &SlotTextures, face: u32) -> FaceData {
    let read =
        |t: &LayeredTexture, bytes| read_texture_layer(&h.ctx, &t.texture, face, bytes).unwrap();
    let geo = read(&slot.geo, 16);
    let ids = read(&slot.ids, 4);
    let albedo = read(&slot.albedo, 4);
    let lit = read(&slot.lit, 16);
    let f32_at = |b: &[u8], i: usize| f32::from_le_bytes([b[i], b[i + 1], b[i + 2], b[i + 3]]);
    FaceData {
        geo: (0..ids.len() / 4)
            .map(|i| [0, 1, 2, 3].map(|k| f32_at(&geo, 16 * i + 4 * k)))
            .collect(),
        ids: ids
            .chunks_exact(4)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect(),
        albedo: albedo
            .chunks_exact(4)
            .map(|b| [b[0], b[1], b[2], b[3]])
            .collect(),
        lit: (0..lit.len() / 16)
            .map(|i| [0, 1, 2].map(|k| f32_at(&lit, 16 * i + 4 * k).to_bits()))
            .collect(),
    }
}

/// Colour → (texel count, one example texel's description).
type Census = BTreeMap<[u32; 3], (usize, String)>;

fn describe(census: &Census) -> String {
    census
        .iter()
        .map(|(c, (count, example))| {
            format!(
                "\n    {:.4?} × {count} (e.g. {example})",
                c.map(f32::from_bits)
            )
        })
        .collect()
}

#[test]
fn a_flat_floor_in_shadow_has_one_colour_per_band_from_every_camera() {
    let size = UVec2::new(192, 108);
    let Some(mut h) = Harness::new(LEVEL, size, N) else {
        return;
    };
    let scene = h.session.scene().clone();
    let casters: Vec<BvhTriangle> = scene
        .objects
        .iter()
        .filter(|o| o.material.casts_shadows)
        .flat_map(|o| {
            o.mesh.indices.chunks_exact(3).map(|t| {
                let w = [0, 1, 2].map(|k| {
                    o.transform
                        .transform_point3(o.mesh.positions[t[k] as usize])
                });
                BvhTriangle::new(0, &w)
            })
        })
        .collect();
    let to_sun = -scene.suns[0].direction.normalize();
    // Whether the floor point under texel `t` sees the sun (the CPU's answer, from a point
    // clearly above the floor, so no grazing subtlety decides it).
    let sunlit = |p: Vec3| {
        !casters
            .iter()
            .any(|t| t.hit(p + Vec3::Y * 0.05, to_sun, 1e4))
    };

    // Several heights and headings, all within sight of the wall's long shadow (it falls
    // toward +X, from x = -3.75 to about x = 8).
    let cameras = [
        Camera::from_yaw_pitch(Vec3::new(2.0, 0.6, 6.0), 0.0, -5.0),
        Camera::from_yaw_pitch(Vec3::new(6.3, 1.6, -3.2), 75.0, -15.0),
        Camera::from_yaw_pitch(Vec3::new(7.5, 3.5, 9.0), 160.0, -25.0),
        Camera::from_yaw_pitch(Vec3::new(9.6, 7.0, 2.4), 250.0, -35.0),
        Camera::from_yaw_pitch(Vec3::new(0.2, 1.2, -12.7), 300.0, -10.0),
    ];
    let mut failures = Vec::new();
    for camera in cameras {
        let mut input = None;
        for _ in 0..8 {
            input = Some(h.frame(camera, 1.0 / 30.0).0);
        }
        let input = input.expect("frames");
        let slot = h.renderer().probes().slot(input.grid.slot);
        let origin = input.grid.origin;
        let (mut shadowed, mut lit) = (Census::new(), Census::new());
        for face in input.grid.valid.iter() {
            let data = read_face(&h, slot, face.index() as u32);
            let at = |x: u32, y: u32| (y * N + x) as usize;
            // Floor points (and whether each sees the sun) on this face.
            let point = |x: u32, y: u32| {
                let r = texel_center_direction(Texel { face, x, y }, N);
                world_position(origin, r, data.geo[at(x, y)][3])
            };
            for y in 1..N - 1 {
                for x in 1..N - 1 {
                    // Only texels inside the floor (all 8 neighbours floor too: an outline
                    // where the floor meets the wall is geometry's edge), away from the shadow's
                    // edge (every neighbour on the same side of it).
                    let block =
                        (y - 1..=y + 1).flat_map(|yy| (x - 1..=x + 1).map(move |xx| (xx, yy)));
                    if block
                        .clone()
                        .any(|(xx, yy)| data.ids[at(xx, yy)] != FLOOR_ID)
                    {
                        continue;
                    }
                    let sides: Vec<bool> = block.map(|(xx, yy)| sunlit(point(xx, yy))).collect();
                    if sides.iter().any(|s| *s != sides[4]) {
                        continue;
                    }
                    let i = at(x, y);
                    let example = format!(
                        "face {face:?} texel ({x}, {y}) at {:.2}, albedo bytes {:?}",
                        point(x, y),
                        data.albedo[i]
                    );
                    let census = if sides[4] { &mut lit } else { &mut shadowed };
                    census.entry(data.lit[i]).or_insert((0, example)).0 += 1;
                }
            }
        }
        let count = |c: &Census| c.values().map(|v| v.0).sum::<usize>();
        println!(
            "camera {:.1} heading {:.2}: shadowed floor texels {} in {} colours, sunlit {} in {} colours",
            camera.position,
            camera.forward,
            count(&shadowed),
            shadowed.len(),
            count(&lit),
            lit.len()
        );
        assert!(
            count(&shadowed) > 200 && count(&lit) > 200,
            "the camera at {} sees too little floor",
            camera.position
        );
        if shadowed.len() != 1 || lit.len() != 1 {
            failures.push(format!(
                "camera at {:.2}, grid probe at {origin}:\n  shadowed floor: {}{}\n  sunlit floor: {}{}",
                camera.position,
                shadowed.len(),
                describe(&shadowed),
                lit.len(),
                describe(&lit)
            ));
        }
    }
    assert!(
        failures.is_empty(),
        "a flat floor shows more than one colour per lighting:\n{}",
        failures.join("\n")
    );
}
