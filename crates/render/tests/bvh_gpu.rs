//! `shaders/lib/bvh.wgsl` on a real GPU (lavapipe here) against the CPU: the same shadow
//! rays must get the same answer from the shader, from `any_hit_cpu` and from brute force.
//!
//! Rays are drawn with a seeded generator, and rays whose answer depends on rounding (they
//! graze an edge or a plane, or hit within rounding of `T_MIN` or `t_max`) are redrawn, as
//! judged by an exact-arithmetic-like f64 classification with a generous error bound. The
//! GPU may round differently (fused multiply-adds, 2.5-ulp division), so only those rays may
//! legitimately differ; with them excluded the comparison is exact.

use glam::{DVec3, EulerRot, Mat4, Quat, Vec3};
use texel_render::bvh::field::{self, HeightField};
use texel_render::bvh::{
    BvhNode, BvhTriangle, GpuBvh, T_MIN, any_hit_brute, any_hit_cpu, build_bvh,
};
use texel_render::context::{GpuContext, test_context};
use texel_render::shader::assemble_source;
use texel_render::target::read_buffer;
use texel_scene::TriMesh;
use texel_scene::primitives::{box_mesh, cylinder};

const RAYS: usize = 4096;

const TEST_SHADER: &str = r#"
#include "lib/bvh.wgsl"

struct Ray {
    origin: vec3<f32>,
    t_max: f32,
    dir: vec3<f32>,
    pad: u32,
}

@group(0) @binding(0) var<storage, read> bvh_nodes: array<BvhNode>;
@group(0) @binding(1) var<storage, read> bvh_triangles: array<BvhTriangle>;
@group(0) @binding(2) var<storage, read> rays: array<Ray>;
@group(0) @binding(3) var<storage, read_write> out: array<u32>;
@group(0) @binding(4) var<storage, read> bvh_instances: array<BvhInstance>;
@group(0) @binding(5) var<uniform> bvh_fields: BvhFields;
@group(0) @binding(6) var bvh_field_data: texture_2d_array<f32>;

@compute @workgroup_size(64)
fn trace(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= arrayLength(&rays) {
        return;
    }
    let r = rays[id.x];
    out[id.x] = select(0u, 1u, bvh_any_hit(r.origin, r.dir, r.t_max));
}

// `trace` with the terrains walked from the rays' far ends.
@compute @workgroup_size(64)
fn trace_far(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= arrayLength(&rays) {
        return;
    }
    let r = rays[id.x];
    out[id.x] = select(0u, 1u, bvh_any_hit_from(r.origin, r.dir, r.t_max, true, BVH_STATICS_ALL));
}

// Writes back every field of node i and triangle i (nodes first, 8 words each, then
// triangles, 12 words each), so the Rust and WGSL layouts are pinned together.
@compute @workgroup_size(64)
fn copy_layout(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    let node_count = arrayLength(&bvh_nodes);
    if i < node_count {
        let n = bvh_nodes[i];
        let o = i * 8u;
        out[o] = bitcast<u32>(n.min.x);
        out[o + 1u] = bitcast<u32>(n.min.y);
        out[o + 2u] = bitcast<u32>(n.min.z);
        out[o + 3u] = n.first;
        out[o + 4u] = bitcast<u32>(n.max.x);
        out[o + 5u] = bitcast<u32>(n.max.y);
        out[o + 6u] = bitcast<u32>(n.max.z);
        out[o + 7u] = n.count;
    }
    if i < arrayLength(&bvh_triangles) {
        let t = bvh_triangles[i];
        let o = node_count * 8u + i * 12u;
        out[o] = bitcast<u32>(t.v0.x);
        out[o + 1u] = bitcast<u32>(t.v0.y);
        out[o + 2u] = bitcast<u32>(t.v0.z);
        out[o + 3u] = t.id;
        out[o + 4u] = bitcast<u32>(t.e1.x);
        out[o + 5u] = bitcast<u32>(t.e1.y);
        out[o + 6u] = bitcast<u32>(t.e1.z);
        out[o + 7u] = t.pad0;
        out[o + 8u] = bitcast<u32>(t.e2.x);
        out[o + 9u] = bitcast<u32>(t.e2.y);
        out[o + 10u] = bitcast<u32>(t.e2.z);
        out[o + 11u] = t.pad1;
    }
}
"#;

