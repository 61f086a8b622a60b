//! The GPU context: instance, adapter, device and queue, headless or for a window.

use std::fmt;
use std::sync::{Arc, Mutex, PoisonError};

use crate::pipeline_cache;

/// Why the GPU could not be opened.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    /// No adapter matched (no GPU driver, or no Vulkan/Metal/DX12/GL implementation).
    #[error(
        "no GPU adapter found ({0}); on Linux without a GPU install Mesa's lavapipe: \
         `apt-get install mesa-vulkan-drivers libvulkan1` (or run `cargo xtask setup`)"
    )]
    NoAdapter(String),
    /// The adapter refused the device we asked for.
    #[error("the GPU adapter `{adapter}` refused a device: {source}")]
    Device {
        /// Adapter name.
        adapter: String,
        /// wgpu's reason.
        source: wgpu::RequestDeviceError,
    },
    /// A window surface could not be created.
    #[error("cannot create a window surface: {0}")]
    Surface(#[from] wgpu::CreateSurfaceError),
    /// Reading back from the GPU failed.
    #[error("GPU readback failed: {0}")]
    Readback(String),
    /// The device reported an error no error scope caught (a validation error or running
    /// out of memory): the work it concerned did not happen.
    #[error("the GPU reported an error: {0}")]
    Uncaptured(String),
    /// The device is gone (driver reset, GPU removed, out of memory): nothing more can be
    /// drawn with it.
    #[error("the GPU device was lost: {0}")]
    Lost(String),
}

/// What the device reported outside any error scope, kept until [`GpuContext::check`] reads
/// it. Installed on every device the project draws with (its own and eframe's), so a GPU
/// error becomes a message instead of wgpu's default handler, which panics.
#[derive(Debug, Default)]
struct Reported {
    /// Uncaptured errors since the last check (the first few, then a count).
    errors: Vec<String>,
    /// Errors past the first few.
    more: usize,
    /// Why the device was lost, once it is.
    lost: Option<String>,
}

/// Uncaptured errors kept in full; later ones are only counted.
const KEPT_ERRORS: usize = 4;

/// The shared record the device's handlers write.
#[derive(Debug, Clone, Default)]
pub struct GpuErrors(Arc<Mutex<Reported>>);

impl GpuErrors {
    /// Installs an uncaptured-error handler and a device-lost callback on `device` that
    /// record what they are told (and print it once to stderr).
    pub fn install(device: &wgpu::Device) -> Self {
        let errors = GpuErrors::default();
        let sink = errors.clone();
        device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            let mut r = sink.lock();
            if r.errors.len() < KEPT_ERRORS {
                eprintln!("GPU error: {e}");
                r.errors.push(e.to_string());
            } else {
                r.more += 1;
            }
        }));
        let sink = errors.clone();
        device.set_device_lost_callback(move |reason, message| {
            // Dropping the device on purpose is not a loss worth reporting.
            if reason != wgpu::DeviceLostReason::Destroyed {
                eprintln!("GPU device lost ({reason:?}): {message}");
            }
            sink.lock().lost = Some(format!("{reason:?}: {message}"));
        });
        errors
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, Reported> {
        self.0.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// `Err` with what was reported since the last call (and clears the errors; a lost
    /// device stays lost).
    pub fn check(&self) -> Result<(), GpuError> {
        let mut r = self.lock();
        if let Some(lost) = &r.lost {
            return Err(GpuError::Lost(lost.clone()));
        }
        if r.errors.is_empty() {
            return Ok(());
        }
        let mut message = r.errors.join("; ");
        if r.more > 0 {
            message.push_str(&format!(" (and {} more)", r.more));
        }
        r.errors.clear();
        r.more = 0;
        Err(GpuError::Uncaptured(message))
    }
}

/// An open GPU: everything the passes need to create resources and submit work. A clone
/// is the same device.
#[derive(Clone)]
pub struct GpuContext {
    /// The wgpu instance (kept to create surfaces).
    pub instance: wgpu::Instance,
    /// The adapter in use.
    pub adapter: wgpu::Adapter,
    /// The device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// Whether GPU timestamps can be written (per-pass GPU times); CPU times otherwise.
    pub timestamps: bool,
    /// What the device reported outside error scopes.
    pub errors: GpuErrors,
    /// The device's modules and pipelines, shared by every renderer built on this context
    /// or a clone of it.
    pub(crate) pipelines: pipeline_cache::PipelineCache,
}

impl fmt::Debug for GpuContext {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let info = self.adapter.get_info();
        f.debug_struct("GpuContext")
            .field("adapter", &info.name)
            .field("backend", &info.backend)
            .field("timestamps", &self.timestamps)
            .finish()
    }
}

