//! Cascaded shadow maps for the sun (seed 004; docs/lights.md "Cascades"): the camera's depth
//! range is cut into N slices (`split`), each slice gets an orthographic map along the sun fitted
//! to its bounding sphere and snapped to whole texels, and every pixel reads the map of the slice
//! it lies in (`stages::cascades`), with one test or pcf's taps.

pub(crate) mod split;

use super::pcf::Pcf;
use super::{
    ChoiceDecl, Family, MethodInfo, MethodOutput, MethodState, ParamDecl, ParamMap, ShadowMethod,
};
use crate::gpu::readback;
use crate::gpu::structs::{GpuCascades, GpuFilter, GpuSample};
use crate::gpu::timing::StageTimer;
use crate::gpu::Stage;
use crate::render::shadow_raster::{self, RasterJob, ShadowMapArray};
use crate::scene::light::orthographic_square;
use crate::scene::{Emitter, LightKind, MapKind, Scene};
use crate::stages::cascades::{CascadeInputs, Cascades as CascadesPass, FILTER_HARD, FILTER_PCF};
use crate::stages::raster::RasterTarget;
use crate::stages::FrameGpu;
use crate::{Error, Result};
use split::Scheme;
use std::sync::Arc;

/// The most cascades: two vec4s of slice ends in the kernel's uniform.
pub const MAX_CASCADES: u32 = 8;
pub const FILTERS: [&str; 2] = ["hard", "pcf"];

pub(crate) const N: ParamDecl<u32> = ParamDecl::new("n", "4", 1, MAX_CASCADES, "cascades, 1..=8");
pub(crate) const SPLIT: ChoiceDecl = ChoiceDecl::new(
    "split",
    "practical",
    &Scheme::NAMES,
    "uniform, log or practical (λ·log + (1−λ)·uniform)",
);
pub(crate) const LAMBDA: ParamDecl<f32> = ParamDecl::new(
    "lambda",
    "0.5",
    0.0,
    1.0,
    "practical: the log split's weight, 0..=1",
);
pub(crate) const FILTER: ChoiceDecl = ChoiceDecl::new(
    "filter",
    "hard",
    &FILTERS,
    "hard (one test per pixel) or pcf (pcf's default taps: Poisson 16, radius 2 texels)",
);

pub(crate) const INFO: MethodInfo = MethodInfo {
    name: "cascades",
    family: Family::Pcf,
    summary: "the sun's cascaded shadow maps: the view's depth range split into N slices, an orthographic map per slice",
    params: &[
        N.param(),
        SPLIT.param(),
        LAMBDA.param(),
        FILTER.param(),
    ],
    parse: |p| Ok(Arc::new(CascadeMaps::from_map(p)?)),
};

/// Why every kind but the sun is refused.
pub const SUN_ONLY: &str = "cascades are orthographic maps along the sun's direction";

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CascadeMaps {
    pub n: u32,
    pub split: Scheme,
    pub lambda: f32,
    pub filter: &'static str,
}

impl CascadeMaps {
    pub(crate) fn from_map(p: &ParamMap) -> Result<Self> {
        let n = N.get(p, "cascades")?;
        let split = Scheme::parse(SPLIT.get(p)?).expect("a listed scheme");
        let lambda = LAMBDA.get(p, "cascades")?;
        let filter = FILTER.get(p)?;
        Ok(Self {
            n,
            split,
            lambda,
            filter,
        })
    }

    /// Where the cascades lie for `scene`'s camera: the slice ends, and one map per slice
    /// (`layer` i), each fitted to its slice's sphere and snapped to its texels.
    pub fn place(&self, scene: &Scene) -> Placement {
        let (near, far) = split::depth_range(&scene.camera, &scene.bounds);
        let ends = split::split_depths(self.split, self.lambda, self.n, near, far);
        let aspect = scene.render.width as f32 / scene.render.height as f32;
        let toward = match scene.emitter {
            Emitter::Sun(sun) => sun.toward(),
            _ => -scene.light.normal(),
        };
        let right = scene.light.edge_u.normalize();
        let samples = ends
            .windows(2)
            .enumerate()
            .map(|(i, z)| {
                let (centre, radius) = split::slice_sphere(&scene.camera, aspect, z[0], z[1]);
                orthographic_square(
                    toward,
                    right,
                    &scene.bounds,
                    centre,
                    split::quantize(radius),
                    scene.render.shadow_map_size,
                    i as u32,
                )
            })
            .collect();
        Placement { ends, samples }
    }