/// A ray as `TEST_SHADER` reads it.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct GpuRay {
    origin: [f32; 3],
    t_max: f32,
    dir: [f32; 3],
    pad: u32,
}

/// Xorshift64*: deterministic and dependency-free.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f32 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 40) as f32 / (1u64 << 24) as f32
    }
    fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.next()
    }
    fn vec(&mut self, lo: Vec3, hi: Vec3) -> Vec3 {
        Vec3::new(
            self.range(lo.x, hi.x),
            self.range(lo.y, hi.y),
            self.range(lo.z, hi.z),
        )
    }
    fn index(&mut self, len: usize) -> usize {
        ((self.next() * len as f32) as usize).min(len - 1)
    }
}

fn push_mesh(out: &mut Vec<[Vec3; 3]>, mesh: &TriMesh, m: Mat4) {
    for t in mesh.indices.chunks_exact(3) {
        out.push([0, 1, 2].map(|k| m.transform_point3(mesh.positions[t[k] as usize])));
    }
}

/// A ground slab, a 6×6 grid of pillars (boxes and cylinders of varied height, some turned)
/// and a few tilted boxes floating above: ~1.3k triangles.
fn scene(rng: &mut Rng) -> Vec<[Vec3; 3]> {
    let mut tris = Vec::new();
    let ground = Mat4::from_translation(Vec3::new(0.0, -0.05, 0.0));
    push_mesh(&mut tris, &box_mesh(Vec3::new(30.0, 0.1, 30.0)), ground);
    for i in 0..6 {
        for j in 0..6 {
            let h = rng.range(0.5, 4.0);
            let at = Vec3::new(i as f32 * 4.0 - 10.0, h * 0.5, j as f32 * 4.0 - 10.0);
            let turn = Quat::from_rotation_y(rng.range(0.0, 3.0));
            let m = Mat4::from_rotation_translation(turn, at);
            let mesh = if (i + j) % 2 == 0 {
                box_mesh(Vec3::new(rng.range(0.4, 1.5), h, rng.range(0.4, 1.5)))
            } else {
                cylinder(rng.range(0.3, 0.8), h, 16)
            };
            push_mesh(&mut tris, &mesh, m);
        }
    }
    for _ in 0..8 {
        let r = Quat::from_euler(
            EulerRot::YXZ,
            rng.range(0.0, 6.0),
            rng.range(0.0, 6.0),
            rng.range(0.0, 6.0),
        );
        let at = rng.vec(Vec3::new(-10.0, 4.0, -10.0), Vec3::new(10.0, 7.0, 10.0));
        let m = Mat4::from_scale_rotation_translation(Vec3::splat(rng.range(0.5, 2.0)), r, at);
        push_mesh(&mut tris, &box_mesh(Vec3::ONE), m);
    }
    tris
}

/// Three-valued logic for the f64 classification.
#[derive(Clone, Copy, PartialEq, Debug)]
enum Tri {
    No,
    Unsure,
    Yes,
}

/// `x > 0` for a value known to within `err`.
fn positive(x: f64, err: f64) -> Tri {
    if x > err {
        Tri::Yes
    } else if x < -err {
        Tri::No
    } else {
        Tri::Unsure
    }
}

fn all(terms: &[Tri]) -> Tri {
    if terms.contains(&Tri::No) {
        Tri::No
    } else if terms.contains(&Tri::Unsure) {
        Tri::Unsure
    } else {
        Tri::Yes
    }
}