impl GpuContext {
    /// Opens a GPU for offscreen rendering. Honours `WGPU_BACKEND` (e.g. `vulkan`) and
    /// `WGPU_ADAPTER_NAME`.
    pub fn headless() -> Result<Self, GpuError> {
        let instance = new_instance();
        pollster::block_on(Self::with_instance(instance, None))
    }

    /// Opens a GPU able to present to `surface` (created from `instance`).
    pub async fn with_instance(
        instance: wgpu::Instance,
        surface: Option<&wgpu::Surface<'_>>,
    ) -> Result<Self, GpuError> {
        let adapter = match wgpu::util::initialize_adapter_from_env(&instance, surface).await {
            Ok(a) => a,
            Err(_) => instance
                .request_adapter(&wgpu::RequestAdapterOptions {
                    power_preference: wgpu::PowerPreference::HighPerformance,
                    force_fallback_adapter: false,
                    compatible_surface: surface,
                    ..Default::default()
                })
                .await
                .map_err(|e| GpuError::NoAdapter(e.to_string()))?,
        };
        Self::on_adapter(instance, adapter).await
    }

    /// Opens a device of its own on `adapter` (the editor's render worker opens one beside
    /// eframe's, so that its frames queue apart from the window's).
    pub async fn on_adapter(
        instance: wgpu::Instance,
        adapter: wgpu::Adapter,
    ) -> Result<Self, GpuError> {
        let features = adapter.features() & TIMESTAMPS;
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("texel::device"),
                required_features: features,
                required_limits: required_limits(&adapter.limits()),
                memory_hints: memory_hints(),
                ..Default::default()
            })
            .await
            .map_err(|source| GpuError::Device {
                adapter: adapter.get_info().name,
                source,
            })?;
        Ok(GpuContext::from_parts(instance, adapter, device, queue))
    }

    /// A context over a device opened elsewhere (eframe's), with the project's error
    /// handlers installed on it; timestamps are used when the device was created with them.
    pub fn from_parts(
        instance: wgpu::Instance,
        adapter: wgpu::Adapter,
        device: wgpu::Device,
        queue: wgpu::Queue,
    ) -> Self {
        record_device_for_test_plan();
        let wanted = TIMESTAMPS;
        let timestamps = device.features().contains(wanted);
        let errors = GpuErrors::install(&device);
        GpuContext {
            pipelines: pipeline_cache::PipelineCache::default(),
            instance,
            adapter,
            device,
            queue,
            timestamps,
            errors,
        }
    }

    /// `Err` with what the device reported outside error scopes since the last check (a
    /// validation error, running out of memory, a lost device).
    pub fn check(&self) -> Result<(), GpuError> {
        self.errors.check()
    }

    /// Adapter name and backend, for reports.
    pub fn describe(&self) -> String {
        let i = self.adapter.get_info();
        format!("{} ({:?}, {:?})", i.name, i.backend, i.device_type)
    }

    /// How many pipelines were compiled on this device (each once, for every renderer on
    /// it: [`pipeline_cache`]).
    pub fn pipelines_compiled(&self) -> u64 {
        self.pipelines.compiled()
    }

    /// Blocks until the GPU has finished all submitted work.
    pub fn wait_idle(&self) -> Result<(), GpuError> {
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(|e| GpuError::Readback(e.to_string()))
    }
}

/// For the test plan (`cargo xtask test`, `xtask/src/plan.rs`): when `TEXEL_GPU_TEST_LOG`
/// names a file, appends the running test's name (cargo-nextest's `NEXTEST_BINARY_ID` and
/// `NEXTEST_TEST_NAME`, `?` outside nextest) to it, one line per device opened. A `texel-run`
/// or `texel-eval` started by a test inherits both, so its device counts for that test. The
/// tests recorded on one driver are the ones the second driver runs; there, where a binary's
/// tests share one device, [`test_context`] records each test that takes it. Unset, it does
/// nothing.
fn record_device_for_test_plan() {
    use std::io::Write as _;
    let Some(path) = std::env::var_os("TEXEL_GPU_TEST_LOG") else {
        return;
    };
    let var = |key| std::env::var(key).unwrap_or_else(|_| "?".to_owned());
    let test = running_test();
    let line = format!(
        "{}\t{}\n",
        var("NEXTEST_BINARY_ID"),
        test.as_deref().unwrap_or("?")
    );
    // One write to a file opened for appending: lines of concurrent processes stay whole.
    let written = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(&path)
        .and_then(|mut file| file.write_all(line.as_bytes()));
    if let Err(e) = written {
        eprintln!(
            "warning: cannot record this GPU test in {}: {e}",
            path.to_string_lossy()
        );
    }
}

