//! `cull = on` where every geometry pixel tests every map (`regular`, `adaptive` with scope =
//! global): the footprint kernel against its twin, the cull it feeds against the cull twin, and V
//! bit-identical to the unculled frame under both rasters, with fewer triangles per map.

mod common;
use penumbra::research::frame::{frame_uniform, FrameOptions, Renderer};
use penumbra::research::gpu::readback;
use penumbra::research::gpu::timing::TimingMode;
use penumbra::research::methods::adaptive::buffers::CULL_TILE_WORDS;
use penumbra::research::methods::Method;
use penumbra::research::scene::Scene;
use penumbra::research::stages::twin;

/// Footprint over a random scene's G-buffer for 6 samples of the light, then cull from its tiles:
/// the raised tiles equal the twin's (their limits within 4 ulps), and the kept triangles equal
/// the cull twin's exactly.
#[test]
fn footprint_and_its_cull_equal_their_twins() {
    use penumbra::research::gpu::structs::GpuSample;
    use penumbra::research::render::gbuffer::{self, GBufferPass};
    use penumbra::research::render::SceneGpu;
    use penumbra::research::scene::light::sample_view;
    use penumbra::research::stages::cull::{cull_face, Cull, CullBatch, ARGS_WORDS};
    use penumbra::research::stages::footprint::Footprint;
    use penumbra::research::stages::shade::GeometryTiles;
    let ctx = common::gpu();
    let (mut raised, mut kept_all, mut culled_away) = (0usize, 0usize, 0usize);
    for seed in [2u64, 31] {
        let sc = Scene::parse(
            &common::random_scene_toml(seed, 64, 256),
            &format!("random-{seed}"),
            None,
            &[],
        )
        .expect("random scene parses");
        let scene_gpu = SceneGpu::upload(ctx, &sc);
        let fr = frame_uniform(&sc);
        let frame = readback::uniform_buffer(ctx, "frame", &fr);
        let points = [
            (0.0, 0.0),
            (1.0, 0.0),
            (0.5, 0.5),
            (0.0, 1.0),
            (1.0, 1.0),
            (0.25, 0.75),
        ];
        let samples: Vec<GpuSample> = points
            .iter()
            .enumerate()
            .map(|(k, &(s, t))| {
                sample_view(
                    &sc.light,
                    sc.light.point(s, t),
                    &sc.bounds,
                    sc.render.shadow_map_size,
                    k as u32,
                )
            })
            .collect();
        let samples_buffer =
            readback::storage_buffer(ctx, "samples", &samples, wgpu::BufferUsages::empty());
        let g = GBufferPass::allocate(ctx, fr.width, fr.height).unwrap();
        let tiles = readback::zeroed_storage(
            ctx,
            "tiles",
            samples.len() as u64 * CULL_TILE_WORDS as u64 * 4,
        );
        let cull = Cull::new(ctx, &sc, &scene_gpu, samples.len() as u32)
            .unwrap()
            .expect("lavapipe culls (indirect first instance)");
        let slots: Vec<u32> = (0..samples.len() as u32).collect();
        let mut enc = ctx.device.create_command_encoder(&Default::default());
        GBufferPass::new(ctx).unwrap().record(
            ctx,
            &mut enc,
            &scene_gpu,
            &gbuffer::camera_uniform(&sc),
            &g,
        );
        Footprint::new(ctx).unwrap().record(
            ctx,
            &mut enc,
            &frame,
            &g,
            &CullBatch {
                samples: &samples_buffer,
                tiles: &tiles,
            },
            samples.len() as u32,
        );
        cull.record(
            ctx,
            &mut enc,
            &frame,
            &scene_gpu,
            &CullBatch {
                samples: &samples_buffer,
                tiles: &tiles,
            },
            &slots,
        );
        ctx.queue.submit([enc.finish()]);
        let gcpu = gbuffer::read_back(ctx, &g).unwrap();
        let gpu_tiles: Vec<u32> = readback::read_buffer(
            ctx,
            &tiles,
            samples.len() as u64 * CULL_TILE_WORDS as u64 * 4,
        )
        .unwrap();
        let twin_tiles = twin::footprint::footprint(&fr, &samples, &gcpu);
        // Which tiles are raised is exact; the limit itself may differ in its last bits (the
        // device fuses multiply-adds the twin rounds separately), at most ULPS apart.
        const ULPS: i64 = 4;
        let empty = gpu_tiles
            .iter()
            .zip(&twin_tiles)
            .filter(|(a, b)| (**a == 0) != (**b == 0))
            .count();
        let worst = gpu_tiles
            .iter()
            .zip(&twin_tiles)
            .map(|(a, b)| (*a as i64 - *b as i64).abs())
            .max()
            .unwrap();
        assert_eq!(
            empty, 0,
            "seed {seed}: {empty} tiles raised on one side only"
        );
        assert!(
            worst <= ULPS,
            "seed {seed}: a tile's limit is {worst} ulps from the twin's"
        );
        raised += twin_tiles.iter().filter(|&&w| w != 0).count();
        // `listed`: the same from the pixels of every third 8 × 8 tile alone (a shade tile
        // list: header (count, 1, 1, 0), then the tiles), against its twin; every limit it
        // raises is at most the whole frame's, and fewer tiles are raised.
        let tiles_x = fr.width.div_ceil(8);
        let chosen: Vec<u32> = (0..tiles_x * fr.height.div_ceil(8))
            .filter(|t| t % 3 == 0)
            .collect();
        let mut words = vec![chosen.len() as u32, 1, 1, 0];
        words.extend(&chosen);
        let list = readback::storage_buffer(ctx, "tile list", &words, wgpu::BufferUsages::INDIRECT);
        let listed_tiles = readback::zeroed_storage(
            ctx,
            "listed tiles",
            samples.len() as u64 * CULL_TILE_WORDS as u64 * 4,
        );
        let geometry_tiles = GeometryTiles::section(&list, 0, words.len() as u64 * 4, fr.height);
        let mut enc = ctx.device.create_command_encoder(&Default::default());
        assert!(Footprint::new(ctx).unwrap().record_listed(
            ctx,
            &mut enc,
            &frame,
            &g,
            &CullBatch {
                samples: &samples_buffer,
                tiles: &listed_tiles,
            },
            samples.len() as u32,
            &geometry_tiles,
        ));
        ctx.queue.submit([enc.finish()]);
        let gpu_listed: Vec<u32> = readback::read_buffer(
            ctx,
            &listed_tiles,
            samples.len() as u64 * CULL_TILE_WORDS as u64 * 4,
        )
        .unwrap();
        let twin_listed = twin::footprint::footprint_listed(&fr, &samples, &gcpu, &chosen);
        let one_side = gpu_listed
            .iter()
            .zip(&twin_listed)
            .filter(|(a, b)| (**a == 0) != (**b == 0))
            .count();
        assert_eq!(
            one_side, 0,
            "seed {seed}: listed: {one_side} tiles raised on one side only"
        );
        assert!(gpu_listed
            .iter()
            .zip(&twin_listed)
            .all(|(a, b)| (*a as i64 - *b as i64).abs() <= ULPS));
        assert!(twin_listed.iter().zip(&twin_tiles).all(|(l, w)| l <= w));
        let (listed_raised, whole_raised) = (
            twin_listed.iter().filter(|&&w| w != 0).count(),
            twin_tiles.iter().filter(|&&w| w != 0).count(),
        );
        println!("seed {seed}: listed raised {listed_raised} of the whole frame's {whole_raised}");
        assert!(listed_raised > 0 && listed_raised < whole_raised);
        let stride = scene_gpu.index_count as usize;
        let args: Vec<u32> =
            readback::read_buffer(ctx, &cull.args, slots.len() as u64 * ARGS_WORDS as u64 * 4)
                .unwrap();
        let culled: Vec<u32> =
            readback::read_buffer(ctx, &cull.culled, (slots.len() * stride) as u64 * 4).unwrap();
        let order = &scene_gpu.shadow_order;
        let positions: Vec<glam::Vec3> = sc
            .vertices
            .iter()
            .map(|v| glam::Vec3::from(v.position))
            .collect();
        // Cull's twin reads the tiles the device wrote: the cull decisions must then match exactly.
        let twin_kept = twin::cull::cull(
            &fr,
            &samples,
            &gpu_tiles,
            &positions,
            order,
            &slots,
            cull_face(sc.render.cull),
        );
        let triples = |v: &[u32]| {
            let mut t: Vec<[u32; 3]> = v.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
            t.sort_unstable();
            t
        };
        for (n, kept) in twin_kept.iter().enumerate() {
            let count = args[n * ARGS_WORDS as usize] as usize;
            assert_eq!(
                count,
                kept.len() * 3,
                "seed {seed} slot {n}: indices in the draw arguments"
            );
            let twin: Vec<u32> = kept
                .iter()
                .flat_map(|&t| order[t as usize * 3..t as usize * 3 + 3].iter().copied())
                .collect();
            assert_eq!(
                triples(&culled[n * stride..n * stride + count]),
                triples(&twin),
                "seed {seed} slot {n}: kept triangles"
            );
            kept_all += kept.len();
            culled_away += stride / 3 - kept.len();
        }
    }
    println!("footprint equals its twin: {raised} tiles raised; cull from it: {kept_all} triangles kept, {culled_away} culled");
    assert!(raised > 1000, "only {raised} tiles raised");
    assert!(
        kept_all > 100 && culled_away > 100,
        "too little happened: {kept_all} kept, {culled_away} culled"
    );
}

