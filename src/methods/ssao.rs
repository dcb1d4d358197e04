//! ssao as its own term: V = the screen-space ambient occlusion (seed 002 §2.4). Combined with the
//! environment methods through their `ssao=on` parameter (V_env · AO).

use super::environment::common::{SsaoSettings, SsaoStage};
use super::environment::pixels::{AO_RADIUS, AO_SAMPLES};
use super::{Family, MethodInfo, MethodOutput, MethodState, ShadowMethod};
use crate::gpu::readback;
use crate::gpu::structs::{GpuCamera, GpuEnvParams};
use crate::gpu::timing::StageTimer;
use crate::gpu::Stage;
use crate::stages::FrameGpu;
use crate::Result;
use std::sync::Arc;

pub(crate) const INFO: MethodInfo = MethodInfo {
    name: "ssao",
    family: Family::Environment,
    summary: "screen-space ambient occlusion alone: V = AO from the G-buffer",
    params: &[AO_SAMPLES.param(), AO_RADIUS.param()],
    parse: |p| {
        let samples = AO_SAMPLES.get(p, "ssao")?;
        let radius = AO_RADIUS.get(p, "ssao")?;
        Ok(Arc::new(SsaoMethod(SsaoSettings { samples, radius })))
    },
};

#[derive(Clone, Debug, PartialEq)]
pub(crate) struct SsaoMethod(pub SsaoSettings);

impl ShadowMethod for SsaoMethod {
    /// No shadow maps: it traces or samples the screen.
    fn shadow_maps(&self, _scene: &crate::scene::Scene) -> u32 {
        0
    }
    /// Screen-space occlusion reads no light.
    fn unsupported_light(&self, _kind: crate::scene::LightKind) -> Option<&'static str> {
        None
    }
    fn name(&self) -> &'static str {
        "ssao"
    }
    fn label(&self) -> String {
        format!(
            "ssao:ao_samples={},ao_radius={}",
            self.0.samples, self.0.radius
        )
    }
    fn params_json(&self) -> serde_json::Value {
        serde_json::json!({ "ao_samples": self.0.samples, "ao_radius": self.0.radius })
    }
    fn build(&self, fg: &FrameGpu) -> Result<Box<dyn MethodState>> {
        Ok(Box::new(State(SsaoStage::new(fg, self.0)?)))
    }
    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}

struct State(SsaoStage);

/// Inputs and counts of an ssao frame, for the twin.
pub struct SsaoBuffers {
    pub params: GpuEnvParams,
    pub camera: GpuCamera,
    pub kernel: Vec<[f32; 4]>,
    pub ao: Vec<f32>,
    pub occluded: Vec<u32>,
}

/// ssao's record in run.json (`method_record`).
#[derive(serde::Serialize)]
struct SsaoRecord {
    samples: u32,
    radius_world: f32,
}

impl MethodState for State {
    fn reset(&mut self, _fg: &FrameGpu) -> Result<()> {
        Ok(())
    }
    fn run(
        &mut self,
        fg: &FrameGpu,
        timer: &mut StageTimer,
        _pictures: bool,
    ) -> Result<MethodOutput> {
        let s = &self.0;
        s.run(fg, timer)?;
        let bytes = fg.pixel_count() as u64 * 4;
        timer.stage(fg.ctx, Stage::SSAO_COPY, |enc| {
            enc.copy_buffer_to_buffer(&s.ao, 0, &fg.visibility, 0, bytes);
            Ok(())
        })?;
        Ok(MethodOutput {
            shadow_maps: 0,
            syncs: 0,
            record: super::record_value(
                "ssao",
                &SsaoRecord {
                    samples: s.params.light_count,
                    radius_world: s.params.radius,
                },
            )?,
            pictures: Vec::new(),
            bound: None,
        })
    }
    /// [`SsaoBuffers`].
    fn inspect(&mut self, fg: &FrameGpu) -> Result<Option<Box<dyn std::any::Any>>> {
        let s = &self.0;
        let bytes = fg.pixel_count() as u64 * 4;
        let c = SsaoBuffers {
            params: s.params,
            camera: s.camera,
            kernel: s.kernel.clone(),
            ao: readback::read_buffer(fg.ctx, &s.ao, bytes)?,
            occluded: readback::read_buffer(fg.ctx, &s.occluded, bytes)?,
        };
        Ok(Some(Box::new(c)))
    }
}