/// The limits asked of a device: wgpu's defaults, with the adapter's own texture sizes and
/// buffer sizes where it offers more (a level's vertices live in one buffer: a generated town
/// of 100,000 needs 602 MiB, against the default 256 MiB; lavapipe offers 2 GiB, SwiftShader
/// 1 GiB). What a scene needs is checked against them before upload
/// (`validate::scene`), with an error naming the limit.
fn required_limits(adapter: &wgpu::Limits) -> wgpu::Limits {
    let mut limits = wgpu::Limits::default().using_resolution(adapter.clone());
    limits.max_buffer_size = limits.max_buffer_size.max(adapter.max_buffer_size);
    limits.max_storage_buffer_binding_size =
        (limits.max_storage_buffer_binding_size).max(adapter.max_storage_buffer_binding_size);
    limits
}

/// How the device sizes its memory blocks: small ones (`MemoryUsage`: blocks of 8–64 MiB
/// rather than 128–256), since the renderer holds a few large buffers whose sizes follow the
/// level. With `Performance`, a town of 10,000's 53 MB vertex buffer took a 128 MiB block,
/// and on a CPU driver every block is the process's own memory. `TEXEL_MEMORY_HINTS=performance`
/// asks for wgpu's default instead (to compare).
fn memory_hints() -> wgpu::MemoryHints {
    match std::env::var("TEXEL_MEMORY_HINTS").as_deref() {
        Ok("performance") => wgpu::MemoryHints::Performance,
        _ => wgpu::MemoryHints::MemoryUsage,
    }
}

/// The features per-pass GPU timestamps need.
const TIMESTAMPS: wgpu::Features =
    wgpu::Features::TIMESTAMP_QUERY.union(wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS);

/// A wgpu instance with backends from `WGPU_BACKEND` (all primary backends by default).
pub fn new_instance() -> wgpu::Instance {
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
    if std::env::var_os("WGPU_BACKEND").is_none() {
        desc.backends = wgpu::Backends::PRIMARY;
    }
    wgpu::Instance::new(desc)
}

/// The running test's name: cargo-nextest's `NEXTEST_TEST_NAME`, or outside nextest the
/// name of the thread libtest runs each test on.
fn running_test() -> Option<String> {
    std::env::var("NEXTEST_TEST_NAME").ok().or_else(|| {
        (std::thread::current().name())
            .filter(|name| *name != "main")
            .map(str::to_owned)
    })
}

/// For the test plan: whether the running test is one `cargo xtask test` runs in a shorter
/// form on this driver. The second driver's pass names those tests in `TEXEL_SHORT_TESTS`
/// (comma-separated parts of test names: `SECOND_DRIVER_SHORT` in `xtask/src/plan.rs`, each
/// with its reason); such a test flies fewer frames of the same path and checks the same
/// kind of bound. Unset (every other run), false.
pub fn short_form() -> bool {
    let Ok(list) = std::env::var("TEXEL_SHORT_TESTS") else {
        return false;
    };
    let Some(test) = running_test() else {
        return false;
    };
    list.split(',')
        .map(str::trim)
        .any(|part| !part.is_empty() && test.contains(part))
}

/// For GPU tests: a headless context, one per process, shared by the tests of a test binary
/// that runs them in one process (libtest does; cargo-nextest runs each test in a process of
/// its own), so they open one device and compile each pipeline once. Without an adapter this
/// panics, so a GPU test can never pass without running; `TEXEL_ALLOW_NO_GPU=1` is the
/// explicit opt-out, under which it returns `None` and prints SKIPPED on stderr.
pub fn test_context() -> Option<GpuContext> {
    static SHARED: Mutex<Option<GpuContext>> = Mutex::new(None);
    let mut shared = SHARED.lock().unwrap_or_else(PoisonError::into_inner);
    if let Some(ctx) = shared.as_ref() {
        // The test uses a device as much as the one that opened it.
        record_device_for_test_plan();
        return Some(ctx.clone());
    }
    match GpuContext::headless() {
        Ok(ctx) => {
            // A run meant for one driver (SwiftShader, say) must not pass on another.
            if let Ok(want) = std::env::var("TEXEL_EXPECT_ADAPTER") {
                let name = ctx.adapter.get_info().name;
                assert!(
                    name.contains(&want),
                    "TEXEL_EXPECT_ADAPTER={want} but the adapter is `{name}`"
                );
            }
            *shared = Some(ctx.clone());
            Some(ctx)
        }
        Err(e) if std::env::var_os("TEXEL_ALLOW_NO_GPU").is_none() => panic!(
            "this test needs a GPU adapter and none could be opened: {e}\n\
             (set TEXEL_ALLOW_NO_GPU=1 to skip GPU tests instead)"
        ),
        Err(e) => {
            eprintln!("SKIPPED (no GPU, and TEXEL_ALLOW_NO_GPU is set): {e}");
            None
        }
    }
}
