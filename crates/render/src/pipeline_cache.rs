//! Shader modules and pipelines made once per device, shared by every renderer on it.
//!
//! A renderer compiles its pipelines on first use (`passes::LazyCompute`, `LazyRender`), and
//! neither lavapipe nor SwiftShader keeps what it compiled between two renderers (no
//! `VkPipelineCache` they can fill: see `docs/stability-log.md`, 2026-12-06). So a process
//! that builds several renderers on one device (`texel-eval`, one per method and path; the
//! baselines beside the splat renderer; tests that share one device) compiled each pipeline
//! again for every renderer: on SwiftShader 0.7 to 1.5 s for the big ones. Here a device,
//! while a [`GpuContext`](crate::context::GpuContext) holds it, keeps:
//!
//! - its shader modules by file name (a file assembles to the same WGSL every time);
//! - its pipelines by module, owner label, entry points and fixed state (targets, depth,
//!   topology, vertex buffers). Bind group layouts are not in the key: they follow from the
//!   same code, and wgpu gives identical layouts one identity, so a pipeline made for one
//!   renderer's layouts takes another's bind groups; a mismatch would be a validation error
//!   (the context reports it), never a wrong picture.
//!
//! A device no context registered compiles as before, uncached.

use std::collections::HashMap;
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};

/// What one device has made.
#[derive(Default)]
struct Made {
    modules: HashMap<String, wgpu::ShaderModule>,
    compute: HashMap<(wgpu::ShaderModule, String), wgpu::ComputePipeline>,
    render: HashMap<(wgpu::ShaderModule, String), wgpu::RenderPipeline>,
    compiled: u64,
}

/// A registered device: how many registrations hold it, and what it made.
struct Entry {
    device: wgpu::Device,
    holders: usize,
    made: Arc<Mutex<Made>>,
}

static DEVICES: Mutex<Vec<Entry>> = Mutex::new(Vec::new());

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    // A panic elsewhere while holding the lock leaves maps that are still whole.
    m.lock().unwrap_or_else(PoisonError::into_inner)
}

/// Keeps `device`'s modules and pipelines while it lives; dropping the last registration of
/// a device forgets them.
#[derive(Debug)]
pub struct Registration(wgpu::Device);

/// Registers `device`: from now on its modules and pipelines are made once.
pub fn register(device: &wgpu::Device) -> Registration {
    let mut devices = lock(&DEVICES);
    match devices.iter_mut().find(|e| e.device == *device) {
        Some(entry) => entry.holders += 1,
        None => devices.push(Entry {
            device: device.clone(),
            holders: 1,
            made: Arc::default(),
        }),
    }
    Registration(device.clone())
}

impl Drop for Registration {
    fn drop(&mut self) {
        let mut devices = lock(&DEVICES);
        if let Some(i) = devices.iter().position(|e| e.device == self.0) {
            devices[i].holders -= 1;
            if devices[i].holders == 0 {
                devices.swap_remove(i);
            }
        }
    }
}

fn made(device: &wgpu::Device) -> Option<Arc<Mutex<Made>>> {
    let devices = lock(&DEVICES);
    (devices.iter())
        .find(|e| e.device == *device)
        .map(|e| e.made.clone())
}

/// The module of the shader file `name`, made by `make` the first time on `device`.
pub(crate) fn module<E>(
    device: &wgpu::Device,
    name: &str,
    make: impl FnOnce() -> Result<wgpu::ShaderModule, E>,
) -> Result<wgpu::ShaderModule, E> {
    let Some(made) = made(device) else {
        return make();
    };
    let mut made = lock(&made);
    if let Some(m) = made.modules.get(name) {
        return Ok(m.clone());
    }
    let m = make()?;
    made.modules.insert(name.to_owned(), m.clone());
    Ok(m)
}

/// A pipeline of `key` in `module` from the map `pick` chooses, made by `make` the first
/// time on `device`.
fn pipeline<P: Clone>(
    device: &wgpu::Device,
    module: &wgpu::ShaderModule,
    key: String,
    pick: fn(&mut Made) -> &mut HashMap<(wgpu::ShaderModule, String), P>,
    make: impl FnOnce() -> P,
) -> P {
    let Some(made) = made(device) else {
        return make();
    };
    let mut made = lock(&made);
    let key = (module.clone(), key);
    if let Some(p) = pick(&mut made).get(&key) {
        return p.clone();
    }
    let p = make();
    made.compiled += 1;
    pick(&mut made).insert(key, p.clone());
    p
}

/// The compute pipeline `key` names in `module`, compiled by `make` the first time on
/// `device`.
pub(crate) fn compute(
    device: &wgpu::Device,
    module: &wgpu::ShaderModule,
    key: String,
    make: impl FnOnce() -> wgpu::ComputePipeline,
) -> wgpu::ComputePipeline {
    pipeline(device, module, key, |m| &mut m.compute, make)
}

/// The render pipeline `key` names in `module`, compiled by `make` the first time on
/// `device`.
pub(crate) fn render(
    device: &wgpu::Device,
    module: &wgpu::ShaderModule,
    key: String,
    make: impl FnOnce() -> wgpu::RenderPipeline,
) -> wgpu::RenderPipeline {
    pipeline(device, module, key, |m| &mut m.render, make)
}

/// How many pipelines were compiled on `device` since it was registered (none counted on a
/// device no context holds).
pub fn compiled(device: &wgpu::Device) -> u64 {
    made(device).map_or(0, |m| lock(&m).compiled)
}
