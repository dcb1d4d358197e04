//! env-shadowmaps (seed 002's baseline): K directional lights from median cut, one shadow map each
//! from a point 50 scene diagonals away along the light (near-orthographic), filtered by the pcf
//! family's tap patterns (box by default).

use super::common::{environment, gpu_lights};
use super::common::{SsaoSettings, SsaoStage};
use super::picture;
use super::pixels::{parse_ssao, AO_RADIUS, AO_SAMPLES, SSAO};
use crate::gpu::readback;
use crate::gpu::structs::{GpuEnvLight, GpuEnvParams, GpuFilter, GpuFrame, GpuSample};
use crate::gpu::timing::StageTimer;
use crate::gpu::Stage;
use crate::methods::pcf::{poisson_disk, KERNELS};
use crate::methods::{
    check_range, get_u32, ChoiceDecl, Family, MethodInfo, MethodOutput, MethodState, Param,
    ParamDecl, ShadowMethod,
};
use crate::render::shadow_raster::{self, RasterJob};
use crate::scene::environment::median_cut;
use crate::scene::light::{sample_view, AreaLight};
use crate::stages::env_shadowmaps::{EnvMapInputs, EnvShadowmaps as Pass, FilterBuffers};
use crate::stages::raster::RasterTarget;
use crate::stages::FrameGpu;
use crate::{Error, Result};
use glam::Vec3;
use std::sync::Arc;

pub const K: ParamDecl<u32> = ParamDecl::new(
    "k",
    "16",
    1,
    256,
    "lights from median cut, a power of two 1..=256",
);
pub const FILTER: ChoiceDecl = ChoiceDecl::new(
    "filter",
    "box",
    &KERNELS,
    "the pcf family's tap pattern: box, bilinear, poisson, stratified or rotated (as pcf:kernel)",
);
pub const PCF_RADIUS: ParamDecl<u32> = ParamDecl::new(
    "pcf_radius",
    "1",
    0,
    4,
    "filter radius in texels, 0..=4 (box: (2r+1)² taps)",
);

pub const INFO: MethodInfo = MethodInfo {
    name: "env-shadowmaps",
    family: Family::Environment,
    summary: "seed 002's baseline: K median-cut directional lights, a shadow map each, PCF-filtered (pcf's patterns)",
    params: &[
        K.param(),
        FILTER.param(),
        PCF_RADIUS.param(),
        Param { key: "taps", default: "2r+1 | 16", help: "box/bilinear: N per side (default 2·pcf_radius+1), 1..=16; poisson/rotated: 4, 16, 32 or 64; stratified: 1..=64" },
        SSAO.param(),
        AO_SAMPLES.param(),
        AO_RADIUS.param(),
    ],
    parse: |p| {
        let k = K.get(p, "env-shadowmaps")?;
        if !k.is_power_of_two() {
            return Err(Error::Param(format!("env-shadowmaps: k = {k}: median cut gives a power of two (1, 2, 4, … 256)")));
        }
        let pcf_radius = PCF_RADIUS.get(p, "env-shadowmaps")?;
        let filter = FILTER.get(p).map_err(|e| Error::Param(format!("env-shadowmaps: {e}")))?;
        let taps = check_taps(filter, get_u32(p, "taps", default_taps(filter, pcf_radius))?)?;
        Ok(Arc::new(EnvShadowmaps { k, filter, pcf_radius, taps, ssao: parse_ssao(p, "env-shadowmaps")? }))
    },
};

#[derive(Clone, Debug, PartialEq)]
pub struct EnvShadowmaps {
    pub(crate) k: u32,
    /// One of the pcf family's patterns (`pcf::KERNELS`).
    pub(crate) filter: &'static str,
    pub(crate) pcf_radius: u32,
    pub(crate) taps: u32,
    pub(crate) ssao: Option<SsaoSettings>,
}

/// Box keeps the (2r+1)² texel grid it always had; the disk patterns default to 16 taps (as pcf's).
fn default_taps(filter: &str, radius: u32) -> u32 {
    match filter {
        "box" | "bilinear" => 2 * radius + 1,
        _ => 16,
    }
}

