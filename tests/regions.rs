//! The `regions` method: its decision kernels equal their CPU twins, every region forced to one
//! grid gives regular's V bit for bit, and bad parameters are refused with one message.

mod common;
use penumbra::research::frame::{frame_uniform, FrameOptions, Renderer};
use penumbra::research::gpu::timing::TimingMode;
use penumbra::research::methods::regions::RegionsBuffers;
use penumbra::research::methods::Method;
use penumbra::research::scene::Scene;
use penumbra::research::stages::regions::{unordered, REGION_WORDS};
use penumbra::research::stages::twin;

fn visibility(sc: &Scene, spec: &str) -> Vec<f32> {
    let method = Method::parse(spec, &[]).unwrap();
    let mut renderer = Renderer::new(common::gpu(), sc, &method).expect("renderer");
    renderer
        .frame(FrameOptions {
            mode: TimingMode::Frame,
            pictures: false,
        })
        .expect("frame")
        .visibility
}

#[test]
fn forced_uniform_regions_equal_the_centred_grid() {
    // Every region forced to N×N on maps of one size over the whole scene: each class's tiles
    // together are the geometry tiles, each pixel adds the same samples in the same order.
    for (seed, n, size) in [(3u64, 3u32, 64u32), (11, 4, 128), (29, 5, 128)] {
        let sc = Scene::parse(
            &common::random_scene_toml(seed, 48, size),
            "random",
            None,
            &[],
        )
        .unwrap();
        let grid = visibility(&sc, &format!("regular:n={n},layout=centred"));
        let forced = visibility(&sc, &format!("regions:force={n},force_size={size}"));
        let shadowed = grid.iter().filter(|&&v| v > 0.0 && v < 1.0).count();
        println!("seed {seed}: n = {n}, {size}², {shadowed} penumbra pixels");
        assert!(
            shadowed > 20,
            "seed {seed}: too few penumbra pixels ({shadowed}) for the test to show anything"
        );
        let differ = grid
            .iter()
            .zip(&forced)
            .filter(|(a, b)| a.to_bits() != b.to_bits())
            .count();
        assert_eq!(differ, 0, "seed {seed}: {differ} pixels of regions:force={n} differ from regular:n={n},layout=centred");
    }
}

#[test]
fn decision_kernels_equal_their_twins() {
    let ctx = common::gpu();
    let mut classes_seen = Vec::new();
    for seed in [5u64, 17, 23] {
        let sc = Scene::parse(
            &common::random_scene_toml(seed, 48, 128),
            "random",
            None,
            &[],
        )
        .unwrap();
        // The plan alone (certify = off): its buffers, groups and read-backs are what the twins
        // check; the certified classes are tests/regions_certified.rs's.
        let method = Method::parse(
            "regions:target=0.01,region=8,centre_size=64,certify=off",
            &[],
        )
        .unwrap();
        let options = FrameOptions {
            mode: TimingMode::Frame,
            pictures: true,
        };
        let (r, b): (_, RegionsBuffers) = common::inspected(ctx, &sc, &method, options);
        let p = &b.params;
        // measure: each region's pixel counts and box exactly, its footprint and penumbra width to
        // float rounding (the GPU may fuse the divisions' multiply-adds).
        // The decision's map is 64 texels a side, the scene's 128: measure binds its own map_size.
        assert_eq!(b.centre_size, 64, "seed {seed}: the decision's map side");
        assert_eq!(
            b.map.len(),
            64 * 64,
            "seed {seed}: the decision's map texels"
        );
        let frame = penumbra::research::gpu::structs::GpuFrame {
            map_size: b.centre_size,
            ..frame_uniform(&sc)
        };
        let cpu = twin::regions::measure(&frame, p, &b.sample, &b.map, &r.gbuffer);
        assert_eq!(cpu.len(), b.regions.len());
        let mut worst = 0.0f32;
        for (k, (g, c)) in b
            .regions
            .chunks(REGION_WORDS)
            .zip(cpu.chunks(REGION_WORDS))
            .enumerate()
        {
            assert_eq!(
                &g[..2],
                &c[..2],
                "seed {seed} region {k}: geometry and penumbra pixels"
            );
            assert_eq!(&g[4..], &c[4..], "seed {seed} region {k}: receiver box");
            for w in 2..4 {
                assert_eq!(
                    g[w] == u32::MAX,
                    c[w] == u32::MAX,
                    "seed {seed} region {k}: word {w}"
                );
                if g[w] != u32::MAX {
                    worst = worst.max((unordered(g[w]) / unordered(c[w]) - 1.0).abs());
                }
            }
        }
        assert!(
            worst <= 1e-5,
            "seed {seed}: footprint or width differs from the twin by {worst} (relative)"
        );
        assert_eq!(
            b.totals,
            twin::regions::total(p, &b.regions),
            "seed {seed}: totals"
        );
        // classify, on the GPU's regions and totals: the classes' words and tile lists exactly.
        let (words, lists) =
            twin::regions::classify(p, r.gbuffer.width, &b.regions, b.totals, &b.geometry_tiles);
        assert_eq!(b.classes, words, "seed {seed}: class words");
        for (c, list) in lists.iter().enumerate() {
            assert_eq!(&b.class_list(c), list, "seed {seed}: class {c}'s tiles");
        }
        assert_eq!(
            lists.iter().map(Vec::len).sum::<usize>(),
            b.geometry_tiles.len(),
            "seed {seed}: every geometry tile in one class"
        );
        let used: Vec<u32> = b.records.iter().map(|c| c.decided_n).collect();
        let shaded: Vec<(u32, u32)> = b.records.iter().map(|c| (c.group, c.n)).collect();
        println!("seed {seed}: classes n = {used:?}, (group, n shaded) = {shaded:?}, texel need max rel. diff {worst:e}");
        assert!(r.visibility.iter().all(|v| (0.0..=1.0).contains(v)));
        // A class only joins a group of more samples, and groups are runs of the ladder.
        for (k, c) in b.records.iter().enumerate() {
            assert!(
                c.n >= c.decided_n,
                "seed {seed}: class {} shaded with {} < its {} samples per side",
                c.class,
                c.n,
                c.decided_n
            );
            assert!(
                k == 0 || (c.group, c.class) > (b.records[k - 1].group, b.records[k - 1].class),
                "seed {seed}: records out of order"
            );
        }
        let groups = b.records.last().map_or(0, |c| c.group + 1);
        // A group of several classes shades their lists joined into one.
        for g in 0..groups {
            let members: Vec<usize> = b
                .records
                .iter()
                .filter(|c| c.group == g)
                .map(|c| c.class as usize)
                .collect();
            if members.len() > 1 {
                let mut union: Vec<u32> = members.iter().flat_map(|&c| lists[c].clone()).collect();
                union.sort_unstable();
                assert_eq!(
                    b.group_list(g as usize),
                    union,
                    "seed {seed}: group {g}'s joined tiles (classes {members:?})"
                );
            }
        }
        assert_eq!(
            r.output.syncs,
            1 + groups,
            "seed {seed}: the decision's read-back and one per culled group"
        );
        assert!(
            r.output
                .pictures
                .iter()
                .any(|(name, _)| name == "region_samples.png")
                && r.output
                    .pictures
                    .iter()
                    .any(|(name, _)| name == "region_texels.png")
        );
        classes_seen.push(used.len());
    }
    assert!(
        classes_seen.iter().any(|&c| c >= 2),
        "no scene split into two classes or more: {classes_seen:?}"
    );
}

