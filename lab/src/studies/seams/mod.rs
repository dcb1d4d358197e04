//! The cube-map seams of a point light (docs/lights.md, "The seams"): per pixel, how many texels
//! its direction from the light lies from the nearest edge of its cube face; V's error against the
//! continuous reference inside a band of `band` texels along the face edges, and outside it, for
//! each method and map size.

pub mod command;

use crate::frame;
use crate::gpu::timing::TimingMode;
use crate::gpu::GpuContext;
use crate::methods::Method;
use crate::record::row_core::RowCore;
use crate::reference::truth::{self, Cache};
use crate::reference::ReferenceMode;
use crate::render::gbuffer::GBufferCpu;
use crate::scene::{Emitter, Scene};
use crate::{Error, Result};
use glam::Vec3;

pub struct SeamsJob {
    /// The scene (a built-in name or a file) and its `--set` pairs; each map size is set on top.
    pub scene: String,
    pub sets: Vec<(String, String)>,
    pub map_sizes: Vec<u32>,
    pub methods: Vec<Method>,
    /// The band's width in texels of the face's map.
    pub band: f32,
    pub reference: ReferenceMode,
    pub cache: Cache,
}

/// One method at one map size: error inside the band and outside it (geometry pixels only).
#[derive(Clone, Debug, serde::Serialize)]
pub struct SeamRow {
    /// Scene, the method's label as spec, method, params, maps, map size, RMSE over all geometry
    /// pixels, the frame's wall clock, adapter, build.
    #[serde(flatten)]
    pub core: RowCore,
    /// The method's label (`regular:n=5`).
    pub label: String,
    pub band_texels: f32,
    pub band_pixels: usize,
    pub outside_pixels: usize,
    pub band_rmse: f64,
    pub band_mae: f64,
    pub outside_rmse: f64,
    pub outside_mae: f64,
    /// The same over the penumbra alone (the reference in (0.01, 0.99)), where the band's share
    /// of shadow edges cannot tilt the comparison.
    pub band_penumbra_pixels: usize,
    pub band_penumbra_rmse: f64,
    pub outside_penumbra_pixels: usize,
    pub outside_penumbra_rmse: f64,
}

/// Texels of a `map_size` cube face from direction `d` to its face's nearest edge: the face's
/// other two coordinates run over [-1, 1], the larger of them sets the distance.
pub fn edge_texels(d: Vec3, map_size: u32) -> f32 {
    let a = d.abs();
    let major = a.max_element();
    if major <= 0.0 {
        return 0.0;
    }
    let middle = a.x + a.y + a.z - major - a.min_element();
    (1.0 - middle / major) * 0.5 * map_size as f32
}

/// Whether each pixel lies in the band: a geometry pixel within `band` texels of a face edge, seen
/// from the light's centre (every sample point lies within the emitter's radius of it).
pub fn band_mask(g: &GBufferCpu, centre: Vec3, map_size: u32, band: f32) -> Vec<bool> {
    (0..g.position.len())
        .map(|i| {
            g.is_geometry(i)
                && edge_texels(Vec3::from_slice(&g.position[i][..3]) - centre, map_size) < band
        })
        .collect()
}

pub struct SeamsOutcome {
    pub rows: Vec<SeamRow>,
    /// (file name, bytes): seams.json, seams.csv, seams.md and one band picture per map size.
    pub files: Vec<(String, Vec<u8>)>,
}

pub fn run(ctx: &GpuContext, job: &SeamsJob, log: &dyn Fn(&str)) -> Result<SeamsOutcome> {
    let mut rows = Vec::new();
    let mut files = Vec::new();
    let mut reference: Option<Vec<f32>> = None;
    let adapter =
        serde_json::Value::from(format!("{} ({})", ctx.summary.name, ctx.summary.backend));
    for &size in &job.map_sizes {
        let mut sets = job.sets.clone();
        sets.push(("shadow_map_size".into(), size.to_string()));
        let scene = Scene::load(&job.scene, &sets)?;
        let Emitter::Point(point) = scene.emitter else {
            return Err(Error::param(format!("seams: scene {} has a `{}` light; the seams are a point light's cube faces (kind = \"point\")", scene.name, scene.emitter.kind().name())));
        };
        crate::methods::check_lights(&scene, &job.methods)?;
        for method in &job.methods {
            let r = frame::render(ctx, &scene, method, TimingMode::Frame)?;
            // The G-buffer is the same at every map size: the reference is traced once.
            let values = match &reference {
                Some(v) => v,
                None => reference
                    .insert(truth::compute(&scene, &r.gbuffer, job.reference, &job.cache)?.values),
            };
            let band = band_mask(&r.gbuffer, point.position, size, job.band);
            let core = RowCore {
                maps: r.output.shadow_maps,
                map_size: size,
                frame_ms: r.total_ms,
                adapter: adapter.clone(),
                ..RowCore::of(&scene.name, &method.label(), method)
            };
            let row = errors(core, job.band, &r.gbuffer, &band, &r.visibility, values);
            log(&format!("{} at {size}²: band {} px RMSE {:.4} MAE {:.4}; outside {} px RMSE {:.4} MAE {:.4}", row.label, row.band_pixels, row.band_rmse, row.band_mae, row.outside_pixels, row.outside_rmse, row.outside_mae));
            rows.push(row);
            if method == &job.methods[0] {
                files.push((
                    format!("band_{size}.png"),
                    crate::record::run_files::png(&band_picture(&r.gbuffer, &band))?,
                ));
            }
        }
    }
    files.push((
        "seams.json".into(),
        serde_json::to_vec_pretty(
            &serde_json::json!({ "scene": job.scene, "band_texels": job.band, "rows": rows }),
        )
        .map_err(|e| Error::param(e.to_string()))?,
    ));
    files.push(("seams.csv".into(), csv(&rows).into_bytes()));
    files.push(("seams.md".into(), markdown(&rows).into_bytes()));
    Ok(SeamsOutcome { rows, files })
}

