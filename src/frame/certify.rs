//! `--certify`: a certificate for any method's frame. The scene's truth tracer is built once;
//! each frame draws its pixels by a truth-free proxy, traces them, and bounds the frame's RMSE.
//!
//! The proxy is the candidate's own penumbra band and a second opinion's: a centred 3 × 3 grid
//! with the error estimate (`SECOND_OPINION`), whose per-pixel bound says where a grid errs and
//! whose difference from the candidate says where one of the two does. A proxy from the
//! candidate alone cannot see a single-map filter's error where it drew no penumbra
//! (docs/certify.md §2).

use super::{FrameOptions, FrameResult, Renderer};
use crate::certify::bound::BoundKind;
use crate::certify::design::{self, Design};
use crate::certify::truth::TruthTracer;
use crate::certify::{certificate, Certificate, Options, TraceFigures};
use crate::gpu::timing::TimingMode;
use crate::gpu::GpuContext;
use crate::methods::Method;
use crate::scene::Scene;
use crate::{Error, Result};
use std::time::Instant;

/// The second opinion the proxy reads: 9 maps and the estimate's per-pixel bound.
pub const SECOND_OPINION: &str = "regular:n=3,layout=centred,estimate=on";

/// Which truth-free proxy draws the pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ProxyKind {
    /// The candidate's penumbra band alone (dilated [`design::BAND_DILATE`] pixels).
    Band,
    /// The band, the second opinion's band and bound, and the two frames' difference.
    SecondOpinion,
}

impl ProxyKind {
    pub fn name(self) -> &'static str {
        match self {
            ProxyKind::Band => "band",
            ProxyKind::SecondOpinion => "second-opinion",
        }
    }
}

/// A second opinion's frame: its V and the estimate's per-pixel bound.
pub struct Opinion {
    pub visibility: Vec<f32>,
    pub bound: Vec<f32>,
}

/// The proxy of `kind` for candidate `v` over `subset` (the second opinion where it reads one).
pub fn proxy(
    kind: ProxyKind,
    v: &[f32],
    subset: &[bool],
    width: u32,
    height: u32,
    second: Option<&Opinion>,
) -> Vec<f32> {
    let own = design::band(v, subset, width, height, design::BAND_DILATE);
    match (kind, second) {
        (ProxyKind::SecondOpinion, Some(o)) => {
            let band = design::band(&o.visibility, subset, width, height, design::BAND_DILATE);
            let spread = design::spread(v, &o.visibility, subset);
            design::proxy(&[&own, &band, &o.bound, &spread], subset)
        }
        _ => own,
    }
}

/// run.json's `certify`: the certificate and what it cost.
#[derive(Clone, Debug, serde::Serialize)]
pub struct CertifyRecord {
    #[serde(flatten)]
    pub certificate: Certificate,
    pub(crate) proxy: ProxyKind,
    /// The exact pixels' trace: rays, ties, samples per pixel and its wall clock.
    pub(crate) trace: TraceFigures,
    /// Wall clock of the pixels: the proxy, the draw, the trace and the bounds, ms. Apart from it,
    /// what a scene pays once (its first certificate; 0 on the others): the second opinion's
    /// frame (its renderer built) and the truth tracer's BVH build and upload.
    pub pixels_ms: f64,
    pub second_opinion_ms: f64,
    pub bvh_ms: f64,
    pub(crate) clock: &'static str,
}

/// Certifies the frames of one scene.
pub struct FrameCertifier<'a> {
    ctx: &'a GpuContext,
    tracer: TruthTracer,
    second: Option<Renderer<'a>>,
    /// The second opinion's frame: the scene and camera are fixed, so it is rendered once.
    opinion: Option<Opinion>,
    options: Options,
    proxy: ProxyKind,
    /// The BVH build, charged to the first certificate.
    bvh_ms: Option<f64>,
}

impl<'a> FrameCertifier<'a> {
    /// The scene's truth tracer (an environment scene is refused) and, for the second-opinion
    /// proxy, its renderer.
    pub fn new(
        ctx: &'a GpuContext,
        scene: &'a Scene,
        options: Options,
        proxy: ProxyKind,
    ) -> Result<FrameCertifier<'a>> {
        if !(options.delta > 0.0 && options.delta < 1.0) || options.pixels == 0 {
            return Err(Error::Param(format!(
                "certify: {}",
                options.check(usize::MAX).expect_err("one of them fails")
            )));
        }
        let tracer = TruthTracer::new(ctx, scene)?;
        let second = match proxy {
            ProxyKind::SecondOpinion => Some(Renderer::new(
                ctx,
                scene,
                &Method::parse(SECOND_OPINION, &[])?,
            )?),
            ProxyKind::Band => None,
        };
        let bvh_ms = Some(tracer.build_ms);
        Ok(FrameCertifier {
            ctx,
            tracer,
            second,
            opinion: None,
            options,
            proxy,
            bvh_ms,
        })
    }

    /// The certificate of `frame` (a frame of this certifier's scene, from the same camera).
    pub fn certify(&mut self, frame: &FrameResult) -> Result<CertifyRecord> {
        let g = &frame.gbuffer;
        let subset: Vec<bool> = (0..g.position.len()).map(|i| g.is_geometry(i)).collect();
        let geometry = subset.iter().filter(|s| **s).count();
        self.options
            .check(geometry)
            .map_err(|e| Error::Param(format!("certify: {e}")))?;
        let second_start = Instant::now();
        if let (Some(r), None) = (&mut self.second, &self.opinion) {
            let f = r.frame(FrameOptions {
                mode: TimingMode::Frame,
                pictures: false,
            })?;
            let bound = f
                .output
                .bound
                .ok_or_else(|| Error::Limit(format!("certify: {SECOND_OPINION} gave no bound")))?;
            self.opinion = Some(Opinion {
                visibility: f.visibility,
                bound,
            });
            // Its renderer is no longer needed: its maps go.
            self.second = None;
        }
        let second_opinion_ms = second_start.elapsed().as_secs_f64() * 1e3;
        let start = Instant::now();
        let proxy = proxy(
            self.proxy,
            &frame.visibility,
            &subset,
            g.width,
            g.height,
            self.opinion.as_ref(),
        );
        let design = Design::new(&subset, &proxy, design::DEFENSIVE)?;
        let sampled = crate::certify::sample(self.ctx, &self.tracer, g, &design, &self.options)?;
        let certificate = certificate(
            &frame.visibility,
            &sampled,
            &design,
            self.options.delta,
            BoundKind::Calibrated,
        );
        Ok(CertifyRecord {
            certificate,
            proxy: self.proxy,
            trace: sampled.trace.expect("traced"),
            pixels_ms: start.elapsed().as_secs_f64() * 1e3,
            second_opinion_ms,
            bvh_ms: self.bvh_ms.take().unwrap_or(0.0),
            clock: "wall clock (submit → device poll wait), milliseconds",
        })
    }
}
