//! Headless device: adapter from `WGPU_BACKEND` / `WGPU_ADAPTER_NAME` when set, else Vulkan first.

use crate::{Error, Result};
use serde::Serialize;

pub const INSTALL_HINT: &str = "no GPU adapter found. On Debian/Ubuntu install the Vulkan software driver: \
`sudo apt-get install -y mesa-vulkan-drivers libvulkan1` (lavapipe); or set WGPU_BACKEND / WGPU_ADAPTER_NAME to pick another adapter";

/// What the run record says about the adapter.
#[derive(Clone, Debug, Serialize)]
pub struct AdapterSummary {
    pub name: String,
    pub backend: String,
    pub device_type: String,
    pub driver: String,
    pub driver_info: String,
}

pub struct GpuContext {
    pub adapter: wgpu::Adapter,
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub summary: AdapterSummary,
    /// Timestamps are recorded only where they can be trusted (not on CPU adapters).
    pub timestamps_trusted: bool,
}

impl GpuContext {
    pub fn new() -> Result<Self> {
        pollster::block_on(Self::new_async())
    }

    async fn new_async() -> Result<Self> {
        // Vulkan first: probing GL as well would only add noise (lavapipe exposes both).
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
        let from_env = std::env::var_os("WGPU_BACKEND").is_some();
        if !from_env {
            desc.backends = wgpu::Backends::VULKAN;
        }
        let mut adapters = wgpu::Instance::new(desc).enumerate_adapters(wgpu::Backends::all()).await;
        if adapters.is_empty() && !from_env {
            let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
            adapters = instance.enumerate_adapters(wgpu::Backends::all()).await;
        }
        if let Ok(wanted) = std::env::var("WGPU_ADAPTER_NAME") {
            let wanted = wanted.to_lowercase();
            adapters.retain(|a| a.get_info().name.to_lowercase().contains(&wanted));
        }
        // Prefer Vulkan, then real GPUs over CPU devices; lavapipe also exposes a GL adapter.
        adapters.sort_by_key(|a| {
            let info = a.get_info();
            let backend_rank = match info.backend {
                wgpu::Backend::Vulkan => 0,
                wgpu::Backend::Metal | wgpu::Backend::Dx12 => 1,
                _ => 2,
            };
            let type_rank = match info.device_type {
                wgpu::DeviceType::DiscreteGpu => 0,
                wgpu::DeviceType::IntegratedGpu => 1,
                wgpu::DeviceType::VirtualGpu => 2,
                wgpu::DeviceType::Cpu => 3,
                wgpu::DeviceType::Other => 4,
            };
            (backend_rank, type_rank)
        });
        let adapter = adapters.into_iter().next().ok_or_else(|| Error::NoAdapter(INSTALL_HINT.to_string()))?;
        let info = adapter.get_info();
        // Request the adapter's real limits: 2048 array layers and large storage bindings matter here.
        let limits = adapter.limits();
        let wanted_features = wgpu::Features::TIMESTAMP_QUERY | wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS;
        let features = adapter.features() & wanted_features;
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("penumbra"),
                required_features: features,
                required_limits: limits,
                ..Default::default()
            })
            .await
            .map_err(|e| Error::Gpu(format!("request_device on {}: {e}", info.name)))?;
        let summary = AdapterSummary {
            name: info.name.clone(),
            backend: format!("{:?}", info.backend),
            device_type: format!("{:?}", info.device_type),
            driver: info.driver.clone(),
            driver_info: info.driver_info.clone(),
        };
        let timestamps_trusted =
            features.contains(wgpu::Features::TIMESTAMP_QUERY) && info.device_type != wgpu::DeviceType::Cpu;
        Ok(Self { adapter, device, queue, summary, timestamps_trusted })
    }

    pub fn limits(&self) -> wgpu::Limits {
        self.device.limits()
    }

    /// Waits until every submitted command has finished; one CPU↔GPU synchronisation.
    pub fn wait(&self) -> Result<()> {
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(|e| Error::Gpu(format!("poll: {e}")))
    }

    /// Text for `penumbra info`.
    pub fn describe(&self) -> String {
        let l = self.limits();
        let s = &self.summary;
        format!(
            "adapter:      {}\nbackend:      {}\ndevice type:  {}\ndriver:       {} ({})\ntimestamps:   {}\n\
             limits in use:\n  max_texture_dimension_2d      {}\n  max_texture_array_layers      {}\n  \
             max_storage_buffer_binding    {}\n  max_buffer_size               {}\n  max_compute_invocations/wg    {}\n  \
             max_compute_workgroups/dim    {}\n  max_compute_workgroup_storage {}\n  max_bind_groups               {}\n  \
             max_sampled_textures/stage    {}\n  max_storage_buffers/stage     {}",
            s.name,
            s.backend,
            s.device_type,
            s.driver,
            s.driver_info,
            if self.timestamps_trusted { "trusted (GPU timestamps recorded)" } else { "not trusted on this adapter (wall clock only)" },
            l.max_texture_dimension_2d,
            l.max_texture_array_layers,
            l.max_storage_buffer_binding_size,
            l.max_buffer_size,
            l.max_compute_invocations_per_workgroup,
            l.max_compute_workgroups_per_dimension,
            l.max_compute_workgroup_storage_size,
            l.max_bind_groups,
            l.max_sampled_textures_per_shader_stage,
            l.max_storage_buffers_per_shader_stage,
        )
    }
}
