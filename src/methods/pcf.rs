//! Percentage-closer filtering of one shadow map (seeds 001 and 004): every pixel averages the
//! binary shadow test over taps around its place in the map.

use super::hybrid_maps::HybridRecord;
use super::single_map::{CentreMap, SingleMapBuffers};
use super::{
    check_range, get_u32, ChoiceDecl, Family, MethodInfo, MethodOutput, MethodState, Param,
    ParamDecl, ParamMap, ShadowMethod,
};
use crate::gpu::readback;
use crate::gpu::structs::GpuFilter;
use crate::gpu::timing::StageTimer;
use crate::gpu::Stage;
use crate::stages::pcf::Pcf as PcfPass;
use crate::stages::shade::MapFilter;
use crate::stages::FrameGpu;
use crate::{Error, Result};
use std::sync::Arc;

pub(crate) const KERNELS: [&str; 5] = ["box", "bilinear", "poisson", "stratified", "rotated"];

pub(crate) const KERNEL: ChoiceDecl = ChoiceDecl::new(
    "kernel",
    "poisson",
    &KERNELS,
    "box (N×N), bilinear (N×N comparison-sampler lookups), poisson, stratified (seed 004), rotated",
);
pub(crate) const RADIUS: ParamDecl<f32> =
    ParamDecl::new("radius", "2", 0.0, 64.0, "filter radius in texels");
pub(crate) const DARKENING: ParamDecl<f32> = ParamDecl::new(
    "darkening",
    "0",
    0.0,
    1.0,
    "seed 004: V = 1 − darkening·(shadowed taps); 0 averages the taps",
);

pub(crate) const INFO: MethodInfo = MethodInfo {
    name: "pcf",
    family: Family::Pcf,
    summary: "percentage-closer filtering of the centre map: box, bilinear, Poisson, stratified or rotated taps",
    params: &[
        KERNEL.param(),
        Param { key: "taps", default: "16", help: "box/bilinear: N per side (default 5 / 3); poisson/rotated: 4, 16, 32 or 64; stratified: 1..=64 drawn from 16 points" },
        RADIUS.param(),
        Param { key: "spread", default: "none", help: "radius as a fraction of the map (seed 004: 1/700); overrides radius" },
        DARKENING.param(),
    ],
    parse: |p| Ok(Arc::new(Pcf::from_map(p)?)),
};

#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Pcf {
    pub(crate) kernel: &'static str,
    pub(crate) taps: u32,
    pub(crate) radius: f32,
    pub(crate) spread: Option<f32>,
    pub(crate) darkening: f32,
}

/// `a/b` or a plain number (seed 004 writes its spread as 1/700).
fn fraction(params: &ParamMap, key: &str) -> Result<Option<f32>> {
    let Some(v) = params.get(key) else {
        return Ok(None);
    };
    let parsed = match v.split_once('/') {
        Some((a, b)) => a
            .trim()
            .parse::<f32>()
            .ok()
            .zip(b.trim().parse::<f32>().ok())
            .map(|(a, b)| a / b),
        None => v.parse::<f32>().ok(),
    };
    match parsed {
        Some(x) if x.is_finite() && x > 0.0 && x < 1.0 => Ok(Some(x)),
        _ => Err(Error::Param(format!(
            "pcf: {key} = `{v}` is not a fraction in (0, 1) such as 1/700"
        ))),
    }
}

impl Pcf {
    pub(crate) fn from_map(p: &ParamMap) -> Result<Self> {
        let kernel = KERNEL.get(p)?;
        let default_taps = match kernel {
            "box" => 5,
            "bilinear" => 3,
            _ => 16,
        };
        let taps = get_u32(p, "taps", default_taps)?;
        match kernel {
            "box" | "bilinear" => check_range("pcf", "taps", taps, 1, 16).map(|_| ())?,
            "stratified" => check_range("pcf", "taps", taps, 1, 64).map(|_| ())?,
            _ if ![4, 16, 32, 64].contains(&taps) => {
                return Err(Error::Param(format!(
                    "pcf: taps = {taps} with kernel = {kernel}: use 4, 16, 32 or 64"
                )));
            }
            _ => {}
        }
        let radius = RADIUS.get(p, "pcf")?;
        let darkening = DARKENING.get(p, "pcf")?;
        Ok(Self {
            kernel,
            taps,
            radius,
            spread: fraction(p, "spread")?,
            darkening,
        })
    }

    fn default_taps(&self) -> u32 {
        match self.kernel {
            "box" => 5,
            "bilinear" => 3,
            _ => 16,
        }
    }

    /// The tap offsets (unit disk) the kernel reads.
    pub(crate) fn disk(&self) -> Vec<[f32; 2]> {
        match self.kernel {
            "box" | "bilinear" => vec![[0.0, 0.0]],
            "stratified" => poisson_disk(16),
            _ => poisson_disk(self.taps as usize),
        }
    }

    pub(crate) fn filter(&self, map_size: u32) -> GpuFilter {
        GpuFilter {
            kind: KERNELS.iter().position(|k| *k == self.kernel).unwrap_or(2) as u32,
            taps: self.taps,
            order: 16,
            radius: self.spread.map_or(self.radius, |s| s * map_size as f32),
            darkening: self.darkening,
            ..Default::default()
        }
    }
}

