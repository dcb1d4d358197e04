//! env-adaptive: the environment refined like the light quad. A quadtree over the panorama
//! (level 0: `cells`), split where the rays to a cell's corners disagree in more than `p_m`
//! pixels (env_count, atomics) or where its quadrants' powers differ by more than `contrast`
//! (env_split); cells under `min_share` of the power never split. Every leaf becomes one light at
//! its power centroid carrying its power, and env_trace shades with them (docs/environment.md §2).

pub(crate) use super::common::EnvLevelBuffers;
use super::common::SsaoSettings;
use super::common::{environment, gpu_lights, resolution, SceneRays};
use super::picture;
use super::pixels::{parse_ssao, RayLights, AO_RADIUS, AO_SAMPLES, SSAO};
use crate::gpu::readback;
use crate::gpu::structs::{GpuEnvCell, GpuEnvParams};
use crate::gpu::timing::StageTimer;
use crate::gpu::Stage;
use crate::methods::{
    Family, MethodInfo, MethodOutput, MethodState, Param, ParamDecl, ShadowMethod,
};
use crate::scene::environment::panorama::luminance;
use crate::scene::environment::{EnvLight, Environment};
use crate::stages::env_count::{EnvCount, EnvCountInputs};
use crate::stages::env_split::{EnvSplit, EnvSplitIo};
use crate::stages::FrameGpu;
use crate::{Error, Result};
use glam::Vec3;
use std::sync::Arc;

pub(crate) const MAX_LEVEL: ParamDecl<u32> =
    ParamDecl::new("max_level", "4", 0, 6, "levels of splitting, 0..=6");
pub(crate) const P_M: ParamDecl<u32> = ParamDecl::new(
    "p_m",
    "0",
    0,
    u32::MAX,
    "split when more than p_m pixels see the cell's corners disagree",
);
pub(crate) const CONTRAST: ParamDecl<f32> = ParamDecl::new(
    "contrast",
    "4",
    1.0,
    1e9,
    "split when the cell's quadrants' powers differ by more than this factor",
);
pub(crate) const MIN_SHARE: ParamDecl<f32> = ParamDecl::new(
    "min_share",
    "0.01",
    0.0,
    1.0,
    "cells under this share of the panorama's power never split",
);
pub(crate) const COUNT_STRIDE: ParamDecl<u32> = ParamDecl::new(
    "count_stride",
    "2",
    1,
    8,
    "count every n-th pixel in x and y (1..=8): p_m is in counted pixels",
);

pub(crate) const INFO: MethodInfo = MethodInfo {
    name: "env-adaptive",
    family: Family::Environment,
    summary: "a quadtree over the panorama split where visibility or radiance disagrees (GPU atomics), one ray per leaf",
    params: &[
        Param { key: "cells", default: "4x2", help: "level-0 cells, WxH; the finest lattice is cells × 2^max_level and must divide the panorama" },
        MAX_LEVEL.param(),
        P_M.param(),
        CONTRAST.param(),
        MIN_SHARE.param(),
        COUNT_STRIDE.param(),
        SSAO.param(),
        AO_SAMPLES.param(),
        AO_RADIUS.param(),
    ],
    parse: |p| {
        let (bw, bh) = resolution(p, "env-adaptive", "cells", (4, 2))?;
        let max_level = MAX_LEVEL.get(p, "env-adaptive")?;
        let p_m = P_M.get(p, "env-adaptive")?;
        let contrast = CONTRAST.get(p, "env-adaptive")?;
        let min_share = MIN_SHARE.get(p, "env-adaptive")?;
        let count_stride = COUNT_STRIDE.get(p, "env-adaptive")?;
        Ok(Arc::new(EnvAdaptive { base: (bw, bh), max_level, p_m, contrast, min_share, count_stride, ssao: parse_ssao(p, "env-adaptive")? }))
    },
};

#[derive(Clone, Debug, PartialEq)]
pub(crate) struct EnvAdaptive {
    pub(crate) base: (u32, u32),
    pub(crate) max_level: u32,
    pub(crate) p_m: u32,
    pub(crate) contrast: f32,
    pub(crate) min_share: f32,
    pub(crate) count_stride: u32,
    pub(crate) ssao: Option<SsaoSettings>,
}

