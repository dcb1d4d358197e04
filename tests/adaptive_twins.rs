//! GPU results equal the CPU twins on randomised scenes, cameras and light placements: the lattice
//! masks (shadow_test), every comparison map (reproject_count), the low-quality flags
//! (neighbourhood), the per-quad counters (quad_count), the quads, samples and levels appended by
//! subdivide, the weighted shade, and the whole scope = local pipeline in exact integers.
//! Each stage's twin is fed the GPU's own inputs, so a mismatch points at one stage.

mod common;
use penumbra::research::frame::frame_uniform;
use penumbra::research::methods::adaptive::buffers::{CULL_TILE_WORDS, LATTICE_POINTS, MIXED_WORD};
use penumbra::research::methods::AdaptiveParams;
use penumbra::research::scene::Scene;
use penumbra::research::stages::twin::{self, neighbourhood::Screen};

const SEEDS: [u64; 4] = [1, 7, 23, 101];
/// The seed's pixel threshold, a level-aware share, and the error budget (method.md §6).
const CRITERIA: [&str; 4] = ["p_m=0", "p_m=3", "p_share=0.002,growth=4", "tol=0.004"];

fn params(spec: &str) -> AdaptiveParams {
    let m = penumbra::research::methods::Method::parse(&format!("adaptive:{spec}"), &[])
        .expect("criterion parses");
    m.adaptive_params()
        .cloned()
        .unwrap_or_else(|| panic!("{m:?} is not adaptive"))
}

fn scene(seed: u64) -> Scene {
    Scene::parse(
        &common::random_scene_toml(seed, 48, 128),
        &format!("random-{seed}"),
        None,
        &[],
    )
    .expect("random scene parses")
}

fn sorted_quads(q: &[penumbra::research::gpu::structs::GpuQuad]) -> Vec<(u32, u32, u32)> {
    let mut v: Vec<_> = q.iter().map(|q| (q.i, q.j, q.size)).collect();
    v.sort();
    v
}

#[test]
fn global_stages_equal_their_cpu_twins() {
    let ctx = common::gpu();
    let mut levels_checked = 0;
    let mut quads_checked = 0;
    let (mut mixed_words, mut uniform_words) = (0, 0);
    let mut block_sizes = std::collections::BTreeSet::new();
    // Seed 0: the default scene at 512², whose balanced lists need every block size of shadow_test.
    let sets = [("resolution", "512"), ("shadow_map_size", "512")]
        .map(|(k, v)| (k.to_string(), v.to_string()));
    let cases = SEEDS
        .iter()
        .flat_map(|&s| CRITERIA.map(|c| (s, c)))
        .chain([(0, "preset=balanced")]);
    for (seed, spec) in cases {
        {
            let sc = if seed == 0 {
                Scene::load("default", &sets).expect("default scene")
            } else {
                scene(seed)
            };
            let p = params(spec);
            let p_m = spec;
            let (r, t) = common::traced(ctx, &sc, &p, true);
            let g = &r.gbuffer;
            let fr = frame_uniform(&sc);
            let maps = |k: u32| {
                t.maps
                    .iter()
                    .find(|(m, _)| *m == k)
                    .expect("map kept")
                    .1
                    .clone()
            };
            let screen = Screen {
                width: g.width,
                height: g.height,
            };
            let geometry = (0..g.position.len()).filter(|&i| g.is_geometry(i)).count() as u32;
            assert_eq!(
                t.levels[0].geometry_pixels, geometry,
                "seed {seed}: reproject_count's geometry pixels"
            );
            let mut masks = vec![0u32; g.position.len() * 10];
            let mut state = vec![0u32; 289];
            for k in [0, 16, 272, 288] {
                state[k] = 1;
            }
            let mut sample_level = vec![0u32; 289];
            for (d, lvl) in t.levels.iter().enumerate() {
                let new: Vec<u32> = if d == 0 {
                    vec![0, 16, 272, 288]
                } else {
                    t.levels[d - 1].new_samples.clone()
                };
                let blocks = twin::shadow_test::fill_blocks(
                    &new,
                    &[1; LATTICE_POINTS as usize],
                    new.len() as u32,
                );
                block_sizes.extend(blocks.iter().map(|b| b.len()).filter(|&n| n > 0));
                twin::shadow_test::shadow_test(&fr, &t.samples, &maps, g, &new, &mut masks);
                let gpu_masks = lvl.masks.as_ref().unwrap();
                let wrong_bits: u32 = masks
                    .iter()
                    .zip(gpu_masks)
                    .map(|(a, b)| (a ^ b).count_ones())
                    .sum();
                assert_eq!(
                    wrong_bits, 0,
                    "seed {seed} p_m {p_m} level {d}: shadow_test differs in {wrong_bits} bits"
                );
                masks.clone_from(gpu_masks);
                let n = lvl.quads.len();
                if lvl.evaluated {
                    let counts = twin::reproject_count::reproject_count(&lvl.quads, gpu_masks, g);
                    let states = twin::reproject_count::word_state(gpu_masks, g.width, g.height);
                    assert_eq!(
                        &states,
                        lvl.word_state.as_ref().unwrap(),
                        "seed {seed} level {d}: reproject_count's word states differ"
                    );
                    mixed_words += states.iter().filter(|&&s| s == MIXED_WORD).count();
                    uniform_words += states.iter().filter(|&&s| s != MIXED_WORD).count();
                    assert_eq!(
                        &counts,
                        lvl.counts.as_ref().unwrap(),
                        "seed {seed} level {d}: reproject_count differs"
                    );
                    let flags = twin::neighbourhood::neighbourhood(
                        lvl.counts.as_ref().unwrap(),
                        &screen,
                        n,
                    );
                    assert_eq!(
                        &flags,
                        lvl.flags.as_ref().unwrap(),
                        "seed {seed} level {d}: neighbourhood differs"
                    );
                    let words = (g.height * screen.flag_words_per_row()) as usize;
                    let counters =
                        twin::quad_count::quad_count(lvl.flags.as_ref().unwrap(), words, n);
                    assert_eq!(
                        counters, lvl.low_quality,
                        "seed {seed} level {d}: quad_count differs"
                    );
                    quads_checked += n;
                }
                let at = twin::subdivide::SplitLevel {
                    level: d as u32,
                    max_level: p.max_level,
                    rule: p.split_rule(d as u32),
                    geometry_pixels: geometry,
                };
                let sub = twin::subdivide::subdivide(
                    &at,
                    &lvl.quads,
                    &lvl.low_quality,
                    &mut state,
                    &mut sample_level,
                );
                assert_eq!(
                    sorted_quads(&sub.next_quads),
                    sorted_quads(&lvl.next_quads),
                    "seed {seed} level {d}: subdivide quads"
                );
                assert_eq!(
                    sub.new_samples, lvl.new_samples,
                    "seed {seed} level {d}: subdivide samples"
                );
                assert_eq!(
                    sample_level, lvl.sample_level,
                    "seed {seed} level {d}: sample levels"
                );
                let split_gpu: Vec<bool> = lvl.split_base.iter().map(|&s| s != u32::MAX).collect();
                let split_cpu: Vec<bool> = sub.split_base.iter().map(|&s| s != u32::MAX).collect();
                assert_eq!(
                    split_cpu, split_gpu,
                    "seed {seed} level {d}: split decisions"
                );
                levels_checked += 1;
            }
            let v = twin::shade::from_masks(&t.weights, &masks, g);
            let worst = v
                .iter()
                .zip(&r.visibility)
                .map(|(a, b)| (a.clamp(0.0, 1.0) - b).abs())
                .fold(0.0f32, f32::max);
            assert!(worst <= 1e-6, "seed {seed}: shade differs by {worst}");
            println!(
                "seed {seed} p_m {p_m}: {} levels, {} maps, twins equal",
                t.levels.len(),
                t.rendered.len()
            );
        }
    }
    assert!(
        levels_checked >= 16 && quads_checked >= 40,
        "too little was compared: {levels_checked} levels, {quads_checked} quads"
    );
    // Both kinds of word were compared: maps read through word_state and through the quads' own words.
    assert!(
        mixed_words > 100 && uniform_words > 100,
        "word states: {mixed_words} mixed, {uniform_words} uniform"
    );
    // shadow_test's masks were compared through every block entry point.
    assert_eq!(
        block_sizes.into_iter().collect::<Vec<_>>(),
        [1, 2, 4, 8, 16],
        "block sizes used"
    );
}

