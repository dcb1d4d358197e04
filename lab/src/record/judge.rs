//! The one metrics call: a frame's visibility against the reference, over the reference's
//! geometry pixels, with FLIP on the shaded images (definitions in docs/compare-and-report.md).

use crate::frame::FrameResult;
use crate::metrics::{self, Metrics};
use crate::record::run_files;
use crate::render::gbuffer::GBufferCpu;
use crate::scene::Scene;
use crate::{Error, Result};
use image::RgbImage;

/// The reference of one scene, ready to judge frames of any method against.
pub struct Judge {
    pub reference: Vec<f32>,
    pub shaded_reference: RgbImage,
    /// Geometry pixels of the reference's G-buffer: the pixels every figure is taken over.
    pub mask: Vec<bool>,
    pub width: u32,
    pub height: u32,
}

/// A judged frame: its figures and its shaded image (pictures reuse it).
pub struct Judged {
    pub metrics: Metrics,
    pub shaded: RgbImage,
}

impl Judge {
    pub fn new(scene: &Scene, g: &GBufferCpu, reference: Vec<f32>) -> Judge {
        let mask = (0..g.position.len()).map(|i| g.is_geometry(i)).collect();
        let shaded_reference = run_files::shaded_image(&reference, g, scene);
        Judge {
            reference,
            shaded_reference,
            mask,
            width: g.width,
            height: g.height,
        }
    }

    pub fn geometry_pixels(&self) -> usize {
        self.mask.iter().filter(|m| **m).count()
    }

    /// `label` names the method in the error when its G-buffer is not the reference's.
    pub fn judge(&self, scene: &Scene, label: &str, f: &FrameResult) -> Result<Judged> {
        let differ = (0..self.mask.len())
            .filter(|&i| f.gbuffer.is_geometry(i) != self.mask[i])
            .count();
        if differ > 0 || f.visibility.len() != self.mask.len() {
            return Err(Error::gpu(format!(
                "{label}: the G-buffer differs from the reference's in {differ} pixels"
            )));
        }
        self.judge_values(scene, &f.gbuffer, &f.visibility)
    }

    /// V (one value per pixel of `g`, `g` the reference's G-buffer) judged as [`Judge::judge`] judges
    /// a frame: for callers that hold V without its frame (the Python package's `metrics`).
    pub fn judge_values(&self, scene: &Scene, g: &GBufferCpu, v: &[f32]) -> Result<Judged> {
        let shaded = run_files::shaded_image(v, g, scene);
        let metrics = metrics::compute(
            v,
            &self.reference,
            &self.mask,
            &shaded,
            &self.shaded_reference,
            self.width,
            self.height,
        )?;
        Ok(Judged { metrics, shaded })
    }
}
