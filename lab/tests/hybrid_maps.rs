//! Hybrid-resolution shadow maps (seed 003, docs/hybrid.md): the merge on a synthetic depth map with
//! known plateaus and steps (exact pattern), and on the GPU: hybrid_build equals its twin word for
//! word, the lookup (through shade) equals the twin's, and a store too small for every map gives
//! the same image through flushes.

mod common;
use penumbra::research::frame::{self, frame_uniform, FrameOptions};
use penumbra::research::gpu::timing::TimingMode;
use penumbra::research::methods::{fixed_samples, Method};
use penumbra::research::scene::Scene;
use penumbra::research::stages::hybrid_build::{CHILDREN, DEPTH_UNIT};
use penumbra::research::stages::twin::{self, hybrid_build as hy};

/// The test binary's shared GPU context.
fn gpu() -> &'static penumbra::research::gpu::GpuContext {
    common::gpu()
}

/// 16x16 depths (4x4 coarse texels of 4x4 at levels = 2), far plane 1.0 where nothing is drawn.
/// Each region has a known fate; see `expected_levels`.
fn synthetic() -> Vec<f32> {
    let mut d = vec![1.0f32; 256];
    for y in 0..16 {
        for x in 0..16 {
            let v = match (x / 4, y / 4) {
                (0, 0) => 0.5,                   // plateau
                (1, 0) => 0.5 + x as f32 * 1e-6, // ramp within eps (0.25 units = 3.8e-6)
                (2, 0) => {
                    if x < 10 {
                        0.5
                    } else {
                        0.25
                    }
                } // step between 2x2 blocks
                (3, 0) => {
                    if x < 13 {
                        0.5
                    } else {
                        0.25
                    }
                } // step inside 2x2 blocks
                (1, 1) => {
                    if (x, y) == (5, 5) {
                        0.4
                    } else {
                        0.5
                    }
                } // one-texel spike
                (2, 1) => 0.5 + x as f32 * 1e-5, // ramp beyond eps: no block merges
                (3, 1) => 0.5 + ((x - 12) / 2) as f32 * 1e-5, // flat 2x2 blocks at different depths
                _ => 1.0,
            };
            d[y * 16 + x] = v;
        }
    }
    d
}

/// The level each texel's depth is stored at: 2 = merged 4x4, 1 = merged 2x2, 0 = full resolution.
fn expected_levels(levels: u32) -> Vec<u32> {
    (0..256)
        .map(|i| {
            let (x, y) = (i % 16, i / 16);
            if levels == 1 {
                let open = matches!((x / 2, y / 2), (6, 0) | (6, 1) | (2, 2))
                    || (8..12).contains(&x) && (4..8).contains(&y);
                return if open { 0 } else { 1 };
            }
            match (x / 4, y / 4) {
                (2, 0) | (3, 1) => 1,
                (3, 0) => {
                    if (12..14).contains(&x) {
                        0
                    } else {
                        1
                    }
                }
                (1, 1) => {
                    if x < 6 && y < 6 {
                        0
                    } else {
                        1
                    }
                }
                (2, 1) => 0,
                _ => 2,
            }
        })
        .collect()
}

#[test]
fn synthetic_map_merges_in_the_expected_pattern() {
    let depth = synthetic();
    let eps = 0.25 * DEPTH_UNIT;
    for levels in [2u32, 1] {
        let pool = hy::single_map_pool(&depth, 16, levels, eps);
        let got = hy::stored_levels(&pool, 0, 16, levels);
        let want = expected_levels(levels);
        let rows = |v: &[u32]| {
            v.chunks(16)
                .map(|r| r.iter().map(|l| l.to_string()).collect::<String>())
                .collect::<Vec<_>>()
                .join("\n")
        };
        assert_eq!(
            got,
            want,
            "levels {levels}: stored levels\n{}\nexpected\n{}",
            rows(&got),
            rows(&want)
        );
        // Words: the coarse grid, then 4 per open coarse node and 4 per open mid node (levels 2).
        let words = if levels == 2 {
            16 + 4 + (4 + 8) + (4 + 4) + (4 + 16) + 4
        } else {
            64 + 4 * 7
        };
        assert_eq!(pool.len() - 1, words, "levels {levels}: pool words");
        // Full-resolution texels read their own depth; merged ones their block's mean.
        let decoded = hy::decode(&pool, 0, 16, levels);
        for i in 0..256 {
            if want[i] == 0 {
                assert_eq!(
                    decoded[i], depth[i],
                    "levels {levels}: texel {i} is full resolution"
                );
            } else {
                assert!(
                    (decoded[i] - depth[i]).abs() <= eps * 2.0,
                    "levels {levels}: texel {i}: {} for {}",
                    decoded[i],
                    depth[i]
                );
            }
        }
        assert_eq!(decoded[0], 0.5);
        assert_eq!(decoded[255], 1.0);
    }
    // Same map, eps 0: only exactly flat blocks merge, so both ramps stay at full resolution.
    let strict = hy::stored_levels(&hy::single_map_pool(&depth, 16, 2, 0.0), 0, 16, 2);
    assert_eq!(
        strict[4], 0,
        "ramp within 0.25 units does not merge at eps 0"
    );
    assert_eq!(strict[0], 2);
}