/// Whether the f32 Möller–Trumbore test of `tri` (as stored, so the same triangle) must
/// report a hit, must not, or could go either way by rounding. Each quantity the test
/// compares with zero is computed in f64 and trusted only beyond 1e-5 of the magnitudes
/// that make it up (f32 rounding of these few operations is ~1e-6 of them).
fn classify(tri: &BvhTriangle, o: Vec3, d: Vec3, t_max: f32) -> Tri {
    const REL: f64 = 1e-5;
    let f = |a: [f32; 3]| DVec3::new(a[0].into(), a[1].into(), a[2].into());
    let (v0, e1, e2, o, d) = (f(tri.v0), f(tri.e1), f(tri.e2), o.as_dvec3(), d.as_dvec3());
    let s = o - v0;
    // `origin - v0` is rounded at the scale of its operands, not of the difference.
    let sl = s.length() + o.length() + v0.length();
    let (l1, l2, ld) = (e1.length(), e2.length(), d.length());
    let det = e1.dot(d.cross(e2));
    let u = s.dot(d.cross(e2));
    let v = d.dot(s.cross(e1));
    let t = e2.dot(s.cross(e1));
    let (bd, bu, bv, bt) = (
        REL * l1 * l2 * ld,
        REL * sl * ld * l2,
        REL * sl * ld * l1,
        REL * l1 * l2 * sl,
    );
    let (t_min, t_max) = (f64::from(T_MIN), f64::from(t_max));
    match positive(det.abs(), bd) {
        Tri::Yes => {
            // The f32 test accepts u, v, w = 0 and rejects t = T_MIN or t_max; both sit
            // inside the uncertainty band, so `positive` serves for `>=` and `>` alike.
            let sg = det.signum();
            all(&[
                positive(u * sg, bu),
                positive((det - u) * sg, bd + bu),
                positive(v * sg, bv),
                positive((det - u - v) * sg, bd + bu + bv),
                positive((t - t_min * det) * sg, bt + t_min * bd),
                positive((t_max * det - t) * sg, bt + t_max * bd),
            ])
        }
        // Nearly parallel: the sign of det is unknown, but a crossing this far away is
        // outside (T_MIN, t_max) either way (or det rounds to 0: a miss too).
        _ if t.abs() - bt > t_max * (det.abs() + bd) => Tri::No,
        _ => Tri::Unsure,
    }
}

/// The certain answer for a ray, or `None` when rounding could decide it.
fn certain_answer(tris: &[BvhTriangle], o: Vec3, d: Vec3, t_max: f32) -> Option<bool> {
    let mut unsure = false;
    for t in tris {
        match classify(t, o, d, t_max) {
            Tri::Yes => return Some(true),
            Tri::Unsure => unsure = true,
            Tri::No => {}
        }
    }
    (!unsure).then_some(false)
}

/// Shadow rays of three kinds: from just above a random surface point towards a light
/// (the renderer's case), from a random point in the scene's volume in a random
/// direction, and aimed at a random triangle with `t_max` close to its distance.
fn random_ray(rng: &mut Rng, tris: &[[Vec3; 3]]) -> GpuRay {
    let lo = Vec3::new(-13.0, -0.5, -13.0);
    let hi = Vec3::new(13.0, 8.0, 13.0);
    let point_on = |rng: &mut Rng, t: &[Vec3; 3]| {
        let (mut a, mut b) = (rng.next(), rng.next());
        if a + b > 1.0 {
            (a, b) = (1.0 - a, 1.0 - b);
        }
        t[0] + (t[1] - t[0]) * a + (t[2] - t[0]) * b
    };
    let (origin, dir, t_max) = match rng.index(3) {
        0 => {
            let t = &tris[rng.index(tris.len())];
            let n = (t[1] - t[0]).cross(t[2] - t[0]).normalize_or_zero();
            let origin = point_on(rng, t) + n * rng.range(0.0, 0.02);
            let light = rng.vec(lo, hi) + Vec3::Y * 6.0;
            if rng.next() < 0.5 {
                (origin, light - origin, 1.0) // point light: t = 1 at the light
            } else {
                (origin, (light - origin).normalize(), 1e4) // sun
            }
        }
        1 => {
            let dir = rng.vec(Vec3::splat(-1.0), Vec3::ONE);
            let t_max = if rng.next() < 0.3 {
                1e30
            } else {
                rng.range(0.1, 40.0)
            };
            (rng.vec(lo, hi), dir, t_max)
        }
        _ => {
            let t = &tris[rng.index(tris.len())];
            let target = point_on(rng, t);
            let origin = rng.vec(lo, hi);
            (origin, target - origin, rng.range(0.9, 1.1))
        }
    };
    GpuRay {
        origin: origin.to_array(),
        t_max,
        dir: dir.to_array(),
        pad: 0,
    }
}

fn storage(ctx: &GpuContext, label: &str, bytes: &[u8], usage: wgpu::BufferUsages) -> wgpu::Buffer {
    use wgpu::util::DeviceExt;
    ctx.device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: bytes,
            usage,
        })
}

