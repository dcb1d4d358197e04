//! Percentage-closer soft shadows (Fernando 2005): blocker search, penumbra width from the light
//! size by similar triangles, then PCF of that width, all on the centre map.

use super::hybrid_maps::HybridRecord;
use super::single_map::{light_size, CentreMap, SingleMapBuffers};
use super::{label_from, Family, MethodInfo, MethodOutput, MethodState, ParamDecl, ShadowMethod};
use crate::gpu::readback;
use crate::gpu::structs::GpuFilter;
use crate::gpu::timing::StageTimer;
use crate::gpu::Stage;
use crate::stages::pcss::Pcss as PcssPass;
use crate::stages::shade::MapFilter;
use crate::stages::FrameGpu;
use crate::Result;
use std::sync::Arc;

pub(crate) const TAPS: ParamDecl<u32> =
    ParamDecl::new("taps", "8", 1, 16, "filter taps per side (N×N box), 1..=16");
pub(crate) const BLOCKER_TAPS: ParamDecl<u32> = ParamDecl::new(
    "blocker_taps",
    "6",
    1,
    16,
    "blocker-search taps per side, 1..=16",
);
pub(crate) const MAX_RADIUS: ParamDecl<f32> = ParamDecl::new(
    "max_radius",
    "32",
    1.0,
    256.0,
    "largest search and filter half-width in texels",
);

pub(crate) const INFO: MethodInfo = MethodInfo {
    name: "pcss",
    family: Family::Pcf,
    summary: "percentage-closer soft shadows: blocker search, w = (d_r − d_b)·w_light/d_b, PCF of that width",
    params: &[
        TAPS.param(),
        BLOCKER_TAPS.param(),
        MAX_RADIUS.param(),
    ],
    parse: |p| {
        Ok(Arc::new(Pcss {
            taps: TAPS.get(p, "pcss")?,
            blocker_taps: BLOCKER_TAPS.get(p, "pcss")?,
            max_radius: MAX_RADIUS.get(p, "pcss")?,
        }))
    },
};

#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Pcss {
    pub(crate) taps: u32,
    pub(crate) blocker_taps: u32,
    pub(crate) max_radius: f32,
}

impl ShadowMethod for Pcss {
    fn unsupported_light(&self, kind: crate::scene::LightKind) -> Option<&'static str> {
        // The disk's radius, or the sun's angle (`single_map::light_size`).
        (!(super::maps_from_the_emitter(kind) || super::cube_maps(kind)))
            .then_some(super::PCSS_RECTANGLE)
    }
    fn name(&self) -> &'static str {
        "pcss"
    }
    fn label(&self) -> String {
        label_from(
            &INFO,
            &[
                ("taps", self.taps.to_string()),
                ("blocker_taps", self.blocker_taps.to_string()),
                ("max_radius", self.max_radius.to_string()),
            ],
        )
    }
    fn params_json(&self) -> serde_json::Value {
        serde_json::json!({ "taps": self.taps, "blocker_taps": self.blocker_taps, "max_radius": self.max_radius })
    }
    /// One map from the light's centre (six cube faces for a point light: `CentreMap`).
    fn shadow_maps(&self, scene: &crate::scene::Scene) -> u32 {
        crate::methods::faces(scene)
    }
    /// Its pass binds V by bands of rows (stages::shade::Band).
    fn size_needs(
        &self,
        scene: &crate::scene::Scene,
        limits: &wgpu::Limits,
    ) -> Vec<crate::gpu::size_plan::SizeNeed> {
        vec![crate::methods::sizes::visibility(scene, true, limits)]
    }
    fn build(&self, fg: &FrameGpu) -> Result<Box<dyn MethodState>> {
        let (light_u, light_v) = light_size(fg);
        let filter = GpuFilter {
            taps: self.taps,
            blocker_taps: self.blocker_taps,
            max_radius: self.max_radius,
            light_u,
            light_v,
            ..Default::default()
        };
        Ok(Box::new(State {
            map: CentreMap::new(fg)?,
            filter_buffer: readback::uniform_buffer(fg.ctx, "pcss filter", &filter),
            pass: PcssPass::new(fg.ctx, fg.map_access())?,
            filter,
        }))
    }
    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}

struct State {
    map: CentreMap,
    filter: GpuFilter,
    filter_buffer: wgpu::Buffer,
    pass: PcssPass,
}

/// pcss's record in run.json (`method_record`).
#[derive(serde::Serialize)]
struct PcssRecord {
    /// The light's edge lengths the penumbra estimate used.
    light_size: [f32; 2],
    /// `maps = hybrid`: the hybrid store's figures.
    #[serde(skip_serializing_if = "Option::is_none")]
    hybrid: Option<HybridRecord>,
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
        self.map.render(fg, timer)?;
        timer.stage(fg.ctx, Stage::PCSS, |enc| {
            self.pass.record(
                fg.ctx,
                enc,
                &fg.screen(),
                &MapFilter {
                    filter: &self.filter_buffer,
                    samples: &self.map.samples,
                    maps: self.map.view(),
                },
            );
            Ok(())
        })?;
        Ok(MethodOutput {
            shadow_maps: self.map.count(),
            syncs: self.map.syncs(),
            record: super::record_value(
                "pcss",
                &PcssRecord {
                    light_size: [self.filter.light_u, self.filter.light_v],
                    hybrid: self.map.hybrid_record(),
                },
            )?,
            pictures: Vec::new(),
            bound: None,
        })
    }
    /// [`SingleMapBuffers`]: the map pcss read.
    fn inspect(&mut self, fg: &FrameGpu) -> Result<Option<Box<dyn std::any::Any>>> {
        let c = SingleMapBuffers {
            map: self.map.read(fg)?,
            sample: self.map.sample,
            filter: self.filter,
            ..Default::default()
        };
        let c = if self.map.count() > 1 {
            SingleMapBuffers {
                faces: self.map.faces.clone(),
                face_maps: self.map.read_all(fg)?,
                ..c
            }
        } else {
            c
        };
        Ok(Some(Box::new(c)))
    }
}
