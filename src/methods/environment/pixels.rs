//! env-pixels (seed 002): every pixel of the panorama, downsampled to `res` with solid-angle
//! weights, is a directional light; V by one shadow ray per light and pixel through the BVH, or
//! (`at=vertex`, the seed's variant) per mesh vertex, interpolated to the pixels.

use super::common::{environment, gpu_lights, resolution, SceneRays, SsaoSettings, SsaoStage};
use super::picture;
use super::vertex::{VertexBuffers, VertexStage};
use crate::gpu::readback;
use crate::gpu::structs::{GpuEnvLight, GpuEnvParams};
use crate::gpu::timing::StageTimer;
use crate::gpu::Stage;
use crate::methods::{
    ChoiceDecl, Family, MethodInfo, MethodOutput, MethodState, Param, ParamDecl, ParamMap,
    ShadowMethod, SwitchDecl,
};
use crate::render::bvh::Bvh;
use crate::scene::environment::pixel_lights;
use crate::stages::env_trace::{chunk_params, EnvTrace, EnvTraceInputs};
use crate::stages::FrameGpu;
use crate::Result;
use std::sync::Arc;

pub const SSAO: SwitchDecl = SwitchDecl::new(
    "ssao",
    false,
    "on: multiply V by screen-space ambient occlusion (the seed's creases)",
);
pub const AO_SAMPLES: ParamDecl<u32> =
    ParamDecl::new("ao_samples", "16", 1, 64, "ssao samples per pixel, 1..=64");
pub const AO_RADIUS: ParamDecl<f32> = ParamDecl::new(
    "ao_radius",
    "0.05",
    1e-4,
    1.0,
    "ssao radius as a share of the scene's bounding-box diagonal",
);
pub const AT: ChoiceDecl = ChoiceDecl::new(
    "at",
    "pixel",
    &["pixel", "vertex"],
    "pixel: rays from every screen pixel; vertex: from every mesh vertex (the seed's variant), V interpolated by barycentrics",
);

pub const INFO: MethodInfo = MethodInfo {
    name: "env-pixels",
    family: Family::Environment,
    summary: "seed 002: every (downsampled) panorama pixel a light, shadow rays through a GPU BVH",
    params: &[
        Param {
            key: "res",
            default: "32x16",
            help: "panorama resolution of the pixel lights, WxH dividing the panorama's",
        },
        AT.param(),
        SSAO.param(),
        AO_SAMPLES.param(),
        AO_RADIUS.param(),
    ],
    parse: |p| {
        let (w, h) = resolution(p, "env-pixels", "res", (32, 16))?;
        let at = AT
            .get(p)
            .map_err(|e| crate::Error::Param(format!("env-pixels: {e}")))?;
        Ok(Arc::new(EnvPixels {
            width: w,
            height: h,
            per_vertex: at == "vertex",
            ssao: parse_ssao(p, "env-pixels")?,
        }))
    },
};

/// `ssao=on` with its settings, or None.
pub fn parse_ssao(p: &ParamMap, method: &str) -> Result<Option<SsaoSettings>> {
    let samples = AO_SAMPLES.get(p, method)?;
    let radius = AO_RADIUS.get(p, method)?;
    Ok(SSAO
        .get(p, method)?
        .then_some(SsaoSettings { samples, radius }))
}

#[derive(Clone, Debug, PartialEq)]
pub struct EnvPixels {
    pub(crate) width: u32,
    pub(crate) height: u32,
    /// `at=vertex`: trace at the mesh vertices and interpolate.
    pub(crate) per_vertex: bool,
    pub(crate) ssao: Option<SsaoSettings>,
}

impl ShadowMethod for EnvPixels {
    /// No shadow maps: it traces or samples the screen.
    fn shadow_maps(&self, _scene: &crate::scene::Scene) -> u32 {
        0
    }
    /// The panorama lights it; `[light]` is not read.
    fn unsupported_light(&self, _kind: crate::scene::LightKind) -> Option<&'static str> {
        None
    }
    fn name(&self) -> &'static str {
        "env-pixels"
    }
    /// RayLights' per-pixel sums (8 bytes) and blocked counts, besides V.
    fn size_needs(
        &self,
        scene: &crate::scene::Scene,
        limits: &wgpu::Limits,
    ) -> Vec<crate::gpu::size_plan::SizeNeed> {
        use crate::methods::sizes::{per_pixel, visibility};
        vec![
            visibility(scene, false, limits),
            per_pixel(scene, "env sums", 8),
            per_pixel(scene, "env blocked", 4),
        ]
    }
    fn label(&self) -> String {
        let mut s = format!("env-pixels:res={}x{}", self.width, self.height);
        if self.per_vertex {
            s += ",at=vertex";
        }
        if let Some(a) = self.ssao {
            s += &format!(",ssao=on,ao_samples={},ao_radius={}", a.samples, a.radius);
        }
        s
    }
    fn params_json(&self) -> serde_json::Value {
        serde_json::json!({ "res": [self.width, self.height], "at": if self.per_vertex { "vertex" } else { "pixel" }, "ssao": self.ssao })
    }
    fn build(&self, fg: &FrameGpu) -> Result<Box<dyn MethodState>> {
        let env = environment(fg, "env-pixels")?;
        let lights = pixel_lights(env, self.width, self.height)
            .map_err(|e| crate::Error::Param(format!("env-pixels: {e}")))?;
        let mut picture = picture::panorama_picture(env, 512);
        for l in &lights {
            picture::mark(&mut picture, env, l.direction, picture::level_colour(3));
        }
        let rays = RayLights::new(
            fg,
            gpu_lights(&lights),
            self.ssao,
            vec![("panorama_lights.png".into(), picture)],
        )?;
        Ok(Box::new(if self.per_vertex {
            rays.at_vertices(fg)?
        } else {
            rays
        }))
    }
    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}