/// Runs `entry` of `TEST_SHADER` over `threads` invocations, with `fields` walked beside
/// `bvh`, and returns `out`.
fn run(
    ctx: &GpuContext,
    bvh: &GpuBvh,
    fields: &[&HeightField],
    rays: &[GpuRay],
    out_words: usize,
    entry: &str,
    threads: usize,
) -> Vec<u32> {
    let source = assemble_source("bvh_gpu", TEST_SHADER).expect("the test shader assembles");
    assert!(!source.contains("#include"));
    let device = &ctx.device;
    let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("bvh_gpu::shader"),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    });
    let entry_layout = |binding, read_only| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    };
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("bvh_gpu::layout"),
        entries: &[
            entry_layout(0, true),
            entry_layout(1, true),
            entry_layout(2, true),
            entry_layout(3, false),
            entry_layout(4, true),
            wgpu::BindGroupLayoutEntry {
                binding: 5,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            },
            wgpu::BindGroupLayoutEntry {
                binding: 6,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: false },
                    view_dimension: wgpu::TextureViewDimension::D2Array,
                    multisampled: false,
                },
                count: None,
            },
        ],
    });
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("bvh_gpu::pipeline_layout"),
        bind_group_layouts: &[Some(&layout)],
        immediate_size: 0,
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("bvh_gpu::pipeline"),
        layout: Some(&pipeline_layout),
        module: &module,
        entry_point: Some(entry),
        compilation_options: Default::default(),
        cache: None,
    });
    let (nodes, triangles) = bvh.upload(device);
    let usage = wgpu::BufferUsages::STORAGE;
    let rays = storage(ctx, "bvh_gpu::rays", bytemuck::cast_slice(rays), usage);
    let size = (out_words * 4) as u64;
    let out = storage(
        ctx,
        "bvh_gpu::out",
        &vec![0xffu8; size as usize],
        usage | wgpu::BufferUsages::COPY_SRC,
    );
    let readback = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("bvh_gpu::readback"),
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    // No animated objects: one record of no tree.
    let instances = storage(
        ctx,
        "bvh_gpu::instances",
        bytemuck::bytes_of(&texel_render::gpu_scene::GpuBvhInstance::NONE),
        usage,
    );
    let indexed: Vec<_> = fields.iter().copied().enumerate().collect();
    let (block, data) = field::pack(&indexed);
    let block = storage(
        ctx,
        "bvh_gpu::fields",
        bytemuck::bytes_of(&block),
        wgpu::BufferUsages::UNIFORM,
    );
    let view = field::upload_data(device, &ctx.queue, &data);
    let mut entries: Vec<wgpu::BindGroupEntry> = [&nodes, &triangles, &rays, &out, &instances]
        .iter()
        .enumerate()
        .map(|(i, b)| wgpu::BindGroupEntry {
            binding: i as u32,
            resource: b.as_entire_binding(),
        })
        .collect();
    entries.push(wgpu::BindGroupEntry {
        binding: 5,
        resource: block.as_entire_binding(),
    });
    entries.push(wgpu::BindGroupEntry {
        binding: 6,
        resource: wgpu::BindingResource::TextureView(&view),
    });
    let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("bvh_gpu::bind"),
        layout: &layout,
        entries: &entries,
    });
    let mut enc = device.create_command_encoder(&Default::default());
    {
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind, &[]);
        pass.dispatch_workgroups(threads.div_ceil(64) as u32, 1, 1);
    }
    enc.copy_buffer_to_buffer(&out, 0, &readback, 0, size);
    ctx.queue.submit([enc.finish()]);
    if let Some(e) = pollster::block_on(scope.pop()) {
        panic!("wgpu validation: {e}");
    }
    let bytes = read_buffer(ctx, &readback).expect("read back the results");
    bytemuck::cast_slice(&bytes).to_vec()
}