fn check_taps(filter: &str, taps: u32) -> Result<u32> {
    match filter {
        "box" | "bilinear" => check_range("env-shadowmaps", "taps", taps, 1, 16),
        "stratified" => check_range("env-shadowmaps", "taps", taps, 1, 64),
        _ if ![4, 16, 32, 64].contains(&taps) => Err(Error::Param(format!(
            "env-shadowmaps: taps = {taps} with filter = {filter}: use 4, 16, 32 or 64"
        ))),
        _ => Ok(taps),
    }
}

impl EnvShadowmaps {
    /// The pcf family's uniform: same kinds, tap counts and stratified order as `pcf`.
    pub(crate) fn settings(&self) -> GpuFilter {
        GpuFilter {
            kind: KERNELS.iter().position(|k| *k == self.filter).unwrap_or(0) as u32,
            taps: self.taps,
            order: 16,
            radius: self.pcf_radius as f32,
            ..Default::default()
        }
    }

    /// The unit-disk offsets the disk patterns read (one unused point for the grids).
    pub(crate) fn disk(&self) -> Vec<[f32; 2]> {
        match self.filter {
            "box" | "bilinear" => vec![[0.0, 0.0]],
            "stratified" => poisson_disk(16),
            _ => poisson_disk(self.taps as usize),
        }
    }
}

/// Distance of a directional light's map viewpoint, in scene diagonals: far enough that the
/// perspective is near-orthographic (rays from it diverge by < 1.2° across the scene).
pub const MAP_DISTANCE: f32 = 50.0;

/// The shadow-map view of a directional light towards `dir` (unit, pointing at the light).
pub fn directional_sample(fg: &FrameGpu, dir: Vec3, layer: u32) -> GpuSample {
    let b = &fg.scene.bounds;
    let diag = b.diagonal().max(1e-6);
    let y = (b.min + b.max) * 0.5 + dir * (MAP_DISTANCE * diag);
    // An area light whose normal (edge_u × edge_v) points back at the scene fixes the view's axes.
    let forward = -dir;
    let hint = if forward.y.abs() < 0.9 {
        Vec3::Y
    } else {
        Vec3::X
    };
    let u = hint.cross(forward).normalize();
    let v = forward.cross(u);
    let light = AreaLight {
        center: y,
        edge_u: u,
        edge_v: v,
    };
    let mut s = sample_view(&light, y, b, fg.frame.map_size, u32::MAX);
    s.layer = layer;
    s
}

