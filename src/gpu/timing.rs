//! Wall-clock per stage (submit → wait) and per frame. On CPU adapters GPU timestamps are not
//! trustworthy, so wall clock is the figure every report quotes, labelled as such.

use crate::gpu::GpuContext;
use crate::Result;
use std::collections::BTreeMap;
use std::time::Instant;

#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum TimingMode {
    /// Wait after every stage so each stage's wall time is known (adds waits).
    Stages,
    /// Only the waits the algorithm needs; the frame's wall time is the figure.
    Frame,
}

pub struct StageTimer {
    pub mode: TimingMode,
    pub stages_ms: BTreeMap<String, f64>,
    /// Waits added only to time stages (not counted as the algorithm's syncs).
    pub timing_waits: u32,
    pending: Option<wgpu::CommandEncoder>,
    gpu: Option<GpuTimestamps>,
}

/// GPU timestamps around every stage's commands, on adapters where they can be trusted.
struct GpuTimestamps {
    queries: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    capacity: u32,
    labels: Vec<String>,
    period_ns: f32,
}

/// Timestamp pairs one frame can hold; stages beyond it go untimed on the GPU clock.
const TIMESTAMP_CAPACITY: u32 = 1024;

impl StageTimer {
    pub fn new(mode: TimingMode) -> Self {
        Self { mode, stages_ms: BTreeMap::new(), timing_waits: 0, pending: None, gpu: None }
    }

    /// Also records GPU timestamps when the adapter's are trusted, or when `forced` (tests, on CPU
    /// adapters where the figures mean little).
    pub fn with_gpu_timestamps(mut self, ctx: &GpuContext, forced: bool) -> Self {
        let features = ctx.device.features();
        let able = features.contains(wgpu::Features::TIMESTAMP_QUERY | wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS);
        if able && (ctx.timestamps_trusted || forced) {
            let capacity = TIMESTAMP_CAPACITY * 2;
            self.gpu = Some(GpuTimestamps {
                queries: ctx.device.create_query_set(&wgpu::QuerySetDescriptor {
                    label: Some("stage timestamps"),
                    ty: wgpu::QueryType::Timestamp,
                    count: capacity,
                }),
                resolve: ctx.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("timestamp resolve"),
                    size: capacity as u64 * 8,
                    usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                    mapped_at_creation: false,
                }),
                capacity,
                labels: Vec::new(),
                period_ns: ctx.queue.get_timestamp_period(),
            });
        }
        self
    }

    /// Reads the GPU timestamps back (one synchronisation, after the frame) as milliseconds per stage.
    pub fn gpu_stages_ms(&mut self, ctx: &GpuContext) -> Result<Option<BTreeMap<String, f64>>> {
        let Some(g) = &self.gpu else { return Ok(None) };
        let used = g.labels.len() as u32 * 2;
        if used == 0 {
            return Ok(Some(BTreeMap::new()));
        }
        let mut enc = ctx.device.create_command_encoder(&Default::default());
        enc.resolve_query_set(&g.queries, 0..used, &g.resolve, 0);
        let staging = crate::gpu::readback::stage_copy(ctx, &mut enc, &g.resolve, used as u64 * 8);
        ctx.queue.submit([enc.finish()]);
        let ticks: Vec<u64> = crate::gpu::readback::map_staging(ctx, &staging)?;
        let mut out = BTreeMap::new();
        for (i, label) in g.labels.iter().enumerate() {
            let ns = ticks[2 * i + 1].saturating_sub(ticks[2 * i]) as f64 * g.period_ns as f64;
            *out.entry(label.clone()).or_insert(0.0) += ns / 1e6;
        }
        Ok(Some(out))
    }

    /// Records one stage into an encoder; in `Stages` mode submits and waits, charging the time to `name`.
    pub fn stage<T>(
        &mut self,
        ctx: &GpuContext,
        name: &str,
        record: impl FnOnce(&mut wgpu::CommandEncoder) -> Result<T>,
    ) -> Result<T> {
        let start = Instant::now();
        let mut encoder =
            self.pending.take().unwrap_or_else(|| ctx.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some(name) }));
        let slot = match &mut self.gpu {
            Some(g) if (g.labels.len() as u32 + 1) * 2 <= g.capacity => {
                let slot = g.labels.len() as u32 * 2;
                g.labels.push(name.to_string());
                encoder.write_timestamp(&g.queries, slot);
                Some(slot)
            }
            _ => None,
        };
        let out = record(&mut encoder)?;
        if let (Some(slot), Some(g)) = (slot, &self.gpu) {
            encoder.write_timestamp(&g.queries, slot + 1);
        }
        match self.mode {
            TimingMode::Stages => {
                ctx.queue.submit([encoder.finish()]);
                ctx.wait()?;
                self.timing_waits += 1;
            }
            TimingMode::Frame => self.pending = Some(encoder),
        }
        self.add(name, start.elapsed().as_secs_f64() * 1e3);
        Ok(out)
    }

    /// Submits whatever is recorded (before a read-back the algorithm needs).
    pub fn flush(&mut self, ctx: &GpuContext) {
        if let Some(encoder) = self.pending.take() {
            ctx.queue.submit([encoder.finish()]);
        }
    }

    pub fn add(&mut self, name: &str, ms: f64) {
        *self.stages_ms.entry(name.to_string()).or_insert(0.0) += ms;
    }

    /// Times CPU-side work (and read-backs) under `name`.
    pub fn cpu<T>(&mut self, name: &str, f: impl FnOnce() -> Result<T>) -> Result<T> {
        let start = Instant::now();
        let out = f()?;
        self.add(name, start.elapsed().as_secs_f64() * 1e3);
        Ok(out)
    }
}