    /// The kernel's uniform for `placement`.
    pub(crate) fn uniform(&self, scene: &Scene, placement: &Placement) -> GpuCascades {
        let mut ends = [[0.0f32; 4]; 2];
        for (i, z) in placement.ends[1..].iter().enumerate() {
            ends[i / 4][i % 4] = *z;
        }
        GpuCascades {
            eye: scene.camera.eye.extend(1.0).to_array(),
            forward: split::forward(&scene.camera).extend(0.0).to_array(),
            ends,
            count: self.n,
            filtering: if self.filter == "hard" {
                FILTER_HARD
            } else {
                FILTER_PCF
            },
            ..Default::default()
        }
    }
}

/// The slices' ends z_0 … z_N and the map of each slice.
#[derive(Clone, Debug)]
pub struct Placement {
    pub ends: Vec<f32>,
    pub samples: Vec<GpuSample>,
}

impl Placement {
    /// run.json's figures: the slice ends and each map's texel in world units.
    pub(crate) fn record(&self, m: &CascadeMaps) -> CascadesRecord {
        CascadesRecord {
            split_depths: self.ends.clone(),
            texel_world: self.samples.iter().map(|s| s.texel_angle).collect(),
            n: m.n,
            split: m.split.name(),
            lambda: m.lambda,
            filter: m.filter,
        }
    }
}

/// cascades' record in run.json (`method_record`): the placement and the settings it came from.
#[derive(Clone, Debug, serde::Serialize)]
pub(crate) struct CascadesRecord {
    /// The slices' ends z_0 … z_N.
    pub(crate) split_depths: Vec<f32>,
    /// Each cascade's texel in world units.
    pub(crate) texel_world: Vec<f32>,
    pub(crate) n: u32,
    pub(crate) split: &'static str,
    pub(crate) lambda: f32,
    pub(crate) filter: &'static str,
}

impl ShadowMethod for CascadeMaps {
    fn unsupported_light(&self, kind: LightKind) -> Option<&'static str> {
        (kind != LightKind::Sun).then_some(SUN_ONLY)
    }
    fn name(&self) -> &'static str {
        "cascades"
    }
    fn label(&self) -> String {
        let mut parts = vec![
            format!("n={}", self.n),
            format!("split={}", self.split.name()),
        ];
        if self.split == Scheme::Practical && self.lambda != 0.5 {
            parts.push(format!("lambda={}", self.lambda));
        }
        if self.filter != "hard" {
            parts.push(format!("filter={}", self.filter));
        }
        format!("cascades:{}", parts.join(","))
    }
    fn params_json(&self) -> serde_json::Value {
        serde_json::json!({ "n": self.n, "split": self.split.name(), "lambda": self.lambda, "filter": self.filter })
    }
    /// One map per cascade.
    fn shadow_maps(&self, _scene: &Scene) -> u32 {
        self.n
    }
    /// V and the cascade index are bound by bands of rows, as pcf's V.
    fn size_needs(
        &self,
        scene: &Scene,
        limits: &wgpu::Limits,
    ) -> Vec<crate::gpu::size_plan::SizeNeed> {
        vec![
            super::sizes::visibility(scene, true, limits),
            super::sizes::per_pixel_in(scene, CHOSEN, 4, true, limits),
        ]
    }
    fn build(&self, fg: &FrameGpu) -> Result<Box<dyn MethodState>> {
        let s = fg.scene;
        if s.render.maps == MapKind::Hybrid {
            return Err(Error::Param(format!(
                "cascades: maps = hybrid is not supported (each cascade is a layer of the plain map array); scene {}: use maps = plain",
                s.origin
            )));
        }
        let placement = self.place(s);
        let uniform = self.uniform(s, &placement);
        let pcf = Pcf::from_map(&ParamMap::new())?;
        let (filter, disk) = (pcf.filter(s.render.shadow_map_size), pcf.disk());
        let array = fg.raster.allocate(fg.ctx, s.render.shadow_map_size, self.n);
        shadow_raster::clear_all(fg.ctx, &array)?;
        let pixels = fg.pixel_count() as u64;
        Ok(Box::new(State {
            method: *self,
            samples_buffer: readback::storage_buffer(
                fg.ctx,
                "cascade samples",
                &placement.samples,
                wgpu::BufferUsages::empty(),
            ),
            cascades_buffer: readback::uniform_buffer(fg.ctx, "cascades", &uniform),
            filter_buffer: readback::uniform_buffer(fg.ctx, "cascades filter", &filter),
            disk_buffer: readback::storage_buffer(
                fg.ctx,
                "cascades disk",
                &disk,
                wgpu::BufferUsages::empty(),
            ),
            chosen: readback::zeroed_storage(fg.ctx, CHOSEN, pixels * 4),
            pass: CascadesPass::new(fg.ctx, fg.map_access())?,
            array,
            placement,
            uniform,
            filter,
            disk,
        }))
    }
    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}