/// Fixed lights traced every frame (env-pixels; env-adaptive's final pass uses the same parts).
pub struct RayLights {
    pub(crate) rays: SceneRays,
    pub(crate) trace: EnvTrace,
    pub(crate) lights: Vec<GpuEnvLight>,
    pub(crate) params: GpuEnvParams,
    /// One parameter block per chunk of lights (enough for the most lights this state may hold).
    pub(crate) chunk_buffers: Vec<wgpu::Buffer>,
    sums: wgpu::Buffer,
    pub(crate) lights_buffer: wgpu::Buffer,
    pub(crate) blocked: wgpu::Buffer,
    /// Bound as `ao` when ssao is off (never read then).
    no_ao: wgpu::Buffer,
    pub(crate) ssao: Option<SsaoStage>,
    pub(crate) pictures: Vec<(String, image::RgbImage)>,
    /// `at=vertex`: rays from the mesh vertices instead of the pixels.
    pub(crate) vertex: Option<VertexStage>,
}

impl RayLights {
    pub(crate) fn new(
        fg: &FrameGpu,
        lights: Vec<GpuEnvLight>,
        ssao: Option<SsaoSettings>,
        pictures: Vec<(String, image::RgbImage)>,
    ) -> Result<RayLights> {
        let rays = SceneRays::build(fg);
        let mut params = rays.params(fg);
        params.light_count = lights.len() as u32;
        params.use_ao = ssao.is_some() as u32;
        let ctx = fg.ctx;
        let ssao = ssao.map(|s| SsaoStage::new(fg, s)).transpose()?;
        let lights_buffer = readback::storage_buffer(
            ctx,
            "env lights",
            &if lights.is_empty() {
                vec![GpuEnvLight::default()]
            } else {
                lights.clone()
            },
            wgpu::BufferUsages::empty(),
        );
        let chunk_buffers = chunk_params(&params, lights.len() as u32)
            .iter()
            .map(|p| readback::uniform_buffer(ctx, "env params", p))
            .collect();
        Ok(RayLights {
            trace: EnvTrace::new(fg.ctx)?,
            chunk_buffers,
            sums: readback::zeroed_storage(ctx, "env sums", fg.pixel_count() as u64 * 8),
            lights_buffer,
            blocked: readback::zeroed_storage(ctx, "env blocked", fg.pixel_count() as u64 * 4),
            no_ao: readback::zeroed_storage(ctx, "no ao", 16),
            params,
            lights,
            rays,
            ssao,
            pictures,
            vertex: None,
        })
    }

    /// The per-vertex variant: the same lights, traced from every mesh vertex.
    pub(crate) fn at_vertices(mut self, fg: &FrameGpu) -> Result<RayLights> {
        let stage = VertexStage::new(fg)?;
        self.params.vertex_count = stage.vertex_count;
        self.vertex = Some(stage);
        Ok(self)
    }

    /// ssao (if on), then env_trace.
    pub(crate) fn run(&self, fg: &FrameGpu, timer: &mut StageTimer) -> Result<()> {
        if let Some(s) = &self.ssao {
            s.run(fg, timer)?;
        }
        let ao = self.ssao.as_ref().map_or(&self.no_ao, |s| &s.ao);
        let chunks = chunk_params(&self.params, self.params.light_count);
        for (p, buffer) in chunks.iter().zip(&self.chunk_buffers) {
            fg.ctx.queue.write_buffer(buffer, 0, bytemuck::bytes_of(p));
        }
        if let Some(v) = &self.vertex {
            v.run(
                fg,
                timer,
                &self.chunk_buffers[..chunks.len()],
                &self.lights_buffer,
                &self.rays.buffers,
                ao,
            )?;
        } else {
            timer.stage(fg.ctx, Stage::ENV_TRACE, |enc| {
                for buffer in &self.chunk_buffers[..chunks.len()] {
                    let inputs = EnvTraceInputs {
                        params: buffer,
                        lights: &self.lights_buffer,
                        blocked: &self.blocked,
                        ao,
                        sums: &self.sums,
                        bvh: &self.rays.buffers,
                    };
                    self.trace
                        .record(fg.ctx, enc, &fg.gbuffer, &inputs, &fg.visibility);
                }
                Ok(())
            })?;
        }
        Ok(())
    }