#[test]
fn local_pipeline_equals_its_cpu_twin_exactly() {
    let ctx = common::gpu();
    let mut probes_seen = 0;
    for seed in SEEDS {
        for spec in ["p_m=0", "tol=0.004"] {
            let sc = scene(seed);
            let p = params(&format!("{spec},scope=local"));
            let (r, t) = common::traced(ctx, &sc, &p, true);
            let fr = frame_uniform(&sc);
            let maps = |k: u32| {
                t.maps
                    .iter()
                    .find(|(m, _)| *m == k)
                    .expect("map kept")
                    .1
                    .clone()
            };
            let out = twin::local::local(&fr, &t.samples, &maps, &r.gbuffer, p.max_level, &|l| {
                p.split_rule(l)
            });
            let items: Vec<u32> = t.levels.iter().map(|l| l.items).collect();
            let probes: Vec<u32> = t.levels.iter().map(|l| l.probes).collect();
            assert_eq!(out.items, items, "seed {seed} {spec}: items per level");
            assert_eq!(out.probes, probes, "seed {seed} {spec}: probes per level");
            for (d, lvl) in t.levels.iter().enumerate() {
                assert_eq!(
                    out.quads[d]
                        .iter()
                        .map(|q| (q.i, q.j, q.size))
                        .collect::<Vec<_>>(),
                    sorted_quads(&lvl.quads),
                    "seed {seed} {spec} level {d}: quads"
                );
                assert_eq!(
                    out.new_samples[d], lvl.new_samples,
                    "seed {seed} {spec} level {d}: new samples"
                );
            }
            let scale = (4u32 << (2 * p.max_level)) as f32;
            let wrong = out
                .visibility_fixed
                .iter()
                .zip(&r.visibility)
                .filter(|(a, b)| **a as f32 / scale != **b)
                .count();
            assert_eq!(
                wrong, 0,
                "seed {seed} {spec}: {wrong} pixels differ from the twin"
            );
            probes_seen += probes.iter().sum::<u32>();
            println!("seed {seed} {spec}: local, {} levels, items {items:?}, probes {probes:?}, twin equal", t.levels.len());
        }
    }
    assert!(
        probes_seen > 1000,
        "too few probes were compared: {probes_seen}"
    );
}

/// shadow_test `list` and `probes` (scope = local) look each (pixel, sample) pair up once per frame:
/// at every level the GPU's lookups equal the twin's and the number of pairs consulted for the first
/// time (new bits of the GPU's own consulted masks); the consulted samples and the lattice masks
/// equal the twin's bit for bit; level 0 looks up the root's 4 corners of every geometry pixel.
#[test]
fn local_lookups_equal_the_distinct_pairs_consulted() {
    let ctx = common::gpu();
    let (mut lookups, mut per_item) = (0u64, 0u64);
    for seed in [SEEDS[0], SEEDS[2]] {
        for spec in ["p_m=0", "p_m=-1,max_level=3"] {
            let sc = scene(seed);
            let p = params(&format!("{spec},scope=local"));
            let (r, t) = common::traced(ctx, &sc, &p, true);
            let fr = frame_uniform(&sc);
            let maps = |k: u32| {
                t.maps
                    .iter()
                    .find(|(m, _)| *m == k)
                    .expect("map kept")
                    .1
                    .clone()
            };
            let out = twin::local::local(&fr, &t.samples, &maps, &r.gbuffer, p.max_level, &|l| {
                p.split_rule(l)
            });
            let geometry = (0..r.gbuffer.position.len())
                .filter(|&i| r.gbuffer.is_geometry(i))
                .count() as u32;
            assert_eq!(
                t.levels[0].lookups,
                4 * geometry,
                "seed {seed} {spec}: level 0 looks up the root's corners once per pixel"
            );
            let mut before = 0u32;
            for (d, lvl) in t.levels.iter().enumerate() {
                let consulted = lvl.consulted.as_ref().expect("consulted kept");
                let now: u32 = consulted.iter().map(|w| w.count_ones()).sum();
                assert_eq!(
                    lvl.lookups,
                    now - before,
                    "seed {seed} {spec} level {d}: lookups against the pairs first consulted"
                );
                assert_eq!(
                    lvl.lookups, out.lookups[d],
                    "seed {seed} {spec} level {d}: lookups against the twin"
                );
                assert!(
                    consulted == &out.consulted[d],
                    "seed {seed} {spec} level {d}: consulted samples differ from the twin"
                );
                assert!(
                    lvl.masks.as_ref().unwrap() == &out.masks[d],
                    "seed {seed} {spec} level {d}: lattice masks differ from the twin"
                );
                before = now;
                lookups += lvl.lookups as u64;
                // What testing every item's corners and every probe's samples would look up.
                per_item += 4 * lvl.items as u64
                    + if d > 0 {
                        5 * t.levels[d - 1].probes as u64
                    } else {
                        0
                    };
            }
            println!("seed {seed} {spec}: lookups per level {:?}", out.lookups);
        }
    }
    println!("{lookups} lookups, {per_item} with a lookup per item corner and probe sample");
    assert!(
        lookups * 2 < per_item,
        "deduplication saved too little: {lookups} of {per_item}"
    );
}

/// cull (scope = local): the triangles kept for every culled map equal the twin's count exactly,
/// from the GPU's own rectangles and samples; culling changes no pixel and no map choice.
#[test]
fn cull_equals_its_cpu_twin_and_changes_no_pixel() {
    let ctx = common::gpu();
    let (mut maps_checked, mut culled_away) = (0, 0u64);
    // The random scenes' occluders fill the light's view; default's bunny sits in a small part of it.
    let sets = [("resolution", "128"), ("shadow_map_size", "256")]
        .map(|(k, v)| (k.to_string(), v.to_string()));
    let scenes = SEEDS
        .iter()
        .map(|&s| (s, scene(s)))
        .chain([(0, Scene::load("default", &sets).expect("default scene"))]);
    for (seed, sc) in scenes {
        let fr = frame_uniform(&sc);
        let positions: Vec<glam::Vec3> = sc
            .vertices
            .iter()
            .map(|v| glam::Vec3::from(v.position))
            .collect();
        let whole = sc.indices.len() as u64 / 3;
        let order = penumbra::research::render::shadow_order::shadow_order(&positions, &sc.indices);
        // Always splitting reaches small quads, whose pixels test small rectangles.
        let (on, t) = common::traced(
            ctx,
            &sc,
            &params("p_m=-1,max_level=3,scope=local,cull=on"),
            false,
        );
        let (off, t_off) =
            common::traced(ctx, &sc, &params("p_m=-1,max_level=3,scope=local"), false);
        let changed = on
            .visibility
            .iter()
            .zip(&off.visibility)
            .filter(|(a, b)| a.to_bits() != b.to_bits())
            .count();
        assert_eq!(
            changed, 0,
            "seed {seed}: culling changed V in {changed} pixels"
        );
        assert_eq!(
            t.rendered, t_off.rendered,
            "seed {seed}: culling changed the maps"
        );
        assert!(
            t_off.triangles.iter().all(|&n| n == whole),
            "seed {seed}: cull=off rasterizes the whole mesh"
        );
        assert_eq!(
            t.culled.len(),
            t.rendered.len(),
            "seed {seed}: every map is culled, level 0's too"
        );
        // Level 0's corners serve every pixel: every tile of theirs takes an infinite limit.
        let corners = [0u32, 16, 272, 288];
        let mut every = vec![0u32; (LATTICE_POINTS * CULL_TILE_WORDS) as usize];
        for &k in &corners {
            every[(k * CULL_TILE_WORDS) as usize..((k + 1) * CULL_TILE_WORDS) as usize]
                .fill(f32::INFINITY.to_bits());
        }
        for d in 0..t.levels.len() {
            let (ks, tiles) = if d == 0 {
                (&corners.to_vec(), &every)
            } else {
                (&t.levels[d - 1].new_samples, &t.levels[d - 1].tiles)
            };
            let kept = twin::cull::cull(
                &fr,
                &t.samples,
                tiles,
                &positions,
                &order,
                ks,
                penumbra::research::stages::cull::cull_face(sc.render.cull),
            );
            for (k, tris) in ks.iter().zip(&kept) {
                let at = t
                    .rendered
                    .iter()
                    .position(|r| r == k)
                    .expect("new sample rendered");
                assert!(
                    t.culled.contains(k),
                    "seed {seed} level {d}: map {k} was not culled"
                );
                assert_eq!(
                    t.triangles[at],
                    tris.len() as u64,
                    "seed {seed} level {d}: map {k}'s kept triangles"
                );
                culled_away += whole - tris.len() as u64;
                maps_checked += 1;
            }
        }
    }
    assert!(
        maps_checked >= 8,
        "only {maps_checked} culled maps compared"
    );
    println!("{maps_checked} culled maps equal their twin; {culled_away} triangles culled in all");
    assert!(
        culled_away > 0,
        "no triangle was culled: the comparison says nothing"
    );
}

