//! Shader modules and pipelines made once per device, shared by every renderer on it.
//!
//! A renderer compiles its pipelines on first use (`passes::LazyCompute`, `LazyRender`), and
//! neither lavapipe nor SwiftShader keeps what it compiled between two renderers (no
//! `VkPipelineCache` they can fill: see `docs/stability-log.md`, 2026-12-06). So a process
//! that builds several renderers on one device (`texel-eval`, one per method and path; the
//! baselines beside the splat renderer; tests that share one device) compiled each pipeline
//! again for every renderer: on SwiftShader 0.7 to 1.5 s for the big ones. Here each
//! [`GpuContext`](crate::context::GpuContext) holds a [`PipelineCache`] for its device
//! (its clones share it), which keeps:
//!
//! - the device's shader modules by file name (a file assembles to the same WGSL every time);
//! - its pipelines by module, owner label, entry points and fixed state (targets, depth,
//!   topology, vertex buffers). Bind group layouts are not in the key: they follow from the
//!   same code, and wgpu gives identical layouts one identity, so a pipeline made for one
//!   renderer's layouts takes another's bind groups; a mismatch would be a validation error
//!   (the context reports it), never a wrong picture.
//!
//! A renderer's constructor names its context's cache for the passes it builds
//! ([`building`]); the cache is not found from the `wgpu::Device`, because wgpu compares
//! devices by an id that two devices of two instances may share.

use std::cell::RefCell;
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

/// One device's modules and pipelines (a clone is the same cache).
#[derive(Clone, Default)]
pub struct PipelineCache(Arc<Mutex<Made>>);

impl std::fmt::Debug for PipelineCache {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "PipelineCache({} compiled)", self.compiled())
    }
}

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    // A panic elsewhere while holding the lock leaves maps that are still whole.
    m.lock().unwrap_or_else(PoisonError::into_inner)
}

thread_local! {
    /// The cache of the renderer being built on this thread ([`building`]).
    static BUILDING: RefCell<Option<PipelineCache>> = const { RefCell::new(None) };
}

/// While the returned guard lives, the modules and pipelines this thread's passes are built
/// with come from (and go to) `cache`.
pub(crate) fn building(cache: &PipelineCache) -> Building {
    Building(BUILDING.with(|b| b.replace(Some(cache.clone()))))
}

/// Restores the cache named before [`building`] when dropped.
pub(crate) struct Building(Option<PipelineCache>);

impl Drop for Building {
    fn drop(&mut self) {
        let before = self.0.take();
        BUILDING.with(|b| *b.borrow_mut() = before);
    }
}

/// The cache named by the innermost [`building`] on this thread, if any.
pub(crate) fn current() -> Option<PipelineCache> {
    BUILDING.with(|b| b.borrow().clone())
}

/// The module of the shader file `name`, made by `make` the first time for the cache being
/// built with (every time without one).
pub(crate) fn module<E>(
    name: &str,
    make: impl FnOnce() -> Result<wgpu::ShaderModule, E>,
) -> Result<wgpu::ShaderModule, E> {
    let Some(cache) = current() else {
        return make();
    };
    let mut made = lock(&cache.0);
    if let Some(m) = made.modules.get(name) {
        return Ok(m.clone());
    }
    let m = make()?;
    made.modules.insert(name.to_owned(), m.clone());
    Ok(m)
}

impl PipelineCache {
    /// How many pipelines were compiled into this cache.
    pub fn compiled(&self) -> u64 {
        lock(&self.0).compiled
    }

    /// A pipeline of `key` in `module` from the map `pick` chooses, made by `make` the first
    /// time.
    fn pipeline<P: Clone>(
        &self,
        module: &wgpu::ShaderModule,
        key: String,
        pick: fn(&mut Made) -> &mut HashMap<(wgpu::ShaderModule, String), P>,
        make: impl FnOnce() -> P,
    ) -> P {
        let mut made = lock(&self.0);
        let key = (module.clone(), key);
        if let Some(p) = pick(&mut made).get(&key) {
            return p.clone();
        }
        let p = make();
        made.compiled += 1;
        pick(&mut made).insert(key, p.clone());
        p
    }

    /// The compute pipeline `key` names in `module`, compiled by `make` the first time.
    pub(crate) fn compute(
        &self,
        module: &wgpu::ShaderModule,
        key: String,
        make: impl FnOnce() -> wgpu::ComputePipeline,
    ) -> wgpu::ComputePipeline {
        self.pipeline(module, key, |m| &mut m.compute, make)
    }

    /// The render pipeline `key` names in `module`, compiled by `make` the first time.
    pub(crate) fn render(
        &self,
        module: &wgpu::ShaderModule,
        key: String,
        make: impl FnOnce() -> wgpu::RenderPipeline,
    ) -> wgpu::RenderPipeline {
        self.pipeline(module, key, |m| &mut m.render, make)
    }
}
