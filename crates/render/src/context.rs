//! The GPU context: instance, adapter, device and queue, headless or for a window.

use std::fmt;

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
}

/// An open GPU: everything the passes need to create resources and submit work.
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
        let wanted =
            wgpu::Features::TIMESTAMP_QUERY | wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS;
        let features = adapter.features() & wanted;
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("texel::device"),
                required_features: features,
                required_limits: wgpu::Limits::default().using_resolution(adapter.limits()),
                ..Default::default()
            })
            .await
            .map_err(|source| GpuError::Device {
                adapter: adapter.get_info().name,
                source,
            })?;
        Ok(GpuContext {
            instance,
            adapter,
            device,
            queue,
            timestamps: features.contains(wanted),
        })
    }

    /// Adapter name and backend, for reports.
    pub fn describe(&self) -> String {
        let i = self.adapter.get_info();
        format!("{} ({:?}, {:?})", i.name, i.backend, i.device_type)
    }

    /// Blocks until the GPU has finished all submitted work.
    pub fn wait_idle(&self) -> Result<(), GpuError> {
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(|e| GpuError::Readback(e.to_string()))
    }
}

/// A wgpu instance with backends from `WGPU_BACKEND` (all primary backends by default).
pub fn new_instance() -> wgpu::Instance {
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
    if std::env::var_os("WGPU_BACKEND").is_none() {
        desc.backends = wgpu::Backends::PRIMARY;
    }
    wgpu::Instance::new(desc)
}

/// For GPU tests: a headless context, or `None` (with a message on stderr) when no adapter
/// exists — unless `TEXEL_REQUIRE_GPU` is set, as in CI, where that is a failure.
pub fn test_context() -> Option<GpuContext> {
    match GpuContext::headless() {
        Ok(ctx) => Some(ctx),
        Err(e) if std::env::var_os("TEXEL_REQUIRE_GPU").is_some() => {
            panic!("TEXEL_REQUIRE_GPU is set but the GPU cannot be opened: {e}")
        }
        Err(e) => {
            eprintln!("SKIPPED (no GPU; set TEXEL_REQUIRE_GPU=1 to make this a failure): {e}");
            None
        }
    }
}
