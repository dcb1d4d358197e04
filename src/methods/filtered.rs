//! Prefiltered shadow maps: the centre map becomes a statistic (`moments`), a separable box blur
//! whose radius follows from the light size prefilters it (`blur`), and each pixel reconstructs V
//! from the filtered statistic (`reconstruct`). ESM, VSM, EVSM, MSM and CSM differ only in the
//! statistic and the reconstruction.

use super::single_map::{light_size, CentreMap, SingleMapBuffers};
use super::{
    check_range, get_f32, get_u32, Family, MethodInfo, MethodOutput, MethodState, Param, ParamDecl,
    ParamMap, ShadowMethod,
};
use crate::gpu::readback;
use crate::gpu::stages::bind;
use crate::gpu::structs::GpuFilter;
use crate::gpu::timing::StageTimer;
use crate::gpu::Stage;
use crate::stages::{
    blur::{Blur, BlurMaps},
    moments::Moments,
    reconstruct::Reconstruct,
    FrameGpu,
};
use crate::{Error, Result};
use std::sync::Arc;

/// The largest exponent whose square e^{2c} stays finite in the f32 planes (ln(f32::MAX)/2 ≈ 44.4),
/// with a margin for the blur's sums: EVSM clamps to it.
pub(crate) const EVSM_MAX_EXPONENT: f32 = 42.0;
/// ESM stores e^{c z} with z ≤ 1: c must keep e^c finite in f32 (ln(f32::MAX) ≈ 88.7).
pub(crate) const ESM_MAX_EXPONENT: f32 = 85.0;

const RADIUS: Param = Param { key: "radius", default: "auto", help: "blur radius in texels; auto = penumbra half-width of a blocker 2/3 of the way to the farthest receiver" };

pub(crate) const C: ParamDecl<f32> = ParamDecl::new(
    "c",
    "80",
    1.0,
    ESM_MAX_EXPONENT,
    "exponent, 1..=85 (f32 holds e^85)",
);
/// vsm and evsm; `parse` checks 0..<1 itself (an open end `check_range` does not state).
pub(crate) const BLEED: ParamDecl<f32> = ParamDecl::new(
    "bleed",
    "0",
    f32::MIN,
    f32::MAX,
    "light-bleeding reduction: p' = clamp((p − bleed)/(1 − bleed)), 0..<1",
);
pub(crate) const C_POS: ParamDecl<f32> = ParamDecl::new(
    "c_pos",
    "42",
    0.0,
    f32::MAX,
    "positive exponent, clamped to 42 (e^{2c} must stay finite in f32)",
);
pub(crate) const C_NEG: ParamDecl<f32> = ParamDecl::new(
    "c_neg",
    "42",
    0.0,
    f32::MAX,
    "negative exponent, clamped to 42",
);
pub(crate) const MOMENT_BIAS: ParamDecl<f32> = ParamDecl::new(
    "moment_bias",
    "0.00003",
    0.0,
    0.5,
    "α: moments pulled toward 0.5 by α before the solve",
);
pub(crate) const ORDER: ParamDecl<u32> =
    ParamDecl::new("order", "4", 1, 16, "Fourier order M, 1..=16 (2M terms)");