/// The seed's four points (opengl-tutorial / Babylon.js), else `n` points in the unit disk by
/// Mitchell's best-candidate sampling with a fixed generator: deterministic, well spread.
pub(crate) fn poisson_disk(n: usize) -> Vec<[f32; 2]> {
    if n == 4 {
        return vec![
            [-0.94201624, -0.39906216],
            [0.945_586_1, -0.76890725],
            [-0.094_184_1, -0.929_388_7],
            [0.34495938, 0.293_877_6],
        ];
    }
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut next = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((state >> 40) as f32) / (1u64 << 24) as f32
    };
    let mut points: Vec<[f32; 2]> = Vec::with_capacity(n);
    while points.len() < n {
        let mut best = ([0.0f32; 2], -1.0f32);
        for _ in 0..(10 * (points.len() + 1)).min(400) {
            let (r, a) = (next().sqrt(), next() * std::f32::consts::TAU);
            let c = [r * a.cos(), r * a.sin()];
            let d = points
                .iter()
                .map(|p| (p[0] - c[0]).powi(2) + (p[1] - c[1]).powi(2))
                .fold(f32::INFINITY, f32::min);
            if d > best.1 {
                best = (c, d);
            }
        }
        points.push(best.0);
    }
    points
}

impl ShadowMethod for Pcf {
    fn unsupported_light(&self, kind: crate::scene::LightKind) -> Option<&'static str> {
        (!(super::maps_from_the_emitter(kind) || super::cube_maps(kind)))
            .then_some(super::FROM_THE_CENTRE)
    }
    fn name(&self) -> &'static str {
        "pcf"
    }
    fn label(&self) -> String {
        let mut s = format!("pcf:kernel={}", self.kernel);
        if self.taps != self.default_taps() {
            s += &format!(",taps={}", self.taps);
        }
        if let Some(spread) = self.spread {
            s += &format!(",spread={spread}");
        } else if self.radius != 2.0 {
            s += &format!(",radius={}", self.radius);
        }
        if self.darkening > 0.0 {
            s += &format!(",darkening={}", self.darkening);
        }
        s
    }
    fn params_json(&self) -> serde_json::Value {
        serde_json::json!({ "kernel": self.kernel, "taps": self.taps, "radius": self.radius, "spread": self.spread, "darkening": self.darkening })
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
        let filter = self.filter(fg.frame.map_size);
        let disk = self.disk();
        Ok(Box::new(State {
            map: CentreMap::new(fg)?,
            filter_buffer: readback::uniform_buffer(fg.ctx, "pcf filter", &filter),
            disk_buffer: readback::storage_buffer(
                fg.ctx,
                "pcf disk",
                &disk,
                wgpu::BufferUsages::empty(),
            ),
            pass: PcfPass::new(fg.ctx, fg.map_access())?,
            filter,
            disk,
        }))
    }
    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}

struct State {
    map: CentreMap,
    filter: GpuFilter,
    disk: Vec<[f32; 2]>,
    filter_buffer: wgpu::Buffer,
    disk_buffer: wgpu::Buffer,
    pass: PcfPass,
}

/// pcf's record in run.json (`method_record`).
#[derive(serde::Serialize)]
struct PcfRecord {
    radius_texels: f32,
    taps: u32,
    /// `maps = hybrid`: the hybrid store's figures.
    #[serde(skip_serializing_if = "Option::is_none")]
    hybrid: Option<HybridRecord>,
}

impl MethodState for State {
    fn reset(&mut self, _fg: &FrameGpu) -> Result<()> {
        Ok(()) // the raster clears its map; pcf writes every geometry pixel
    }
    fn run(
        &mut self,
        fg: &FrameGpu,
        timer: &mut StageTimer,
        _pictures: bool,
    ) -> Result<MethodOutput> {
        self.map.render(fg, timer)?;
        timer.stage(fg.ctx, Stage::PCF, |enc| {
            self.pass.record(
                fg.ctx,
                enc,
                &fg.screen(),
                &MapFilter {
                    filter: &self.filter_buffer,
                    samples: &self.map.samples,
                    maps: self.map.view(),
                },
                &self.disk_buffer,
            );
            Ok(())
        })?;
        Ok(MethodOutput {
            shadow_maps: self.map.count(),
            syncs: self.map.syncs(),
            record: super::record_value(
                "pcf",
                &PcfRecord {
                    radius_texels: self.filter.radius,
                    taps: self.filter.taps,
                    hybrid: self.map.hybrid_record(),
                },
            )?,
            pictures: Vec::new(),
            bound: None,
        })
    }
    /// [`SingleMapBuffers`]: the map and the kernel pcf read.
    fn inspect(&mut self, fg: &FrameGpu) -> Result<Option<Box<dyn std::any::Any>>> {
        let c = SingleMapBuffers {
            map: self.map.read(fg)?,
            sample: self.map.sample,
            filter: self.filter,
            disk: self.disk.clone(),
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

#[cfg(test)]
mod tests {
    #[test]
    fn disks_are_in_the_unit_disk_and_spread() {
        for n in [16, 32, 64] {
            let d = super::poisson_disk(n);
            assert_eq!(d.len(), n);
            let mut closest = f32::INFINITY;
            for (i, a) in d.iter().enumerate() {
                assert!(a[0] * a[0] + a[1] * a[1] <= 1.0 + 1e-6);
                for b in &d[i + 1..] {
                    closest = closest.min(((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt());
                }
            }
            // A Poisson disk keeps points apart: at least half the spacing of a hexagonal packing.
            let hex = (2.0 * std::f32::consts::PI / (3f32.sqrt() * n as f32)).sqrt();
            assert!(
                closest > 0.5 * hex,
                "{n} points: closest pair {closest}, hex spacing {hex}"
            );
        }
    }
}
