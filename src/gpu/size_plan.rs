//! A frame's sizes, checked before any GPU work: every buffer, binding, texture side and texture
//! array the frame and its method will create, against the device's limits by their wgpu names and
//! against the most the device can allocate at once (its largest memory heap), and the host memory
//! the frame needs against what /proc/meminfo says is available. Past a limit wgpu would end the
//! process with a validation or out-of-memory error, and the host would abort on out of memory;
//! this gives one line.

use crate::{Error, Result};

/// Which limit a size is held to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Bound {
    /// A storage buffer bound whole by one binding: `max_storage_buffer_binding_size` and
    /// `max_buffer_size`.
    Binding,
    /// A storage buffer bound in ranges of whole rows, `row` bytes each: the buffer must fit
    /// `max_buffer_size` and one row `max_storage_buffer_binding_size`.
    RowChunks { row: u64 },
    /// A buffer only copied (staging, read-backs): `max_buffer_size`.
    Buffer,
    /// The side of a 2D texture, in texels: `max_texture_dimension_2d`.
    TextureSide,
    /// A texture array of `layers` layers, `amount` bytes in all: `max_texture_array_layers`, and
    /// one allocation, so at most the device's largest memory heap.
    Array { layers: u32 },
}

/// What the device allows: its limits, and the most it can allocate at once (None: not known).
#[derive(Clone, Debug)]
pub struct DeviceBounds {
    pub limits: wgpu::Limits,
    /// The largest device-local memory heap, in bytes (`GpuContext::largest_heap`).
    pub largest_heap: Option<u64>,
}

/// One size: what it is (the buffer's label), how large (bytes, or texels for a side), which limit.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SizeNeed {
    pub what: String,
    pub amount: u64,
    pub bound: Bound,
    /// The setting that sizes it, when not the plan's (the resolution): `shadow_map_size = 100000`.
    pub(crate) setting: Option<String>,
}

impl SizeNeed {
    pub(crate) fn binding(what: impl Into<String>, bytes: u64) -> Self {
        Self {
            what: what.into(),
            amount: bytes,
            bound: Bound::Binding,
            setting: None,
        }
    }
    pub(crate) fn rows(what: impl Into<String>, bytes: u64, row: u64) -> Self {
        Self {
            what: what.into(),
            amount: bytes,
            bound: Bound::RowChunks { row },
            setting: None,
        }
    }
    pub(crate) fn buffer(what: impl Into<String>, bytes: u64) -> Self {
        Self {
            what: what.into(),
            amount: bytes,
            bound: Bound::Buffer,
            setting: None,
        }
    }
    pub(crate) fn side(what: impl Into<String>, texels: u64) -> Self {
        Self {
            what: what.into(),
            amount: texels,
            bound: Bound::TextureSide,
            setting: None,
        }
    }
    pub(crate) fn array(what: impl Into<String>, bytes: u64, layers: u32) -> Self {
        Self {
            what: what.into(),
            amount: bytes,
            bound: Bound::Array { layers },
            setting: None,
        }
    }

    /// Names `setting` in the error instead of the plan's.
    pub(crate) fn sized_by(mut self, setting: impl Into<String>) -> Self {
        self.setting = Some(setting.into());
        self
    }