/// The GPU-steered loop (no read-back in the frame) equals the waiting loop exactly: the same maps
/// in the same order, the same levels, the GPU weights equal the CPU weights (their twin) bit for
/// bit, and V is bit-identical; it needs no sync.
#[test]
fn steered_frame_equals_the_waiting_loop() {
    let ctx = common::gpu();
    let sets = [("resolution", "96"), ("shadow_map_size", "128")]
        .map(|(k, v)| (k.to_string(), v.to_string()));
    let scenes = SEEDS
        .iter()
        .map(|&s| (s, scene(s)))
        .chain([(0, Scene::load("default", &sets).expect("default scene"))]);
    let mut frames = 0;
    for (seed, sc) in scenes {
        for spec in [
            "preset=seed",
            "preset=balanced",
            "p_m=3,weights=area",
            "tol=0.004,weights=coons",
            "p_m=-1,max_level=2",
        ] {
            let (gpu, t) = common::traced(ctx, &sc, &params(&format!("{spec},steer=gpu")), false);
            let (cpu, t_cpu) =
                common::traced(ctx, &sc, &params(&format!("{spec},steer=cpu")), false);
            assert_eq!(
                gpu.output.syncs, 0,
                "seed {seed} {spec}: the steered frame waited"
            );
            assert!(
                cpu.output.syncs > 0,
                "seed {seed} {spec}: the waiting loop did not wait"
            );
            assert_eq!(t.rendered, t_cpu.rendered, "seed {seed} {spec}: maps");
            assert_eq!(
                t.levels.len(),
                t_cpu.levels.len(),
                "seed {seed} {spec}: levels"
            );
            for (a, b) in t.levels.iter().zip(&t_cpu.levels) {
                assert_eq!(
                    sorted_quads(&a.quads),
                    sorted_quads(&b.quads),
                    "seed {seed} {spec} level {}: quads",
                    a.level
                );
                assert_eq!(
                    a.low_quality.iter().sum::<u32>(),
                    b.low_quality.iter().sum::<u32>(),
                    "seed {seed} {spec} level {}: low-quality pixels",
                    a.level
                );
            }
            let p = params(spec);
            let last = t.levels.last().unwrap();
            let twin = penumbra::research::methods::adaptive::sample_weights(
                &p,
                &t.levels,
                &last.sample_level,
                &t.rendered,
            );
            let bits = |w: &[f32]| w.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(
                bits(&t.weights),
                bits(&twin),
                "seed {seed} {spec}: GPU weights differ from the CPU's"
            );
            assert_eq!(
                bits(&t.weights),
                bits(&t_cpu.weights),
                "seed {seed} {spec}: weights differ from the waiting loop's"
            );
            let changed = gpu
                .visibility
                .iter()
                .zip(&cpu.visibility)
                .filter(|(a, b)| a.to_bits() != b.to_bits())
                .count();
            assert_eq!(
                changed, 0,
                "seed {seed} {spec}: V differs in {changed} pixels"
            );
            frames += 1;
        }
    }
    assert_eq!(frames, 25);
}

/// scope = local under the GPU-steered loop: no read-back in the frame, and the same maps, levels,
/// quads, lookups and bit-identical V as the waiting loop, over both rasters (the compute raster
/// rasterizes only the requested maps, the fixed-function one draws every candidate layer with its
/// request flag as the instance count).
#[test]
fn local_steered_frame_equals_the_waiting_loop() {
    let ctx = common::gpu();
    let (mut frames, mut deeper) = (0usize, 0usize);
    for raster in ["compute", "hardware"] {
        let sets = [
            ("resolution", "96"),
            ("shadow_map_size", "128"),
            ("raster", raster),
        ]
        .map(|(k, v)| (k.to_string(), v.to_string()));
        let scenes = SEEDS[..2]
            .iter()
            .map(|&s| {
                (
                    s,
                    Scene::parse(
                        &common::random_scene_toml(s, 48, 128),
                        &format!("random-{s}"),
                        None,
                        &sets[2..],
                    )
                    .unwrap(),
                )
            })
            .chain([(0, Scene::load("default", &sets).expect("default scene"))]);
        for (seed, sc) in scenes {
            for spec in [
                "scope=local",
                "preset=balanced,scope=local",
                "p_m=3,scope=local",
            ] {
                let (gpu, t) =
                    common::traced(ctx, &sc, &params(&format!("{spec},steer=gpu")), false);
                let (cpu, t_cpu) =
                    common::traced(ctx, &sc, &params(&format!("{spec},steer=cpu")), false);
                assert_eq!(
                    gpu.output.syncs, 0,
                    "{raster} seed {seed} {spec}: the steered frame waited"
                );
                assert!(
                    gpu.output.record["steer"]
                        .as_str()
                        .is_some_and(|s| s.starts_with("gpu")),
                    "{raster} seed {seed} {spec}: not steered: {}",
                    gpu.output.record
                );
                assert!(
                    cpu.output.syncs > 0,
                    "{raster} seed {seed} {spec}: the waiting loop did not wait"
                );
                let sorted = |v: &[u32]| {
                    let mut v = v.to_vec();
                    v.sort_unstable();
                    v
                };
                assert_eq!(
                    sorted(&t.rendered),
                    sorted(&t_cpu.rendered),
                    "{raster} seed {seed} {spec}: maps"
                );
                assert_eq!(
                    t.levels.len(),
                    t_cpu.levels.len(),
                    "{raster} seed {seed} {spec}: levels"
                );
                for (a, b) in t.levels.iter().zip(&t_cpu.levels) {
                    assert_eq!(
                        sorted_quads(&a.quads),
                        sorted_quads(&b.quads),
                        "{raster} seed {seed} {spec} level {}: quads",
                        a.level
                    );
                    assert_eq!(
                        a.lookups, b.lookups,
                        "{raster} seed {seed} {spec} level {}: lookups",
                        a.level
                    );
                }
                let changed = gpu
                    .visibility
                    .iter()
                    .zip(&cpu.visibility)
                    .filter(|(a, b)| a.to_bits() != b.to_bits())
                    .count();
                assert_eq!(
                    changed, 0,
                    "{raster} seed {seed} {spec}: V differs in {changed} pixels"
                );
                deeper += (t.rendered.len() > 4) as usize;
                frames += 1;
            }
        }
    }
    println!("{frames} steered local frames equal the waiting loop; {deeper} of them went past the corners");
    assert_eq!(frames, 2 * 3 * 3);
    // 8 of the 18 refine past the corners (p_m = 3 stops at them on most of these scenes).
    assert!(
        deeper >= frames / 3,
        "only {deeper} of {frames} frames refined past the corners"
    );
}

/// shadow_test `fill_blocks` (scope = global) equals its twin exactly: which requested samples go
/// to which block slot, in which order, byte-identical sample records, and workgroups for exactly
/// the slots that hold samples among those the host dispatches; for listed and requested counts.
#[test]
fn fill_blocks_equals_its_cpu_twin() {
    use penumbra::research::gpu::readback;
    use penumbra::research::gpu::structs::{
        GpuControl, GpuFrame, GpuLevel, GpuSample, GpuTestBlock,
    };
    use penumbra::research::stages::shadow_test::{
        block_slots, ShadowTest, TEST_BLOCK, TEST_BLOCK_BYTES, TEST_SLOTS,
    };
    let ctx = common::gpu();
    let test = ShadowTest::new(
        ctx,
        penumbra::research::gpu::kernels::MapAccess::Depth,
        false,
    )
    .expect("shadow_test kernels");
    let frame = GpuFrame {
        width: 100,
        height: 37,
        ..Default::default()
    };
    // The blocks' workgroups: one per listed geometry tile (a list of 29 tiles here).
    let tiles = 29u32;
    // Every record distinct, so a sample copied from the wrong index shows.
    let samples: Vec<GpuSample> = (0..LATTICE_POINTS)
        .map(|k| GpuSample {
            texel_angle: k as f32 + 0.5,
            layer: 1000 + k,
            lattice: k,
            light_from_world: [[k as f32 * 3.0; 4]; 4],
            ..Default::default()
        })
        .collect();
    let mut rng = common::Lcg(5);
    let mut sizes_used = std::collections::BTreeSet::new();
    let mut cases = 0;
    for case in 0..40u32 {
        // A sorted list; the listed length and the bound vary, and some samples are not requested.
        let keep = [0.08, 0.3, 0.9, 1.0][case as usize % 4];
        let mut listed: Vec<u32> = (0..LATTICE_POINTS)
            .filter(|_| rng.next_f32() < keep)
            .collect();
        listed.truncate(1 + (rng.next_f32() * 80.0) as usize);
        let state: Vec<u32> = (0..LATTICE_POINTS)
            .map(|_| (rng.next_f32() < 0.75) as u32)
            .collect();
        let requested = case % 2 == 1;
        let bound = if requested {
            listed.len() as u32 + (rng.next_f32() * 20.0) as u32
        } else {
            listed.len() as u32
        };
        let level = GpuLevel {
            work_count: bound,
            requested: requested as u32,
            ..Default::default()
        };
        let control = GpuControl {
            new_sample_count: listed.len() as u32,
            ..Default::default()
        };
        let mut list = listed.clone();
        list.resize(bound.max(1) as usize, 7);
        let buffers = (
            readback::uniform_buffer(ctx, "frame", &frame),
            readback::uniform_buffer(ctx, "level", &level),
            readback::storage_buffer(ctx, "samples", &samples, wgpu::BufferUsages::empty()),
            readback::storage_buffer(ctx, "list", &list, wgpu::BufferUsages::empty()),
            readback::storage_buffer(ctx, "state", &state, wgpu::BufferUsages::empty()),
            readback::storage_buffer(ctx, "control", &[control], wgpu::BufferUsages::empty()),
            readback::storage_buffer(ctx, "tiles", &[tiles, 1, 1, 0], wgpu::BufferUsages::empty()),
        );
        let mut enc = ctx.device.create_command_encoder(&Default::default());
        enc.clear_buffer(&test.block_buffer, 0, None);
        enc.clear_buffer(&test.block_args, 0, None);
        let fill = penumbra::research::gpu::stages::bind::shadow_test::FillBlocks {
            level: buffers.1.as_entire_binding(),
            samples: buffers.2.as_entire_binding(),
            test_list: buffers.3.as_entire_binding(),
            lattice_state: buffers.4.as_entire_binding(),
            control_words: buffers.5.as_entire_binding(),
            blocks: test.block_buffer.as_entire_binding(),
            block_args: test.block_args.as_entire_binding(),
            tile_list: buffers.6.as_entire_binding(),
        };
        test.record_fill(ctx, &mut enc, fill);
        ctx.queue.submit([enc.finish()]);
        let blocks: Vec<GpuTestBlock> = readback::read_buffer(
            ctx,
            &test.block_buffer,
            TEST_SLOTS as u64 * TEST_BLOCK_BYTES,
        )
        .unwrap();
        let args: Vec<u32> =
            readback::read_buffer(ctx, &test.block_args, TEST_SLOTS as u64 * 12).unwrap();
        let slots = twin::shadow_test::fill_blocks(&listed, &state, bound);
        let dispatched = block_slots(bound);
        for (s, ks) in slots.iter().enumerate() {
            if ks.is_empty() {
                continue;
            }
            assert!(
                dispatched.contains(&(s as u32, ks.len() as u32)),
                "case {case}: slot {s} of {} samples is not dispatched as such ({dispatched:?})",
                ks.len()
            );
            sizes_used.insert(ks.len());
            let gpu_ks: Vec<u32> = (0..ks.len()).map(|j| blocks[s].ks[j / 4][j % 4]).collect();
            assert_eq!(&gpu_ks, ks, "case {case} slot {s}: lattice indices");
            for (j, &k) in ks.iter().enumerate() {
                assert_eq!(
                    bytemuck::bytes_of(&blocks[s].samples[j]),
                    bytemuck::bytes_of(&samples[k as usize]),
                    "case {case} slot {s}: sample {j}"
                );
            }
        }
        for &(s, _) in &dispatched {
            let used = !slots[s as usize].is_empty();
            let x = args[3 * s as usize];
            assert_eq!(
                x,
                if used { tiles } else { 0 },
                "case {case} slot {s}: workgroups in x"
            );
            if used {
                assert_eq!(
                    args[3 * s as usize + 1..3 * s as usize + 3],
                    [1, 1],
                    "case {case} slot {s}: workgroups in y, z"
                );
            }
        }
        let total: usize = slots.iter().map(|b| b.len()).sum();
        assert_eq!(
            total,
            listed.iter().filter(|&&k| state[k as usize] != 0).count(),
            "case {case}: samples placed"
        );
        assert!(slots.iter().all(|b| b.len() as u32 <= TEST_BLOCK));
        cases += 1;
    }
    assert_eq!(cases, 40);
    assert_eq!(
        sizes_used.into_iter().collect::<Vec<_>>(),
        [1, 2, 4, 8, 16],
        "every block size was filled"
    );
}

