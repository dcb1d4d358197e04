//! Exact truth at chosen pixels: the reference's own integrator (32 × 32 stratified samples with
//! the per-pixel seed of the lab's reference, every light kind as the reference treats it) run on
//! the GPU by `truth_trace` through the scene's BVH. The value at a pixel is the full reference's
//! value there (lab/tests/truth_trace.rs holds the two equal), so a few thousand pixels of it are
//! as true as the whole image, at a cost that scales with the pixels, not the frame.

use crate::gpu::readback;
use crate::gpu::stages::bind;
use crate::gpu::structs::{
    GpuBvhNode, GpuTruthCount, GpuTruthParams, GpuTruthPoint, GpuTruthTriangle,
};
use crate::gpu::GpuContext;
use crate::render::bvh::Bvh;
use crate::render::gbuffer::GBufferCpu;
use crate::scene::{Emitter, Scene};
use crate::stages::truth_trace::TruthTrace;
use crate::{Error, Result};
use glam::Vec3;
use std::time::Instant;

/// Shadow rays stop at `dist · (1 − LIGHT_END_EPS)`, so an emitter that is itself scene geometry
/// does not shadow its own samples (the lab's reference uses the same constant).
pub(crate) const LIGHT_END_EPS: f32 = 1e-4;
/// The reference's default samples: 32 × 32 stratified, seed 0x5eed (method.md §5).
pub const REFERENCE_SAMPLES: TruthSamples = TruthSamples::Continuous {
    m: 32,
    seed: 0x5eed,
};
/// The second stream of a paired truth (`paired`): a seed no per-pixel stream of the
/// reference's shares, so the two estimates at a pixel are independent.
const PAIR_SEED: u64 = 0xd1b5_4a32_d192_ed03;

/// Two independent m × m stratified estimates per pixel (2m² rays, against the reference's
/// 1,024): the first is the reference's integrator at m × m, the second the same on another
/// stream. `certify::Sampled::from_pair` turns them into an unbiased estimate of e².
pub(crate) fn paired(m: u32) -> [TruthSamples; 2] {
    let TruthSamples::Continuous { seed, .. } = REFERENCE_SAMPLES else {
        unreachable!("the reference's samples are continuous")
    };
    [
        TruthSamples::Continuous { m, seed },
        TruthSamples::Continuous {
            m,
            seed: seed ^ PAIR_SEED,
        },
    ]
}

/// Points per dispatch: a real GPU's watchdog never sees a long one, and progress is reported
/// between them.
pub(crate) const CHUNK_POINTS: usize = 16384;

/// The light as the reference samples it: the rectangle; a disk; the sun (a disk of directions
/// of radius `tan_half`, rays `reach` long); a sphere seen from each receiver (the point light,
/// and the spot, whose cone scales lighting, not V).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum TruthLight {
    Rect {
        center: Vec3,
        edge_u: Vec3,
        edge_v: Vec3,
    },
    Disk {
        center: Vec3,
        normal: Vec3,
        radius: f32,
    },
    Sun {
        toward: Vec3,
        tan_half: f32,
        reach: f32,
    },
    Sphere {
        center: Vec3,
        radius: f32,
    },
}

/// Which light points each pixel averages over (the lab's `ReferenceMode`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TruthSamples {
    /// m × m stratified jitter from the pixel's own SplitMix64 stream.
    Continuous { m: u32, seed: u64 },
    /// The 17 × 17 lattice `s = i/16, t = j/16`.
    Lattice,
    /// One light point.
    Point { s: f32, t: f32 },
}

impl TruthSamples {
    pub fn per_pixel(&self) -> u32 {
        match *self {
            TruthSamples::Continuous { m, .. } => m * m,
            TruthSamples::Lattice => 289,
            TruthSamples::Point { .. } => 1,
        }
    }
}

/// Why the truth cannot be traced for a scene: one line, for `--certify` and the GPU tracer.
pub fn unsupported(scene: &Scene) -> Option<&'static str> {
    scene.environment.is_some().then_some("an environment scene is lit by a panorama, and the exact truth at pixels is traced for area lights only")
}