impl EnvAdaptive {
    pub(crate) fn finest(&self) -> (u32, u32) {
        (self.base.0 << self.max_level, self.base.1 << self.max_level)
    }
}

impl ShadowMethod for EnvAdaptive {
    /// No shadow maps: it traces or samples the screen.
    fn shadow_maps(&self, _scene: &crate::scene::Scene) -> u32 {
        0
    }
    /// The panorama lights it; `[light]` is not read.
    fn unsupported_light(&self, _kind: crate::scene::LightKind) -> Option<&'static str> {
        None
    }
    fn name(&self) -> &'static str {
        "env-adaptive"
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
        let values = [
            ("cells", format!("{}x{}", self.base.0, self.base.1)),
            ("max_level", self.max_level.to_string()),
            ("p_m", self.p_m.to_string()),
            ("contrast", self.contrast.to_string()),
            ("min_share", self.min_share.to_string()),
            ("count_stride", self.count_stride.to_string()),
        ];
        let mut s = crate::methods::label_from(&INFO, &values);
        if let Some(a) = self.ssao {
            s += &format!(
                "{}ssao=on,ao_samples={},ao_radius={}",
                if s.contains(':') { "," } else { ":" },
                a.samples,
                a.radius
            );
        }
        s
    }
    fn params_json(&self) -> serde_json::Value {
        serde_json::json!({ "cells": [self.base.0, self.base.1], "max_level": self.max_level, "p_m": self.p_m, "contrast": self.contrast, "min_share": self.min_share, "count_stride": self.count_stride, "ssao": self.ssao })
    }
    fn build(&self, fg: &FrameGpu) -> Result<Box<dyn MethodState>> {
        let env = environment(fg, "env-adaptive")?;
        let (fw, fh) = self.finest();
        let p = &env.panorama;
        if p.width % fw != 0 || p.height % fh != 0 {
            return Err(Error::Param(format!(
                "env-adaptive: the finest lattice {fw}x{fh} (cells {}x{} × 2^{}) must divide the panorama's {}x{}",
                self.base.0, self.base.1, self.max_level, p.width, p.height
            )));
        }
        let tables = PowerTables::new(env);
        let cell_power = tables.finest(fw, fh);
        let corners: Vec<[f32; 4]> = (0..=fh)
            .flat_map(|j| (0..=fw).map(move |i| (i, j)))
            .map(|(i, j)| {
                env.direction(i as f32 / fw as f32, j as f32 / fh as f32)
                    .extend(0.0)
                    .to_array()
            })
            .collect();
        let base: Vec<GpuEnvCell> = (0..self.base.1)
            .flat_map(|j| (0..self.base.0).map(move |i| (i, j)))
            .map(|(i, j)| GpuEnvCell {
                i: i << self.max_level,
                j: j << self.max_level,
                size: 1 << self.max_level,
                level: 0,
            })
            .collect();
        let capacity = (fw * fh) as u64;
        let ctx = fg.ctx;
        let cell_bytes = capacity * std::mem::size_of::<GpuEnvCell>() as u64;
        // The final pass: env_trace with a light list rewritten every frame (at most one per finest cell).
        let mut trace = RayLights::new(
            fg,
            vec![Default::default(); capacity as usize],
            self.ssao,
            Vec::new(),
        )?;
        trace.params.light_count = 0;
        let rays: &SceneRays = &trace.rays;
        let mut params = rays.params(fg);
        params.finest_width = fw;
        params.finest_height = fh;
        params.max_level = self.max_level;
        params.p_m = self.p_m;
        params.contrast = self.contrast;
        params.min_share = self.min_share;
        params.total_power = cell_power.iter().sum();
        params.count_stride = self.count_stride;
        Ok(Box::new(State {
            count: EnvCount::new(ctx)?,
            split: EnvSplit::new(ctx)?,
            corners_buffer: readback::storage_buffer(
                ctx,
                "env corners",
                &corners,
                wgpu::BufferUsages::empty(),
            ),
            power_buffer: readback::storage_buffer(
                ctx,
                "env cell power",
                &cell_power,
                wgpu::BufferUsages::empty(),
            ),
            cells: [
                readback::zeroed_storage(ctx, "env cells a", cell_bytes),
                readback::zeroed_storage(ctx, "env cells b", cell_bytes),
            ],
            leaves: readback::zeroed_storage(ctx, "env leaves", cell_bytes),
            counts: readback::zeroed_storage(ctx, "env counts", capacity * 4),
            control: readback::zeroed_storage(ctx, "env control", 16),
            level_params: (0..=self.max_level)
                .map(|_| readback::uniform_buffer(ctx, "env level", &params))
                .collect(),
            params,
            corners,
            cell_power,
            base,
            tables,
            env: env.clone(),
            trace,
            keep: false,
            kept: Vec::new(),
        }))
    }
    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}