/// reproject_count, neighbourhood, quad_count and subdivide driven one by one, with no scene, frame
/// or method: typed inputs built here (synthetic masks of two soft edges, the quads of a level),
/// one pass at a time, its typed output read back and compared with its twin exactly.
#[test]
fn count_stages_alone_equal_their_twins() {
    use penumbra::research::gpu::readback;
    use penumbra::research::gpu::structs::{GpuControl, GpuFrame, GpuQuad, GpuSample};
    use penumbra::research::methods::adaptive::buffers::{
        AdaptiveBuffers, Level, Shape, CONTROL_BYTES, QUAD_CAPACITY,
    };
    use penumbra::research::methods::adaptive::level_uniform;
    use penumbra::research::stages::{
        neighbourhood::Neighbourhood, quad_count::QuadCount, reproject_count::ReprojectCount,
        subdivide::Subdivide,
    };
    let ctx = common::gpu();
    let (reproject, neighbourhood, quad_count, subdivide) = (
        ReprojectCount::new(ctx).unwrap(),
        Neighbourhood::new(ctx).unwrap(),
        QuadCount::new(ctx).unwrap(),
        Subdivide::new(ctx).unwrap(),
    );
    let run = |record: &dyn Fn(&mut wgpu::CommandEncoder)| {
        let mut enc = ctx.device.create_command_encoder(&Default::default());
        record(&mut enc);
        ctx.queue.submit([enc.finish()]);
    };
    let (mut flagged, mut split, mut compared) = (0u32, 0usize, 0);
    for (seed, (w, h)) in [(1u64, (61u32, 37u32)), (2, (128, 96)), (3, (33, 70))] {
        let e = twin::synthetic::edge_masks(w, h, seed);
        let g = e.gbuffer();
        let geometry = e.geometry.iter().filter(|&&x| x).count() as u32;
        let b = AdaptiveBuffers::new(
            ctx,
            w,
            h,
            &[GpuSample::default(); LATTICE_POINTS as usize],
            false,
            None,
        )
        .unwrap();
        let frame = readback::uniform_buffer(
            ctx,
            "frame",
            &GpuFrame {
                width: w,
                height: h,
                ..Default::default()
            },
        );
        let screen = Screen {
            width: w,
            height: h,
        };
        for (level, spec) in [
            (0u32, "p_m=0"),
            (2, "p_m=3"),
            (3, "p_share=0.002,growth=4"),
            (3, "tol=0.004"),
        ] {
            let p = params(spec);
            // Level 3: two quads in three, so the list is not the whole grid.
            let quads: Vec<GpuQuad> = twin::synthetic::level_quads(level)
                .into_iter()
                .enumerate()
                .filter(|(n, _)| level < 3 || n % 3 != 0)
                .map(|(_, q)| q)
                .collect();
            let n = quads.len() as u32;
            // The level's grid is rendered; geometry pixels come from level 0's count.
            let step = 16 >> level;
            let mut state: Vec<u32> = (0..LATTICE_POINTS)
                .map(|k| ((k % 17) % step == 0 && (k / 17) % step == 0) as u32)
                .collect();
            let mut sample_level = vec![0u32; LATTICE_POINTS as usize];
            let control = GpuControl {
                geometry_pixels: if level == 0 { 0 } else { geometry },
                ..Default::default()
            };
            ctx.queue
                .write_buffer(&b.masks.lit, 0, bytemuck::cast_slice(&e.masks));
            ctx.queue
                .write_buffer(&b.quads[0], 0, bytemuck::cast_slice(&quads));
            ctx.queue
                .write_buffer(&b.control, 0, bytemuck::bytes_of(&control));
            ctx.queue
                .write_buffer(&b.low.per_quad, 0, &[0u8; QUAD_CAPACITY as usize * 4]);
            ctx.queue
                .write_buffer(&b.decisions.lattice_state, 0, bytemuck::cast_slice(&state));
            ctx.queue.write_buffer(
                &b.decisions.sample_level,
                0,
                bytemuck::cast_slice(&sample_level),
            );
            let uniform =
                readback::uniform_buffer(ctx, "level", &level_uniform(&p, b.shape, level, n, 0));
            let lv = Level {
                frame: &frame,
                uniform: &uniform,
                quads: &b.quads[0],
                control: &b.control,
                cur: 0,
                shape: b.shape,
            };
            let case = format!("seed {seed} {w}x{h} level {level} {spec}");

            run(&|enc| reproject.record_dense(ctx, enc, &lv, &b.masks, &b.counts));
            let mut counts: Vec<u32> = readback::read_buffer(
                ctx,
                &b.counts.maps,
                b.shape.counts_bytes_per_quad() * n as u64,
            )
            .unwrap();
            let states: Vec<u32> =
                readback::read_buffer(ctx, &b.counts.word_state, b.shape.counts_bytes_per_quad())
                    .unwrap();
            assert_eq!(
                states,
                twin::reproject_count::word_state(&e.masks, w, h),
                "{case}: reproject_count's word states"
            );
            Shape::dense_counts(&mut counts, &states);
            assert_eq!(
                counts,
                twin::reproject_count::reproject_count(&quads, &e.masks, &g),
                "{case}: reproject_count's comparison maps"
            );
            let control: Vec<u32> = readback::read_buffer(ctx, &b.control, CONTROL_BYTES).unwrap();
            assert_eq!(control[4], geometry, "{case}: geometry pixels");

            run(&|enc| neighbourhood.record_dense(ctx, enc, &lv, &b.counts, &b.low));
            let flags: Vec<u32> =
                readback::read_buffer(ctx, &b.low.flags, b.shape.flags_bytes_per_quad() * n as u64)
                    .unwrap();
            assert_eq!(
                flags,
                twin::neighbourhood::neighbourhood(&counts, &screen, n as usize),
                "{case}: neighbourhood's flags"
            );

            run(&|enc| quad_count.record(ctx, enc, &lv, &b.low, n, None));
            let per_quad: Vec<u32> =
                readback::read_buffer(ctx, &b.low.per_quad, n as u64 * 4).unwrap();
            let words = (h * screen.flag_words_per_row()) as usize;
            assert_eq!(
                per_quad,
                twin::quad_count::quad_count(&flags, words, n as usize),
                "{case}: quad_count's counters"
            );

            run(&|enc| subdivide.record(ctx, enc, &lv, &b.low, &b.quads[1], &b.decisions));
            let at = twin::subdivide::SplitLevel {
                level,
                max_level: p.max_level,
                rule: p.split_rule(level),
                geometry_pixels: geometry,
            };
            let sub =
                twin::subdivide::subdivide(&at, &quads, &per_quad, &mut state, &mut sample_level);
            let control: Vec<u32> = readback::read_buffer(ctx, &b.control, CONTROL_BYTES).unwrap();
            // A read-back of nothing is no list.
            let read = |buf: &wgpu::Buffer, bytes: u64| {
                if bytes == 0 {
                    Vec::new()
                } else {
                    readback::read_buffer::<u32>(ctx, buf, bytes).unwrap()
                }
            };
            let next: Vec<GpuQuad> =
                bytemuck::cast_slice(&read(&b.quads[1], control[0] as u64 * 16)).to_vec();
            let mut new = read(&b.decisions.new_samples, control[1] as u64 * 4);
            new.sort_unstable();
            let mut twin_new = sub.new_samples.clone();
            twin_new.sort_unstable();
            assert_eq!(
                sorted_quads(&next),
                sorted_quads(&sub.next_quads),
                "{case}: subdivide's quads"
            );
            assert_eq!(new, twin_new, "{case}: subdivide's new samples");
            let gpu_level: Vec<u32> =
                readback::read_buffer(ctx, &b.decisions.sample_level, LATTICE_POINTS as u64 * 4)
                    .unwrap();
            assert_eq!(gpu_level, sample_level, "{case}: sample levels");
            let split_base: Vec<u32> =
                readback::read_buffer(ctx, &b.decisions.split_base, n as u64 * 4).unwrap();
            let split_gpu: Vec<bool> = split_base.iter().map(|&s| s != u32::MAX).collect();
            let split_cpu: Vec<bool> = sub.split_base.iter().map(|&s| s != u32::MAX).collect();
            assert_eq!(split_gpu, split_cpu, "{case}: split decisions");
            flagged += per_quad.iter().sum::<u32>();
            split += split_cpu.iter().filter(|&&s| s).count();
            compared += 1;
        }
    }
    println!("{compared} levels driven stage by stage: {flagged} low-quality pixels, {split} quads split");
    assert_eq!(compared, 12);
    // The inputs exercised the stages: flags were raised and quads split, not all of them.
    assert!(
        flagged > 100 && split > 10,
        "too little happened: {flagged} low-quality pixels, {split} splits"
    );
}

