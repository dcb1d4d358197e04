//! Run outputs: visibility.png (16-bit gray), visibility.exr (float), shaded.png, run.json and the
//! method's pictures. Everything is encoded in memory first, then each file is written to a temporary
//! name and renamed, so a failed run leaves no partial file.

use crate::frame::FrameResult;
use crate::gpu::AdapterSummary;
use crate::methods::Method;
use crate::render::gbuffer::GBufferCpu;
use crate::scene::Scene;
use crate::{Error, Result};
use glam::Vec3;
use image::{ImageBuffer, Luma, Rgb, Rgb32FImage, RgbImage};
use std::io::Cursor;
use std::path::{Path, PathBuf};

pub fn visibility_png(v: &[f32], w: u32, h: u32) -> Result<Vec<u8>> {
    let img: ImageBuffer<Luma<u16>, Vec<u16>> = ImageBuffer::from_fn(w, h, |x, y| {
        Luma([(v[(y * w + x) as usize].clamp(0.0, 1.0) * 65535.0).round() as u16])
    });
    encode(
        &image::DynamicImage::ImageLuma16(img),
        image::ImageFormat::Png,
    )
}

pub fn visibility_exr(v: &[f32], w: u32, h: u32) -> Result<Vec<u8>> {
    let img: Rgb32FImage = ImageBuffer::from_fn(w, h, |x, y| {
        let a = v[(y * w + x) as usize];
        Rgb([a, a, a])
    });
    encode(
        &image::DynamicImage::ImageRgb32F(img),
        image::ImageFormat::OpenExr,
    )
}

fn srgb(linear: f32) -> u8 {
    let c = linear.clamp(0.0, 1.0);
    let s = if c <= 0.0031308 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0).round() as u8
}

/// albedo · (ambient + (1 − ambient) · V · max(0, n·l)), l towards the light's centre (method.md §1).
pub fn shaded_image(v: &[f32], g: &GBufferCpu, scene: &Scene) -> RgbImage {
    if let Some(env) = &scene.environment {
        return crate::record::shaded_environment::shaded_image(v, g, scene, env);
    }
    let ambient = scene.render.ambient;
    ImageBuffer::from_fn(g.width, g.height, |x, y| {
        let i = (y * g.width + x) as usize;
        if !g.is_geometry(i) {
            return Rgb([40, 44, 52]);
        }
        let p = Vec3::from_slice(&g.position[i][..3]);
        let n = Vec3::from_slice(&g.shading_normal[i][..3]);
        let albedo = scene
            .albedos
            .get(g.normal[i][3] as usize)
            .copied()
            .unwrap_or([0.8; 3]);
        let l = (scene.light.center - p).normalize_or_zero();
        let shade = ambient + (1.0 - ambient) * v[i] * n.dot(l).max(0.0);
        Rgb(albedo.map(|a| srgb(a * shade)))
    })
}

pub fn png(img: &RgbImage) -> Result<Vec<u8>> {
    encode(
        &image::DynamicImage::ImageRgb8(img.clone()),
        image::ImageFormat::Png,
    )
}

fn encode(img: &image::DynamicImage, format: image::ImageFormat) -> Result<Vec<u8>> {
    let mut out = Cursor::new(Vec::new());
    img.write_to(&mut out, format)
        .map_err(|e| Error::io_text(format!("<{format:?} encoder>"), e.to_string()))?;
    Ok(out.into_inner())
}

/// Writes all files as one set (crate::record::output_set): `dir` ends up holding exactly these files (and
/// whatever an earlier set did not write), or, on any failure or interrupt, what it held before.
pub fn write_files(dir: &Path, files: &[(String, Vec<u8>)]) -> Result<Vec<PathBuf>> {
    let set = crate::record::output_set::OutputSet::begin(dir)?;
    let mut written = Vec::new();
    for (name, bytes) in files {
        written.push(set.write(name, bytes)?);
    }
    set.commit()?;
    Ok(written)
}

