//! Property tests of the invariants texel splatting rests on.

use glam::{IVec3, Vec3};
use proptest::prelude::*;
use texel_probes::bayer::threshold_of;
use texel_probes::cube::{
    Face, QuadHalfSizes, Texel, chebyshev_norm, direction_from_face_uv, face_uv_from_direction,
    quad_corners, texel_center_direction, texel_from_direction,
};
use texel_probes::grid::{GridDefaults, GridOverride, ProbeKey, resolve_grid};
use texel_probes::probe_set::{FadeConfig, FadeDirection, ProbeSet, Readiness, TransitionEvent};
use texel_probes::schedule::Scheduler;
use texel_probes::visibility::{CameraView, frustum, visible_faces};

const DEFAULTS: GridDefaults = GridDefaults {
    cell_size: 1.5,
    face_resolution: 32,
};
const FAR: f32 = 60.0;

fn face() -> impl Strategy<Value = Face> {
    (0usize..6).prop_map(|i| Face::from_index(i).unwrap())
}

fn direction() -> impl Strategy<Value = Vec3> {
    (-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0)
        .prop_map(|(x, y, z)| Vec3::new(x, y, z))
        .prop_filter("not tiny", |v| chebyshev_norm(*v) > 1e-3)
}

fn camera_view(position: Vec3, yaw: f32, pitch: f32, fov_y: f32) -> CameraView {
    let forward = Vec3::new(
        yaw.sin() * pitch.cos(),
        pitch.sin(),
        yaw.cos() * pitch.cos(),
    );
    CameraView {
        position,
        forward,
        up: Vec3::Y,
        fov_y,
        aspect: 16.0 / 9.0,
        near: 0.1,
        far: FAR,
    }
}

/// A camera position inside the cell of vertex `index` (cell size 1.5), off its faces.
fn in_cell(index: IVec3, offset: Vec3) -> Vec3 {
    (index.as_vec3() + offset) * DEFAULTS.cell_size
}