#[test]
fn gpu_shadow_rays_match_cpu_traversal_and_brute_force() {
    let Some(ctx) = test_context() else { return };
    let mut rng = Rng(0x5eed_cafe_f00d_1234);
    let tris = scene(&mut rng);
    let start = std::time::Instant::now();
    let bvh = build_bvh(&tris);
    println!(
        "{} triangles -> {} nodes, depth {}, built in {:?}",
        tris.len(),
        bvh.nodes.len(),
        bvh.depth(),
        start.elapsed()
    );
    assert!(tris.len() > 1000, "{} triangles", tris.len());
    let stored: Vec<BvhTriangle> = tris
        .iter()
        .enumerate()
        .map(|(i, t)| BvhTriangle::new(i as u32, t))
        .collect();

    // The certain rays first, then the ambiguous ones met while drawing them.
    let mut rays = Vec::with_capacity(RAYS);
    let mut want = Vec::with_capacity(RAYS);
    let mut ambiguous = Vec::new();
    while rays.len() < RAYS {
        let r = random_ray(&mut rng, &tris);
        let (o, d) = (Vec3::from(r.origin), Vec3::from(r.dir));
        match certain_answer(&stored, o, d, r.t_max) {
            Some(hit) => {
                rays.push(r);
                want.push(hit);
            }
            None => ambiguous.push(r),
        }
    }
    let hits = want.iter().filter(|&&h| h).count();
    let redrawn = ambiguous.len();
    assert!(
        hits > RAYS / 5 && hits < RAYS * 4 / 5,
        "{hits} of {RAYS}: test too weak"
    );
    assert!(
        redrawn < RAYS / 20,
        "{redrawn} rays were ambiguous: classification too loose"
    );
    rays.extend_from_slice(&ambiguous);

    let gpu = run(&ctx, &bvh, &[], &rays, rays.len(), "trace", rays.len());
    let mut mismatches = Vec::new();
    let mut ambiguous_gpu_differs = 0;
    for (i, r) in rays.iter().enumerate() {
        let (o, d) = (Vec3::from(r.origin), Vec3::from(r.dir));
        let brute = any_hit_brute(&tris, o, d, r.t_max);
        let cpu = any_hit_cpu(&bvh, o, d, r.t_max);
        assert!(gpu[i] <= 1, "ray {i}: GPU wrote {}", gpu[i]);
        let gpu = gpu[i] == 1;
        // The CPU traversal and brute force run the same f32 triangle test, and the boxes
        // are conservative: they agree on every ray, ambiguous or not.
        let same_cpu = cpu == brute;
        let ok = match want.get(i) {
            Some(&w) => same_cpu && gpu == w && cpu == w,
            None => {
                ambiguous_gpu_differs += usize::from(gpu != cpu);
                same_cpu
            }
        };
        if !ok {
            mismatches.push(format!(
                "ray {i} {r:?}: expected {:?} gpu {gpu} cpu {cpu} brute {brute}",
                want.get(i)
            ));
        }
    }
    println!(
        "{}: {RAYS} certain rays ({hits} shadowed) all agree; {redrawn} ambiguous rays \
         redrawn, where the GPU differs from the CPU on {ambiguous_gpu_differs}",
        ctx.describe()
    );
    assert!(mismatches.is_empty(), "{}", mismatches.join("\n"));
}

#[test]
fn gpu_layout_matches_rust_structs() {
    let Some(ctx) = test_context() else { return };
    let mut rng = Rng(42);
    let tris = scene(&mut rng);
    let bvh = build_bvh(&tris[..40]);
    let n = bvh.nodes.len().max(bvh.triangles.len());
    let words = bvh.nodes.len() * 8 + bvh.triangles.len() * 12;
    let gpu = run(
        &ctx,
        &bvh,
        &[],
        &[random_ray(&mut rng, &tris)],
        words,
        "copy_layout",
        n,
    );
    let mut want: Vec<u32> = bytemuck::cast_slice::<BvhNode, u32>(&bvh.nodes).to_vec();
    want.extend_from_slice(bytemuck::cast_slice::<BvhTriangle, u32>(&bvh.triangles));
    assert_eq!(gpu, want);
}

#[test]
fn gpu_empty_scene_hits_nothing() {
    let Some(ctx) = test_context() else { return };
    let bvh = build_bvh(&[]);
    let mut rng = Rng(9);
    let tris = scene(&mut rng);
    let rays: Vec<GpuRay> = (0..256).map(|_| random_ray(&mut rng, &tris)).collect();
    let gpu = run(&ctx, &bvh, &[], &rays, rays.len(), "trace", rays.len());
    assert_eq!(gpu, vec![0; rays.len()]);
}

/// A hilly field of 65 × 49 samples (cells of 0.5 × 0.75), its corner off the origin.
fn hills(rng: &mut Rng) -> HeightField {
    let (w, d) = (65u32, 49u32);
    let heights: Vec<f32> = (0..w * d)
        .map(|i| {
            let (x, z) = ((i % w) as f32, (i / w) as f32);
            let ridge = if (x as u32 / 9 + z as u32 / 6).is_multiple_of(5) {
                1.5
            } else {
                0.0
            };
            2.5 * (x * 0.21).sin() * (z * 0.17).cos() + ridge + rng.range(-0.1, 0.1)
        })
        .collect();
    HeightField::new(
        Vec3::new(-16.0, 0.5, -18.0),
        glam::Vec2::new(32.0, 36.0),
        glam::UVec2::new(w, d),
        &heights,
    )
    .expect("a valid field")
}