impl TruthLight {
    /// The scene's light, as the reference samples it; an environment scene is refused.
    pub(crate) fn of_scene(scene: &Scene) -> Result<TruthLight> {
        if let Some(why) = unsupported(scene) {
            return Err(Error::Param(format!("{}: {why}", scene.origin)));
        }
        Ok(match scene.emitter {
            Emitter::Rect => TruthLight::Rect {
                center: scene.light.center,
                edge_u: scene.light.edge_u,
                edge_v: scene.light.edge_v,
            },
            Emitter::Disk(d) => TruthLight::Disk {
                center: d.center,
                normal: d.normal,
                radius: d.radius,
            },
            Emitter::Sun(s) => TruthLight::Sun {
                toward: s.toward(),
                tan_half: s.tan_half_angle(),
                reach: crate::scene::rays::env_ray_length(scene),
            },
            Emitter::Spot(s) => TruthLight::Sphere {
                center: s.position,
                radius: s.radius,
            },
            Emitter::Point(p) => TruthLight::Sphere {
                center: p.position,
                radius: p.radius,
            },
        })
    }

    /// The kernel's parameters for `samples` (count and first are set per dispatch).
    fn params(&self, samples: &TruthSamples, ray_offset: f32) -> GpuTruthParams {
        let v4 = |v: Vec3| v.extend(0.0).to_array();
        let mut p = GpuTruthParams {
            ray_offset,
            end_factor: 1.0 - LIGHT_END_EPS,
            ..Default::default()
        };
        match *samples {
            TruthSamples::Continuous { m, seed } => {
                (p.mode, p.m, p.inv_m) = (0, m, 1.0 / m as f32);
                (p.seed_lo, p.seed_hi) = (seed as u32, (seed >> 32) as u32);
            }
            TruthSamples::Lattice => p.mode = 1,
            TruthSamples::Point { s, t } => (p.mode, p.point_s, p.point_t) = (2, s, t),
        }
        match *self {
            TruthLight::Rect {
                center,
                edge_u,
                edge_v,
            } => {
                p.kind = 0;
                (p.center, p.edge_u, p.edge_v) = (v4(center), v4(edge_u), v4(edge_v));
                p.light_normal = v4(edge_u.cross(edge_v).normalize_or_zero());
            }
            TruthLight::Disk {
                center,
                normal,
                radius,
            } => {
                p.kind = 1;
                (p.center, p.light_normal, p.radius) = (v4(center), v4(normal), radius);
            }
            TruthLight::Sun {
                toward,
                tan_half,
                reach,
            } => {
                p.kind = 2;
                (p.edge_u, p.radius, p.reach) = (v4(toward), tan_half, reach);
            }
            TruthLight::Sphere { center, radius } => {
                p.kind = 3;
                (p.center, p.radius) = (v4(center), radius);
            }
        }
        p
    }
}

/// One pixel as the tracer sees it: the G-buffer's position and normal there.
pub fn point_of(g: &GBufferCpu, pixel: u32) -> GpuTruthPoint {
    let (p, n) = (g.position[pixel as usize], g.normal[pixel as usize]);
    GpuTruthPoint {
        position: [p[0], p[1], p[2]],
        pixel,
        normal: [n[0], n[1], n[2]],
        pad: 0,
    }
}

/// What a trace found at each point, in the order given.
#[derive(Clone, Debug, PartialEq)]
pub struct TruthCounts {
    pub(crate) counts: Vec<GpuTruthCount>,
    pub samples_per_pixel: u32,
    /// Wall clock of the trace (upload, dispatches, read-back), ms.
    pub ms: f64,
}

impl TruthCounts {
    /// V at point `i`: lit samples over samples, as the reference divides.
    pub fn visibility(&self, i: usize) -> f32 {
        self.counts[i].lit as f32 / self.samples_per_pixel as f32
    }
    pub fn rays(&self) -> u64 {
        self.counts.iter().map(|c| c.rays as u64).sum()
    }
    /// Rays whose answer an edge function of exactly 0 in f32 decided (the CPU settles them in f64).
    pub fn ties(&self) -> u64 {
        self.counts.iter().map(|c| c.ties as u64).sum()
    }
}

/// A scene's truth tracer: its BVH on the GPU and the kernel, built once, then any pixels of any
/// frame of that scene (the light and the triangles fixed).
pub struct TruthTracer {
    kernel: TruthTrace,
    nodes: wgpu::Buffer,
    triangles: wgpu::Buffer,
    light: TruthLight,
    ray_offset: f32,
    /// Wall clock of the BVH build and upload, ms.
    pub build_ms: f64,
}