#[test]
fn gpu_build_and_lookup_equal_their_twins() {
    let ctx = gpu();
    let opts = FrameOptions {
        mode: TimingMode::Frame,
        pictures: false,
    };
    for (seed, method, base, levels) in [
        (3u64, Method::hard(), 256u32, 2u32),
        (11, Method::regular(2), 128, 1),
        (29, Method::regular(2), 256, 2),
    ] {
        let set = |k: &str, v: String| (k.to_string(), v);
        let overrides = [
            set("maps", "hybrid".into()),
            set("base", base.to_string()),
            set("levels", levels.to_string()),
        ];
        let sc = Scene::parse(
            &common::random_scene_toml(seed, 48, 64),
            "random",
            None,
            &overrides,
        )
        .unwrap();
        assert_eq!(sc.render.shadow_map_size, base, "base is the raster size");
        let (r, c): (_, fixed_samples::FixedBuffers) = common::inspected(ctx, &sc, &method, opts);
        let eps = sc.render.hybrid.eps * DEPTH_UNIT;
        let (mut full, mut merged) = (0usize, 0usize);
        for (slot, raw) in c.raw_maps.iter().enumerate() {
            let map_base = c.hybrid_pool[slot];
            let want = hy::build(raw, base, levels, eps, map_base);
            let got = &c.hybrid_pool[map_base as usize..map_base as usize + want.len()];
            let diff = want.iter().zip(got).filter(|(a, b)| a != b).count();
            assert_eq!(
                diff,
                0,
                "seed {seed} slot {slot}: {diff} of {} words differ from the twin",
                want.len()
            );
            let coarse = (base >> levels) as usize;
            full += want[..coarse * coarse]
                .iter()
                .filter(|w| *w & CHILDREN != 0)
                .count();
            merged += want[..coarse * coarse]
                .iter()
                .filter(|w| *w & CHILDREN == 0)
                .count();
        }
        assert!(full > 0 && merged > 0, "seed {seed}: {full} refined and {merged} merged coarse texels: the map should have both");
        // The lookup: shade over the store equals the shade twin over the maps the lookup twin decodes.
        let mut v = vec![0.0f32; r.visibility.len()];
        let n = c.samples.len();
        twin::shade::shade(
            &frame_uniform(&sc),
            &c.samples,
            &c.weights,
            &c.maps,
            &r.gbuffer,
            0..n,
            &mut v,
        );
        let mut shadowed = 0;
        for (i, (twin, gpu)) in v.iter().zip(&r.visibility).enumerate() {
            if r.gbuffer.is_geometry(i) {
                assert_eq!(
                    twin.clamp(0.0, 1.0),
                    *gpu,
                    "seed {seed} pixel {i}: GPU lookup differs from its twin"
                );
                shadowed += (*gpu < 1.0) as usize;
            }
        }
        println!("seed {seed} {method:?} base {base} levels {levels}: {full} refined / {merged} merged coarse texels, {shadowed} pixels shadowed");
        assert!(
            shadowed > 20,
            "seed {seed}: too little shadow for the test to prove much"
        );
    }

    // A store too small for all 16 maps is shaded in several flushes and gives the same image.
    let image = |budget: &str| {
        let overrides: Vec<(String, String)> = [
            ("maps", "hybrid"),
            ("base", "512"),
            ("shadow_map_budget_mib", budget),
        ]
        .iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
        let sc = Scene::parse(
            &common::random_scene_toml(7, 32, 64),
            "random",
            None,
            &overrides,
        )
        .unwrap();
        let r = frame::render(ctx, &sc, &Method::regular(4), TimingMode::Frame).unwrap();
        let flushes = r.output.record["hybrid"]["flushes"].as_u64().unwrap();
        (r.visibility, flushes)
    };
    let (roomy, one) = image("64");
    let (tight, several) = image("5");
    assert_eq!(one, 1, "64 MiB holds every map");
    assert!(
        several >= 2,
        "5 MiB (4 MiB of it the transient raster) needs several flushes, got {several}"
    );
    assert_eq!(roomy, tight, "flushing the store changes nothing in V");
}