#[test]
fn bad_parameters_are_refused_with_the_key_and_value() {
    for (spec, want) in [
        (
            "regions:target=0",
            "regions: target = 0 is outside 0.0005..=0.5",
        ),
        (
            "regions:region=12",
            "regions: region = 12 is not a multiple of 8",
        ),
        (
            "regions:max_size=1000",
            "regions: max_size = 1000 is not a power of two",
        ),
        (
            "regions:min_size=512,max_size=256",
            "regions: min_size = 512 is above max_size = 256",
        ),
        (
            "regions:force_size=128",
            "regions: force_size = 128 needs force = N",
        ),
        (
            "regions:force=0",
            "regions: force = `0`: use `off` or samples per side 1..=128",
        ),
        (
            "regions:cull=maybe",
            "regions: cull = `maybe`: use `on`, `off` or `auto`",
        ),
        (
            "regions:merge=yes",
            "regions: merge = `yes`: use `on` or `off`",
        ),
    ] {
        let e = Method::parse(spec, &[])
            .err()
            .unwrap_or_else(|| panic!("{spec} was accepted"));
        assert!(e.to_string().contains(want), "{spec}: {e}");
    }
}

#[test]
fn map_sides_round_up_by_half_octaves() {
    // At most √2 above the side asked for (2× the texels, where a power of two may give 4×).
    use penumbra::research::methods::regions::half_octave;
    assert_eq!(
        [
            half_octave(1024.0),
            half_octave(1025.0),
            half_octave(1448.0),
            half_octave(1449.0),
            half_octave(300.0)
        ],
        [1024, 1456, 1456, 2048, 368]
    );
    assert_eq!(half_octave(f32::INFINITY), 1);
    for want in [20.0f32, 77.0, 500.0, 1000.0, 3000.0] {
        let side = half_octave(want) as f32;
        assert!(
            side >= want && side <= want * 2f32.sqrt() + 16.0,
            "{want} -> {side}"
        );
    }
}

