//! What the device can allocate, and what happens when an allocation fails anyway. The size plan
//! (`size_plan`) refuses a frame before anything is created; whatever still fails (another process
//! holding device memory, a limit the plan does not know) is caught here as one error instead of
//! wgpu's default handler, which panics.

use crate::{Error, Result};
use std::sync::{Arc, Mutex};

/// The largest device-local memory heap, in bytes: one allocation (a texture array, a buffer)
/// must fit in one heap. wgpu does not report it, so it is read from Vulkan through wgpu-hal; None
/// on other backends. lavapipe reports one heap of 2 GiB, whatever the host's memory.
pub(crate) fn largest_heap(adapter: &wgpu::Adapter) -> Option<u64> {
    // SAFETY: the hal adapter is only read (its instance and physical device), never destroyed,
    // and the guard is dropped before this returns.
    let hal = unsafe { adapter.as_hal::<wgpu::hal::api::Vulkan>() }?;
    let instance = hal.shared_instance().raw_instance();
    // SAFETY: the physical device belongs to this instance, which the adapter keeps alive.
    let props =
        unsafe { instance.get_physical_device_memory_properties(hal.raw_physical_device()) };
    // VK_MEMORY_HEAP_DEVICE_LOCAL_BIT is bit 0.
    props
        .memory_heaps_as_slice()
        .iter()
        .filter(|h| h.flags.as_raw() & 1 != 0)
        .map(|h| h.size)
        .max()
}

/// The first error no scope caught, kept for the next `GpuContext::wait` to return.
pub(crate) type Uncaptured = Arc<Mutex<Option<String>>>;

/// Replaces wgpu's default handler (a panic, exit 101) on a device this crate requested: the
/// first error is kept, one line, and the next wait returns it.
pub(crate) fn keep_uncaptured(device: &wgpu::Device) -> Uncaptured {
    let slot: Uncaptured = Arc::default();
    let kept = slot.clone();
    device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
        let mut first = kept.lock().unwrap_or_else(|p| p.into_inner());
        first.get_or_insert_with(|| one_line(&e));
    }));
    slot
}

/// Runs `create` inside out-of-memory and validation error scopes: an allocation the device
/// refuses becomes `what: …`, one line, instead of an uncaptured error.
pub(crate) fn scoped<T>(
    device: &wgpu::Device,
    what: &str,
    create: impl FnOnce() -> Result<T>,
) -> Result<T> {
    let validation = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let memory = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
    let made = create();
    let oom = pollster::block_on(memory.pop());
    let invalid = pollster::block_on(validation.pop());
    match oom.or(invalid) {
        Some(e) => Err(Error::Gpu(format!("{what}: {}", one_line(&e)))),
        None => made,
    }
}

/// wgpu's error text spans lines (a header, then the source chain): one line, sources joined.
fn one_line(e: &wgpu::Error) -> String {
    let mut text = e.to_string();
    let mut source = std::error::Error::source(e);
    while let Some(s) = source {
        let part = s.to_string();
        if !text.contains(&part) {
            text += ": ";
            text += &part;
        }
        source = s.source();
    }
    text.split('\n')
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect::<Vec<_>>()
        .join("; ")
}
