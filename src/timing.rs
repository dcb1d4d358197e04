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
}

impl StageTimer {
    pub fn new(mode: TimingMode) -> Self {
        Self { mode, stages_ms: BTreeMap::new(), timing_waits: 0, pending: None }
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
        let out = record(&mut encoder)?;
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
