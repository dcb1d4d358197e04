//! `penumbra cascades` (docs/lights.md "Cascades"): the sun's cascaded shadow maps on one scene
//! for each number of cascades and split scheme, judged against the continuous reference, with
//! each cascade's texel density on screen: how many screen pixels one of its map's texels spans.

pub(crate) mod charts;
pub mod command;
pub mod files;

use crate::frame::Renderer;
use crate::gpu::timing::TimingMode;
use crate::gpu::GpuContext;
use crate::methods::cascades::{split::Scheme, CascadeBuffers, CascadeMaps};
use crate::methods::Method;
use crate::record::stats::median;
use crate::record::RowCore;
use crate::reference::truth::{self, Cache};
use crate::reference::ReferenceMode;
use crate::render::gbuffer::GBufferCpu;
use crate::scene::Scene;
use crate::stages::cascades::NO_CASCADE;
use crate::{Error, Result};
use glam::Vec3;
use serde::{Deserialize, Serialize};

pub struct CascadeJob<'a> {
    pub scene: &'a Scene,
    /// Numbers of cascades, each in 1..=MAX_CASCADES.
    pub ns: Vec<u32>,
    pub schemes: Vec<Scheme>,
    /// The practical scheme's weight of the log split.
    pub lambda: f32,
    /// `hard` or `pcf`.
    pub filter: &'static str,
    pub reference: ReferenceMode,
    pub cache: Cache,
}

/// One cascade of one setting.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct CascadeFigures {
    pub index: u32,
    /// Its slice of the view depth.
    pub near: f32,
    pub far: f32,
    /// Its map's texel in world units.
    pub texel_world: f32,
    /// Geometry pixels it serves, and their share of all geometry pixels.
    pub pixels: usize,
    pub share: f64,
    /// Screen pixels one texel spans, across the view (texel / the pixel's footprint at its view
    /// depth, foreshortening not counted): the median over the pixels it serves; `null` when it
    /// serves none.
    pub density_median: Option<f64>,
}

/// One line of `cascades.jsonl`: one (scheme, n) setting.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct CascadeLine {
    /// Scene, the label as spec, method, params, maps (one per cascade), map size, RMSE over
    /// geometry pixels, adapter, build; `frame_ms` 0: the study times no frame.
    #[serde(flatten)]
    pub core: RowCore,
    pub n: u32,
    pub split: String,
    pub lambda: f32,
    pub filter: String,
    pub label: String,
    pub geometry_pixels: usize,
    pub cascades: Vec<CascadeFigures>,
    pub resolution: [u32; 2],
    pub reference: String,
}

impl CascadeLine {
    /// The chart's and the table's name of the scheme: practical carries its λ.
    pub fn scheme(&self) -> String {
        if self.split == "practical" {
            format!("practical (λ = {})", self.lambda)
        } else {
            self.split.clone()
        }
    }
}

/// Screen pixels per texel, per geometry pixel: `texel_world[chosen]` over the pixel's footprint
/// `2·z·tan(fov/2)/height` at view depth z. `None` for background.
pub fn densities(scene: &Scene, g: &GBufferCpu, b: &CascadeBuffers) -> Vec<Option<(u32, f64)>> {
    let eye = scene.camera.eye;
    let forward = crate::methods::cascades::split::forward(&scene.camera);
    let per_depth =
        2.0 * (0.5 * scene.camera.fov_y_deg.to_radians()).tan() as f64 / g.height as f64;
    (0..g.position.len())
        .map(|i| {
            let k = b.chosen[i];
            if k == NO_CASCADE || !g.is_geometry(i) {
                return None;
            }
            let z = (Vec3::from_slice(&g.position[i][..3]) - eye).dot(forward) as f64;
            Some((
                k,
                b.placement.samples[k as usize].texel_angle as f64 / (z.max(1e-6) * per_depth),
            ))
        })
        .collect()
}

/// Every setting, scheme by scheme, n by n, against one reference. `log` gets one line each.
pub fn run(ctx: &GpuContext, job: &CascadeJob, log: &dyn Fn(&str)) -> Result<Vec<CascadeLine>> {
    let scene = job.scene;
    let (_, reference) = truth::for_scene(ctx, scene, job.reference, &job.cache)?;
    let bar = crate::progress::bar((job.schemes.len() * job.ns.len()) as u64, "cascades");
    let mut lines = Vec::new();
    for &split in &job.schemes {
        for &n in &job.ns {
            let m = CascadeMaps {
                n,
                split,
                lambda: job.lambda,
                filter: job.filter,
            };
            let method = Method::new(m);
            bar.set_message(method.label());
            let mut renderer = Renderer::new(ctx, scene, &method)?;
            let f = renderer.frame(TimingMode::Frame)?;
            let b: CascadeBuffers = renderer
                .inspect()?
                .ok_or_else(|| Error::param("cascades: the frame kept no buffers".into()))?;
            let g = &f.gbuffer;
            let (mut sq, mut count) = (0.0f64, 0usize);
            for i in (0..g.position.len()).filter(|&i| g.is_geometry(i)) {
                sq += (f.visibility[i] as f64 - reference.values[i] as f64).powi(2);
                count += 1;
            }
            let mut per: Vec<Vec<f64>> = vec![Vec::new(); n as usize];
            for (k, d) in densities(scene, g, &b).into_iter().flatten() {
                per[k as usize].push(d);
            }
            let cascades = per
                .iter_mut()
                .enumerate()
                .map(|(k, d)| CascadeFigures {
                    index: k as u32,
                    near: b.placement.ends[k],
                    far: b.placement.ends[k + 1],
                    texel_world: b.placement.samples[k].texel_angle,
                    pixels: d.len(),
                    share: d.len() as f64 / count.max(1) as f64,
                    density_median: median(d),
                })
                .collect();
            let line = CascadeLine {
                core: RowCore {
                    maps: f.output.shadow_maps,
                    map_size: scene.render.shadow_map_size,
                    rmse: (sq / count.max(1) as f64).sqrt(),
                    adapter: format!("{} ({})", ctx.summary.name, ctx.summary.backend).into(),
                    ..RowCore::of(&scene.name, &method.label(), &method)
                },
                n,
                split: split.name().to_string(),
                lambda: job.lambda,
                filter: job.filter.to_string(),
                label: method.label(),
                geometry_pixels: count,
                cascades,
                resolution: [scene.render.width, scene.render.height],
                reference: truth::mode_label(&reference.mode),
            };
            bar.inc(1);
            crate::progress::suspend(|| {
                log(&format!("{}: RMSE {:.5}", line.label, line.core.rmse))
            });
            lines.push(line);
        }
    }
    bar.finish_and_clear();
    Ok(lines)
}