/// The per-pixel buffer of the cascade each pixel took (its label in the size plan).
pub(crate) const CHOSEN: &str = "cascade index";

struct State {
    method: CascadeMaps,
    placement: Placement,
    uniform: GpuCascades,
    filter: GpuFilter,
    disk: Vec<[f32; 2]>,
    samples_buffer: wgpu::Buffer,
    cascades_buffer: wgpu::Buffer,
    filter_buffer: wgpu::Buffer,
    disk_buffer: wgpu::Buffer,
    chosen: wgpu::Buffer,
    array: ShadowMapArray,
    pass: CascadesPass,
}

/// A frame's inputs and outputs for the twin and the cascade study (`Renderer::inspect`).
#[derive(Clone, Debug)]
pub struct CascadeBuffers {
    pub placement: Placement,
    pub uniform: GpuCascades,
    pub filter: GpuFilter,
    pub disk: Vec<[f32; 2]>,
    /// Cascade i's map, row by row.
    pub maps: Vec<Vec<f32>>,
    /// The cascade of every pixel (`stages::cascades::NO_CASCADE` on background).
    pub chosen: Vec<u32>,
}

impl MethodState for State {
    fn reset(&mut self, _fg: &FrameGpu) -> Result<()> {
        Ok(()) // the raster clears its layers; the kernel writes every pixel's cascade
    }
    fn run(
        &mut self,
        fg: &FrameGpu,
        timer: &mut StageTimer,
        _pictures: bool,
    ) -> Result<MethodOutput> {
        let jobs: Vec<RasterJob> = (0..self.method.n)
            .map(|i| RasterJob {
                sample: i,
                layer: i,
                scissor: None,
            })
            .collect();
        timer.stage(fg.ctx, fg.raster.stage(), |enc| {
            fg.raster.record(
                fg.ctx,
                enc,
                &RasterTarget {
                    scene: &fg.scene_gpu,
                    samples: &self.samples_buffer,
                    array: &self.array,
                },
                &jobs,
            )
        })?;
        let inputs = CascadeInputs {
            filter: &self.filter_buffer,
            disk: &self.disk_buffer,
            samples: &self.samples_buffer,
            maps: &self.array.array_view,
            cascades: &self.cascades_buffer,
            chosen: &self.chosen,
        };
        timer.stage(fg.ctx, Stage::CASCADES, |enc| {
            self.pass.record(fg.ctx, enc, &fg.screen(), &inputs);
            Ok(())
        })?;
        Ok(MethodOutput {
            shadow_maps: self.method.n,
            syncs: 0,
            record: super::record_value("cascades", &self.placement.record(&self.method))?,
            pictures: Vec::new(),
            bound: None,
        })
    }
    fn inspect(&mut self, fg: &FrameGpu) -> Result<Option<Box<dyn std::any::Any>>> {
        let maps = (0..self.method.n)
            .map(|i| readback::read_texture(fg.ctx, &self.array.texture, i, 4))
            .collect::<Result<Vec<Vec<f32>>>>()?;
        let chosen = readback::read_buffer(fg.ctx, &self.chosen, fg.pixel_count() as u64 * 4)?;
        Ok(Some(Box::new(CascadeBuffers {
            placement: self.placement.clone(),
            uniform: self.uniform,
            filter: self.filter,
            disk: self.disk.clone(),
            maps,
            chosen,
        })))
    }
    fn buffer_sizes(&self) -> Vec<(String, u64)> {
        vec![(CHOSEN.to_string(), self.chosen.size())]
    }
}