fn offset() -> impl Strategy<Value = Vec3> {
    (-0.49f32..0.49, -0.49f32..0.49, -0.49f32..0.49).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

fn cell_index() -> impl Strategy<Value = IVec3> {
    (-500i32..500, -20i32..20, -500i32..500).prop_map(|(x, y, z)| IVec3::new(x, y, z))
}

/// Angles: yaw, pitch (kept off the poles so `up = Y` stays valid), fov.
fn orientation() -> impl Strategy<Value = (f32, f32, f32)> {
    (-7.0f32..7.0, -1.4f32..1.4, 0.4f32..2.0)
}

proptest! {
    #[test]
    fn direction_face_uv_round_trips(r in direction()) {
        let fuv = face_uv_from_direction(r).unwrap();
        prop_assert!(fuv.u.abs() <= 1.0 && fuv.v.abs() <= 1.0);
        let back = direction_from_face_uv(fuv.face, fuv.u, fuv.v);
        prop_assert!((back - r / chebyshev_norm(r)).abs().max_element() < 1e-5);
    }

    #[test]
    fn face_uv_direction_round_trips(f in face(), u in -1.0f32..1.0, v in -1.0f32..1.0) {
        // Open interval: on an edge the face may legitimately be the neighbour.
        prop_assume!(u.abs() < 0.9999 && v.abs() < 0.9999);
        let fuv = face_uv_from_direction(direction_from_face_uv(f, u, v) * 3.7).unwrap();
        prop_assert_eq!(fuv.face, f);
        prop_assert!((fuv.u - u).abs() < 1e-5 && (fuv.v - v).abs() < 1e-5);
    }

    #[test]
    fn texel_centre_maps_back_to_its_texel(
        f in face(), n in 1u32..1024, xs in 0.0f64..1.0, ys in 0.0f64..1.0, scale in 0.01f32..100.0,
    ) {
        let texel = Texel { face: f, x: (xs * n as f64) as u32, y: (ys * n as f64) as u32 };
        let r = texel_center_direction(texel, n) * scale;
        prop_assert_eq!(texel_from_direction(r, n), Some(texel));
    }

    #[test]
    fn moving_inside_a_cell_keeps_the_grid_origin(
        index in cell_index(), a in offset(), b in offset(),
    ) {
        let first = resolve_grid(in_cell(index, a), &DEFAULTS, &[]).unwrap();
        let second = resolve_grid(in_cell(index, b), &DEFAULTS, &[]).unwrap();
        prop_assert_eq!(first.key, second.key);
        prop_assert_eq!(first.origin(), index.as_vec3() * DEFAULTS.cell_size);
        // Also inside an override volume of another cell size.
        let fine = GridOverride {
            min: Vec3::splat(-1.0e4),
            max: Vec3::splat(1.0e4),
            cell_size: 0.75,
            face_resolution: Some(48),
            priority: 1,
        };
        let p = in_cell(index, a);
        let snapped = resolve_grid(p, &DEFAULTS, &[fine]).unwrap();
        let nudged = p + (snapped.origin() - p) * 0.5;
        prop_assert_eq!(resolve_grid(nudged, &DEFAULTS, &[fine]).unwrap().key, snapped.key);
    }

    #[test]
    fn rotating_in_place_never_changes_an_origin(
        index in cell_index(),
        at in offset(),
        turns in prop::collection::vec(orientation(), 1..40),
    ) {
        let camera = in_cell(index, at);
        let choice = resolve_grid(camera, &DEFAULTS, &[]).unwrap();
        let mut probes = ProbeSet::new(camera, choice.key, FadeConfig::default()).unwrap();
        let mut scheduler = Scheduler::new(9, FAR).unwrap();
        let mut seen = [false; 6];
        for (yaw, pitch, fov) in turns {
            let choice = resolve_grid(camera, &DEFAULTS, &[]).unwrap();
            probes.begin_frame(camera, choice.key, 1.0 / 60.0);
            let view = frustum(&camera_view(camera, yaw, pitch, fov)).unwrap();
            let plan = scheduler.plan(&view, &probes, 0);
            scheduler.commit(&plan);
            probes.advance_fade(plan.readiness());
            prop_assert_eq!(probes.eye().origin, camera);
            prop_assert_eq!(probes.grid().origin, choice.origin());
            prop_assert!(probes.previous().is_none());
            prop_assert_eq!(probes.fade_t(), 1.0);
            for f in plan.grid.capture.iter() {
                prop_assert!(!seen[f.index()], "grid face {:?} captured twice", f);
                seen[f.index()] = true;
            }
        }
    }

    #[test]
    fn quads_depend_only_on_origin_face_texel_depth(
        index in cell_index(),
        a in offset(),
        b in offset(),
        f in face(),
        x in 0u32..32,
        y in 0u32..32,
        depth in 0.1f32..50.0,
        half in 0.5f32..2.0,
    ) {
        // Two cameras anywhere in the same cell (and looking anywhere: orientation is no
        // input of the probe set): the grid probe's quad for a texel and depth is the same,
        // bit for bit.
        let texel = Texel { face: f, x, y };
        let quad_for = |camera: Vec3| {
            let key: ProbeKey = resolve_grid(camera, &DEFAULTS, &[]).unwrap().key;
            let mut probes = ProbeSet::new(Vec3::ZERO, key, FadeConfig::default()).unwrap();
            probes.update(camera, key, 1.0 / 60.0, Readiness::ALL);
            let grid = probes.grid();
            quad_corners(grid.origin, texel, grid.face_resolution, depth, QuadHalfSizes::uniform(half))
        };
        prop_assert_eq!(quad_for(in_cell(index, a)), quad_for(in_cell(index, b)));
        // Exact quads lie in the face plane at the stored depth.
        let origin = index.as_vec3() * DEFAULTS.cell_size;
        let tolerance = 4.0 * f32::EPSILON * (depth + origin.abs().max_element());
        for c in quad_corners(origin, texel, 32, depth, QuadHalfSizes::EXACT) {
            prop_assert!((f.axis().dot(c - origin) - depth).abs() <= tolerance);
        }
    }

    #[test]
    fn visible_faces_are_never_missed(
        camera in (-3.0f32..3.0, -3.0f32..3.0, -3.0f32..3.0),
        probe in (-3.0f32..3.0, -3.0f32..3.0, -3.0f32..3.0),
        (yaw, pitch, fov) in orientation(),
        samples in prop::collection::vec((-1.0f32..1.0, -1.0f32..1.0, 0.0f32..1.0), 64),
    ) {
        let camera = Vec3::new(camera.0, camera.1, camera.2);
        let origin = Vec3::new(probe.0, probe.1, probe.2);
        let view = camera_view(camera, yaw, pitch, fov);
        let fr = frustum(&view).unwrap();
        let mask = visible_faces(&fr, origin, FAR, 1.0);
        let f = view.forward.normalize();
        let r = f.cross(view.up).normalize();
        let u = r.cross(f);
        let th = (view.fov_y * 0.5).tan();
        for (sx, sy, t) in samples {
            let dist = view.near + t * (view.far - view.near);
            let p = camera + (f + r * (sx * th * view.aspect) + u * (sy * th)) * dist;
            let d = p - origin;
            if chebyshev_norm(d) > FAR || chebyshev_norm(d) < 1e-3 {
                continue;
            }
            let face = face_uv_from_direction(d).unwrap().face;
            prop_assert!(mask.contains(face), "point {} lies in {:?}, mask {:?}", p, face, mask);
        }
    }

    #[test]
    fn crossfades_never_pop(
        steps in prop::collection::vec((0i32..4, 0.0f32..0.12, any::<bool>(), any::<bool>()), 1..120),
    ) {
        let keys: Vec<ProbeKey> = (0..4)
            .map(|i| resolve_grid(Vec3::new(i as f32 * 1.5, 0.0, 0.0), &DEFAULTS, &[]).unwrap().key)
            .collect();
        let cfg = FadeConfig::default();
        let mut set = ProbeSet::new(Vec3::ZERO, keys[0], cfg).unwrap();
        let owners = |s: &ProbeSet| -> Vec<(usize, [u32; 3])> {
            (0..16u8).map(|v| {
                let p = s.stable_owner(threshold_of(v));
                (p.slot.index(), p.origin.to_array().map(f32::to_bits))
            }).collect()
        };
        let mut before = owners(&set);
        let mut frames_since_crossing = None;
        for (cell, dt, grid_ready, previous_ready) in steps {
            let camera = keys[cell as usize].origin();
            let event = set.begin_frame(camera, keys[cell as usize], dt);
            prop_assert_eq!(owners(&set), before.clone(), "begin_frame never changes a pixel");
            let fading_before = set.previous_active();
            let direction = set.fade_direction();
            let t0 = set.fade_t();
            set.advance_fade(Readiness::whole(grid_ready, previous_ready));
            let t1 = set.fade_t();
            prop_assert!((0.0..=1.0).contains(&t1));
            let after = owners(&set);
            let changed = before.iter().zip(&after).filter(|(a, b)| a != b).count();
            prop_assert!(changed <= 16 / cfg.min_frames as usize, "{} cells changed", changed);
            if fading_before && set.previous_active() {
                if !grid_ready { prop_assert!(t1 <= t0, "grid not ready: t may not rise"); }
                if !previous_ready { prop_assert!(t1 >= t0, "previous not ready: t may not fall"); }
            }
            if matches!(event, TransitionEvent::CrossingStarted | TransitionEvent::Retargeted) {
                frames_since_crossing = Some(0u32);
                prop_assert!(set.previous_active(), "trigger frame keeps the previous probe");
                prop_assert_eq!(set.fade_t(), 0.0);
            } else if let Some(n) = frames_since_crossing.as_mut() {
                *n += 1;
                if !set.previous_active() {
                    if direction == Some(FadeDirection::TowardGrid) {
                        prop_assert!(*n >= cfg.min_frames, "finished after {} frames", n);
                    }
                    frames_since_crossing = None;
                }
            }
            before = after;
        }
    }
}