/// With eps = 0 only blocks of four equal depths merge, so the store reads back exactly the raster:
/// every map-reading method must then give the plain map's image bit for bit (the bilinear PCF
/// taps, computed by hand instead of by the comparison sampler, to rounding).
#[test]
fn every_map_reading_method_reads_hybrid_maps() {
    let ctx = gpu();
    let methods = [
        "hard",
        "pcf",
        "pcf:kernel=bilinear",
        "pcss",
        "regular:n=3",
        "adaptive",
        "adaptive:preset=balanced",
    ];
    for (seed, levels) in [(5u64, 2u32), (13, 1)] {
        let scene = |overrides: &[(&str, String)]| {
            let o: Vec<(String, String)> = overrides
                .iter()
                .map(|(k, v)| (k.to_string(), v.clone()))
                .collect();
            Scene::parse(
                &common::random_scene_toml(seed, 40, 256),
                "random",
                None,
                &o,
            )
            .unwrap()
        };
        let plain = scene(&[]);
        let hybrid = scene(&[
            ("maps", "hybrid".into()),
            ("base", "256".into()),
            ("levels", levels.to_string()),
            ("eps", "0".into()),
        ]);
        for m in methods {
            let method = Method::parse(m, &[]).unwrap();
            let a = frame::render(ctx, &plain, &method, TimingMode::Frame).unwrap();
            let b = frame::render(ctx, &hybrid, &method, TimingMode::Frame).unwrap();
            let worst = a
                .visibility
                .iter()
                .zip(&b.visibility)
                .map(|(x, y)| (x - y).abs())
                .fold(0.0f32, f32::max);
            let tolerance = if m.contains("bilinear") { 1e-6 } else { 0.0 };
            let record = &b.output.record["hybrid"];
            assert!(
                record["bytes_per_map"].as_f64().unwrap() > 0.0,
                "{m}: no hybrid record: {}",
                b.output.record
            );
            println!("seed {seed} levels {levels} {m}: max |plain - hybrid| = {worst:e}, {:.3} of a plain map", record["share_of_plain"]);
            assert!(
                worst <= tolerance,
                "seed {seed} levels {levels} {m}: hybrid at eps 0 differs from plain by {worst}"
            );
        }
    }
}

/// `reference --mode point` is the exact hard shadow: binary, matched by `hard` up to a few edge
/// pixels that shrink as the map grows, and a different point gives a different shadow.
#[test]
fn point_reference_is_the_hard_shadow_maps_converge_to() {
    use penumbra_lab::metrics;
    use penumbra_lab::reference::truth::{self, Cache};
    use penumbra_lab::reference::ReferenceMode;
    let ctx = gpu();
    let centre = ReferenceMode::Point { s: 0.5, t: 0.5 };
    let base = Scene::parse(&common::random_scene_toml(17, 64, 256), "random", None, &[]).unwrap();
    let (g, reference) = truth::for_scene(ctx, &base, centre, &Cache::Off).unwrap();
    let mask: Vec<bool> = (0..g.position.len()).map(|i| g.is_geometry(i)).collect();
    assert!(
        reference.values.iter().all(|v| *v == 0.0 || *v == 1.0),
        "a point reference is binary"
    );
    let shadowed = mask
        .iter()
        .zip(&reference.values)
        .filter(|(m, v)| **m && **v == 0.0)
        .count();
    assert!(
        shadowed > 100,
        "the scene should cast a shadow ({shadowed} pixels)"
    );
    let mismatch = |overrides: &[(&str, &str)]| {
        let o: Vec<(String, String)> = overrides
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect();
        let sc = Scene::parse(&common::random_scene_toml(17, 64, 256), "random", None, &o).unwrap();
        let r = frame::render(ctx, &sc, &Method::hard(), TimingMode::Frame).unwrap();
        let shaded = penumbra_lab::record::run_files::shaded_image(&r.visibility, &r.gbuffer, &sc);
        let shaded_ref = penumbra_lab::record::run_files::shaded_image(&reference.values, &g, &sc);
        metrics::compute(
            &r.visibility,
            &reference.values,
            &mask,
            &shaded,
            &shaded_ref,
            64,
            64,
        )
        .unwrap()
        .mismatch_share
    };
    let coarse = mismatch(&[("shadow_map_size", "64")]);
    let fine = mismatch(&[("shadow_map_size", "1024")]);
    let hybrid = mismatch(&[("maps", "hybrid"), ("base", "1024"), ("levels", "2")]);
    println!("mismatch against the point reference: plain 64² {coarse:.4}, plain 1024² {fine:.4}, hybrid 1024→256 {hybrid:.4}");
    assert!(fine < 0.02, "a 1024² map mismatches {fine} of the pixels");
    assert!(
        coarse > fine,
        "a 64² map ({coarse}) should mismatch more than a 1024² map ({fine})"
    );
    assert!(
        hybrid <= fine + 1.0 / 4096.0,
        "hybrid 1024→256 ({hybrid}) should match plain 1024² ({fine})"
    );
    let (_, corner) = truth::for_scene(
        ctx,
        &base,
        ReferenceMode::Point { s: 0.0, t: 0.0 },
        &Cache::Off,
    )
    .unwrap();
    assert_ne!(
        corner.values, reference.values,
        "another light point casts another shadow"
    );
}
