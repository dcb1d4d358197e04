//! The `shade` kernel (hard and regular methods) equals its CPU twin on random scenes, including
//! when the maps are split into chunks by the memory budget.

mod common;
use penumbra::research::frame::{frame_uniform, FrameOptions};
use penumbra::research::gpu::timing::TimingMode;
use penumbra::research::methods::{fixed_samples, Method};
use penumbra::research::scene::Scene;
use penumbra::research::stages::shade::{blocks, SHADE_BLOCK};
use penumbra::research::stages::twin;

#[test]
fn shade_equals_its_cpu_twin() {
    let ctx = common::gpu();
    for (seed, method, budget) in [
        (3u64, Method::hard(), "64"),
        (11, Method::regular(4), "64"),
        (29, Method::regular(5), "1"),
    ] {
        let sc = Scene::parse(
            &common::random_scene_toml(seed, 48, 128),
            "random",
            None,
            &[("shadow_map_budget_mib".into(), budget.into())],
        )
        .unwrap();
        let options = FrameOptions {
            mode: TimingMode::Frame,
            pictures: true,
        };
        let (r, c): (_, fixed_samples::FixedBuffers) =
            common::inspected(ctx, &sc, &method, options);
        let mut v = vec![0.0f32; r.visibility.len()];
        let n = c.samples.len();
        if seed == 29 {
            // Shade adds full blocks of SHADE_BLOCK samples, then the rest in smaller blocks: this
            // case has a full block and two tail blocks (25 = 16 + 8 + 1).
            let sizes: Vec<u32> = blocks(0, n as u32).iter().map(|&(_, size)| size).collect();
            assert_eq!(sizes, [SHADE_BLOCK, 8, 1], "seed {seed}: {n} samples");
        }
        // Shade runs only on the tiles with a geometry pixel: exactly the twin's.
        let tiles = twin::shade::geometry_tiles(&r.gbuffer);
        let all = r.gbuffer.width.div_ceil(8) * r.gbuffer.height.div_ceil(8);
        assert_eq!(
            c.tiles, tiles,
            "seed {seed}: geometry tiles differ from the twin's"
        );
        assert!(
            !tiles.is_empty() && (tiles.len() as u32) < all,
            "seed {seed}: {} of {all} tiles: the scene should leave some background",
            tiles.len()
        );
        twin::shade::shade(
            &frame_uniform(&sc),
            &c.samples,
            &c.weights,
            &c.maps,
            &r.gbuffer,
            0..n,
            &mut v,
        );
        let (mut worst, mut shadowed) = (0.0f32, 0usize);
        for (i, twin_v) in v.iter().enumerate() {
            if r.gbuffer.is_geometry(i) {
                worst = worst.max((twin_v.clamp(0.0, 1.0) - r.visibility[i]).abs());
                shadowed += (r.visibility[i] < 1.0) as usize;
            }
        }
        println!("seed {seed} {method:?}: {n} maps, max |GPU - twin| = {worst:e}, {shadowed} pixels not fully lit");
        assert!(
            shadowed > 20,
            "seed {seed}: the scene casts almost no shadow, the test would prove little"
        );
        assert!(
            worst <= 1e-6,
            "seed {seed}: shade differs from its twin by {worst}"
        );
    }
}
