//! Headless device on the adapter `gpu::adapter::choose` picks (Vulkan first); the request is a
//! parameter, never read from the environment here (the binary maps `--backend` and `WGPU_BACKEND`).

use super::adapter::{self, AdapterRequest, BackendChoice, Candidate};
use super::allocation::{self, Uncaptured};
use super::size_plan::DeviceBounds;
use crate::{Error, Result};
use serde::Serialize;

/// What the run record says about the adapter.
#[derive(Clone, Debug, Serialize)]
pub struct AdapterSummary {
    pub name: String,
    pub backend: String,
    pub device_type: String,
    pub driver: String,
    pub driver_info: String,
    /// Why this adapter was chosen.
    pub(crate) chosen_because: String,
}

pub struct GpuContext {
    pub adapter: wgpu::Adapter,
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub summary: AdapterSummary,
    /// Timestamps are recorded only where they can be trusted (not on CPU adapters).
    pub timestamps_trusted: bool,
    /// The largest device-local memory heap (`allocation::largest_heap`): the most one allocation
    /// may take. None where the backend does not say.
    pub largest_heap: Option<u64>,
    /// The first device error no scope caught, on a device requested here; `wait` returns it.
    uncaptured: Option<Uncaptured>,
}

impl GpuContext {
    /// The best usable adapter, Vulkan first.
    pub fn new() -> Result<Self> {
        Self::with_request(&AdapterRequest::default())
    }

    pub fn with_request(req: &AdapterRequest) -> Result<Self> {
        pollster::block_on(Self::new_async(req, None))
    }

    /// Tests: a device whose storage bindings are capped at `bytes` (a multiple of 256), so a small
    /// frame takes the chunked paths a large one takes on the real limit.
    pub fn with_binding_cap(req: &AdapterRequest, bytes: u64) -> Result<Self> {
        pollster::block_on(Self::new_async(req, Some(bytes)))
    }

    async fn enumerate(backends: wgpu::Backends) -> Vec<wgpu::Adapter> {
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
        desc.backends = backends;
        wgpu::Instance::new(desc).enumerate_adapters(backends).await
    }

    async fn new_async(req: &AdapterRequest, binding_cap: Option<u64>) -> Result<Self> {
        // Auto probes Vulkan alone first: probing GL as well would only add noise (lavapipe exposes
        // both), and GL is looked at only when no Vulkan adapter can run the pipeline.
        let mut adapters = Self::enumerate(if req.backend == BackendChoice::Auto {
            wgpu::Backends::VULKAN
        } else {
            req.backend.backends()
        })
        .await;
        let mut candidates: Vec<Candidate> = adapters.iter().map(Candidate::of).collect();
        let mut choice = adapter::choose(&candidates, req);
        if choice.is_err() && req.backend == BackendChoice::Auto {
            adapters = Self::enumerate(wgpu::Backends::all()).await;
            candidates = adapters.iter().map(Candidate::of).collect();
            choice = adapter::choose(&candidates, req);
        }
        let choice = choice?;
        let adapter = adapters.swap_remove(choice.index);
        let info = adapter.get_info();
        // Request the adapter's real limits: 2048 array layers and large storage bindings matter here.
        let mut limits = adapter.limits();
        if let Some(cap) = binding_cap {
            limits.max_storage_buffer_binding_size =
                limits.max_storage_buffer_binding_size.min(cap);
        }
        // INDIRECT_FIRST_INSTANCE: culled shadow-map draws select their sample by first instance.
        let wanted_features = wgpu::Features::TIMESTAMP_QUERY
            | wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS
            | wgpu::Features::INDIRECT_FIRST_INSTANCE;
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
        let uncaptured = allocation::keep_uncaptured(&device);
        let mut ctx = Self::from_device(adapter, device, queue, choice.reason);
        ctx.uncaptured = Some(uncaptured);
        Ok(ctx)
    }

    /// A context on a device someone else requested (the embedding API: the caller's device);
    /// `chosen_because` is the run record's reason for the adapter.
    pub(crate) fn from_device(
        adapter: wgpu::Adapter,
        device: wgpu::Device,
        queue: wgpu::Queue,
        chosen_because: String,
    ) -> Self {
        let info = adapter.get_info();
        let summary = AdapterSummary {
            name: info.name.clone(),
            backend: format!("{:?}", info.backend),
            device_type: format!("{:?}", info.device_type),
            driver: info.driver.clone(),
            driver_info: info.driver_info.clone(),
            chosen_because,
        };
        let timestamps_trusted = device.features().contains(wgpu::Features::TIMESTAMP_QUERY)
            && info.device_type != wgpu::DeviceType::Cpu;
        // The caller's device keeps the caller's error handler.
        let largest_heap = allocation::largest_heap(&adapter);
        Self {
            adapter,
            device,
            queue,
            summary,
            timestamps_trusted,
            largest_heap,
            uncaptured: None,
        }
    }

    pub fn limits(&self) -> wgpu::Limits {
        self.device.limits()
    }

    /// The limits and the largest heap, as the size plan checks them.
    pub(crate) fn bounds(&self) -> DeviceBounds {
        DeviceBounds {
            limits: self.limits(),
            largest_heap: self.largest_heap,
        }
    }

    /// Runs `create` (buffers, textures, pipelines) inside error scopes: what the device refuses
    /// becomes `Error::Gpu("{what}: …")`, one line (`allocation::scoped`).
    pub fn scoped<T>(&self, what: &str, create: impl FnOnce() -> Result<T>) -> Result<T> {
        allocation::scoped(&self.device, what, create)
    }

    /// Waits until every submitted command has finished; one CPU↔GPU synchronisation. A device
    /// error that no scope caught since the last wait is returned here.
    pub fn wait(&self) -> Result<()> {
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(|e| Error::Gpu(format!("poll: {e}")))?;
        let kept = self
            .uncaptured
            .as_ref()
            .and_then(|u| u.lock().unwrap_or_else(|p| p.into_inner()).take());
        kept.map_or(Ok(()), |e| Err(Error::Gpu(e)))
    }

    /// Text for `penumbra info`.
    pub fn describe(&self) -> String {
        let l = self.limits();
        let s = &self.summary;
        format!(
            "adapter:      {}\nbackend:      {}\nchosen:       {}\ndevice type:  {}\ndriver:       {} ({})\ntimestamps:   {}\n\
             largest heap: {}\n\
             limits in use:\n  max_texture_dimension_2d      {}\n  max_texture_array_layers      {}\n  \
             max_storage_buffer_binding_size {}\n  min_storage_buffer_offset_alignment {}\n  max_buffer_size               {}\n  max_compute_invocations/wg    {}\n  \
             max_compute_workgroups/dim    {}\n  max_compute_workgroup_storage {}\n  max_bind_groups               {}\n  \
             max_sampled_textures/stage    {}\n  max_storage_buffers/stage     {}",
            s.name,
            s.backend,
            s.chosen_because,
            s.device_type,
            s.driver,
            s.driver_info,
            if self.timestamps_trusted { "trusted (GPU timestamps recorded)" } else { "not trusted on this adapter (wall clock only)" },
            self.largest_heap.map_or("not known on this backend".to_string(), |b| format!("{b} bytes (the most one allocation may take)")),
            l.max_texture_dimension_2d,
            l.max_texture_array_layers,
            l.max_storage_buffer_binding_size,
            l.min_storage_buffer_offset_alignment,
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