pub(crate) const ESM: MethodInfo = MethodInfo {
    name: "esm",
    family: Family::Filtered,
    summary: "exponential shadow maps: prefiltered e^{c z}, V = min(1, E[e^{c z}]·e^{−c z_r})",
    params: &[C.param(), RADIUS],
    parse: |p| Filtered::parse(Kind::Esm, p),
};
pub(crate) const VSM: MethodInfo = MethodInfo {
    name: "vsm",
    family: Family::Filtered,
    summary:
        "variance shadow maps: prefiltered (z, z²), Chebyshev's bound, light-bleeding reduction",
    params: &[BLEED.param(), RADIUS],
    parse: |p| Filtered::parse(Kind::Vsm, p),
};
pub(crate) const EVSM: MethodInfo = MethodInfo {
    name: "evsm",
    family: Family::Filtered,
    summary:
        "exponential variance shadow maps: Chebyshev on e^{c+ w} and −e^{−c− w}, the smaller bound",
    params: &[
        C_POS.param(),
        C_NEG.param(),
        BLEED.param_with_help("light-bleeding reduction amount, 0..<1"),
        RADIUS,
    ],
    parse: |p| Filtered::parse(Kind::Evsm, p),
};
pub(crate) const MSM: MethodInfo = MethodInfo {
    name: "msm",
    family: Family::Filtered,
    summary: "moment shadow maps (Hamburger 4MSM, Peters & Klein 2015): 4 moments, 16-bit optimised quantisation",
    params: &[MOMENT_BIAS.param(), RADIUS],
    parse: |p| Filtered::parse(Kind::Msm, p),
};
pub(crate) const CSM: MethodInfo = MethodInfo {
    name: "csm",
    family: Family::Filtered,
    summary: "convolution shadow maps (Annen et al. 2007): Fourier expansion of order M of the shadow test, prefiltered",
    params: &[
        ORDER.param(),
        Param { key: "offset", default: "auto", help: "receiver depth offset (normalised depth); auto = 1/(2M), half the series' rise" },
        RADIUS,
    ],
    parse: |p| Filtered::parse(Kind::Csm, p),
};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kind {
    Esm,
    Vsm,
    Evsm,
    Msm,
    Csm,
}