impl ShadowMethod for EnvShadowmaps {
    /// One map per median-cut light, `k` of them.
    fn shadow_maps(&self, _scene: &crate::scene::Scene) -> u32 {
        self.k
    }
    /// The panorama lights it; `[light]` is not read.
    fn unsupported_light(&self, _kind: crate::scene::LightKind) -> Option<&'static str> {
        None
    }
    fn name(&self) -> &'static str {
        "env-shadowmaps"
    }
    fn label(&self) -> String {
        let mut s = format!("env-shadowmaps:k={}", self.k);
        if self.filter != "box" {
            s += &format!(",filter={}", self.filter);
        }
        if self.pcf_radius != 1 {
            s += &format!(",pcf_radius={}", self.pcf_radius);
        }
        if self.taps != default_taps(self.filter, self.pcf_radius) {
            s += &format!(",taps={}", self.taps);
        }
        if let Some(a) = self.ssao {
            s += &format!(",ssao=on,ao_samples={},ao_radius={}", a.samples, a.radius);
        }
        s
    }
    fn params_json(&self) -> serde_json::Value {
        serde_json::json!({ "k": self.k, "filter": self.filter, "pcf_radius": self.pcf_radius, "taps": self.taps, "ssao": self.ssao })
    }
    fn build(&self, fg: &FrameGpu) -> Result<Box<dyn MethodState>> {
        let env = environment(fg, "env-shadowmaps")?;
        let cut = median_cut(env, self.k);
        let mut picture = picture::panorama_picture(env, 512);
        let (pw, ph) = (env.panorama.width as f32, env.panorama.height as f32);
        for (l, [x0, y0, x1, y1]) in &cut {
            picture::rect(
                &mut picture,
                (*x0 as f32 / pw, *y0 as f32 / ph),
                (*x1 as f32 / pw, *y1 as f32 / ph),
                picture::level_colour(2),
            );
            picture::mark(&mut picture, env, l.direction, picture::level_colour(0));
        }
        let lights: Vec<GpuEnvLight> = gpu_lights(&cut.iter().map(|c| c.0).collect::<Vec<_>>());
        let samples: Vec<GpuSample> = lights
            .iter()
            .enumerate()
            .map(|(k, l)| {
                directional_sample(
                    fg,
                    Vec3::new(l.direction[0], l.direction[1], l.direction[2]),
                    k as u32,
                )
            })
            .collect();
        let ctx = fg.ctx;
        let s = fg.scene;
        let per_array = fg.raster.maps_per_array(
            ctx,
            s.render.shadow_map_size,
            s.render.shadow_map_budget_mib,
        )?;
        if (samples.len() as u32) > per_array {
            return Err(Error::Limit(format!("env-shadowmaps: k = {} maps of {}² exceed the shadow-map budget ({per_array} maps)", samples.len(), s.render.shadow_map_size)));
        }
        let array = fg
            .raster
            .allocate(ctx, s.render.shadow_map_size, samples.len().max(1) as u32);
        // Every point lies on the light side of a plane under the scene: the lights' own facing
        // test (cos > 0) decides what each light reaches.
        let mut frame = fg.frame;
        let diag = s.bounds.diagonal().max(1e-6);
        frame.light_center = [
            (s.bounds.min.x + s.bounds.max.x) * 0.5,
            s.bounds.min.y - diag,
            (s.bounds.min.z + s.bounds.max.z) * 0.5,
            1.0,
        ];
        frame.light_normal = [0.0, 1.0, 0.0, 0.0];
        let params = GpuEnvParams {
            width: fg.gbuffer.width,
            height: fg.gbuffer.height,
            light_count: lights.len() as u32,
            use_ao: self.ssao.is_some() as u32,
            ..Default::default()
        };
        let (filter, disk) = (self.settings(), self.disk());
        Ok(Box::new(State {
            pass: Pass::new(ctx, fg.raster.raster_access())?,
            filter_buffer: readback::uniform_buffer(ctx, "env shadowmaps filter", &filter),
            disk_buffer: readback::storage_buffer(
                ctx,
                "env shadowmaps disk",
                &disk,
                wgpu::BufferUsages::empty(),
            ),
            filter,
            disk,
            frame_buffer: readback::uniform_buffer(ctx, "env shadowmaps frame", &frame),
            params_buffer: readback::uniform_buffer(ctx, "env shadowmaps params", &params),
            samples_buffer: readback::storage_buffer(
                ctx,
                "env shadowmaps samples",
                &samples,
                wgpu::BufferUsages::empty(),
            ),
            lights_buffer: readback::storage_buffer(
                ctx,
                "env shadowmaps lights",
                &lights,
                wgpu::BufferUsages::empty(),
            ),
            ssao: self.ssao.map(|a| SsaoStage::new(fg, a)).transpose()?,
            array,
            frame,
            params,
            samples,
            lights,
            picture,
        }))
    }
    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}

struct State {
    pass: Pass,
    filter: GpuFilter,
    disk: Vec<[f32; 2]>,
    filter_buffer: wgpu::Buffer,
    disk_buffer: wgpu::Buffer,
    frame: GpuFrame,
    params: GpuEnvParams,
    samples: Vec<GpuSample>,
    lights: Vec<GpuEnvLight>,
    frame_buffer: wgpu::Buffer,
    params_buffer: wgpu::Buffer,
    samples_buffer: wgpu::Buffer,
    lights_buffer: wgpu::Buffer,
    array: shadow_raster::ShadowMapArray,
    ssao: Option<SsaoStage>,
    picture: image::RgbImage,
}