/// V of `regular` and global `adaptive` with cull = on equals V with cull = off bit for bit under
/// both rasters; run.json's record says how many triangles each map drew, fewer than the mesh.
#[test]
fn culling_every_pixel_changes_no_pixel() {
    let ctx = common::gpu();
    let dir = common::temp_dir("culled_maps");
    let text = common::random_scene_toml(5, 64, 256);
    let options = FrameOptions {
        mode: TimingMode::Frame,
        pictures: false,
    };
    let mut checked = 0;
    for raster in ["hardware", "compute"] {
        let sc = Scene::parse(
            &text,
            "random-5",
            Some(&dir),
            &[("raster".into(), raster.into())],
        )
        .unwrap();
        for (off, on) in [
            ("regular:n=4", "regular:n=4,cull=on"),
            (
                "regular:n=3,layout=centred",
                "regular:n=3,layout=centred,cull=on",
            ),
            (
                "adaptive:preset=balanced",
                "adaptive:p_m=0,max_level=3,weights=coons,cull=on",
            ),
        ] {
            let [a, b] = [off, on].map(|spec| {
                let method = Method::parse(spec, &[]).unwrap();
                let mut renderer = Renderer::new(ctx, &sc, &method)
                    .unwrap_or_else(|e| panic!("{spec}, raster = {raster}: {e}"));
                renderer
                    .frame(options)
                    .unwrap_or_else(|e| panic!("{spec}, raster = {raster}: {e}"))
            });
            assert_eq!(
                a.output.shadow_maps, b.output.shadow_maps,
                "{on} ({raster}): maps"
            );
            let geometry = (0..a.visibility.len())
                .filter(|&i| a.gbuffer.is_geometry(i))
                .count();
            let shadowed = (0..a.visibility.len())
                .filter(|&i| a.gbuffer.is_geometry(i) && a.visibility[i] < 1.0)
                .count();
            let differ = a
                .visibility
                .iter()
                .zip(&b.visibility)
                .filter(|(x, y)| x != y)
                .count();
            let rec = &b.output.record;
            let per_map: Vec<u64> = serde_json::from_value(rec["triangles_per_map"].clone())
                .unwrap_or_else(|_| panic!("{on}: triangles_per_map in {rec}"));
            let whole = a.output.record["triangles_per_map_mean"].as_f64().unwrap();
            let mean = rec["triangles_per_map_mean"].as_f64().unwrap();
            println!("{on} ({raster}): {differ} of {geometry} pixels differ ({shadowed} shadowed); {} maps drew {mean:.1} of {whole} triangles on average", per_map.len());
            assert_eq!(differ, 0, "{on} ({raster}): V differs from {off}");
            assert!(shadowed > 20, "{on}: only {shadowed} shadowed pixels");
            assert_eq!(
                per_map.len() as u32,
                b.output.shadow_maps,
                "{on}: one count per map"
            );
            assert!(
                mean > 0.0 && mean < whole,
                "{on}: {mean} triangles per map of {whole}"
            );
            assert!(per_map.iter().all(|&t| t as f64 <= whole));
            checked += 1;
        }
    }
    // A light at infinity: the sun's orthographic maps (linear depth, no face cull).
    let sets = [("resolution", "64"), ("shadow_map_size", "128")]
        .map(|(k, v)| (k.to_string(), v.to_string()));
    let sun = Scene::load("sun-edge", &sets).expect("sun-edge");
    let [a, b] = ["regular:n=4", "regular:n=4,cull=on"].map(|spec| {
        Renderer::new(ctx, &sun, &Method::parse(spec, &[]).unwrap())
            .unwrap()
            .frame(options)
            .unwrap()
    });
    let differ = a
        .visibility
        .iter()
        .zip(&b.visibility)
        .filter(|(x, y)| x != y)
        .count();
    let shadowed = (0..a.visibility.len())
        .filter(|&i| a.gbuffer.is_geometry(i) && a.visibility[i] < 1.0)
        .count();
    let mean = b.output.record["triangles_per_map_mean"].as_f64().unwrap();
    println!("regular:n=4,cull=on on sun-edge: {differ} pixels differ ({shadowed} shadowed), {mean:.1} triangles per map");
    assert_eq!(differ, 0, "sun-edge: V differs with cull = on");
    assert!(shadowed > 20, "sun-edge: only {shadowed} shadowed pixels");
    assert_eq!(checked, 6);
}