pub use crate::version;

/// The run record (run.json).
pub fn run_record(
    scene: &Scene,
    method: &Method,
    r: &FrameResult,
    adapter: &AdapterSummary,
    timestamps_trusted: bool,
) -> serde_json::Value {
    run_record_of(
        scene,
        method,
        r,
        VFigures::of(&r.visibility, &r.gbuffer),
        adapter,
        timestamps_trusted,
    )
}

/// What a run record says of V: its geometry pixels and the mean of V over them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VFigures {
    pub geometry_pixels: usize,
    pub mean_visibility: f64,
}

impl VFigures {
    pub fn of(v: &[f32], g: &GBufferCpu) -> VFigures {
        let mut sum = VSum::default();
        for (i, x) in v.iter().enumerate() {
            if g.is_geometry(i) {
                sum.add(*x);
            }
        }
        sum.figures()
    }
}

/// `VFigures` summed by a caller that passes over V anyway (the Python package, as it writes NaN
/// on the background): it adds each geometry pixel's V in index order, as `VFigures::of` does,
/// so the figures are the same to the bit.
#[derive(Default)]
pub struct VSum {
    sum: f64,
    pixels: usize,
}

impl VSum {
    pub fn add(&mut self, v: f32) {
        self.sum += v as f64;
        self.pixels += 1;
    }

    pub fn figures(&self) -> VFigures {
        VFigures {
            geometry_pixels: self.pixels,
            mean_visibility: if self.pixels == 0 {
                0.0
            } else {
                self.sum / self.pixels as f64
            },
        }
    }
}

/// `run_record` with V's figures taken before: the frame's V and G-buffer are not read, so a
/// caller that handed them on (the Python package gives V to numpy and builds the record only
/// when it is read) keeps just these two numbers.
pub fn run_record_of(
    scene: &Scene,
    method: &Method,
    r: &FrameResult,
    v: VFigures,
    adapter: &AdapterSummary,
    timestamps_trusted: bool,
) -> serde_json::Value {
    let staged = r.timing == crate::gpu::timing::TimingMode::Stages;
    serde_json::json!({
        "scene": scene.name,
        "scene_origin": scene.origin,
        "triangles": scene.triangle_count(),
        "method": method.name(),
        "label": method.label(),
        "params": method.params_json(),
        "adapter": adapter,
        "resolution": [scene.render.width, scene.render.height],
        "geometry_pixels": v.geometry_pixels,
        "shadow_map_size": scene.render.shadow_map_size,
        "render": scene.render,
        "raster": r.raster,
        "shadow_maps": r.output.shadow_maps,
        // Maps rasterized whole, kept from earlier frames, partly drawn again (docs/reuse.md).
        "reuse": r.reuse,
        "syncs": r.output.syncs,
        "timing_waits": r.timing_waits,
        "clock": "wall clock (submit → device poll wait), milliseconds",
        "timing": r.timing,
        "stages_ms": r.stages_ms,
        // GPU timestamps are recorded only on real GPUs; on CPU adapters they are not trustworthy.
        // GPU timestamps only where trusted: on CPU adapters they report ~0.1 ms for ~1 s dispatches.
        "gpu_stages_ms": if timestamps_trusted { serde_json::to_value(&r.gpu_stages_ms).unwrap_or_default() } else { serde_json::Value::Null },
        "gpu_clock": if timestamps_trusted { "GPU timestamps around each stage's commands, milliseconds" } else { "none: timestamps are not trustworthy on a CPU adapter" },
        "total_ms": r.total_ms,
        // raster / decision / shade / waits (the stage table's split) need per-stage wall times: a
        // frame-mode frame has only its waits, so it gets no split (null) rather than a false one.
        "frame_split_ms": staged.then(|| crate::gpu::stages::frame_split(&r.stages_ms)),
        "decision_stages_ms": staged.then(|| decision_ms(&r.stages_ms)),
        "decision_share": staged.then(|| if r.total_ms > 0.0 { decision_ms(&r.stages_ms) / r.total_ms } else { 0.0 }),
        "method_record": r.output.record,
        "mean_visibility": v.mean_visibility,
        "version": version(),
    })
}