/// A terrain walked as a heightfield on the GPU (`field_hit` in `lib/bvh.wgsl`) answers as
/// its CPU walk, as brute force over its triangles, and as the f64 classification: shadow
/// rays, rays skimming the hills from one surface point toward another (the probes' edge
/// rays), and random rays.
#[test]
fn gpu_heightfield_rays_match_cpu_walk_and_brute_force() {
    let Some(ctx) = test_context() else { return };
    let mut rng = Rng(0xfee1_600d_1234_5678);
    let f = hills(&mut rng);
    let tris = f.triangles();
    let stored: Vec<BvhTriangle> = (tris.iter().enumerate())
        .map(|(i, t)| BvhTriangle::new(i as u32, t))
        .collect();
    let on = |rng: &mut Rng| {
        let t = &tris[rng.index(tris.len())];
        let (mut a, mut b) = (rng.next(), rng.next());
        if a + b > 1.0 {
            (a, b) = (1.0 - a, 1.0 - b);
        }
        t[0] + (t[1] - t[0]) * a + (t[2] - t[0]) * b
    };
    let (mut rays, mut want, mut ambiguous) = (Vec::new(), Vec::new(), 0);
    while rays.len() < 2048 {
        let (origin, dir, t_max) = match rng.index(3) {
            0 => {
                let o = on(&mut rng) + Vec3::Y * rng.range(0.01, 0.05);
                let sun = Vec3::new(
                    rng.range(-1.0, 1.0),
                    rng.range(0.05, 1.0),
                    rng.range(-1.0, 1.0),
                );
                (o, sun.normalize(), 1e4)
            }
            1 => {
                let o = on(&mut rng) + Vec3::Y * rng.range(0.2, 2.0);
                (o, on(&mut rng) - o, rng.range(0.5, 1.2))
            }
            _ => (
                rng.vec(Vec3::new(-20.0, -1.0, -22.0), Vec3::new(20.0, 6.0, 22.0)),
                rng.vec(Vec3::splat(-1.0), Vec3::ONE),
                if rng.next() < 0.3 {
                    1e30
                } else {
                    rng.range(0.1, 50.0)
                },
            ),
        };
        match certain_answer(&stored, origin, dir, t_max) {
            Some(hit) => {
                rays.push(GpuRay {
                    origin: origin.to_array(),
                    t_max,
                    dir: dir.to_array(),
                    pad: 0,
                });
                want.push(hit);
            }
            None => ambiguous += 1,
        }
    }
    let hits = want.iter().filter(|&&h| h).count();
    assert!(
        hits > rays.len() / 5 && hits < rays.len() * 4 / 5,
        "{hits} hits: test too weak"
    );
    assert!(ambiguous < rays.len() / 20, "{ambiguous} ambiguous rays");
    let empty = build_bvh(&[]);
    let gpu = run(&ctx, &empty, &[&f], &rays, rays.len(), "trace", rays.len());
    let mut mismatches = Vec::new();
    for (i, r) in rays.iter().enumerate() {
        let (o, d) = (Vec3::from(r.origin), Vec3::from(r.dir));
        let cpu = f.hit(o, d, r.t_max);
        let brute = any_hit_brute(&tris, o, d, r.t_max);
        if gpu[i] != u32::from(want[i]) || cpu != want[i] || brute != want[i] {
            mismatches.push(format!(
                "ray {i} {r:?}: expected {} gpu {} cpu {cpu} brute {brute}",
                want[i], gpu[i]
            ));
        }
    }
    println!(
        "{}: {} certain field rays ({hits} hit) agree; {ambiguous} ambiguous redrawn",
        ctx.describe(),
        rays.len()
    );
    assert!(mismatches.is_empty(), "{}", mismatches.join("\n"));
    let far = run(
        &ctx,
        &empty,
        &[&f],
        &rays,
        rays.len(),
        "trace_far",
        rays.len(),
    );
    assert_eq!(far, gpu, "walked from the far end, the same answers");
    // A field beside the tree: the tree's answer stands where the field has none.
    let gpu_none = run(&ctx, &empty, &[], &rays, rays.len(), "trace", rays.len());
    assert_eq!(gpu_none, vec![0; rays.len()]);
}