    /// The first limit this size passes: the limit's wgpu name and value.
    fn over(&self, d: &DeviceBounds) -> Option<(&'static str, u64)> {
        let l = &d.limits;
        let buffer = ("max_buffer_size", l.max_buffer_size);
        let binding = (
            "max_storage_buffer_binding_size",
            l.max_storage_buffer_binding_size,
        );
        let side = (
            "max_texture_dimension_2d",
            l.max_texture_dimension_2d as u64,
        );
        let layers = (
            "max_texture_array_layers",
            l.max_texture_array_layers as u64,
        );
        let heap = (HEAP, d.largest_heap.unwrap_or(u64::MAX));
        let checks: &[((&'static str, u64), u64)] = match self.bound {
            Bound::Binding => &[(buffer, self.amount), (binding, self.amount)],
            Bound::RowChunks { row } => &[(buffer, self.amount), (binding, row)],
            Bound::Buffer => &[(buffer, self.amount)],
            Bound::TextureSide => &[(side, self.amount)],
            Bound::Array { layers: n } => &[(layers, n as u64), (heap, self.amount)],
        };
        checks
            .iter()
            .find(|&&((_, limit), amount)| amount > limit)
            .map(|&(limit, _)| limit)
    }
}

/// Everything one frame creates, for the setting that sizes it (`resolution = 6000`).
#[derive(Clone, Debug)]
pub struct SizePlan {
    /// The setting, as the one-line error names it.
    pub(crate) setting: String,
    pub needs: Vec<SizeNeed>,
    /// Host memory the frame needs at its peak: read-backs, the CPU G-buffer, images, and on a
    /// CPU device (lavapipe) the device's own buffers and textures, which live in host memory.
    pub host_bytes: u64,
    /// The setting that sizes most of `host_bytes`, when not the plan's (a shadow-map budget).
    pub(crate) host_setting: Option<String>,
}

/// How the one-line error names the device's largest memory heap.
const HEAP: &str = "largest memory heap (one allocation must fit in one heap)";

impl SizePlan {
    /// The first size over a device limit, then the host memory against `available` (None: not
    /// known, not checked), as one line naming the setting, the size and the limit.
    pub fn check(&self, device: &DeviceBounds, available: Option<u64>) -> Result<()> {
        let limits = &device.limits;
        for need in &self.needs {
            if let Some((name, limit)) = need.over(device) {
                let amount = match need.bound {
                    Bound::TextureSide => format!("a side of {} texels", need.amount),
                    Bound::RowChunks { row } if need.amount <= limits.max_buffer_size => {
                        format!("{row} bytes per row, bound at least a row at a time")
                    }
                    Bound::Array { layers } if name != HEAP => format!("{layers} layers"),
                    Bound::Array { .. } => format!("{} bytes ({})", need.amount, gib(need.amount)),
                    _ => format!("{} bytes", need.amount),
                };
                // One array past the heap: a lower budget splits its maps into smaller arrays.
                let limit = if name == HEAP {
                    format!(
                        "{limit} ({}); lower it to split the maps into smaller arrays",
                        gib(limit)
                    )
                } else {
                    limit.to_string()
                };
                let setting = need.setting.as_deref().unwrap_or(&self.setting);
                return Err(Error::Limit(format!(
                    "{setting}: {} needs {amount}, over this device's {name} {limit}",
                    need.what
                )));
            }
        }
        if let Some(available) = available {
            if self.host_bytes > available {
                return Err(Error::Limit(format!(
                    "{}: the frame needs about {} of host memory (G-buffer read-back, V, images, and the device's memory on a CPU device), over the {} available (MemAvailable in /proc/meminfo)",
                    self.host_setting.as_deref().unwrap_or(&self.setting),
                    gib(self.host_bytes),
                    gib(available)
                )));
            }
        }
        Ok(())
    }
}

fn gib(bytes: u64) -> String {
    format!("{:.1} GiB", bytes as f64 / (1u64 << 30) as f64)
}

/// MemAvailable from /proc/meminfo, in bytes; None where there is no such file (not Linux).
pub fn mem_available() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    parse_mem_available(&text)
}

fn parse_mem_available(meminfo: &str) -> Option<u64> {
    let line = meminfo.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line
        .trim_start_matches("MemAvailable:")
        .trim()
        .trim_end_matches("kB")
        .trim()
        .parse()
        .ok()?;
    Some(kib * 1024)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lavapipe() -> wgpu::Limits {
        wgpu::Limits {
            max_storage_buffer_binding_size: 134_217_728,
            max_buffer_size: 2_147_483_647,
            max_texture_dimension_2d: 16384,
            max_texture_array_layers: 2048,
            ..Default::default()
        }
    }

    fn device(largest_heap: Option<u64>) -> DeviceBounds {
        DeviceBounds {
            limits: lavapipe(),
            largest_heap,
        }
    }

    fn plan(needs: Vec<SizeNeed>, host_bytes: u64) -> SizePlan {
        SizePlan {
            setting: "resolution = 6000".into(),
            needs,
            host_bytes,
            host_setting: None,
        }
    }

    #[test]
    fn each_bound_names_its_limit() {
        let l = device(None);
        let err = |p: SizePlan| p.check(&l, Some(1 << 40)).unwrap_err().to_string();
        assert_eq!(
            err(plan(vec![SizeNeed::binding("V (visibility)", 144_000_000)], 0)),
            "resolution = 6000: V (visibility) needs 144000000 bytes, over this device's max_storage_buffer_binding_size 134217728"
        );
        assert_eq!(
            err(plan(vec![SizeNeed::buffer("G-buffer read-back", 4 << 30)], 0)),
            "resolution = 6000: G-buffer read-back needs 4294967296 bytes, over this device's max_buffer_size 2147483647"
        );
        assert_eq!(
            err(plan(vec![SizeNeed::side("the G-buffer", 20000)], 0)),
            "resolution = 6000: the G-buffer needs a side of 20000 texels, over this device's max_texture_dimension_2d 16384"
        );
        // Chunked: the whole buffer may pass the binding limit, one row may not.
        assert!(plan(vec![SizeNeed::rows("V", 144_000_000, 24_000)], 0)
            .check(&l, None)
            .is_ok());
        assert_eq!(
            err(plan(vec![SizeNeed::rows("V", 1 << 30, 200_000_000)], 0)),
            "resolution = 6000: V needs 200000000 bytes per row, bound at least a row at a time, over this device's max_storage_buffer_binding_size 134217728"
        );
        assert_eq!(
            err(plan(vec![SizeNeed::rows("V", 3 << 30, 1024)], 0)),
            "resolution = 6000: V needs 3221225472 bytes, over this device's max_buffer_size 2147483647"
        );
    }

    #[test]
    fn an_array_is_one_allocation_within_the_largest_heap_and_the_layer_limit() {
        let maps = |layers: u32| {
            SizeNeed::array("the shadow-map array", layers as u64 * (64 << 20), layers)
                .sized_by("shadow_map_budget_mib = 4096")
        };
        let lavapipe = device(Some(2 << 30));
        // 32 maps of 4096² are exactly the 2 GiB heap; 36 are over it.
        assert!(plan(vec![maps(32)], 0).check(&lavapipe, None).is_ok());
        assert_eq!(
            plan(vec![maps(36)], 0).check(&lavapipe, None).unwrap_err().to_string(),
            "shadow_map_budget_mib = 4096: the shadow-map array needs 2415919104 bytes (2.2 GiB), over this device's largest memory heap (one allocation must fit in one heap) 2147483648 (2.0 GiB); lower it to split the maps into smaller arrays"
        );
        // Without a known heap only the layer limit holds it.
        assert!(plan(vec![maps(36)], 0).check(&device(None), None).is_ok());
        assert_eq!(
            plan(vec![SizeNeed::array("the shadow-map array", 4096, 4096)], 0).check(&device(None), None).unwrap_err().to_string(),
            "resolution = 6000: the shadow-map array needs 4096 layers, over this device's max_texture_array_layers 2048"
        );
    }

    #[test]
    fn host_memory_names_the_setting_that_sizes_most_of_it() {
        let mut p = plan(vec![], 3 << 30);
        p.host_setting = Some("shadow_map_budget_mib = 100000".into());
        let e = p
            .check(&device(None), Some(2 << 30))
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with(
                "shadow_map_budget_mib = 100000: the frame needs about 3.0 GiB of host memory"
            ),
            "{e}"
        );
    }

    #[test]
    fn host_memory_is_checked_after_the_device_limits() {
        let l = device(None);
        let p = plan(vec![SizeNeed::binding("V", 1 << 20)], 3 << 30);
        assert!(p.check(&l, None).is_ok());
        assert!(p.check(&l, Some(4 << 30)).is_ok());
        assert_eq!(
            p.check(&l, Some(2 << 30)).unwrap_err().to_string(),
            "resolution = 6000: the frame needs about 3.0 GiB of host memory (G-buffer read-back, V, images, and the device's memory on a CPU device), over the 2.0 GiB available (MemAvailable in /proc/meminfo)"
        );
    }

    #[test]
    fn mem_available_is_read_in_kib() {
        assert_eq!(
            parse_mem_available("MemTotal:       24684000 kB\nMemAvailable:   23882840 kB\n"),
            Some(23_882_840 * 1024)
        );
        assert_eq!(parse_mem_available("MemTotal: 1 kB\n"), None);
    }
}