/// compact (`main`) and then probe (`begin`, `main`) driven alone under scope = local: synthetic
/// items over the quads of a level (counts only at the items' pixels, as reproject_count `list`
/// leaves them), every other quad split; the next items, probes, V's integer sums, and then the
/// probes' expanded items and lit shares compared with their twins exactly (as sets: the GPU
/// appends in any order).
#[test]
fn local_stages_alone_equal_their_twins() {
    use penumbra::research::gpu::readback;
    use penumbra::research::gpu::structs::{GpuControl, GpuFrame, GpuSample};
    use penumbra::research::methods::adaptive::buffers::{AdaptiveBuffers, Level, CONTROL_BYTES};
    use penumbra::research::methods::adaptive::level_uniform;
    use penumbra::research::render::gbuffer::GBufferPass;
    use penumbra::research::stages::{
        compact::{Compact, CompactInputs},
        probe::Probe,
    };
    use twin::probe::PROBE_LIT;
    let ctx = common::gpu();
    let (compact, probe) = (Compact::new(ctx).unwrap(), Probe::new(ctx).unwrap());
    let run = |record: &dyn Fn(&mut wgpu::CommandEncoder)| {
        let mut enc = ctx.device.create_command_encoder(&Default::default());
        record(&mut enc);
        ctx.queue.submit([enc.finish()]);
    };
    let read = |buf: &wgpu::Buffer, words: u32| {
        if words == 0 {
            Vec::new()
        } else {
            readback::read_buffer::<u32>(ctx, buf, words as u64 * 4).unwrap()
        }
    };
    let pairs = |v: &[u32]| -> Vec<(u32, u32)> {
        let mut p: Vec<_> = v.chunks_exact(2).map(|c| (c[0], c[1])).collect();
        p.sort_unstable();
        p
    };
    let sorted = |v: &[(u32, u32)]| {
        let mut v = v.to_vec();
        v.sort_unstable();
        v
    };
    let p = params("p_m=0");
    let (
        mut refined,
        mut probes_lit,
        mut probes_unlit,
        mut shares,
        mut expanded,
        mut probe_shares,
        mut compared,
    ) = (0, 0, 0, 0, 0, 0, 0);
    for (seed, (w, h)) in [(4u64, (48u32, 40u32)), (5, (64, 64))] {
        let e = twin::synthetic::edge_masks(w, h, seed);
        let g = e.gbuffer();
        let b = AdaptiveBuffers::new(
            ctx,
            w,
            h,
            &[GpuSample::default(); LATTICE_POINTS as usize],
            true,
            None,
        )
        .unwrap();
        // compact `main` binds the G-buffer but reads it only in `main_rects`.
        let gb = GBufferPass::allocate(ctx, w, h).unwrap();
        let frame = readback::uniform_buffer(
            ctx,
            "frame",
            &GpuFrame {
                width: w,
                height: h,
                ..Default::default()
            },
        );
        let screen = Screen {
            width: w,
            height: h,
        };
        let words = (h * screen.words_per_row()) as usize;
        for level in [0u32, 1, 2] {
            let case = format!("seed {seed} {w}x{h} level {level}");
            let quads = twin::synthetic::level_quads(level);
            let n = quads.len() as u32;
            // Every other quad splits.
            let (split_base, next_quads) = twin::synthetic::split(&quads, |q| q % 2 == 0);
            // Items: each geometry pixel in about two quads of three (in 4x4 blocks), so the halo
            // sees both evaluated and unevaluated neighbours.
            let items: Vec<(u32, u32)> = (0..w * h)
                .filter(|&px| e.geometry[px as usize])
                .flat_map(|px| {
                    (0..n)
                        .filter(move |q| n == 1 || (px % w / 4 + px / w / 4 + q) % 3 != 0)
                        .map(move |q| (px, q))
                })
                .collect();
            let dense = twin::reproject_count::reproject_count(&quads, &e.masks, &g);
            let mut counts = vec![0u32; n as usize * words];
            for &(px, q) in &items {
                let (x, y) = (px % w, px / w);
                let at = q as usize * words + (y * screen.words_per_row() + x / 4) as usize;
                counts[at] |= dense[at] & (0xff << ((x & 3) * 8));
            }
            let fixed: Vec<u32> = (0..w * h).map(|px| px % 5).collect();
            let flat: Vec<u32> = items.iter().flat_map(|&(a, b)| [a, b]).collect();
            ctx.queue
                .write_buffer(&b.items.items[0], 0, bytemuck::cast_slice(&flat));
            ctx.queue
                .write_buffer(&b.items.total, 0, bytemuck::bytes_of(&(items.len() as u32)));
            ctx.queue.write_buffer(
                &b.items.list_args,
                0,
                bytemuck::cast_slice(&[(items.len() as u32).div_ceil(64), 1, 1]),
            );
            ctx.queue
                .write_buffer(&b.counts.maps, 0, bytemuck::cast_slice(&counts));
            ctx.queue.write_buffer(
                &b.decisions.split_base,
                0,
                bytemuck::cast_slice(&split_base),
            );
            ctx.queue
                .write_buffer(&b.quads[0], 0, bytemuck::cast_slice(&quads));
            ctx.queue
                .write_buffer(&b.quads[1], 0, bytemuck::cast_slice(&next_quads));
            ctx.queue
                .write_buffer(&b.control, 0, bytemuck::bytes_of(&GpuControl::default()));
            ctx.queue
                .write_buffer(&b.items.visibility_fixed, 0, bytemuck::cast_slice(&fixed));
            let uniform =
                readback::uniform_buffer(ctx, "level", &level_uniform(&p, b.shape, level, n, 0));
            let lv = Level {
                frame: &frame,
                uniform: &uniform,
                quads: &b.quads[0],
                control: &b.control,
                cur: 0,
                shape: b.shape,
            };
            run(&|enc| {
                compact.record_main(
                    ctx,
                    enc,
                    &lv,
                    &gb,
                    &CompactInputs {
                        counts: &b.counts,
                        decisions: &b.decisions,
                        next_quads: &b.quads[1],
                        samples: &b.samples,
                        items: &b.items,
                        footprints: &b.footprints,
                    },
                    false,
                )
            });

            let mut twin_fixed = fixed.clone();
            let out = twin::compact::compact(
                &screen,
                level,
                p.max_level,
                &items,
                &counts,
                &split_base,
                &mut twin_fixed,
            );
            let control = read(&b.control, (CONTROL_BYTES / 4) as u32);
            assert_eq!(control[2], 0, "{case}: compact overflowed");
            assert_eq!(
                pairs(&read(&b.items.items[1], control[3] * 2)),
                sorted(&out.next_items),
                "{case}: compact's next items"
            );
            let gpu_probes: Vec<(u32, u32)> = pairs(&read(&b.items.probes, control[5] * 2));
            let twin_probes: Vec<(u32, u32)> = out
                .probes
                .iter()
                .map(|&(px, base, lit)| (px, base | if lit { PROBE_LIT } else { 0 }))
                .collect();
            assert_eq!(gpu_probes, sorted(&twin_probes), "{case}: compact's probes");
            assert_eq!(
                read(&b.items.visibility_fixed, w * h),
                twin_fixed,
                "{case}: compact's integer sums"
            );
            refined += out.next_items.len() / 4;
            probes_lit += out.probes.iter().filter(|x| x.2).count();
            probes_unlit += out.probes.iter().filter(|x| !x.2).count();
            shares += fixed
                .iter()
                .zip(&twin_fixed)
                .filter(|(a, b)| a != b)
                .count();

            // probe, one level down: the compacted probes over the children, with the centre sample
            // of every third probe's pixel flipped so that some probes disagree and expand.
            let mut masks = e.masks.clone();
            for &(px, base, _) in out.probes.iter().step_by(3) {
                let k = twin::probe_point(&next_quads[base as usize], 2);
                masks[(px * 10 + k / 32) as usize] ^= 1 << (k % 32);
            }
            let encoded: Vec<u32> = twin_probes.iter().flat_map(|&(a, b)| [a, b]).collect();
            ctx.queue
                .write_buffer(&b.masks.lit, 0, bytemuck::cast_slice(&masks));
            ctx.queue
                .write_buffer(&b.quads[0], 0, bytemuck::cast_slice(&next_quads));
            ctx.queue
                .write_buffer(&b.items.probes, 0, bytemuck::cast_slice(&encoded));
            ctx.queue.write_buffer(
                &b.control,
                0,
                bytemuck::bytes_of(&GpuControl {
                    probe_count: out.probes.len() as u32,
                    ..Default::default()
                }),
            );
            let uniform = readback::uniform_buffer(
                ctx,
                "level",
                &level_uniform(&p, b.shape, level + 1, next_quads.len() as u32, 0),
            );
            let lv = Level {
                frame: &frame,
                uniform: &uniform,
                quads: &b.quads[0],
                control: &b.control,
                cur: 1,
                shape: b.shape,
            };
            run(&|enc| {
                probe.record_begin(ctx, enc, &uniform, &b.control, &b.items);
                probe.record(ctx, enc, &lv, &b.masks, &b.items);
            });
            let mut twin_items = Vec::new();
            let before = twin_fixed.clone();
            twin::probe::probe(
                &out.probes,
                &next_quads,
                &masks,
                level + 1,
                p.max_level,
                &mut twin_items,
                &mut twin_fixed,
            );
            let control = read(&b.control, (CONTROL_BYTES / 4) as u32);
            assert_eq!(
                (control[2], control[5]),
                (0, 0),
                "{case}: probe overflowed or did not restart the probe counter"
            );
            assert_eq!(
                read(&b.items.probe_total, 1),
                [out.probes.len() as u32],
                "{case}: probe begin's count"
            );
            assert_eq!(
                pairs(&read(&b.items.items[1], control[3] * 2)),
                sorted(&twin_items),
                "{case}: probe's items"
            );
            assert_eq!(
                read(&b.items.visibility_fixed, w * h),
                twin_fixed,
                "{case}: probe's integer sums"
            );
            expanded += twin_items.len() / 4;
            probe_shares += before
                .iter()
                .zip(&twin_fixed)
                .filter(|(a, b)| a != b)
                .count();
            compared += 1;
        }
    }
    println!("{compared} levels: compact refined {refined} items, made {probes_lit} lit and {probes_unlit} unlit probes, added {shares} shares; probe expanded {expanded}, added {probe_shares} shares");
    assert_eq!(compared, 6);
    // Every branch of both kernels ran, and the probes' three outcomes all happened.
    assert!(
        refined > 100 && probes_lit > 100 && probes_unlit > 100 && shares > 100,
        "compact: too little happened"
    );
    assert!(
        expanded > 50 && probe_shares > 50 && expanded + probe_shares < probes_lit + probes_unlit,
        "probe: too little happened"
    );
}