/// Summed-area tables of the full-resolution panorama: power (luminance · Δω) and power-weighted
/// direction, so any cell's power and power centroid cost four reads.
pub(crate) struct PowerTables {
    width: usize,
    height: usize,
    sat: Vec<[f64; 4]>,
}

impl PowerTables {
    pub(crate) fn new(env: &Environment) -> PowerTables {
        let p = &env.panorama;
        let (w, h) = (p.width as usize, p.height as usize);
        let mut sat = vec![[0.0f64; 4]; (w + 1) * (h + 1)];
        for y in 0..h {
            let angle = p.pixel_solid_angle(y as u32) as f64;
            let mut row = [0.0f64; 4];
            for x in 0..w {
                let e = luminance(p.at(x as u32, y as u32)) as f64 * angle * env.intensity as f64;
                let d = env.direction((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
                row[0] += e;
                row[1] += e * d.x as f64;
                row[2] += e * d.y as f64;
                row[3] += e * d.z as f64;
                let above = sat[y * (w + 1) + x + 1];
                sat[(y + 1) * (w + 1) + x + 1] = [
                    above[0] + row[0],
                    above[1] + row[1],
                    above[2] + row[2],
                    above[3] + row[3],
                ];
            }
        }
        PowerTables {
            width: w,
            height: h,
            sat,
        }
    }

    /// Σ over full-resolution pixels [x0, x1) × [y0, y1): (power, Σ power · direction).
    fn sum(&self, x0: usize, y0: usize, x1: usize, y1: usize) -> [f64; 4] {
        let at = |x: usize, y: usize| self.sat[y * (self.width + 1) + x];
        let (a, b, c, d) = (at(x1, y1), at(x0, y1), at(x1, y0), at(x0, y0));
        [0, 1, 2, 3].map(|k| a[k] - b[k] - c[k] + d[k])
    }

    /// Power of every cell of the `fw` × `fh` lattice, row-major.
    pub(crate) fn finest(&self, fw: u32, fh: u32) -> Vec<f32> {
        let (sx, sy) = (self.width / fw as usize, self.height / fh as usize);
        (0..fh as usize)
            .flat_map(|j| (0..fw as usize).map(move |i| (i, j)))
            .map(|(i, j)| self.sum(i * sx, j * sy, (i + 1) * sx, (j + 1) * sy)[0] as f32)
            .collect()
    }

    /// The light of a leaf (in finest-lattice units of a `fw` × `fh` lattice): its power centroid.
    pub(crate) fn leaf_light(&self, c: &GpuEnvCell, fw: u32, fh: u32) -> Option<EnvLight> {
        let (sx, sy) = (self.width / fw as usize, self.height / fh as usize);
        let (x0, y0) = (c.i as usize * sx, c.j as usize * sy);
        let s = self.sum(x0, y0, x0 + c.size as usize * sx, y0 + c.size as usize * sy);
        let d = Vec3::new(s[1] as f32, s[2] as f32, s[3] as f32).normalize_or_zero();
        (s[0] > 0.0 && d != Vec3::ZERO).then_some(EnvLight {
            direction: d,
            power: s[0] as f32,
        })
    }
}

struct State {
    count: EnvCount,
    split: EnvSplit,
    params: GpuEnvParams,
    corners: Vec<[f32; 4]>,
    cell_power: Vec<f32>,
    base: Vec<GpuEnvCell>,
    tables: PowerTables,
    env: Environment,
    corners_buffer: wgpu::Buffer,
    power_buffer: wgpu::Buffer,
    cells: [wgpu::Buffer; 2],
    leaves: wgpu::Buffer,
    counts: wgpu::Buffer,
    control: wgpu::Buffer,
    level_params: Vec<wgpu::Buffer>,
    trace: RayLights,
    /// Tests: each level's cells and counts are kept, since the next level overwrites them.
    keep: bool,
    kept: Vec<EnvLevelBuffers>,
}

/// env-adaptive's record in run.json (`method_record`).
#[derive(serde::Serialize)]
struct EnvAdaptiveRecord {
    /// Lights traced per pixel: one per leaf that carries power.
    samples: usize,
    rays_per_pixel: usize,
    leaves_per_level: Vec<u32>,
    /// Cells per side of the finest lattice.
    finest: [u32; 2],
    levels: Vec<EnvLevelRecord>,
}

/// One level of env-adaptive's cell tree.
#[derive(serde::Serialize)]
struct EnvLevelRecord {
    level: u32,
    active_cells: u32,
    split_cells: u32,
    leaves: u32,
    /// Whether env_count ran (the last level splits nothing).
    counted: bool,
}

impl MethodState for State {
    fn reset(&mut self, fg: &FrameGpu) -> Result<()> {
        fg.ctx
            .queue
            .write_buffer(&self.cells[0], 0, bytemuck::cast_slice(&self.base));
        Ok(())
    }

    fn run(
        &mut self,
        fg: &FrameGpu,
        timer: &mut StageTimer,
        pictures: bool,
    ) -> Result<MethodOutput> {
        let ctx = fg.ctx;
        let (fw, fh) = (self.params.finest_width, self.params.finest_height);
        let mut cell_count = self.base.len() as u32;
        let mut levels = Vec::new();
        self.kept.clear();
        let mut syncs = 0;
        let mut leaves_so_far = 0u32;
        let cell_size = std::mem::size_of::<GpuEnvCell>() as u64;
        for level in 0..=self.params.max_level {
            let mut params = self.params;
            params.cell_count = cell_count;
            ctx.queue.write_buffer(
                &self.level_params[level as usize],
                0,
                bytemuck::bytes_of(&params),
            );
            let (cur, next) = (
                &self.cells[level as usize % 2],
                &self.cells[(level as usize + 1) % 2],
            );
            let counted = level < self.params.max_level;
            if counted {
                timer.stage(ctx, Stage::ENV_COUNT, |enc| {
                    enc.clear_buffer(&self.counts, 0, Some(cell_count as u64 * 4));
                    let inputs = EnvCountInputs {
                        params: &self.level_params[level as usize],
                        corners: &self.corners_buffer,
                        cells: cur,
                        counts: &self.counts,
                        cell_count,
                        stride: self.params.count_stride,
                    };
                    self.count
                        .record(ctx, enc, &fg.gbuffer, &inputs, &self.trace.rays.buffers);
                    Ok(())
                })?;
            }
            timer.stage(ctx, Stage::ENV_SPLIT, |enc| {
                if !counted {
                    enc.clear_buffer(&self.counts, 0, Some(cell_count as u64 * 4));
                }
                // Next-level count restarts; the leaf count runs on across levels.
                enc.clear_buffer(&self.control, 0, Some(4));
                if level == 0 {
                    enc.clear_buffer(&self.control, 4, Some(4));
                }
                let io = EnvSplitIo {
                    params: &self.level_params[level as usize],
                    cells: cur,
                    counts: &self.counts,
                    cell_power: &self.power_buffer,
                    next_cells: next,
                    leaves: &self.leaves,
                    control: &self.control,
                };
                self.split.record(ctx, enc, &io, cell_count);
                Ok(())
            })?;
            timer.flush(ctx);
            let control: Vec<u32> = timer.cpu(Stage::ENV_READBACK, || {
                readback::read_buffer(ctx, &self.control, 16)
            })?;
            syncs += 1;
            let (next_count, leaf_count) = (control[0], control[1]);
            if self.keep {
                let read_cells = |b: &wgpu::Buffer, n: u32, skip: u32| -> Result<Vec<GpuEnvCell>> {
                    let all: Vec<GpuEnvCell> =
                        readback::read_buffer(ctx, b, ((skip + n) as u64 * cell_size).max(16))?;
                    let mut v = all[skip as usize..(skip + n) as usize].to_vec();
                    v.sort();
                    Ok(v)
                };
                let counts: Vec<u32> =
                    readback::read_buffer(ctx, &self.counts, (cell_count as u64 * 4).max(16))?;
                let unsorted: Vec<GpuEnvCell> =
                    readback::read_buffer(ctx, cur, (cell_count as u64 * cell_size).max(16))?;
                self.kept.push(EnvLevelBuffers {
                    params,
                    cells: unsorted[..cell_count as usize].to_vec(),
                    counts: counts[..cell_count as usize].to_vec(),
                    next: read_cells(next, next_count, 0)?,
                    leaves: read_cells(&self.leaves, leaf_count - leaves_so_far, leaves_so_far)?,
                    corners: self.corners.clone(),
                    cell_power: self.cell_power.clone(),
                });
            }
            levels.push(EnvLevelRecord {
                level,
                active_cells: cell_count,
                split_cells: next_count / 4,
                leaves: leaf_count - leaves_so_far,
                counted,
            });
            leaves_so_far = leaf_count;
            cell_count = next_count;
            if next_count == 0 {
                break;
            }
        }
        // The leaves become lights: one read-back, the centroids from the summed-area tables.
        let leaves: Vec<GpuEnvCell> = timer.cpu(Stage::ENV_READBACK, || {
            readback::read_buffer(
                ctx,
                &self.leaves,
                (leaves_so_far as u64 * cell_size).max(16),
            )
        })?;
        syncs += 1;
        // Leaves arrive in atomic-append order, which varies from frame to frame; the light list
        // (and so the order env_trace sums in) must not, or V differs in its last bits.
        let mut leaves = leaves[..leaves_so_far as usize].to_vec();
        leaves.sort();
        let leaves = &leaves[..];
        let lights: Vec<EnvLight> = timer.cpu(Stage::ENV_LIGHTS, || {
            Ok(leaves
                .iter()
                .filter_map(|c| self.tables.leaf_light(c, fw, fh))
                .collect())
        })?;
        let gpu = gpu_lights(&lights);
        self.trace.params.light_count = gpu.len() as u32;
        self.trace.lights = gpu.clone();
        if !gpu.is_empty() {
            ctx.queue
                .write_buffer(&self.trace.lights_buffer, 0, bytemuck::cast_slice(&gpu));
        }
        self.trace.run(fg, timer)?;
        let pictures = if pictures {
            vec![(
                "panorama_quadtree.png".to_string(),
                self.picture(leaves, &lights),
            )]
        } else {
            Vec::new()
        };
        let mut per_level = vec![0u32; self.params.max_level as usize + 1];
        for c in leaves {
            per_level[c.level as usize] += 1;
        }
        Ok(MethodOutput {
            shadow_maps: lights.len() as u32,
            syncs,
            record: crate::methods::record_value(
                "env-adaptive",
                &EnvAdaptiveRecord {
                    samples: lights.len(),
                    rays_per_pixel: lights.len(),
                    leaves_per_level: per_level,
                    finest: [fw, fh],
                    levels,
                },
            )?,
            pictures,
            bound: None,
        })
    }
    fn keep_intermediates(&mut self) {
        self.keep = true;
    }
    /// env_trace's [`EnvTraceBuffers`](super::pixels::EnvTraceBuffers), with the levels kept when
    /// `keep_intermediates` was called before the frame.
    fn inspect(&mut self, fg: &FrameGpu) -> Result<Option<Box<dyn std::any::Any>>> {
        let mut c = self.trace.read(fg)?;
        c.levels = self.kept.clone();
        Ok(Some(Box::new(c)))
    }
}

impl State {
    fn picture(&self, leaves: &[GpuEnvCell], lights: &[EnvLight]) -> image::RgbImage {
        let mut img = picture::panorama_picture(&self.env, 512);
        let (fw, fh) = (
            self.params.finest_width as f32,
            self.params.finest_height as f32,
        );
        for c in leaves {
            let uv0 = (c.i as f32 / fw, c.j as f32 / fh);
            let uv1 = ((c.i + c.size) as f32 / fw, (c.j + c.size) as f32 / fh);
            picture::rect(&mut img, uv0, uv1, picture::level_colour(c.level));
        }
        for l in lights {
            picture::mark(
                &mut img,
                &self.env,
                l.direction,
                image::Rgb([255, 255, 255]),
            );
        }
        img
    }
}
