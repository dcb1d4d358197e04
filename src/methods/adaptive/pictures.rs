//! Pictures of the adaptive decisions: the level-0 comparison map in the seed's five colours, the
//! low-quality pixels of every level, the light's quadtree, and samples per pixel (scope = local).

use super::AdaptiveTrace;
use crate::methods::adaptive::buffers::NO_SPLIT;
use crate::stages::FrameGpu;
use image::{Rgb, RgbImage};

const SEED_COLOURS: [[u8; 3]; 5] = [
    [0, 0, 0],
    [220, 30, 30],
    [30, 190, 60],
    [40, 80, 230],
    [255, 255, 255],
];
const LEVEL_COLOURS: [[u8; 3]; 5] = [
    [230, 60, 60],
    [240, 150, 40],
    [235, 220, 60],
    [80, 200, 90],
    [70, 140, 240],
];
const BACKGROUND: [u8; 3] = [40, 44, 52];

pub(crate) fn all(
    fg: &FrameGpu,
    trace: &AdaptiveTrace,
    consulted: Option<&[u32]>,
) -> Vec<(String, RgbImage)> {
    let (w, h) = (fg.gbuffer.width, fg.gbuffer.height);
    let wpr = w.div_ceil(4);
    let fwpr = w.div_ceil(32);
    let mut out = Vec::new();
    if let Some(counts) = trace.levels.first().and_then(|l| l.counts.as_ref()) {
        let img = RgbImage::from_fn(w, h, |x, y| {
            let b = (counts[(y * wpr + x / 4) as usize] >> ((x % 4) * 8)) & 0xff;
            Rgb(if b == 0 {
                BACKGROUND
            } else {
                SEED_COLOURS[(b - 1).min(4) as usize]
            })
        });
        out.push(("comparison_map.png".to_string(), img));
    }
    let mut low = RgbImage::from_pixel(w, h, Rgb([20, 20, 20]));
    for level in &trace.levels {
        let Some(flags) = &level.flags else { continue };
        let per_quad = (h * fwpr) as usize;
        for q in 0..level.quads.len() {
            for y in 0..h {
                for x in 0..w {
                    let word = flags[q * per_quad + (y * fwpr + x / 32) as usize];
                    if word >> (x % 32) & 1 == 1 {
                        low.put_pixel(x, y, Rgb(LEVEL_COLOURS[level.level.min(4) as usize]));
                    }
                }
            }
        }
    }
    out.push(("low_quality.png".to_string(), low));
    out.push(("light_quadtree.png".to_string(), quadtree(trace)));
    if let Some(masks) = consulted {
        let counts: Vec<u32> = masks
            .chunks_exact(10)
            .map(|m| m.iter().map(|x| x.count_ones()).sum())
            .collect();
        let max = counts.iter().copied().max().unwrap_or(1).max(1);
        let img = RgbImage::from_fn(w, h, |x, y| {
            let c = counts[(y * w + x) as usize];
            if c == 0 {
                return Rgb(BACKGROUND);
            }
            let t = (c as f32 / max as f32).sqrt();
            Rgb([
                (255.0 * t) as u8,
                (255.0 * (1.0 - (t - 0.5).abs() * 2.0).max(0.0) * 0.8) as u8,
                (255.0 * (1.0 - t)) as u8,
            ])
        });
        out.push(("samples_per_pixel.png".to_string(), img));
    }
    out
}

/// The 17x17 lattice: split quads outlined, rendered samples coloured by their level.
fn quadtree(trace: &AdaptiveTrace) -> RgbImage {
    const STEP: u32 = 32;
    const MARGIN: u32 = 16;
    let size = 16 * STEP + 2 * MARGIN;
    let mut img = RgbImage::from_pixel(size, size, Rgb([250, 250, 250]));
    let to_px = |i: u32| MARGIN + i * STEP;
    let line = |img: &mut RgbImage, x0: u32, y0: u32, x1: u32, y1: u32| {
        for x in x0..=x1 {
            for y in y0..=y1 {
                img.put_pixel(x, y, Rgb([90, 90, 90]));
            }
        }
    };
    for level in &trace.levels {
        for (q, quad) in level.quads.iter().enumerate() {
            let (x0, y0, x1, y1) = (
                to_px(quad.i),
                to_px(quad.j),
                to_px(quad.i + quad.size),
                to_px(quad.j + quad.size),
            );
            line(&mut img, x0, y0, x1, y0);
            line(&mut img, x0, y1, x1, y1);
            line(&mut img, x0, y0, x0, y1);
            line(&mut img, x1, y0, x1, y1);
            if level.split_base.get(q).is_some_and(|&s| s != NO_SPLIT) {
                let (cx, cy) = (to_px(quad.i + quad.size / 2), to_px(quad.j + quad.size / 2));
                line(&mut img, x0, cy, x1, cy);
                line(&mut img, cx, y0, cx, y1);
            }
        }
    }
    let levels = trace
        .levels
        .last()
        .map(|l| l.sample_level.clone())
        .unwrap_or_default();
    for k in 0..289u32 {
        let (cx, cy) = (to_px(k % 17) as i32, to_px(k / 17) as i32);
        let rendered = trace.rendered.contains(&k);
        let (r, colour) = if rendered {
            (
                6,
                LEVEL_COLOURS[levels.get(k as usize).copied().unwrap_or(0).min(4) as usize],
            )
        } else {
            (2, [180, 180, 180])
        };
        for dy in -r..=r {
            for dx in -r..=r {
                if dx * dx + dy * dy <= r * r {
                    img.put_pixel((cx + dx) as u32, (cy + dy) as u32, Rgb(colour));
                }
            }
        }
    }
    img
}
