//! Per-frame view data shared by cull, splat and background (`shaders/lib/view.wgsl`).

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec4};
use texel_probes::probe_set::{Role, Slot};

use crate::input::{FrameInput, MAX_NEAR_FACES, ProbeView, Schedule};

/// Depth push-back of eye quads, as a fraction of clip w: grid and previous quads win where
/// both cover a pixel.
pub const EYE_BIAS: f32 = 0.001;

/// `SlotView` in WGSL.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct SlotView {
    origin: [f32; 3],
    n: u32,
    role: u32,
    draw_mask: u32,
    /// An orthographic probe's half extent (`OrthoFrame::half`), 0 for a cube.
    half: f32,
    _pad: u32,
    right: [f32; 4],
    down: [f32; 4],
    forward: [f32; 4],
    /// `ProbeView::near_faces`.
    near_faces: [[f32; 4]; MAX_NEAR_FACES],
}

/// `ViewGlobals` in WGSL (752 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct ViewGlobals {
    view_proj: [[f32; 4]; 4],
    inv_view_proj: [[f32; 4]; 4],
    planes: [[f32; 4]; 6],
    camera: [f32; 4],
    sky: [f32; 4],
    slots: [SlotView; 3],
    size: [u32; 2],
    /// Largest face resolution of the three slots (texel keys are dense over it).
    pub max_n: u32,
    schedule: u32,
    fade_t: f32,
    eye_bias: f32,
    eye_slot: u32,
    grid_slot: u32,
    haze: f32,
    ortho: u32,
    /// OKLab lightness bands (the cull pass colours outline strips with them).
    bands: u32,
    _pad2: u32,
    forward: [f32; 4],
}

/// Role numbers of `lib/view.wgsl`.
fn role_code(role: Role) -> u32 {
    match role {
        Role::Eye => 0,
        Role::Grid => 1,
        Role::Previous => 2,
    }
}

/// The six frustum planes `(normal, d)` of `view_proj`, normals pointing inside
/// (Gribb–Hartmann, depth 0..1).
pub fn frustum_planes(m: Mat4) -> [Vec4; 6] {
    let r = |i| m.row(i);
    let planes = [
        r(3) + r(0),
        r(3) - r(0),
        r(3) + r(1),
        r(3) - r(1),
        r(2),
        r(3) - r(2),
    ];
    planes.map(|p| p / p.truncate().length())
}

impl ViewGlobals {
    /// The four side planes of the view frustum (left, right, bottom, top).
    pub fn side_planes(&self) -> [[f32; 4]; 4] {
        [
            self.planes[0],
            self.planes[1],
            self.planes[2],
            self.planes[3],
        ]
    }

    /// The view data of `input`; `slot_n` is each slot's current face resolution.
    pub fn new(input: &FrameInput, slot_n: [u32; 3]) -> Self {
        let size = input.size;
        let aspect = size.x as f32 / size.y.max(1) as f32;
        // The frame's depth buffer is reversed (1 near, 0 far): see `Camera::projection_reverse_z`.
        let vp = input.camera.projection_reverse_z(aspect) * input.camera.view();
        let mut slots = [SlotView {
            origin: [0.0; 3],
            n: 1,
            role: 3,
            draw_mask: 0,
            half: 0.0,
            _pad: 0,
            right: [0.0; 4],
            down: [0.0; 4],
            forward: [0.0; 4],
            near_faces: [[0.0; 4]; MAX_NEAR_FACES],
        }; 3];
        for (i, s) in slots.iter_mut().enumerate() {
            s.n = slot_n[i];
        }
        let mut set = |p: &ProbeView| {
            let s = &mut slots[p.slot.index()];
            s.origin = p.origin.to_array();
            s.role = role_code(p.role);
            s.draw_mask = u32::from(p.draw.bits());
            s.near_faces = p.near_faces.map(|f| f.to_array());
            if let Some(f) = p.ortho {
                s.half = f.half;
                s.right = f.right.extend(0.0).to_array();
                s.down = f.down.extend(0.0).to_array();
                s.forward = f.forward.extend(0.0).to_array();
            }
        };
        set(&input.eye);
        set(&input.grid);
        if let Some(prev) = &input.previous {
            set(prev);
        }
        let fade_t = if input.previous.is_some() {
            input.fade_t.clamp(0.0, 1.0)
        } else {
            1.0
        };
        ViewGlobals {
            view_proj: vp.to_cols_array_2d(),
            inv_view_proj: vp.inverse().to_cols_array_2d(),
            planes: frustum_planes(vp).map(|p| p.to_array()),
            camera: input.camera.position.extend(1.0).to_array(),
            sky: input.look.sky.extend(1.0).to_array(),
            slots,
            size: [size.x, size.y],
            max_n: slot_n.into_iter().max().unwrap_or(1),
            schedule: u32::from(input.schedule == Schedule::Paper),
            fade_t,
            eye_bias: EYE_BIAS,
            eye_slot: Slot::Eye.index() as u32,
            grid_slot: input.grid.slot.index() as u32,
            haze: input.look.haze.max(0.0),
            ortho: u32::from(input.camera.ortho_height.is_some()),
            bands: input.look.bands.max(2),
            _pad2: 0,
            forward: input
                .camera
                .forward
                .normalize_or_zero()
                .extend(0.0)
                .to_array(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn frustum_planes_contain_what_the_camera_sees() {
        let cam = crate::input::Camera::looking(Vec3::ZERO, -Vec3::Z);
        let vp = cam.projection(16.0 / 9.0) * cam.view();
        let planes = frustum_planes(vp);
        let inside = |p: Vec3| planes.iter().all(|q| q.truncate().dot(p) + q.w >= 0.0);
        assert!(inside(Vec3::new(0.0, 0.0, -5.0)));
        assert!(!inside(Vec3::new(0.0, 0.0, 5.0)), "behind");
        assert!(!inside(Vec3::new(50.0, 0.0, -5.0)), "far right");
        assert!(!inside(Vec3::new(0.0, 0.0, -1000.0)), "past far");
    }
}