/// The decision stages' time: the frame split's decision part (the stage table's `Decision`
/// stages, docs/gpu-frame.md §3). Meaningful with `--timing stages`.
pub use crate::gpu::stages::decision_ms;

/// run.json of a measured method (compare, sweep): its last timed frame's record, with the
/// timing of the whole measurement. A timed frame runs in frame mode and knows only its waits, so
/// the stages, the split and the decision share come from the method's stages-mode frame, and
/// the share is over that frame's stages; `total_ms` is the timed frames' median.
pub fn measured_record(
    mut record: serde_json::Value,
    t: &crate::record::measure::Timing,
) -> serde_json::Value {
    let staged: f64 = t.stages_ms.values().sum();
    let decision = decision_ms(&t.stages_ms);
    let fields = serde_json::json!({
        "timing": "median of the frame-mode frames; stages from one stages-mode frame",
        "total_ms": t.median_ms,
        "total_ms_min": t.min_ms,
        "total_ms_max": t.max_ms,
        "totals_ms": t.totals_ms,
        "stages_ms": t.stages_ms,
        "frame_split_ms": crate::gpu::stages::frame_split(&t.stages_ms),
        "decision_stages_ms": decision,
        "decision_share": if staged > 0.0 { decision / staged } else { 0.0 },
    });
    if let (Some(out), serde_json::Value::Object(add)) = (record.as_object_mut(), fields) {
        out.extend(add);
    }
    record
}

/// Encodes the standard files of one run.
/// `warm_up_frames`: untimed frames that ran before `r` on the same renderer (its `setup` then
/// holds no build).
/// `certify`: the frame's certificate (`--certify`), kept as run.json's `certify`.
pub fn run_files(
    scene: &Scene,
    method: &Method,
    r: &FrameResult,
    adapter: &AdapterSummary,
    ts: bool,
    warm_up_frames: u32,
    certify: Option<serde_json::Value>,
) -> Result<Vec<(String, Vec<u8>)>> {
    let (w, h) = (scene.render.width, scene.render.height);
    let mut files = vec![
        (
            "visibility.png".to_string(),
            visibility_png(&r.visibility, w, h)?,
        ),
        (
            "visibility.exr".to_string(),
            visibility_exr(&r.visibility, w, h)?,
        ),
        (
            "shaded.png".to_string(),
            png(&shaded_image(&r.visibility, &r.gbuffer, scene))?,
        ),
    ];
    for (name, img) in &r.output.pictures {
        files.push((name.clone(), png(img)?));
    }
    if let Some(bound) = &r.output.bound {
        // The error estimate's bound on |V − V_true|, drawn as the error images are (magma, 0..0.25).
        let mask: Vec<bool> = (0..bound.len()).map(|i| r.gbuffer.is_geometry(i)).collect();
        let zeros = vec![0.0f32; bound.len()];
        let picture = crate::metrics::abs_error_image(bound, &zeros, &mask, w, h, 0.25)
            .map_err(|e| Error::limit(format!("error-bound.png: {e}")))?;
        files.push(("error-bound.png".to_string(), png(&picture)?));
        files.push(("error-bound.exr".to_string(), visibility_exr(bound, w, h)?));
    }
    let mut record = run_record(scene, method, r, adapter, ts);
    record["warm_up_frames"] = warm_up_frames.into();
    if let Some(c) = certify {
        record["certify"] = c;
    }
    let json = serde_json::to_vec_pretty(&record)
        .map_err(|e| Error::io_text("run.json".into(), e.to_string()))?;
    files.push(("run.json".to_string(), json));
    Ok(files)
}