/// weights driven alone: random quadtrees down to level 4, each level's leaves appended by
/// `leaves_of_level` from its quads and split decisions, then `main`: the integer numerators equal
/// `lattice_numerators` and ŵ equals `sample_weights` bit for bit, for the level, area and Coons rules.
#[test]
fn weights_alone_equal_their_twin() {
    use penumbra::research::gpu::readback;
    use penumbra::research::gpu::structs::{GpuQuad, GpuSample};
    use penumbra::research::methods::adaptive::buffers::{AdaptiveBuffers, NO_SPLIT};
    use penumbra::research::methods::adaptive::{
        lattice_numerators, level_uniform, sample_weights, LevelReport,
    };
    use penumbra::research::stages::weights::{WeightsPass, RULE_AREA, RULE_COONS, RULE_LEVEL};
    let ctx = common::gpu();
    let b = AdaptiveBuffers::new(
        ctx,
        32,
        32,
        &[GpuSample::default(); LATTICE_POINTS as usize],
        false,
        None,
    )
    .unwrap();
    let run = |record: &dyn Fn(&mut wgpu::CommandEncoder)| {
        let mut enc = ctx.device.create_command_encoder(&Default::default());
        record(&mut enc);
        ctx.queue.submit([enc.finish()]);
    };
    let mut rng = common::Lcg(11);
    let (mut trees, mut deepest, mut leaves, mut negative) = (0, 0, 0, 0);
    for (spec, rule) in [
        ("weights=level", RULE_LEVEL),
        ("weights=area", RULE_AREA),
        ("weights=coons", RULE_COONS),
    ] {
        let p = params(spec);
        let pass = WeightsPass::new(ctx, rule).unwrap();
        for tree in 0..6 {
            let mut levels = Vec::new();
            let mut quads = vec![GpuQuad {
                i: 0,
                j: 0,
                size: 16,
                parent: u32::MAX,
            }];
            let mut state = vec![0u32; LATTICE_POINTS as usize];
            let mut sample_level = vec![0u32; LATTICE_POINTS as usize];
            run(&|enc| pass.record_begin(enc));
            for level in 0..=4u32 {
                for quad in &quads {
                    for c in 0..4 {
                        let k = twin::quad_corner(quad, c) as usize;
                        state[k] = 1;
                        sample_level[k] = sample_level[k].max(level);
                    }
                }
                let (split_base, next) = twin::synthetic::split(&quads, |_| {
                    level < 4 && rng.next_f32() < [0.95, 0.6, 0.45, 0.35][level as usize]
                });
                // Each level's leaves are appended before the next level's quads take the buffers.
                ctx.queue
                    .write_buffer(&b.quads[0], 0, bytemuck::cast_slice(&quads));
                ctx.queue.write_buffer(
                    &b.decisions.split_base,
                    0,
                    bytemuck::cast_slice(&split_base),
                );
                let uniform = readback::uniform_buffer(
                    ctx,
                    "level",
                    &level_uniform(&p, b.shape, level, quads.len() as u32, 0),
                );
                run(&|enc| pass.record_leaves(ctx, enc, &uniform, &b.quads[0], &b.decisions));
                leaves += split_base.iter().filter(|&&s| s == NO_SPLIT).count();
                deepest = deepest.max(level);
                levels.push(LevelReport {
                    level,
                    quads: std::mem::take(&mut quads),
                    split_base,
                    evaluated: true,
                    ..Default::default()
                });
                quads = next;
                if quads.is_empty() {
                    break;
                }
            }
            ctx.queue
                .write_buffer(&b.decisions.lattice_state, 0, bytemuck::cast_slice(&state));
            ctx.queue.write_buffer(
                &b.decisions.sample_level,
                0,
                bytemuck::cast_slice(&sample_level),
            );
            run(&|enc| pass.record(ctx, enc, &b.decisions, &b.weights));
            let rendered: Vec<u32> = (0..LATTICE_POINTS)
                .filter(|&k| state[k as usize] != 0)
                .collect();
            let numerators: Vec<i32> =
                readback::read_buffer(ctx, &pass.numerators, LATTICE_POINTS as u64 * 4).unwrap();
            let twin_numerators = lattice_numerators(&p, &levels, &sample_level, &rendered);
            let numerators: Vec<i64> = numerators.iter().map(|&x| x as i64).collect();
            assert_eq!(
                numerators, twin_numerators,
                "{spec} tree {tree}: numerators"
            );
            let weights: Vec<f32> =
                readback::read_buffer(ctx, &b.weights, LATTICE_POINTS as u64 * 4).unwrap();
            let bits = |w: &[f32]| w.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(
                bits(&weights),
                bits(&sample_weights(&p, &levels, &sample_level, &rendered)),
                "{spec} tree {tree}: weights"
            );
            negative += twin_numerators.iter().filter(|&&x| x < 0).count();
            trees += 1;
        }
    }
    println!("{trees} quadtrees, {leaves} leaves, deepest level {deepest}, {negative} negative Coons numerators: weights equal their twin bit for bit");
    assert_eq!(trees, 18);
    assert!(
        deepest == 4 && leaves > 100,
        "the quadtrees were too shallow: {leaves} leaves, deepest level {deepest}"
    );
}

