//! One check of what a frame is asked to draw, shared by texel splatting ([`frame`]) and the
//! baselines ([`view`], [`face_resolution`]), so the two cannot disagree.

use glam::UVec2;
use texel_geom::limits::{FACE_RESOLUTIONS, face_resolution_error};

use crate::error::RenderError;
use crate::input::{Camera, FrameInput, SceneInput};

/// Largest output side, in pixels.
pub const MAX_OUTPUT_SIDE: u32 = 8192;

use crate::gpu_scene::shapes::ShadowShapes;

fn bad<T>(message: impl Into<String>) -> Result<T, RenderError> {
    Err(RenderError::InvalidFrame(message.into()))
}

/// An output of `size` seen by `camera`: sides within 1..=[`MAX_OUTPUT_SIDE`], a finite
/// position, a finite non-zero direction, and an orthographic height (if any) finite and > 0.
pub fn view(camera: &Camera, size: UVec2) -> Result<(), RenderError> {
    if size.x == 0 || size.y == 0 || size.x > MAX_OUTPUT_SIDE || size.y > MAX_OUTPUT_SIDE {
        return bad(format!(
            "output size must be 1..={MAX_OUTPUT_SIDE} on each side"
        ));
    }
    let c = camera;
    if !c.position.is_finite() || !c.forward.is_finite() || c.forward.length_squared() < 1e-12 {
        return bad("camera position and direction must be finite, direction non-zero");
    }
    if c.ortho_height.is_some_and(|h| !(h.is_finite() && h > 0.0)) {
        return bad("orthographic height must be finite and > 0");
    }
    Ok(())
}

/// An output of `size` this device can hold: each side within the device's
/// `max_texture_dimension_2d` (as well as [`MAX_OUTPUT_SIDE`], see [`view`]), and the
/// read-back buffer of an RGBA8 frame (rows padded to 256 bytes) within `max_buffer_size`.
/// Checked before any target of that size is created, so a size the device refuses is an
/// error rather than a wgpu validation panic.
pub fn device_output(limits: &wgpu::Limits, size: UVec2) -> Result<(), RenderError> {
    device_texture(limits, size)?;
    let bytes = readback_bytes(size);
    if bytes > limits.max_buffer_size {
        return bad(format!(
            "output size {}x{} needs a {bytes}-byte read-back buffer, more than this device's \
             largest buffer ({} bytes)",
            size.x, size.y, limits.max_buffer_size
        ));
    }
    Ok(())
}

/// Textures of `size` fit this device: each side within its `max_texture_dimension_2d` and
/// [`MAX_OUTPUT_SIDE`].
pub fn device_texture(limits: &wgpu::Limits, size: UVec2) -> Result<(), RenderError> {
    let side = limits.max_texture_dimension_2d.min(MAX_OUTPUT_SIDE);
    if size.x == 0 || size.y == 0 || size.x > side || size.y > side {
        return bad(format!(
            "output size {}x{} is out of range: each side must be 1..={side} (renderer limit \
             {MAX_OUTPUT_SIDE}, this device's largest texture {})",
            size.x, size.y, limits.max_texture_dimension_2d
        ));
    }
    Ok(())
}