    /// After a frame: env_trace's inputs and counts, for the twins.
    pub(crate) fn read(&self, fg: &FrameGpu) -> Result<EnvTraceBuffers> {
        let bytes = fg.pixel_count() as u64 * 4;
        let ao = match &self.ssao {
            Some(s) => readback::read_buffer(fg.ctx, &s.ao, bytes)?,
            None => Vec::new(),
        };
        Ok(EnvTraceBuffers {
            params: self.params,
            lights: self.lights.clone(),
            bvh: self.rays.bvh.clone(),
            blocked: readback::read_buffer(fg.ctx, &self.blocked, bytes)?,
            ao,
            levels: Vec::new(),
            vertex: self.vertex.as_ref().map(|v| v.read(fg)).transpose()?,
        })
    }
}

/// env_trace's inputs and counts (and env-adaptive's levels), for the twins.
pub struct EnvTraceBuffers {
    pub params: GpuEnvParams,
    pub lights: Vec<GpuEnvLight>,
    pub bvh: Arc<Bvh>,
    pub blocked: Vec<u32>,
    pub ao: Vec<f32>,
    pub levels: Vec<super::common::EnvLevelBuffers>,
    /// `at=vertex`: the ids, V and blocked rays per vertex.
    pub vertex: Option<VertexBuffers>,
}

/// The ray-traced environment methods' record in run.json (`method_record`).
#[derive(serde::Serialize)]
struct EnvPixelsRecord {
    /// Lights traced per pixel or vertex.
    samples: u32,
    /// Where the rays start: the `at` key and its counts.
    #[serde(flatten)]
    at: TracedAt,
    bvh_nodes: usize,
    bvh_depth: usize,
    ssao: bool,
}

/// Where the rays start (run.json's `at`).
#[derive(serde::Serialize)]
#[serde(tag = "at", rename_all = "lowercase")]
enum TracedAt {
    Pixel {
        rays_per_pixel: u32,
    },
    Vertex {
        vertices_traced: u32,
        rays_per_vertex: u32,
    },
}

impl MethodState for RayLights {
    fn reset(&mut self, _fg: &FrameGpu) -> Result<()> {
        Ok(())
    }
    fn run(
        &mut self,
        fg: &FrameGpu,
        timer: &mut StageTimer,
        pictures: bool,
    ) -> Result<MethodOutput> {
        RayLights::run(self, fg, timer)?;
        let n = self.lights.len() as u32;
        Ok(MethodOutput {
            shadow_maps: n,
            syncs: 0,
            record: crate::methods::record_value(
                "env-pixels",
                &EnvPixelsRecord {
                    samples: n,
                    at: match &self.vertex {
                        None => TracedAt::Pixel { rays_per_pixel: n },
                        Some(v) => TracedAt::Vertex {
                            vertices_traced: v.vertex_count,
                            rays_per_vertex: n,
                        },
                    },
                    bvh_nodes: self.rays.bvh.nodes.len(),
                    bvh_depth: self.rays.bvh.depth,
                    ssao: self.ssao.is_some(),
                },
            )?,
            pictures: if pictures {
                self.pictures.clone()
            } else {
                Vec::new()
            },
            bound: None,
        })
    }
    /// [`EnvTraceBuffers`].
    fn inspect(&mut self, fg: &FrameGpu) -> Result<Option<Box<dyn std::any::Any>>> {
        Ok(Some(Box::new(self.read(fg)?)))
    }
}

#[cfg(test)]
mod tests {
    use super::{EnvPixelsRecord, TracedAt};

    /// `at` is the tag of where the rays start, beside its own counts, in the record's one map.
    #[test]
    fn the_record_names_where_rays_start_beside_its_counts() {
        let record = |at| EnvPixelsRecord {
            samples: 8,
            at,
            bvh_nodes: 5,
            bvh_depth: 3,
            ssao: false,
        };
        let value = serde_json::to_value(record(TracedAt::Vertex {
            vertices_traced: 40,
            rays_per_vertex: 8,
        }))
        .unwrap();
        assert_eq!(
            serde_json::to_string(&value).unwrap(),
            r#"{"at":"vertex","bvh_depth":3,"bvh_nodes":5,"rays_per_vertex":8,"samples":8,"ssao":false,"vertices_traced":40}"#
        );
        let value = serde_json::to_value(record(TracedAt::Pixel { rays_per_pixel: 8 })).unwrap();
        assert_eq!(
            serde_json::to_string(&value).unwrap(),
            r#"{"at":"pixel","bvh_depth":3,"bvh_nodes":5,"rays_per_pixel":8,"samples":8,"ssao":false}"#
        );
    }
}