/// cull driven alone: a random scene uploaded (no G-buffer, frame or method), the lattice's sample
/// views, and synthetic culling tiles (a disc of tiles per map with random depth limits; one map
/// with every tile infinite, as level 0's corners); each slot's kept index triples equal the twin's
/// exactly (as a multiset: the kernel appends in any order), and its draw arguments count them.
#[test]
fn cull_alone_equals_its_twin() {
    use penumbra::research::gpu::readback;
    use penumbra::research::gpu::structs::GpuSample;
    use penumbra::research::methods::adaptive::buffers::{CULL_TILES, LATTICE_SIDE};
    use penumbra::research::render::SceneGpu;
    use penumbra::research::scene::light::sample_view;
    use penumbra::research::stages::cull::{cull_face, Cull, CullBatch, ARGS_WORDS};
    let ctx = common::gpu();
    let p = params("p_m=0");
    let mut rng = common::Lcg(29);
    let (mut kept_all, mut culled_away, mut slots_checked) = (0usize, 0usize, 0);
    for seed in [7u64, 23] {
        let sc = scene(seed);
        let scene_gpu = SceneGpu::upload(ctx, &sc);
        let fr = frame_uniform(&sc);
        let samples: Vec<GpuSample> = (0..LATTICE_POINTS)
            .map(|k| {
                let y = sc.light.point(
                    p.light_coord(k % LATTICE_SIDE),
                    p.light_coord(k / LATTICE_SIDE),
                );
                sample_view(&sc.light, y, &sc.bounds, sc.render.shadow_map_size, k)
            })
            .collect();
        // Tiles only up to the largest lattice index culled for: the kernel reads no further.
        let ks = [0u32, 8, 16, 18, 26, 34];
        let words = CULL_TILE_WORDS as usize;
        let mut tiles = vec![0u32; (ks.iter().max().unwrap() + 1) as usize * words];
        for (n, &k) in ks.iter().enumerate() {
            let mine = &mut tiles[k as usize * words..(k as usize + 1) * words];
            if n == 0 {
                mine.fill(f32::INFINITY.to_bits());
                continue;
            }
            let (cx, cy, r) = (
                rng.range(40.0, 216.0),
                rng.range(40.0, 216.0),
                rng.range(20.0, 90.0),
            );
            for (t, word) in mine.iter_mut().enumerate() {
                let (x, y) = (
                    (t as u32 % CULL_TILES) as f32,
                    (t as u32 / CULL_TILES) as f32,
                );
                if (x - cx).powi(2) + (y - cy).powi(2) < r * r {
                    *word = rng.range(0.3, 1.0).to_bits();
                }
            }
        }
        let cull = Cull::new(ctx, &sc, &scene_gpu, ks.len() as u32)
            .unwrap()
            .expect("lavapipe culls (indirect first instance)");
        let samples_buffer =
            readback::storage_buffer(ctx, "samples", &samples, wgpu::BufferUsages::empty());
        let frame = readback::uniform_buffer(ctx, "frame", &fr);
        let tiles_buffer =
            readback::storage_buffer(ctx, "tiles", &tiles, wgpu::BufferUsages::empty());
        let mut enc = ctx.device.create_command_encoder(&Default::default());
        cull.record(
            ctx,
            &mut enc,
            &frame,
            &scene_gpu,
            &CullBatch {
                samples: &samples_buffer,
                tiles: &tiles_buffer,
            },
            &ks,
        );
        ctx.queue.submit([enc.finish()]);
        let stride = scene_gpu.index_count as usize;
        let args: Vec<u32> =
            readback::read_buffer(ctx, &cull.args, ks.len() as u64 * ARGS_WORDS as u64 * 4)
                .unwrap();
        let culled: Vec<u32> =
            readback::read_buffer(ctx, &cull.culled, (ks.len() * stride) as u64 * 4).unwrap();
        let order = &scene_gpu.shadow_order;
        let positions: Vec<glam::Vec3> = sc
            .vertices
            .iter()
            .map(|v| glam::Vec3::from(v.position))
            .collect();
        let twin_kept = twin::cull::cull(
            &fr,
            &samples,
            &tiles,
            &positions,
            order,
            &ks,
            cull_face(sc.render.cull),
        );
        let triples = |v: &[u32]| {
            let mut t: Vec<[u32; 3]> = v.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
            t.sort_unstable();
            t
        };
        for (n, (&k, kept)) in ks.iter().zip(&twin_kept).enumerate() {
            let count = args[n * ARGS_WORDS as usize] as usize;
            assert_eq!(
                count,
                kept.len() * 3,
                "seed {seed} map {k}: indices in the draw arguments"
            );
            let gpu = triples(&culled[n * stride..n * stride + count]);
            let twin: Vec<u32> = kept
                .iter()
                .flat_map(|&t| order[t as usize * 3..t as usize * 3 + 3].iter().copied())
                .collect();
            assert_eq!(gpu, triples(&twin), "seed {seed} map {k}: kept triangles");
            kept_all += kept.len();
            culled_away += stride / 3 - kept.len();
            slots_checked += 1;
        }
        // The disc maps keep a part of the mesh: culling decided something for them.
        assert!(
            twin_kept[1..]
                .iter()
                .any(|t| !t.is_empty() && t.len() < stride / 3),
            "seed {seed}: no map kept part of the mesh"
        );
    }
    println!("{slots_checked} culled maps equal their twin: {kept_all} triangles kept, {culled_away} culled");
    assert_eq!(slots_checked, 12);
    assert!(
        kept_all > 100 && culled_away > 100,
        "too little happened: {kept_all} kept, {culled_away} culled"
    );
}

/// shadow_test (scope = global) driven alone: a random scene's G-buffer and geometry tiles, 36
/// lattice samples rasterized into one map array through the shadow raster pass, no frame or
/// method. Two calls OR into the same masks, the first of 31 samples (every block size:
/// 16 + 8 + 4 + 2 + 1), the second of 5; the masks equal the twin's bit for bit after each.
#[test]
fn shadow_test_alone_equals_its_twin() {
    use penumbra::research::gpu::readback;
    use penumbra::research::gpu::structs::GpuSample;
    use penumbra::research::methods::adaptive::buffers::{AdaptiveBuffers, Requests, LATTICE_SIDE};
    use penumbra::research::render::gbuffer::{self, GBufferPass};
    use penumbra::research::render::shadow_raster::{self, RasterJob, ShadowRasterPass};
    use penumbra::research::render::SceneGpu;
    use penumbra::research::scene::light::sample_view;
    use penumbra::research::stages::shade::ShadePass;
    use penumbra::research::stages::shadow_test::{ShadowTest, TestFrame};
    let ctx = common::gpu();
    let p = params("p_m=0");
    let test = ShadowTest::new(
        ctx,
        penumbra::research::gpu::kernels::MapAccess::Depth,
        false,
    )
    .expect("shadow_test kernels");
    let (mut lit_bits, mut unlit_bits, mut calls) = (0u32, 0u32, 0);
    for seed in [1u64, 23] {
        let sc = Scene::parse(
            &common::random_scene_toml(seed, 48, 128),
            &format!("random-{seed}"),
            None,
            &[],
        )
        .expect("random scene parses");
        let scene_gpu = SceneGpu::upload(ctx, &sc);
        let fr = frame_uniform(&sc);
        let frame = readback::uniform_buffer(ctx, "frame", &fr);
        // Every eighth lattice index: 36 samples, spread over the light.
        let ks: Vec<u32> = (0..LATTICE_POINTS).step_by(8).take(36).collect();
        let mut samples: Vec<GpuSample> = (0..LATTICE_POINTS)
            .map(|k| {
                let y = sc.light.point(
                    p.light_coord(k % LATTICE_SIDE),
                    p.light_coord(k / LATTICE_SIDE),
                );
                sample_view(&sc.light, y, &sc.bounds, sc.render.shadow_map_size, k)
            })
            .collect();
        for (layer, &k) in ks.iter().enumerate() {
            samples[k as usize].layer = layer as u32;
        }
        let b = AdaptiveBuffers::new(ctx, fr.width, fr.height, &samples, false, None).unwrap();
        ctx.queue.write_buffer(
            &b.decisions.lattice_state,
            0,
            bytemuck::cast_slice(&[1u32; LATTICE_POINTS as usize]),
        );
        let g = GBufferPass::allocate(ctx, fr.width, fr.height).unwrap();
        let shade =
            ShadePass::new(ctx, penumbra::research::gpu::kernels::MapAccess::Depth).unwrap();
        let tiles = shade.tile_list(ctx, &g);
        let array = shadow_raster::allocate(ctx, sc.render.shadow_map_size, ks.len() as u32);
        let jobs: Vec<RasterJob> = ks
            .iter()
            .enumerate()
            .map(|(layer, &k)| RasterJob {
                sample: k,
                layer: layer as u32,
                scissor: None,
            })
            .collect();
        let mut enc = ctx.device.create_command_encoder(&Default::default());
        GBufferPass::new(ctx).unwrap().record(
            ctx,
            &mut enc,
            &scene_gpu,
            &gbuffer::camera_uniform(&sc),
            &g,
        );
        shade.record_geometry_tiles(ctx, &mut enc, &frame, &g, &tiles);
        ShadowRasterPass::new(ctx, sc.render.cull)
            .unwrap()
            .record(ctx, &mut enc, &scene_gpu, &b.samples, &array, &jobs);
        enc.clear_buffer(&b.masks.lit, 0, None);
        ctx.queue.submit([enc.finish()]);
        let gcpu = gbuffer::read_back(ctx, &g).unwrap();
        let maps = |k: u32| {
            readback::read_texture::<f32>(
                ctx,
                &array.texture,
                ks.iter().position(|&x| x == k).unwrap() as u32,
                4,
            )
            .unwrap()
        };
        let rq = Requests {
            samples: &b.samples,
            decisions: &b.decisions,
            control: &b.control,
        };
        let mut masks = vec![0u32; (fr.width * fr.height * 10) as usize];
        for list in [&ks[..31], &ks[31..]] {
            let mut enc = ctx.device.create_command_encoder(&Default::default());
            test.record(
                ctx,
                &mut enc,
                &TestFrame {
                    frame: &frame,
                    gbuffer: &g,
                    tiles: &tiles,
                    rq,
                    out: &b.masks,
                },
                &array.array_view,
                list,
            );
            ctx.queue.submit([enc.finish()]);
            twin::shadow_test::shadow_test(&fr, &samples, &maps, &gcpu, list, &mut masks);
            let gpu: Vec<u32> =
                readback::read_buffer(ctx, &b.masks.lit, b.shape.mask_bytes()).unwrap();
            let wrong: u32 = masks
                .iter()
                .zip(&gpu)
                .map(|(a, b)| (a ^ b).count_ones())
                .sum();
            assert_eq!(
                wrong,
                0,
                "seed {seed}, a list of {}: shadow_test differs in {wrong} bits",
                list.len()
            );
            calls += 1;
        }
        // Lit and unlit (pixel, sample) pairs both occur among the geometry pixels.
        for px in (0..gcpu.position.len()).filter(|&i| gcpu.is_geometry(i)) {
            let lit: u32 = ks
                .iter()
                .map(|&k| (masks[px * 10 + k as usize / 32] >> (k % 32)) & 1)
                .sum();
            lit_bits += lit;
            unlit_bits += ks.len() as u32 - lit;
        }
    }
    println!("{calls} shadow_test calls equal their twin: {lit_bits} lit and {unlit_bits} unlit (pixel, sample) pairs");
    assert_eq!(calls, 4);
    assert!(
        lit_bits > 1000 && unlit_bits > 1000,
        "too little happened: {lit_bits} lit, {unlit_bits} unlit"
    );
}