/// Where a stage's time belongs. Every frame splits into raster (the G-buffer, shadow maps and
/// what prepares them: cull, moments, blur), decision (the adaptive counting, subdivision,
/// compaction, probe and weights), shade (every lookup of a map: shadow_test, shade and the filters) and
/// waits (the read-backs: per level, pictures, V). Work outside the frame (setup) has none.
pub fn split_of(stage: &str) -> Option<&'static str> {
    Some(match stage {
        "gbuffer" | "shadow_raster" | "cull" | "moments" | "blur" => "raster",
        "reproject_count" | "neighbourhood" | "quad_count" | "subdivide" | "compact" | "probe" | "weights" => "decision",
        "shade" | "shadow_test" | "pcf" | "pcss" | "reconstruct" => "shade",
        "readback_level" | "readback" | "pictures" => "waits",
        "setup" | "build" | "upload" => return None,
        _ => "other",
    })
}

/// The frame split (raster, decision, shade, waits; `other` only for a stage `split_of` does not
/// know) from per-stage times. Meaningful from a stages-mode frame, whose stages hold their waits.
pub fn frame_split(stages_ms: &BTreeMap<String, f64>) -> BTreeMap<&'static str, f64> {
    let mut out: BTreeMap<&'static str, f64> = ["raster", "decision", "shade", "waits"].into_iter().map(|k| (k, 0.0)).collect();
    for (stage, ms) in stages_ms {
        if let Some(part) = split_of(stage) {
            *out.entry(part).or_insert(0.0) += ms;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_frame_stage_has_a_part_and_setup_has_none() {
        let stages: BTreeMap<String, f64> =
            [("gbuffer", 1.0), ("shadow_raster", 2.0), ("cull", 4.0), ("subdivide", 8.0), ("shadow_test", 16.0), ("readback_level", 32.0), ("setup", 64.0)]
                .into_iter()
                .map(|(k, v)| (k.to_string(), v))
                .collect();
        let split = frame_split(&stages);
        assert_eq!(split["raster"], 7.0);
        assert_eq!(split["decision"], 8.0);
        assert_eq!(split["shade"], 16.0);
        assert_eq!(split["waits"], 32.0);
        assert!(!split.contains_key("other"));
    }
}
