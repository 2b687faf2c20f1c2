//! Headless wgpu device: a hardware adapter when there is one, else any
//! adapter (Mesa's lavapipe, a software Vulkan driver).

use std::fmt;

/// Debian/Ubuntu packages that provide a software Vulkan adapter.
pub const SOFTWARE_VULKAN_PACKAGES: &str = "mesa-vulkan-drivers libvulkan1";

/// Errors from setting up the GPU.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    #[error(
        "no GPU adapter found (wgpu, Vulkan backend). Install a Vulkan driver; for Mesa's software \
         renderer lavapipe on Debian/Ubuntu: `apt-get install {SOFTWARE_VULKAN_PACKAGES}` \
         (package `mesa-vulkan-drivers`)"
    )]
    NoAdapter,
    // The reason is in the message, not also a `source()` (printed twice
    // by reporters of the chain).
    #[error("cannot open a device on adapter '{adapter}': {cause}")]
    Device {
        adapter: String,
        cause: wgpu::RequestDeviceError,
    },
    #[error("{0}")]
    Unsupported(String),
    #[error("GPU error: {0}")]
    Wgpu(String),
}

/// What `penumbra info --gpu` prints about the adapter.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AdapterSummary {
    pub name: String,
    pub backend: String,
    pub device_type: String,
    pub driver: String,
    pub driver_info: String,
    pub vendor: u32,
    pub device: u32,
}

impl AdapterSummary {
    pub fn from_info(info: &wgpu::AdapterInfo) -> Self {
        Self {
            name: info.name.clone(),
            backend: format!("{:?}", info.backend),
            device_type: match info.device_type {
                wgpu::DeviceType::DiscreteGpu => "discrete GPU",
                wgpu::DeviceType::IntegratedGpu => "integrated GPU",
                wgpu::DeviceType::VirtualGpu => "virtual GPU",
                wgpu::DeviceType::Cpu => "CPU (software)",
                wgpu::DeviceType::Other => "other",
            }
            .to_string(),
            driver: info.driver.clone(),
            driver_info: info.driver_info.clone(),
            vendor: info.vendor,
            device: info.device,
        }
    }

    /// True for software rasterisers such as lavapipe.
    pub fn is_software(&self) -> bool {
        self.device_type.starts_with("CPU")
    }
}

impl fmt::Display for AdapterSummary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} ({}, {}, driver {} {})",
            self.name, self.backend, self.device_type, self.driver, self.driver_info
        )
    }
}

/// A wgpu device and queue without a window.
#[derive(Debug)]
pub struct GpuContext {
    pub instance: wgpu::Instance,
    pub adapter: wgpu::Adapter,
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub summary: AdapterSummary,
}

impl GpuContext {
    /// Opens a device: first a high-performance adapter, then the fallback
    /// (CPU) adapter, then whatever adapter the backends enumerate.
    pub fn new() -> Result<Self, GpuError> {
        pollster::block_on(Self::new_async())
    }

    async fn new_async() -> Result<Self, GpuError> {
        let desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
        let instance = wgpu::Instance::new(desc);
        let mut adapter = None;
        for force_fallback_adapter in [false, true] {
            let options = wgpu::RequestAdapterOptions {
                power_preference: wgpu::PowerPreference::HighPerformance,
                force_fallback_adapter,
                compatible_surface: None,
                ..Default::default()
            };
            if let Ok(a) = instance.request_adapter(&options).await {
                adapter = Some(a);
                break;
            }
        }
        if adapter.is_none() {
            adapter = instance
                .enumerate_adapters(wgpu::Backends::all())
                .await
                .into_iter()
                .next();
        }
        let adapter = adapter.ok_or(GpuError::NoAdapter)?;
        let summary = AdapterSummary::from_info(&adapter.get_info());
        // Format-specific features let 4× MSAA use an Rgba32Float target
        // where the driver allows it; timestamps where there are any.
        // Depth32FloatStencil8 keeps float depth for the stencil shadows.
        let wanted = wgpu::Features::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES
            | wgpu::Features::TIMESTAMP_QUERY
            | wgpu::Features::DEPTH32FLOAT_STENCIL8;
        let required_features = adapter.features() & wanted;
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("penumbra"),
                required_features,
                required_limits: adapter.limits(),
                ..Default::default()
            })
            .await
            .map_err(|cause| GpuError::Device {
                adapter: summary.name.clone(),
                cause,
            })?;
        Ok(Self {
            instance,
            adapter,
            device,
            queue,
            summary,
        })
    }

    /// Waits until the queue has finished all submitted work.
    pub fn wait_idle(&self) -> Result<(), GpuError> {
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(|e| GpuError::Wgpu(e.to_string()))
    }
}