/// subdivide with the hysteresis (`hold`, docs/reuse.md) driven alone: every level's quads with
/// counts around the threshold, a random half of the quad nodes held (split the frame before),
/// under a count rule and a share rule; the split decisions, children and new samples equal the
/// twin's exactly, and both the margin and the held bits decide some quads.
#[test]
fn subdivide_with_hold_equals_its_twin() {
    use penumbra::research::gpu::readback;
    use penumbra::research::gpu::structs::{GpuControl, GpuFrame, GpuQuad, GpuSample};
    use penumbra::research::methods::adaptive::buffers::{
        AdaptiveBuffers, Level, CONTROL_BYTES, QUAD_CAPACITY,
    };
    use penumbra::research::methods::adaptive::level_uniform;
    use penumbra::research::stages::adaptive_buffers::{quad_node, HELD_WORDS, QUAD_NODES};
    use penumbra::research::stages::subdivide::Subdivide;
    use penumbra::research::stages::twin::subdivide::{subdivide_held, Held, SplitLevel};
    let ctx = common::gpu();
    let subdivide = Subdivide::new(ctx).unwrap();
    let b = AdaptiveBuffers::new(
        ctx,
        16,
        16,
        &[GpuSample::default(); LATTICE_POINTS as usize],
        false,
        None,
    )
    .unwrap();
    let frame = readback::uniform_buffer(
        ctx,
        "frame",
        &GpuFrame {
            width: 16,
            height: 16,
            ..Default::default()
        },
    );
    let mut rng = common::Lcg(57);
    let (mut by_margin, mut by_held, mut cases) = (0, 0, 0);
    for spec in ["p_m=3,hold=5", "p_share=0.01,hold=7"] {
        let p = params(spec);
        for level in 0..4u32 {
            let quads: Vec<GpuQuad> =
                penumbra::research::stages::twin::synthetic::level_quads(level);
            let n = quads.len() as u32;
            // Counts from 0 to 14 around either rule's threshold (3, or 0.01 x 400 pixels).
            let counts: Vec<u32> = (0..n).map(|_| (rng.next_f32() * 15.0) as u32).collect();
            let mut bits = vec![0u32; HELD_WORDS as usize];
            for node in 0..QUAD_NODES {
                if rng.next_f32() < 0.5 {
                    bits[(node / 32) as usize] |= 1 << (node % 32);
                }
            }
            let step = 16 >> level;
            let mut state: Vec<u32> = (0..LATTICE_POINTS)
                .map(|k| ((k % 17) % step == 0 && (k / 17) % step == 0) as u32)
                .collect();
            let mut sample_level = vec![0u32; LATTICE_POINTS as usize];
            ctx.queue
                .write_buffer(&b.quads[0], 0, bytemuck::cast_slice(&quads));
            ctx.queue.write_buffer(
                &b.control,
                0,
                bytemuck::bytes_of(&GpuControl {
                    geometry_pixels: 400,
                    ..Default::default()
                }),
            );
            let mut per_quad = counts.clone();
            per_quad.resize(QUAD_CAPACITY as usize, 0);
            ctx.queue
                .write_buffer(&b.low.per_quad, 0, bytemuck::cast_slice(&per_quad));
            ctx.queue
                .write_buffer(&b.decisions.lattice_state, 0, bytemuck::cast_slice(&state));
            ctx.queue.write_buffer(
                &b.decisions.sample_level,
                0,
                bytemuck::cast_slice(&sample_level),
            );
            ctx.queue
                .write_buffer(&b.decisions.held, 0, bytemuck::cast_slice(&bits));
            let uniform =
                readback::uniform_buffer(ctx, "level", &level_uniform(&p, b.shape, level, n, 0));
            let lv = Level {
                frame: &frame,
                uniform: &uniform,
                quads: &b.quads[0],
                control: &b.control,
                cur: 0,
                shape: b.shape,
            };
            let mut enc = ctx.device.create_command_encoder(&Default::default());
            subdivide.record(ctx, &mut enc, &lv, &b.low, &b.quads[1], &b.decisions);
            ctx.queue.submit([enc.finish()]);
            let at = SplitLevel {
                level,
                max_level: p.max_level,
                rule: p.split_rule(level),
                geometry_pixels: 400,
            };
            let held = Held {
                bits: bits.clone(),
                hold: p.hold,
            };
            let sub = subdivide_held(&at, &held, &quads, &counts, &mut state, &mut sample_level);
            let free = subdivide_held(
                &at,
                &Held::every(),
                &quads,
                &counts,
                &mut state.clone(),
                &mut sample_level.clone(),
            );
            let split_base: Vec<u32> =
                readback::read_buffer(ctx, &b.decisions.split_base, n as u64 * 4).unwrap();
            let gpu: Vec<bool> = split_base.iter().map(|&s| s != u32::MAX).collect();
            let twin: Vec<bool> = sub.split_base.iter().map(|&s| s != u32::MAX).collect();
            let case = format!("{spec} level {level}");
            assert_eq!(gpu, twin, "{case}: split decisions");
            let control: Vec<u32> = readback::read_buffer(ctx, &b.control, CONTROL_BYTES).unwrap();
            let next: Vec<GpuQuad> = if control[0] == 0 {
                Vec::new()
            } else {
                bytemuck::cast_slice(
                    &readback::read_buffer::<u32>(ctx, &b.quads[1], control[0] as u64 * 16)
                        .unwrap(),
                )
                .to_vec()
            };
            assert_eq!(
                sorted_quads(&next),
                sorted_quads(&sub.next_quads),
                "{case}: children"
            );
            let mut new: Vec<u32> = if control[1] == 0 {
                Vec::new()
            } else {
                readback::read_buffer(ctx, &b.decisions.new_samples, control[1] as u64 * 4).unwrap()
            };
            new.sort_unstable();
            assert_eq!(new, sub.new_samples, "{case}: new samples");
            for (q, quad) in quads.iter().enumerate() {
                let node = quad_node(quad.i, quad.j, quad.size);
                let was = (bits[(node / 32) as usize] >> (node % 32)) & 1 == 1;
                let without = free.split_base[q] != u32::MAX;
                if without && !twin[q] {
                    assert!(!was, "{case}: quad {q} held and still merged by the margin");
                    by_margin += 1;
                }
                if twin[q] && was {
                    by_held += 1;
                }
            }
            cases += 1;
        }
    }
    assert_eq!(cases, 8);
    assert!(
        by_margin > 5 && by_held > 5,
        "too little decided by the hysteresis: {by_margin} by the margin, {by_held} held"
    );
}