#[test]
fn the_maps_share_of_the_target_sets_the_density() {
    // Three regions: a contact shadow (narrowest penumbra half a pixel wide), a wide penumbra (20
    // pixels) and a lit region; the samples' target is T/√2, as `regions` sets it.
    use penumbra::research::methods::regions::budget::{
        edge_weight, map_density, predicted_map, SAMPLING_SHARE,
    };
    use penumbra::research::stages::regions::{empty_region, ordered, RegionsParams};
    let target = 0.02f32;
    let mut p = RegionsParams {
        region: 16,
        region_count: 3,
        ladder_len: 1,
        max_n: 16,
        target: target * SAMPLING_SHARE,
        ..Default::default()
    };
    p.ladder[0] = 16;
    let mut words = Vec::new();
    for (area, penumbra, foot, width) in [
        (200u32, 40u32, 0.01f32, 0.005f32),
        (256, 200, 0.01, 0.2),
        (256, 0, 0.01, f32::INFINITY),
    ] {
        let mut r = empty_region();
        r[0] = area;
        r[1] = penumbra;
        r[2] = ordered(foot);
        if width.is_finite() {
            r[3] = ordered(width);
        }
        words.extend_from_slice(&r);
    }
    let totals = twin::regions::total(&p, &words);
    let n = twin::regions::samples_of(&p, totals, 256, 200) as f64;
    assert_eq!(
        (n, twin::regions::samples_of(&p, totals, 200, 40)),
        (6.0, 5),
        "the two regions' samples per side"
    );
    let (e, pixels) = edge_weight(&p, &words);
    // Contact: 40 pixels of edge at one footprint a texel, no averaging. Wide: 200/20 = 10 pixels
    // of edge, texels of 20/6 footprints, averaged over 6 columns of samples ((1 + 3/6)/6).
    let want = 40.0 + 10.0 * (20.0 / n) * (1.0 + 3.0 / n) / n;
    assert!(
        (e - want).abs() < 1e-3 * want,
        "edge weight {e}, want {want}"
    );
    assert_eq!(pixels, 712.0);
    // The least density that meets T_m = T/√2, and the floor where that asks for less.
    let d = map_density(e, pixels, target as f64, 2.5);
    assert!(
        (d - e / (6.0 * pixels * 0.0004)).abs() < 1e-6 * d && d > 2.5,
        "density {d}"
    );
    let m = predicted_map(e, pixels, d);
    assert!(
        (m - target as f64 / 2f64.sqrt()).abs() < 1e-6,
        "the maps' error at that density is their share: {m}"
    );
    assert_eq!(
        map_density(e, pixels, 0.5, 2.5),
        2.5,
        "a loose target keeps the lookup's floor"
    );
}

#[test]
fn the_decisions_map_is_twice_the_screen_within_the_scenes_size() {
    let m = |spec: &str| {
        Method::parse(spec, &[])
            .unwrap()
            .as_any()
            .downcast_ref::<penumbra::research::methods::regions::Regions>()
            .cloned()
            .expect("regions")
    };
    let r = m("regions");
    assert_eq!(
        [
            r.centre_side(128, 128, 1024),
            r.centre_side(48, 48, 128),
            r.centre_side(300, 200, 4096),
            r.centre_side(16, 16, 2048),
            r.centre_side(128, 96, 32)
        ],
        [256, 128, 1024, 64, 32]
    );
    assert_eq!(
        m("regions:centre_size=512").centre_side(128, 128, 1024),
        512
    );
    let e = Method::parse("regions:centre_size=300", &[]).expect_err("300 accepted");
    assert!(
        e.to_string()
            .contains("regions: centre_size = 300 is not a power of two"),
        "{e}"
    );
}

#[test]
fn each_group_culled_by_its_own_tiles_keeps_v() {
    // A group's maps are culled from the pixels of its own tiles (footprint `listed`): V equals
    // the uncut frame's bit for bit, and a group's maps keep fewer triangles than the mesh.
    let mut split = 0;
    for seed in [7u64, 19] {
        let sc = Scene::parse(
            &common::random_scene_toml(seed, 128, 256),
            "random",
            None,
            &[],
        )
        .unwrap();
        let spec = "regions:target=0.03,certify=off,max_size=512";
        let run = |cull: &str| {
            let method = Method::parse(&format!("{spec},cull={cull}"), &[]).unwrap();
            let mut renderer = Renderer::new(common::gpu(), &sc, &method).expect("renderer");
            renderer
                .frame(FrameOptions {
                    mode: TimingMode::Frame,
                    pictures: false,
                })
                .expect("frame")
        };
        let (on, off) = (run("on"), run("off"));
        assert_eq!(
            on.visibility, off.visibility,
            "seed {seed}: culling changed V"
        );
        let classes = on.output.record["classes"].as_array().unwrap().clone();
        let triangles = sc.triangle_count() as f64;
        for k in &classes {
            let kept = k["triangles_per_map_mean"].as_f64().unwrap();
            assert!(kept <= triangles, "seed {seed}: {kept} of {triangles}: {k}");
        }
        split += classes
            .iter()
            .filter(|k| k["triangles_per_map_mean"].as_f64().unwrap() < triangles)
            .count();
        println!(
            "seed {seed}: {} classes, {triangles} triangles: {classes:?}",
            classes.len()
        );
    }
    assert!(
        split > 0,
        "no group's maps kept fewer triangles than the mesh"
    );
}