impl Kind {
    fn info(self) -> &'static MethodInfo {
        match self {
            Kind::Esm => &ESM,
            Kind::Vsm => &VSM,
            Kind::Evsm => &EVSM,
            Kind::Msm => &MSM,
            Kind::Csm => &CSM,
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Filtered {
    pub(crate) kind: Kind,
    /// esm: c; evsm: c+.
    pub(crate) c_pos: f32,
    pub(crate) c_neg: f32,
    pub(crate) bleed: f32,
    pub(crate) moment_bias: f32,
    pub(crate) order: u32,
    /// csm: receiver depth offset in normalised depth.
    pub(crate) offset: f32,
    /// None: from the light size.
    pub(crate) radius: Option<u32>,
}

impl Filtered {
    fn parse(kind: Kind, p: &ParamMap) -> Result<Arc<dyn ShadowMethod>> {
        let name = kind.info().name;
        let radius = match p.get("radius").map(String::as_str) {
            None | Some("auto") => None,
            Some(_) => Some(check_range(
                name,
                "radius",
                get_u32(p, "radius", 0)?,
                0,
                64,
            )?),
        };
        let bleed = BLEED.get(p, name)?;
        if !(0.0..1.0).contains(&bleed) {
            return Err(Error::Param(format!(
                "{name}: bleed = {bleed} is outside 0..1"
            )));
        }
        let (c_pos, c_neg) = match kind {
            Kind::Esm => (C.get(p, name)?, 0.0),
            Kind::Evsm => {
                let pos = C_POS.get(p, name)?;
                let neg = C_NEG.get(p, name)?;
                (pos.min(EVSM_MAX_EXPONENT), neg.min(EVSM_MAX_EXPONENT))
            }
            _ => (0.0, 0.0),
        };
        let order = ORDER.get(p, name)?;
        Ok(Arc::new(Filtered {
            kind,
            c_pos,
            c_neg,
            bleed,
            moment_bias: MOMENT_BIAS.get(p, name)?,
            order,
            offset: match p.get("offset").map(String::as_str) {
                None | Some("auto") => 0.5 / order as f32,
                Some(_) => check_range(name, "offset", get_f32(p, "offset", 0.0)?, 0.0, 0.5)?,
            },
            radius,
        }))
    }

    fn layers(&self) -> u32 {
        if self.kind == Kind::Csm {
            self.order.div_ceil(2)
        } else {
            1
        }
    }

    /// Parameters as (key, value) pairs in registry order, values as the label writes them.
    fn values(&self) -> Vec<(&'static str, String)> {
        let r = self.radius.map_or("auto".to_string(), |r| r.to_string());
        match self.kind {
            Kind::Esm => vec![("c", self.c_pos.to_string()), ("radius", r)],
            Kind::Vsm => vec![("bleed", self.bleed.to_string()), ("radius", r)],
            Kind::Evsm => vec![
                ("c_pos", self.c_pos.to_string()),
                ("c_neg", self.c_neg.to_string()),
                ("bleed", self.bleed.to_string()),
                ("radius", r),
            ],
            Kind::Msm => vec![
                ("moment_bias", format!("{}", self.moment_bias)),
                ("radius", r),
            ],
            Kind::Csm => {
                let offset = if self.offset == 0.5 / self.order as f32 {
                    "auto".to_string()
                } else {
                    self.offset.to_string()
                };
                vec![
                    ("order", self.order.to_string()),
                    ("offset", offset),
                    ("radius", r),
                ]
            }
        }
    }

    /// Blur radius in texels: the given one, or the penumbra half-width in map texels of a
    /// blocker two thirds of the way from the light to the farthest receiver,
    /// ¼·w_light / (z_far · texel_angle) (w_light the mean edge), between 1 and 32. On the sun's
    /// orthographic map the way is the box's depth range and w_light the angle's 2·tan(α/2): a
    /// blocker a third of the range in front casts ⅓·range·½·w_light each side, over the texel's
    /// world size.
    pub(crate) fn blur_radius(&self, fg: &FrameGpu, map: &CentreMap) -> u32 {
        self.radius.unwrap_or_else(|| {
            let (u, v) = light_size(fg);
            let w = 0.5 * (u + v);
            let s = &map.sample;
            let texels = if s.orthographic != 0 {
                w * s.depth_lin_a / (6.0 * s.texel_angle)
            } else {
                0.25 * w / (map.far_depth().max(1e-6) * s.texel_angle)
            };
            texels.round().clamp(1.0, 32.0) as u32
        })
    }
}

impl ShadowMethod for Filtered {
    fn unsupported_light(&self, kind: crate::scene::LightKind) -> Option<&'static str> {
        // One map from the emitter's centre (`Emitter::sample_map` at (½, ½)): the disk's and the
        // spot's perspective map, the sun's orthographic one.
        (!super::maps_from_the_emitter(kind)).then_some(super::FROM_THE_CENTRE)
    }
    fn name(&self) -> &'static str {
        self.kind.info().name
    }
    fn label(&self) -> String {
        super::label_from(self.kind.info(), &self.values())
    }
    fn params_json(&self) -> serde_json::Value {
        let mut m = serde_json::Map::new();
        for (k, v) in self.values() {
            let value = v
                .parse::<f64>()
                .map_or(serde_json::Value::String(v), |x| serde_json::json!(x));
            m.insert(k.to_string(), value);
        }
        serde_json::Value::Object(m)
    }
    /// One map from the light's centre (six cube faces for a point light: `CentreMap`).
    fn shadow_maps(&self, scene: &crate::scene::Scene) -> u32 {
        crate::methods::faces(scene)
    }
    /// V by bands of rows (reconstruct), and the prefiltered statistic's planes: 16 bytes per map
    /// texel and layer, bound whole.
    fn size_needs(
        &self,
        scene: &crate::scene::Scene,
        limits: &wgpu::Limits,
    ) -> Vec<crate::gpu::size_plan::SizeNeed> {
        let map = scene.render.shadow_map_size as u64;
        vec![
            crate::methods::sizes::visibility(scene, true, limits),
            crate::gpu::size_plan::SizeNeed::binding(
                "moments",
                map * map * 16 * self.layers() as u64,
            )
            .sized_by(format!("shadow_map_size = {map}")),
        ]
    }
    fn build(&self, fg: &FrameGpu) -> Result<Box<dyn MethodState>> {
        if fg.scene.render.maps == crate::scene::MapKind::Hybrid {
            return Err(crate::Error::Param(format!(
                "{}: maps = hybrid is not supported: a prefiltered map reads the full-resolution raster once into its statistic (docs/hybrid.md); use maps = plain",
                self.name()
            )));
        }
        let map = CentreMap::new(fg)?;
        let (light_u, light_v) = light_size(fg);
        let layers = self.layers();
        let filter = GpuFilter {
            kind: self.kind as u32,
            order: self.order,
            light_u,
            light_v,
            c_pos: self.c_pos,
            c_neg: self.c_neg,
            bleed: self.bleed,
            moment_bias: self.moment_bias,
            layers,
            blur_radius: self.blur_radius(fg, &map),
            depth_offset: self.offset,
            ..Default::default()
        };
        let bytes = fg.frame.map_size as u64 * fg.frame.map_size as u64 * 16 * layers as u64;
        let plane = |label: &str| readback::zeroed_storage(fg.ctx, label, bytes);
        Ok(Box::new(State {
            filter_buffer: readback::uniform_buffer(fg.ctx, "filter", &filter),
            raw: plane("moments"),
            scratch: plane("blur scratch"),
            filtered: plane("filtered moments"),
            moments: Moments::new(fg.ctx, fg.raster.raster_access())?,
            blur: Blur::new(fg.ctx)?,
            reconstruct: Reconstruct::new(fg.ctx)?,
            filter,
            bytes,
            map,
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
    raw: wgpu::Buffer,
    scratch: wgpu::Buffer,
    filtered: wgpu::Buffer,
    bytes: u64,
    moments: Moments,
    blur: Blur,
    reconstruct: Reconstruct,
}

/// A filtered map's record in run.json (`method_record`).
#[derive(serde::Serialize)]
struct FilteredRecord {
    blur_radius_texels: u32,
    /// Planes of the prefiltered statistic.
    planes: u32,
}

impl MethodState for State {
    fn reset(&mut self, _fg: &FrameGpu) -> Result<()> {
        Ok(()) // every stage writes all of its output
    }
    fn run(
        &mut self,
        fg: &FrameGpu,
        timer: &mut StageTimer,
        _pictures: bool,
    ) -> Result<MethodOutput> {
        self.map.render(fg, timer)?;
        let view = self.map.view();
        timer.stage(fg.ctx, Stage::MOMENTS, |enc| {
            let bindings = bind::moments::Main {
                frame: fg.frame_buffer.as_entire_binding(),
                settings: self.filter_buffer.as_entire_binding(),
                samples: self.map.samples.as_entire_binding(),
                shadow_maps: wgpu::BindingResource::TextureView(view),
                moments: self.raw.as_entire_binding(),
            };
            self.moments
                .record(fg.ctx, enc, bindings, fg.frame.map_size);
            Ok(())
        })?;
        timer.stage(fg.ctx, Stage::BLUR, |enc| {
            let maps = BlurMaps {
                size: fg.frame.map_size,
                layers: self.filter.layers,
                source: &self.raw,
                scratch: &self.scratch,
                target: &self.filtered,
            };
            self.blur
                .record(fg.ctx, enc, &fg.frame_buffer, &self.filter_buffer, &maps);
            Ok(())
        })?;
        timer.stage(fg.ctx, Stage::RECONSTRUCT, |enc| {
            self.reconstruct.record(
                fg.ctx,
                enc,
                &fg.screen(),
                &self.filter_buffer,
                &self.map.samples,
                &self.filtered,
            );
            Ok(())
        })?;
        Ok(MethodOutput {
            shadow_maps: 1,
            syncs: 0,
            record: super::record_value(
                "filtered",
                &FilteredRecord {
                    blur_radius_texels: self.filter.blur_radius,
                    planes: self.filter.layers,
                },
            )?,
            pictures: Vec::new(),
            bound: None,
        })
    }
    /// [`SingleMapBuffers`]: the map and the statistic after each filter stage.
    fn inspect(&mut self, fg: &FrameGpu) -> Result<Option<Box<dyn std::any::Any>>> {
        let c = SingleMapBuffers {
            map: self.map.read(fg)?,
            sample: self.map.sample,
            filter: self.filter,
            raw: readback::read_buffer(fg.ctx, &self.raw, self.bytes)?,
            scratch: readback::read_buffer(fg.ctx, &self.scratch, self.bytes)?,
            filtered: readback::read_buffer(fg.ctx, &self.filtered, self.bytes)?,
            ..Default::default()
        };
        Ok(Some(Box::new(c)))
    }
}