impl TruthTracer {
    /// The tracer of `scene`'s light and triangles (an environment scene is refused).
    pub fn new(ctx: &GpuContext, scene: &Scene) -> Result<TruthTracer> {
        let light = TruthLight::of_scene(scene)?;
        TruthTracer::from_triangles(
            ctx,
            &scene.triangles(),
            light,
            crate::scene::rays::ray_offset(scene),
        )
    }

    /// A tracer over any triangle soup (tests, tools).
    pub(crate) fn from_triangles(
        ctx: &GpuContext,
        triangles: &[[Vec3; 3]],
        light: TruthLight,
        ray_offset: f32,
    ) -> Result<TruthTracer> {
        let start = Instant::now();
        let bvh = Bvh::build(triangles);
        let v4 = |v: Vec3| v.extend(0.0).to_array();
        let mut tris: Vec<GpuTruthTriangle> = bvh
            .source
            .iter()
            .map(|&i| triangles[i as usize])
            .map(|t| GpuTruthTriangle {
                v0: v4(t[0]),
                v1: v4(t[1]),
                v2: v4(t[2]),
            })
            .collect();
        let mut nodes = bvh.nodes;
        if tris.is_empty() {
            // Nothing occludes: one leaf far away that no ray's box test reaches (a count of 0
            // would be an inner node).
            let far = [3.0e38f32; 3];
            nodes = vec![GpuBvhNode {
                min: far,
                left_first: 0,
                max: far,
                count: 1,
            }];
            tris = vec![GpuTruthTriangle {
                v0: [3.0e38, 3.0e38, 3.0e38, 0.0],
                v1: [3.0e38, 3.0e38, 3.0e38, 0.0],
                v2: [3.0e38, 3.0e38, 3.0e38, 0.0],
            }];
        }
        let nodes =
            readback::storage_buffer(ctx, "truth bvh nodes", &nodes, wgpu::BufferUsages::empty());
        let triangles_buffer =
            readback::storage_buffer(ctx, "truth triangles", &tris, wgpu::BufferUsages::empty());
        let kernel = TruthTrace::new(ctx)?;
        Ok(TruthTracer {
            kernel,
            nodes,
            triangles: triangles_buffer,
            light,
            ray_offset,
            build_ms: start.elapsed().as_secs_f64() * 1e3,
        })
    }

    /// The counts at `points` under `samples`; `progress(done)` after each chunk of points.
    pub fn trace(
        &self,
        ctx: &GpuContext,
        samples: &TruthSamples,
        points: &[GpuTruthPoint],
        progress: &dyn Fn(usize),
    ) -> Result<TruthCounts> {
        let start = Instant::now();
        if let TruthSamples::Continuous { m: 0, .. } = samples {
            return Err(Error::Param(
                "truth samples: a continuous reference needs m >= 1".into(),
            ));
        }
        let mut counts = Vec::with_capacity(points.len());
        let base = self.light.params(samples, self.ray_offset);
        for chunk in points.chunks(CHUNK_POINTS) {
            let params = GpuTruthParams {
                count: chunk.len() as u32,
                first: 0,
                ..base
            };
            let params = readback::uniform_buffer(ctx, "truth params", &params);
            let points_buffer =
                readback::storage_buffer(ctx, "truth points", chunk, wgpu::BufferUsages::empty());
            let bytes = (chunk.len() * std::mem::size_of::<GpuTruthCount>()) as u64;
            let out = readback::zeroed_storage_with(
                ctx,
                "truth counts",
                bytes,
                wgpu::BufferUsages::COPY_SRC,
            );
            let mut enc = ctx
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("truth_trace"),
                });
            let bindings = bind::truth_trace::Main {
                params: params.as_entire_binding(),
                points: points_buffer.as_entire_binding(),
                counts: out.as_entire_binding(),
                truth_triangles: self.triangles.as_entire_binding(),
                bvh_nodes: self.nodes.as_entire_binding(),
            };
            self.kernel
                .record(ctx, &mut enc, bindings, chunk.len() as u32);
            let staging = readback::stage_copy(ctx, &mut enc, &out, bytes);
            ctx.queue.submit([enc.finish()]);
            counts.extend(readback::map_staging::<GpuTruthCount>(ctx, &staging)?);
            progress(counts.len());
        }
        Ok(TruthCounts {
            counts,
            samples_per_pixel: samples.per_pixel(),
            ms: start.elapsed().as_secs_f64() * 1e3,
        })
    }
}