/// Bytes of the buffer an RGBA8 frame of `size` is read back through (rows padded to
/// `COPY_BYTES_PER_ROW_ALIGNMENT`).
pub fn readback_bytes(size: UVec2) -> u64 {
    let align = u64::from(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
    (u64::from(size.x) * 4).div_ceil(align) * align * u64::from(size.y)
}

/// A face resolution within [`FACE_RESOLUTIONS`].
pub fn face_resolution(n: u32) -> Result<(), RenderError> {
    if FACE_RESOLUTIONS.contains(&n) {
        Ok(())
    } else {
        bad(face_resolution_error("face resolution", n))
    }
}

/// A texel-splatting frame: its view, an internal size within the output, and every probe's
/// and capture's face resolution.
pub fn frame(input: &FrameInput) -> Result<(), RenderError> {
    view(&input.camera, input.size)?;
    let (i, o) = (input.internal_size, input.size);
    if i.x == 0 || i.y == 0 || i.x > o.x || i.y > o.y {
        return bad("internal size must be non-zero and at most the output size");
    }
    if input.filling_ahead && (input.previous.is_none() || input.fade_t != 0.0) {
        return bad(
            "a frame filling ahead of a crossing draws the camera cell's probe as the previous one, at fade 0",
        );
    }
    if let Some(f) = input.far_field
        && !(f.cell.is_finite() && f.cell > 0.0)
    {
        return bad("far_field.cell must be finite and above 0");
    }
    [input.eye.face_resolution, input.grid.face_resolution]
        .into_iter()
        .chain(input.previous.map(|p| p.face_resolution))
        .chain(input.captures.iter().map(|c| c.face_resolution))
        .try_for_each(face_resolution)
}

/// A scene this device can hold: its world-space vertices in one vertex buffer within
/// `max_buffer_size`, its shadow casters' BVH within `max_storage_buffer_binding_size`, and its
/// vertex count within a `u32`. The error says how much is needed against how much is
/// allowed, and names the entity with the most triangles when it holds a tenth of them or
/// more (the one to split or simplify), or else how many entities make the total.
pub fn scene(limits: &wgpu::Limits, scene: &SceneInput) -> Result<(), RenderError> {
    scene_shaped(limits, scene, &ShadowShapes::new(scene, true))
}

/// [`scene`], with the still casters' shadow shapes found already (`shapes`, of `scene`):
/// an object casting through a shape puts a record and a top-level node in the trees, its
/// shape's triangles are there once.
pub fn scene_shaped(
    limits: &wgpu::Limits,
    scene: &SceneInput,
    shapes: &ShadowShapes,
) -> Result<(), RenderError> {
    let tris = |o: &crate::input::ObjectInput| (o.mesh.indices.len() / 3) as u64;
    let total: u64 = scene.objects.iter().map(tris).sum();
    // Terrains walked as heightfields put no triangles in the tree.
    let walked = crate::bvh::field::walked_terrains(&scene.terrains);
    let flat: u64 = (scene.objects.iter().enumerate())
        .filter(|(i, o)| o.material.casts_shadows && !shapes.shared(*i))
        .filter(|(_, o)| {
            o.material
                .terrain
                .is_none_or(|t| walked.get(t) != Some(&true))
        })
        .map(|(_, o)| tris(o))
        .sum();
    let shaped: u64 = shapes.triangles().iter().map(|t| t.len() as u64).sum();
    let casters = flat + shaped;
    let records = (1 + shapes.instances() + scene.animated.len()) as u64;
    let largest = scene.objects.iter().max_by_key(|o| tris(o));
    let vertex_bytes = total * 3 * size_of::<crate::gpu_scene::Vertex>() as u64;
    // A BVH over n triangles has at most 2n - 1 nodes, a top level over n records fewer
    // than 2n.
    let bvh_bytes = (casters * size_of::<crate::bvh::BvhTriangle>() as u64)
        .max(2 * (casters + records) * size_of::<crate::bvh::BvhNode>() as u64)
        .max(records * size_of::<crate::gpu_scene::GpuBvhInstance>() as u64);
    let storage = limits.max_storage_buffer_binding_size;
    let terrain_bytes: u64 = (scene.terrains.iter())
        .map(|t| 4 * (t.heights.len() as u64 + 4 * t.gradient.len() as u64))
        .sum();
    if terrain_bytes > storage {
        return Err(RenderError::SceneTooLarge(format!(
            "the scene is too large for this GPU: its terrains' heights need {} MiB in one \
             binding; this GPU allows {} MiB (use smaller heightmaps)",
            terrain_bytes >> 20,
            storage >> 20
        )));
    }
    let what = if vertex_bytes > limits.max_buffer_size || total * 3 > u64::from(u32::MAX) {
        format!(
            "its {total} triangles need {} MiB of vertices in one buffer; this GPU allows {} MiB",
            vertex_bytes >> 20,
            limits.max_buffer_size >> 20
        )
    } else if bvh_bytes > storage {
        format!(
            "its {casters} shadow-casting triangles ({} objects placing shared shapes) need {} \
             MiB of shadow BVH in one binding; this GPU allows {} MiB",
            shapes.instances(),
            bvh_bytes >> 20,
            storage >> 20
        )
    } else {
        return Ok(());
    };
    // One entity holding a tenth or more of the triangles is the one to change; otherwise
    // the total is made of many small ones, and naming the largest would mislead.
    let culprit = match largest {
        Some(o) if tris(o) * 10 >= total => format!(
            " (entity {} has the most, {} triangles: simplify it, split it, or turn off its \
             shadows)",
            o.id,
            tris(o)
        ),
        Some(o) => format!(
            " ({} entities of at most {} triangles each: place fewer, or split the level)",
            scene.objects.len(),
            tris(o)
        ),
        None => String::new(),
    };
    Err(RenderError::SceneTooLarge(format!(
        "the scene is too large for this GPU: {what}{culprit}"
    )))
}

#[cfg(test)]
mod tests {
    use super::scene as scene_check;
    use super::*;

    #[test]
    fn device_limits_refuse_before_creation() {
        let limits = wgpu::Limits {
            max_texture_dimension_2d: 4096,
            max_buffer_size: 1 << 24,
            ..wgpu::Limits::default()
        };
        assert!(device_output(&limits, UVec2::new(1280, 720)).is_ok());
        let e = device_output(&limits, UVec2::new(4097, 16)).unwrap_err();
        assert!(e.to_string().contains("1..=4096"), "{e}");
        let e = device_output(&limits, UVec2::new(8193, 8192)).unwrap_err();
        assert!(e.to_string().contains("out of range"), "{e}");
        // 4096 x 4096 x 4 = 64 MiB > 16 MiB: the texture fits, its read-back does not.
        let e = device_output(&limits, UVec2::new(4096, 4096)).unwrap_err();
        assert!(e.to_string().contains("read-back buffer"), "{e}");
        assert_eq!(readback_bytes(UVec2::new(1, 2)), 512);
        let big = wgpu::Limits {
            max_texture_dimension_2d: 16384,
            ..wgpu::Limits::default()
        };
        assert!(device_output(&big, UVec2::new(16384, 16384)).is_err());
    }

    /// A frame that says it fills ahead of a crossing must draw the camera cell's probe as
    /// the previous one at fade 0, or `FrameInput::cell_probe` would name the wrong probe.
    #[test]
    fn a_frame_filling_ahead_needs_the_cell_probe_as_previous_at_fade_0() {
        use crate::input::{Look, MAX_NEAR_FACES, ProbeView, Schedule};
        use glam::{Vec3, Vec4};
        use texel_probes::cube::FaceMask;
        use texel_probes::probe_set::{Role, Slot};
        let probe = |role, slot, z| ProbeView {
            role,
            slot,
            origin: Vec3::new(0.0, 1.0, z),
            face_resolution: 64,
            draw: FaceMask::ALL,
            valid: FaceMask::ALL,
            ortho: None,
            near_faces: [Vec4::ZERO; MAX_NEAR_FACES],
        };
        let size = UVec2::new(64, 36);
        let mut input = FrameInput {
            camera: Camera::looking(Vec3::new(0.0, 1.0, 0.4), Vec3::NEG_Z),
            size,
            internal_size: size,
            look: Look {
                sky: Vec3::ONE,
                ambient: Vec3::ZERO,
                bands: 8,
                haze: 0.0,
            },
            eye: probe(Role::Eye, Slot::Eye, 0.4),
            grid: probe(Role::Grid, Slot::StableB, -1.0),
            previous: Some(probe(Role::Previous, Slot::StableA, 0.0)),
            fade_t: 0.0,
            filling_ahead: true,
            prefetch: None,
            captures: Vec::new(),
            schedule: Schedule::Ours,
            grid_complete: true,
            poses: Vec::new(),
            relight: Vec::new(),
            partial: Vec::new(),
            sprites: Vec::new(),
            far_field: None,
        };
        assert!(frame(&input).is_ok());
        assert_eq!(input.cell_probe().origin.z, 0.0);
        input.fade_t = 0.5;
        assert!(frame(&input).is_err(), "filling ahead past fade 0");
        input.fade_t = 0.0;
        input.previous = None;
        let e = frame(&input).unwrap_err().to_string();
        assert!(e.contains("previous"), "{e}");
        input.filling_ahead = false;
        assert!(frame(&input).is_ok());
        assert_eq!(input.cell_probe().origin.z, -1.0);
    }

    #[test]
    fn a_scene_larger_than_the_device_allows_names_its_largest_entity() {
        use crate::input::{MaterialInput, ObjectInput, SceneInput};
        use std::sync::Arc;
        let mesh = |tris: usize| {
            Arc::new(texel_geom::TriMesh {
                positions: vec![glam::Vec3::ZERO; 3],
                normals: vec![glam::Vec3::Y; 3],
                colors: vec![[1.0; 4]; 3],
                indices: [0, 1, 2].repeat(tris),
                ..Default::default()
            })
        };
        let object = |id, tris, casts_shadows| ObjectInput {
            mesh: mesh(tris),
            transform: glam::Mat4::IDENTITY,
            material: MaterialInput {
                albedo: glam::Vec3::ONE,
                emissive: glam::Vec3::ZERO,
                casts_shadows,
                outlined: false,
                ..Default::default()
            },
            id,
        };
        let scene = SceneInput {
            objects: vec![object(3, 1000, false), object(7, 5000, true)],
            ..Default::default()
        };
        // 6,000 triangles are 576,000 bytes of vertices; 5,000 casters 320,000 bytes of BVH.
        let roomy = wgpu::Limits::default();
        assert!(scene_check(&roomy, &scene).is_ok());
        let small_buffers = wgpu::Limits {
            max_buffer_size: 500_000,
            ..wgpu::Limits::default()
        };
        let e = scene_check(&small_buffers, &scene).unwrap_err().to_string();
        assert!(
            e.contains("6000 triangles") && e.contains("entity 7"),
            "{e}"
        );
        let small_bindings = wgpu::Limits {
            max_storage_buffer_binding_size: 300_000,
            ..wgpu::Limits::default()
        };
        let e = scene_check(&small_bindings, &scene)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("5000 shadow-casting") && e.contains("entity 7"),
            "{e}"
        );
        // Many copies, none large: the advice is about their number, not one of them.
        let many = SceneInput {
            objects: (1..=20).map(|id| object(id, 300, true)).collect(),
            ..Default::default()
        };
        let e = scene_check(&small_buffers, &many).unwrap_err().to_string();
        assert!(
            e.contains("20 entities of at most 300 triangles") && !e.contains("entity 20 has"),
            "{e}"
        );
    }
}
