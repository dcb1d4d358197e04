//! The regions' pictures (read after the decision, only when pictures are asked for):
//! - `region_samples.png`: each 8x8 tile's samples per side, dark (1) to bright (the most);
//! - `region_texels.png`: each tile's texel density, the pixel footprint over the world size of
//!   its class's texel at the receiver, as log2 around 1: blue where a texel spans several pixels,
//!   white at one texel per pixel, red where several texels fall in one pixel.

use super::record::ClassRecord;
use crate::gpu::readback;
use crate::stages::regions::RegionsPass;
use crate::stages::shade::TILE_LIST_HEADER;
use crate::stages::FrameGpu;
use crate::Result;
use image::{Rgb, RgbImage};

const BACKGROUND: [u8; 3] = [40, 44, 52];

/// `t` in [0, 1] from dark blue through orange to pale yellow.
fn ramp(t: f32) -> [u8; 3] {
    let t = t.clamp(0.0, 1.0);
    let lerp = |a: f32, b: f32, u: f32| (a + (b - a) * u) as u8;
    if t < 0.5 {
        let u = t * 2.0;
        [
            lerp(20.0, 230.0, u),
            lerp(30.0, 120.0, u),
            lerp(110.0, 30.0, u),
        ]
    } else {
        let u = (t - 0.5) * 2.0;
        [
            lerp(230.0, 255.0, u),
            lerp(120.0, 250.0, u),
            lerp(30.0, 190.0, u),
        ]
    }
}

/// log2 of a density in [-3, 3] as blue .. white .. red.
fn diverging(log2: f32) -> [u8; 3] {
    let u = (log2 / 3.0).clamp(-1.0, 1.0);
    let fade = |c: f32| (255.0 - (255.0 - c) * u.abs()) as u8;
    if u < 0.0 {
        [fade(40.0), fade(90.0), fade(220.0)]
    } else {
        [fade(220.0), fade(50.0), fade(40.0)]
    }
}

pub(crate) fn pictures(
    fg: &FrameGpu,
    pass: &RegionsPass,
    classes: &[ClassRecord],
) -> Result<Vec<(String, RgbImage)>> {
    let (w, h) = (fg.gbuffer.width, fg.gbuffer.height);
    let words = pass.params.section_words as usize;
    let lists: Vec<u32> = readback::read_buffer(
        fg.ctx,
        &pass.class_tiles,
        (pass.params.ladder_len as usize * words * 4) as u64,
    )?;
    let g = crate::render::gbuffer::read_back(fg.ctx, &fg.gbuffer)?;
    let tiles_x = w.div_ceil(8);
    // Per tile: its class's record, if the tile is listed.
    let mut class_of = vec![None; (tiles_x * h.div_ceil(8)) as usize];
    for r in classes {
        let base = r.class as usize * words;
        for &t in &lists[base + TILE_LIST_HEADER..base + TILE_LIST_HEADER + lists[base] as usize] {
            class_of[t as usize] = Some(r);
        }
    }
    let most = classes.iter().map(|r| r.n).max().unwrap_or(1).max(2) as f32;
    let light = &fg.scene.light;
    let (centre, normal) = (light.center, light.normal());
    let samples = RgbImage::from_fn(w, h, |x, y| {
        let i = (y * w + x) as usize;
        match class_of[((y / 8) * tiles_x + x / 8) as usize] {
            Some(r) if g.is_geometry(i) => Rgb(ramp((r.n as f32).ln() / most.ln())),
            _ => Rgb(BACKGROUND),
        }
    });
    let texels = RgbImage::from_fn(w, h, |x, y| {
        let i = (y * w + x) as usize;
        match class_of[((y / 8) * tiles_x + x / 8) as usize] {
            Some(r) if g.is_geometry(i) => {
                let p = glam::Vec4::from(g.position[i]).truncate();
                let depth = (p - centre).dot(normal).abs().max(1e-6);
                let texel = r.extent / r.map_size as f32 * depth;
                let f = crate::stages::regions_rules::footprint(&g, i);
                Rgb(if f > 0.0 {
                    diverging((f / texel).log2())
                } else {
                    BACKGROUND
                })
            }
            _ => Rgb(BACKGROUND),
        }
    });
    Ok(vec![
        ("region_samples.png".to_string(), samples),
        ("region_texels.png".to_string(), texels),
    ])
}