/// Maps and inputs of an env-shadowmaps frame, for its twin.
pub struct EnvShadowmapsBuffers {
    pub frame: GpuFrame,
    pub params: GpuEnvParams,
    pub filter: GpuFilter,
    pub disk: Vec<[f32; 2]>,
    pub samples: Vec<GpuSample>,
    pub lights: Vec<GpuEnvLight>,
    pub maps: Vec<Vec<f32>>,
    pub ao: Vec<f32>,
}

/// env-shadowmaps' record in run.json (`method_record`).
#[derive(serde::Serialize)]
struct EnvShadowmapsRecord {
    samples: u32,
    /// Median-cut lights, one map each.
    lights: u32,
    /// pcf's kernel.
    filter: &'static str,
    pcf_taps: u32,
    ssao: bool,
}

impl MethodState for State {
    fn reset(&mut self, _fg: &FrameGpu) -> Result<()> {
        Ok(())
    }
    fn run(
        &mut self,
        fg: &FrameGpu,
        timer: &mut StageTimer,
        pictures: bool,
    ) -> Result<MethodOutput> {
        let ctx = fg.ctx;
        let k = self.samples.len() as u32;
        let jobs: Vec<RasterJob> = (0..k)
            .map(|i| RasterJob {
                sample: i,
                layer: i,
                scissor: None,
            })
            .collect();
        timer.stage(ctx, fg.raster.stage(), |enc| {
            fg.raster.record(
                ctx,
                enc,
                &RasterTarget {
                    scene: &fg.scene_gpu,
                    samples: &self.samples_buffer,
                    array: &self.array,
                },
                &jobs,
            )?;
            Ok(())
        })?;
        if let Some(s) = &self.ssao {
            s.run(fg, timer)?;
        }
        let ao = self.ssao.as_ref().map_or(&self.lights_buffer, |s| &s.ao);
        timer.stage(ctx, Stage::ENV_SHADOWMAPS, |enc| {
            let inputs = EnvMapInputs {
                frame: &self.frame_buffer,
                params: &self.params_buffer,
                samples: &self.samples_buffer,
                maps: &self.array.array_view,
                lights: &self.lights_buffer,
                ao,
                filter: FilterBuffers {
                    settings: &self.filter_buffer,
                    disk: &self.disk_buffer,
                },
            };
            self.pass
                .record(ctx, enc, &fg.gbuffer, &inputs, &fg.visibility);
            Ok(())
        })?;
        Ok(MethodOutput {
            shadow_maps: k,
            syncs: 0,
            record: crate::methods::record_value(
                "env-shadowmaps",
                &EnvShadowmapsRecord {
                    samples: k,
                    lights: k,
                    filter: KERNELS[self.filter.kind as usize],
                    // box and bilinear take taps per side, the disk kernels a tap count.
                    pcf_taps: self
                        .filter
                        .taps
                        .pow(if self.filter.kind <= 1 { 2 } else { 1 }),
                    ssao: self.ssao.is_some(),
                },
            )?,
            pictures: if pictures {
                vec![("panorama_lights.png".into(), self.picture.clone())]
            } else {
                Vec::new()
            },
            bound: None,
        })
    }
    /// [`EnvShadowmapsBuffers`]: every light's map, and the ambient occlusion where it is on.
    fn inspect(&mut self, fg: &FrameGpu) -> Result<Option<Box<dyn std::any::Any>>> {
        let ctx = fg.ctx;
        let mut maps = Vec::new();
        for layer in 0..self.samples.len() as u32 {
            maps.push(readback::read_texture(ctx, &self.array.texture, layer, 4)?);
        }
        let ao = match &self.ssao {
            Some(s) => readback::read_buffer(ctx, &s.ao, fg.pixel_count() as u64 * 4)?,
            None => Vec::new(),
        };
        let c = EnvShadowmapsBuffers {
            frame: self.frame,
            params: self.params,
            filter: self.filter,
            disk: self.disk.clone(),
            samples: self.samples.clone(),
            lights: self.lights.clone(),
            maps,
            ao,
        };
        Ok(Some(Box::new(c)))
    }
}