/// The row of one frame: `core` with its RMSE over every geometry pixel, and the errors inside
/// the band and outside it.
fn errors(
    core: RowCore,
    band_texels: f32,
    g: &GBufferCpu,
    band: &[bool],
    v: &[f32],
    reference: &[f32],
) -> SeamRow {
    // (squared error, absolute error, pixels) inside the band and outside it.
    // Then the same over the penumbra pixels.
    let mut sums = [(0.0f64, 0.0f64, 0usize); 4];
    for i in (0..v.len()).filter(|&i| g.is_geometry(i)) {
        let e = (v[i] as f64 - reference[i] as f64).abs();
        let penumbra = reference[i] > 0.01 && reference[i] < 0.99;
        for k in [(!band[i]) as usize, 2 + (!band[i]) as usize]
            .into_iter()
            .take(1 + penumbra as usize)
        {
            let s = &mut sums[k];
            *s = (s.0 + e * e, s.1 + e, s.2 + 1);
        }
    }
    let rmse = |s: (f64, f64, usize)| (s.0 / s.2.max(1) as f64).sqrt();
    let mae = |s: (f64, f64, usize)| s.1 / s.2.max(1) as f64;
    let whole = (sums[0].0 + sums[1].0, 0.0, sums[0].2 + sums[1].2);
    SeamRow {
        label: core.spec.clone(),
        core: RowCore {
            rmse: rmse(whole),
            ..core
        },
        band_texels,
        band_pixels: sums[0].2,
        outside_pixels: sums[1].2,
        band_rmse: rmse(sums[0]),
        band_mae: mae(sums[0]),
        outside_rmse: rmse(sums[1]),
        outside_mae: mae(sums[1]),
        band_penumbra_pixels: sums[2].2,
        band_penumbra_rmse: rmse(sums[2]),
        outside_penumbra_pixels: sums[3].2,
        outside_penumbra_rmse: rmse(sums[3]),
    }
}

/// The band in white over the other geometry in grey; background dark.
fn band_picture(g: &GBufferCpu, band: &[bool]) -> image::RgbImage {
    image::ImageBuffer::from_fn(g.width, g.height, |x, y| {
        let i = (y * g.width + x) as usize;
        let level = if band[i] {
            255
        } else if g.is_geometry(i) {
            110
        } else {
            20
        };
        image::Rgb([level; 3])
    })
}

pub fn csv(rows: &[SeamRow]) -> String {
    let own = [
        "label",
        "band_texels",
        "band_pixels",
        "outside_pixels",
        "band_rmse",
        "band_mae",
        "outside_rmse",
        "outside_mae",
        "band_penumbra_pixels",
        "band_penumbra_rmse",
        "outside_penumbra_pixels",
        "outside_penumbra_rmse",
    ];
    let header = RowCore::csv_header(&own);
    let cells = rows.iter().map(|r| {
        let mut c = r.core.cells();
        c.extend([
            r.label.clone(),
            r.band_texels.to_string(),
            r.band_pixels.to_string(),
            r.outside_pixels.to_string(),
            format!("{:.6}", r.band_rmse),
            format!("{:.6}", r.band_mae),
            format!("{:.6}", r.outside_rmse),
            format!("{:.6}", r.outside_mae),
            r.band_penumbra_pixels.to_string(),
            format!("{:.6}", r.band_penumbra_rmse),
            r.outside_penumbra_pixels.to_string(),
            format!("{:.6}", r.outside_penumbra_rmse),
        ]);
        c
    });
    crate::record::csv::lines(std::iter::once(header).chain(cells))
}

pub fn markdown(rows: &[SeamRow]) -> String {
    let mut out = String::from(
        "| method | map | band pixels | band RMSE | band MAE | outside pixels | outside RMSE | outside MAE | band penumbra px | RMSE | outside penumbra px | RMSE |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for r in rows {
        out += &format!(
            "| `{}` | {}² | {} | {:.4} | {:.4} | {} | {:.4} | {:.4} | {} | {:.4} | {} | {:.4} |\n",
            r.label,
            r.core.map_size,
            r.band_pixels,
            r.band_rmse,
            r.band_mae,
            r.outside_pixels,
            r.outside_rmse,
            r.outside_mae,
            r.band_penumbra_pixels,
            r.band_penumbra_rmse,
            r.outside_penumbra_pixels,
            r.outside_penumbra_rmse
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::edge_texels;
    use glam::Vec3;

    #[test]
    fn edge_distance_is_zero_on_a_face_edge_and_half_the_map_at_its_centre() {
        assert_eq!(edge_texels(Vec3::new(0.0, -2.0, 0.0), 256), 128.0);
        assert_eq!(edge_texels(Vec3::new(1.0, -1.0, 0.2), 256), 0.0);
        // Halfway from the centre of the -y face to its edge, in either of its coordinates.
        assert_eq!(edge_texels(Vec3::new(0.0, -2.0, 1.0), 512), 128.0);
        assert_eq!(edge_texels(Vec3::new(-1.0, -2.0, 0.5), 512), 128.0);
    }
}