/// The documented setting on the command line: `regular:cull=on` writes its counts to run.json,
/// and a bad value is refused with the key and value named and nothing written.
#[test]
fn the_cull_setting_is_recorded_and_checked() {
    let dir = common::temp_dir("culled_maps_cli");
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, common::random_scene_toml(3, 48, 128)).unwrap();
    let scene = scene.to_str().unwrap();
    let out = dir.join("render");
    common::ok(
        common::penumbra(&[
            "render",
            "--scene",
            scene,
            "--method",
            "regular:n=3,cull=on",
            "--out",
            out.to_str().unwrap(),
        ]),
        "render",
    );
    let run: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("run.json")).unwrap()).unwrap();
    let text = run.to_string();
    assert!(
        text.contains("\"triangles_per_map\":["),
        "run.json has no triangles_per_map: {text}"
    );
    let bad = dir.join("bad");
    for spec in ["regular:n=3,cull=maybe", "adaptive:cull=maybe"] {
        let o = common::penumbra(&[
            "render",
            "--scene",
            scene,
            "--method",
            spec,
            "--out",
            bad.to_str().unwrap(),
        ]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{spec} was accepted");
        assert!(err.contains("cull = `maybe`"), "{spec}: {err}");
        assert!(!err.contains("panicked"), "{spec}: {err}");
        assert!(!bad.exists(), "{spec}: output written");
    }
}
