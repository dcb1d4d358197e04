//! Wall-clock per stage (submit → wait) and per frame. On CPU adapters GPU timestamps are not
//! trustworthy, so wall clock is the figure every report quotes, labelled as such.

use crate::gpu::{GpuContext, Stage};
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
    pub(crate) mode: TimingMode,
    pub(crate) stages_ms: BTreeMap<String, f64>,
    /// Waits added only to time stages (not counted as the algorithm's syncs).
    pub(crate) timing_waits: u32,
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
    pub(crate) fn new(mode: TimingMode) -> Self {
        Self {
            mode,
            stages_ms: BTreeMap::new(),
            timing_waits: 0,
            pending: None,
            gpu: None,
        }
    }

    /// Also records GPU timestamps when the adapter's are trusted, or when `forced` (tests, on CPU
    /// adapters where the figures mean little).
    pub(crate) fn with_gpu_timestamps(mut self, ctx: &GpuContext, forced: bool) -> Self {
        let features = ctx.device.features();
        let able = features.contains(
            wgpu::Features::TIMESTAMP_QUERY | wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS,
        );
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
    pub(crate) fn gpu_stages_ms(
        &mut self,
        ctx: &GpuContext,
    ) -> Result<Option<BTreeMap<String, f64>>> {
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

    /// Records one stage into an encoder; in `Stages` mode submits and waits, charging the time to `stage`.
    pub(crate) fn stage<T>(
        &mut self,
        ctx: &GpuContext,
        stage: Stage,
        record: impl FnOnce(&mut wgpu::CommandEncoder) -> Result<T>,
    ) -> Result<T> {
        let name = stage.name;
        let start = Instant::now();
        let mut encoder = self.pending.take().unwrap_or_else(|| {
            ctx.device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some(name) })
        });
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
        self.add(stage, start.elapsed().as_secs_f64() * 1e3);
        Ok(out)
    }

    /// Submits whatever is recorded (before a read-back the algorithm needs).
    pub(crate) fn flush(&mut self, ctx: &GpuContext) {
        if let Some(encoder) = self.pending.take() {
            ctx.queue.submit([encoder.finish()]);
        }
    }

    /// Charges `ms` to `stage` (its name is the `stages_ms` key).
    pub(crate) fn add(&mut self, stage: Stage, ms: f64) {
        *self.stages_ms.entry(stage.name.to_string()).or_insert(0.0) += ms;
    }

    /// Times CPU-side work (and read-backs) under `stage`.
    pub(crate) fn cpu<T>(&mut self, stage: Stage, f: impl FnOnce() -> Result<T>) -> Result<T> {
        let start = Instant::now();
        let out = f()?;
        self.add(stage, start.elapsed().as_secs_f64() * 1e3);
        Ok(out)
    }
}
