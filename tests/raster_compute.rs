//! raster_compute (kernels/raster_compute.wgsl): the GPU's words equal the CPU twin's bit for bit
//! on random triangle soups and on `default`, many maps per chain; a closed convex mesh is covered
//! exactly once per texel by its front faces; and the share of texels where it disagrees with the
//! fixed-function raster (render/shadow_raster.rs) stays small. Rules: docs/gpu-frame.md §7.

mod common;

use glam::Vec3;
use penumbra::research::gpu::structs::{GpuRasterJob, GpuSample};
use penumbra::research::gpu::{kernels, readback, GpuContext};
use penumbra::research::render::shadow_raster::{self, RasterJob, ShadowRasterPass};
use penumbra::research::render::SceneGpu;
use penumbra::research::scene::light::sample_view;
use penumbra::research::scene::{CullMode, Scene, Vertex};
use penumbra::research::stages::raster_compute::{self, RasterCompute, FAR};
use penumbra::research::stages::twin::raster_compute as twin;

const MAP: u32 = 256;

fn scene(text_meshes: &str) -> Scene {
    let text = format!(
        "[camera]\neye = [0.0, 6.0, 8.0]\ntarget = [0.0, 0.0, 0.0]\nfov_y_deg = 45.0\n\n\
         [light]\ncenter = [0.5, 8.0, 0.3]\nedge_u = [2.0, 0.0, 0.0]\nedge_v = [0.0, 0.0, 2.0]\n\n\
         [render]\nwidth = 32\nheight = 32\nshadow_map_size = {MAP}\n\n{text_meshes}"
    );
    Scene::parse(&text, "raster-compute-test", None, &[]).expect("test scene")
}

/// A small deterministic generator (splitmix64).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut x = self.0;
        x = (x ^ (x >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        x = (x ^ (x >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        x ^ (x >> 31)
    }
    fn unit(&mut self) -> f32 {
        (self.next() >> 40) as f32 / (1u64 << 24) as f32
    }
    fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.unit()
    }
}

fn positions(scene: &Scene) -> Vec<[f32; 3]> {
    scene.vertices.iter().map(|v| v.position).collect()
}

/// Samples of `scene`'s light at light points `points`, as the methods build them.
fn samples(scene: &Scene, points: &[(f32, f32)]) -> Vec<GpuSample> {
    points
        .iter()
        .enumerate()
        .map(|(k, &(u, v))| {
            sample_view(
                &scene.light,
                scene.light.point(u, v),
                &scene.bounds,
                MAP,
                k as u32,
            )
        })
        .collect()
}

/// Every map's words from one chain on the GPU.
fn gpu_words(
    ctx: &GpuContext,
    scene: &Scene,
    gpu: &SceneGpu,
    samples: &[GpuSample],
    cull: CullMode,
) -> Vec<Vec<u32>> {
    gpu_words_queue(ctx, scene, gpu, samples, cull, None)
}

/// The same with a large-pair queue of `pairs` (None: the pass's own size).
fn gpu_words_queue(
    ctx: &GpuContext,
    scene: &Scene,
    gpu: &SceneGpu,
    samples: &[GpuSample],
    cull: CullMode,
    pairs: Option<u32>,
) -> Vec<Vec<u32>> {
    let pass = RasterCompute::with_queue(
        ctx,
        MAP,
        cull,
        samples.len() as u32,
        scene.render.shadow_map_budget_mib,
        pairs,
    )
    .unwrap();
    assert_eq!(
        pass.capacity,
        samples.len() as u32,
        "one chain holds every map"
    );
    let buffer = readback::storage_buffer(ctx, "samples", samples, wgpu::BufferUsages::empty());
    let jobs: Vec<GpuRasterJob> = (0..samples.len() as u32)
        .map(|k| GpuRasterJob::whole(k, MAP))
        .collect();
    let mut enc = ctx.device.create_command_encoder(&Default::default());
    pass.record(ctx, &mut enc, gpu, &buffer, &jobs);
    ctx.queue.submit([enc.finish()]);
    let words = pass.read_words(ctx, samples.len() as u32).unwrap();
    words
        .chunks((MAP * MAP) as usize)
        .map(|m| m.to_vec())
        .collect()
}

/// GPU and twin on every map; returns the covered texels over all maps.
fn assert_twin_exact(
    ctx: &GpuContext,
    scene: &Scene,
    points: &[(f32, f32)],
    cull: CullMode,
) -> usize {
    let gpu = SceneGpu::upload(ctx, scene);
    let samples = samples(scene, points);
    let words = gpu_words(ctx, scene, &gpu, &samples, cull);
    let pos = positions(scene);
    let mut covered = 0;
    for (m, s) in samples.iter().enumerate() {
        let want = twin::rasterize(&pos, &gpu.shadow_order, s, MAP, cull);
        let differ: Vec<usize> = (0..want.len())
            .filter(|&i| words[m][i] != want[i])
            .collect();
        assert!(
            differ.is_empty(),
            "{} ({cull:?}), map {m}: {} texels differ from the twin, first at {} (gpu {:#x}, twin {:#x})",
            scene.name,
            differ.len(),
            differ[0],
            words[m][differ[0]],
            want[differ[0]]
        );
        covered += want.iter().filter(|&&w| w != FAR).count();
    }
    covered
}

/// Random triangles in and beyond the scene's box (its bounds fit the frustum): large and small,
/// both windings, some reaching past the map's edges or nearer than the near plane.
fn soup(seed: u64, triangles: usize) -> Scene {
    let mut s = scene("[[mesh]]\nbuiltin = \"box\"\nscale = 4.0\n");
    let mut rng = Rng(seed);
    let mut vertices = Vec::new();
    for t in 0..triangles {
        // One in eight spans much of the box; the rest are small, down to below a texel.
        let size = if t % 8 == 0 {
            3.0
        } else {
            0.02 + 0.3 * rng.unit()
        };
        let centre = Vec3::new(
            rng.range(-2.6, 2.6),
            rng.range(-2.0, 2.0),
            rng.range(-2.6, 2.6),
        );
        for _ in 0..3 {
            let p = centre
                + size
                    * Vec3::new(
                        rng.range(-1.0, 1.0),
                        rng.range(-1.0, 1.0),
                        rng.range(-1.0, 1.0),
                    );
            vertices.push(Vertex {
                position: p
                    .clamp(Vec3::new(-3.0, -2.0, -3.0), Vec3::new(3.0, 2.6, 3.0))
                    .to_array(),
                normal: [0.0, 1.0, 0.0],
                material: 0,
            });
        }
    }
    s.indices = (0..vertices.len() as u32).collect();
    s.vertices = vertices;
    s
}

#[test]
fn gpu_equals_twin_on_random_soups_several_maps_per_chain() {
    let ctx = common::gpu();
    let points = [(0.0, 0.0), (1.0, 0.0), (0.3, 0.8), (0.5, 0.5), (1.0, 1.0)];
    for (seed, cull) in [
        (1, CullMode::Back),
        (2, CullMode::None),
        (3, CullMode::Front),
    ] {
        let covered = assert_twin_exact(ctx, &soup(seed, 3000), &points, cull);
        // The soups cover a good part of the maps: the comparison is not of empty maps.
        assert!(
            covered > 5 * (MAP * MAP) as usize / 10,
            "seed {seed}: only {covered} texels covered"
        );
    }
}

/// Past a full queue each large pair is rasterized by the invocation that set it up: with a
/// queue of 8 pairs nearly every large pair of a soup goes that way, and the words are still
/// the twin's, the same as with the pass's own queue. The soup's triangles span 10 to 40 texels
/// (every one large), so an invocation's loops stay within what a CPU device runs (below).
#[test]
fn pairs_past_a_full_queue_equal_the_twin() {
    let ctx = common::gpu();
    let mut scene = scene("[[mesh]]\nbuiltin = \"box\"\nscale = 4.0\n");
    let mut rng = Rng(4);
    let mut vertices = Vec::new();
    for _ in 0..3000 {
        let size = 0.15 + 0.35 * rng.unit();
        let centre = Vec3::new(
            rng.range(-2.6, 2.6),
            rng.range(-2.0, 2.0),
            rng.range(-2.6, 2.6),
        );
        for _ in 0..3 {
            let p = centre
                + size
                    * Vec3::new(
                        rng.range(-1.0, 1.0),
                        rng.range(-1.0, 1.0),
                        rng.range(-1.0, 1.0),
                    );
            vertices.push(Vertex {
                position: p.to_array(),
                normal: [0.0, 1.0, 0.0],
                material: 0,
            });
        }
    }
    scene.indices = (0..vertices.len() as u32).collect();
    scene.vertices = vertices;
    let gpu = SceneGpu::upload(ctx, &scene);
    let samples = samples(&scene, &[(0.0, 0.0), (0.5, 0.5), (1.0, 1.0)]);
    let pos = positions(&scene);
    // Large pairs: boxes over 4 × 4 texel centres (the kernel's RASTER_SMALL_SIDE).
    let large: usize = samples
        .iter()
        .map(|s| {
            (0..pos.len() / 3)
                .filter_map(|t| {
                    twin::setup(s, MAP, twin::whole(MAP), 0, &pos, &gpu.shadow_order, t)
                })
                .filter(|tri| tri.hi[0] - tri.lo[0] >= 4 || tri.hi[1] - tri.lo[1] >= 4)
                .count()
        })
        .sum();
    assert!(
        large > 1000,
        "the soup should overflow a queue of 8 many times over: {large} large pairs"
    );
    let own = gpu_words(ctx, &scene, &gpu, &samples, CullMode::None);
    let small_queue = gpu_words_queue(ctx, &scene, &gpu, &samples, CullMode::None, Some(8));
    for (m, s) in samples.iter().enumerate() {
        let want = twin::rasterize(&pos, &gpu.shadow_order, s, MAP, CullMode::None);
        let covered = want.iter().filter(|&&w| w != FAR).count();
        assert!(
            covered > (MAP * MAP) as usize / 4,
            "map {m}: {covered} texels covered"
        );
        let differ = |words: &[u32]| (0..want.len()).filter(|&i| words[i] != want[i]).count();
        assert_eq!(
            differ(&small_queue[m]),
            0,
            "map {m}: past a full queue, texels differ from the twin"
        );
        assert_eq!(
            differ(&own[m]),
            0,
            "map {m}: with the pass's own queue, texels differ from the twin"
        );
    }
    assert_eq!(
        penumbra::research::stages::raster_compute::large_capacity(289, 2 << 30),
        1 << 24
    );
    assert_eq!(
        penumbra::research::stages::raster_compute::large_capacity(2, 2 << 30),
        1 << 18
    );
    assert_eq!(
        penumbra::research::stages::raster_compute::large_capacity(25, 2 << 30),
        25 << 16
    );
    assert_eq!(
        penumbra::research::stages::raster_compute::large_capacity(289, 1 << 20),
        1 << 17,
        "one binding holds the queue"
    );
    // A mesh of more triangles than the per-map floor: one pair per triangle and map.
    assert_eq!(
        penumbra::research::stages::raster_compute::large_capacity_for(9, 60_000, 2 << 30),
        9 << 16,
        "the floor"
    );
    assert_eq!(
        penumbra::research::stages::raster_compute::large_capacity_for(9, 100_000, 2 << 30),
        900_000
    );
    assert_eq!(
        penumbra::research::stages::raster_compute::large_capacity_for(16, 564_152, 2 << 30),
        9_026_432
    );
    assert_eq!(
        penumbra::research::stages::raster_compute::large_capacity_for(289, 564_152, 2 << 30),
        1 << 24,
        "the most"
    );
}

#[test]
fn gpu_equals_twin_on_default() {
    let ctx = common::gpu();
    let sets = [("shadow_map_size", "256")].map(|(k, v)| (k.to_string(), v.to_string()));
    let scene = Scene::load("default", &sets).unwrap();
    let covered = assert_twin_exact(
        ctx,
        &scene,
        &[(0.0, 0.0), (0.5, 0.5), (1.0, 0.25), (0.25, 1.0)],
        scene.render.cull,
    );
    assert!(
        covered > (MAP * MAP) as usize,
        "{covered} texels covered over 4 maps"
    );
}

/// Jobs with rectangles (the fixed-function scissor's job): inside each map's rectangle the GPU
/// equals the twin bit for bit, and every texel outside keeps the far value.
#[test]
fn rectangles_limit_each_map_and_equal_the_twin() {
    let ctx = common::gpu();
    let scene = soup(4, 3000);
    let samples = samples(&scene, &[(0.0, 0.0), (1.0, 0.0), (0.3, 0.8), (0.5, 0.5)]);
    let rects = [
        [0, 0, 256, 256],
        [10, 20, 100, 37],
        [200, 3, 56, 250],
        [128, 128, 1, 1],
    ];
    let jobs: Vec<GpuRasterJob> = rects
        .iter()
        .enumerate()
        .map(|(k, &r)| GpuRasterJob::new(k as u32, MAP, Some(r)))
        .collect();
    let gpu = SceneGpu::upload(ctx, &scene);
    let pass = RasterCompute::new(
        ctx,
        MAP,
        CullMode::Back,
        4,
        scene.render.shadow_map_budget_mib,
    )
    .unwrap();
    let buffer = readback::storage_buffer(ctx, "samples", &samples, wgpu::BufferUsages::empty());
    let mut enc = ctx.device.create_command_encoder(&Default::default());
    pass.record(ctx, &mut enc, &gpu, &buffer, &jobs);
    ctx.queue.submit([enc.finish()]);
    let words = pass.read_words(ctx, 4).unwrap();
    let pos = positions(&scene);
    for (m, job) in jobs.iter().enumerate() {
        let whole = twin::rasterize(&pos, &gpu.shadow_order, &samples[m], MAP, CullMode::Back);
        let want = twin::rasterize_in(
            &pos,
            &gpu.shadow_order,
            &samples[m],
            MAP,
            job.rect(),
            CullMode::Back,
        );
        let got = &words[m * (MAP * MAP) as usize..(m + 1) * (MAP * MAP) as usize];
        assert_eq!(
            got,
            &want[..],
            "map {m}: GPU and twin inside {:?}",
            rects[m]
        );
        let [x0, y0, x1, y1] = job.rect();
        let (mut inside, mut outside_covered) = (0, 0);
        for (i, &w) in want.iter().enumerate() {
            let (x, y) = ((i % MAP as usize) as i32, (i / MAP as usize) as i32);
            if (x0..=x1).contains(&x) && (y0..=y1).contains(&y) {
                assert_eq!(
                    w, whole[i],
                    "map {m}: texel ({x}, {y}) inside the rectangle is the whole map's"
                );
                inside += usize::from(w != FAR);
            } else {
                assert_eq!(w, FAR, "map {m}: texel ({x}, {y}) outside the rectangle");
                outside_covered += usize::from(whole[i] != FAR);
            }
        }
        assert!(inside > 0, "map {m}: the rectangle holds covered texels");
        if m > 0 {
            assert!(
                outside_covered > 0,
                "map {m}: the rectangle cuts covered texels away"
            );
        }
    }
}

/// A 2048² map filled by a plane's two triangles: each queued pair's box is 65,536 tiles. The words
/// are the twin's. A CPU device (lavapipe) stops a shader's loops after 65,535 iterations in all,
/// so one workgroup per pair left 954,964 of 4,186,116 texels unwritten; the tiles now spread over
/// workgroups of RASTER_TILE_BLOCK (docs/gpu-frame.md §7).
#[test]
fn a_map_filling_triangle_at_2048_equals_the_twin() {
    let ctx = common::gpu();
    let scene = scene("[[mesh]]\nbuiltin = \"plane\"\nscale = 4.0\n");
    let size = 2048;
    let samples: Vec<GpuSample> = [(0.5, 0.5)]
        .iter()
        .enumerate()
        .map(|(k, &(u, v))| {
            sample_view(
                &scene.light,
                scene.light.point(u, v),
                &scene.bounds,
                size,
                k as u32,
            )
        })
        .collect();
    let gpu = SceneGpu::upload(ctx, &scene);
    let buffer = readback::storage_buffer(ctx, "samples", &samples, wgpu::BufferUsages::empty());
    let pass = RasterCompute::new(
        ctx,
        size,
        scene.render.cull,
        1,
        scene.render.shadow_map_budget_mib,
    )
    .unwrap();
    let mut enc = ctx.device.create_command_encoder(&Default::default());
    pass.record(
        ctx,
        &mut enc,
        &gpu,
        &buffer,
        &[GpuRasterJob::whole(0, size)],
    );
    ctx.queue.submit([enc.finish()]);
    let words = pass.read_words(ctx, 1).unwrap();
    let want = twin::rasterize(
        &positions(&scene),
        &gpu.shadow_order,
        &samples[0],
        size,
        scene.render.cull,
    );
    let covered = want.iter().filter(|&&w| w != FAR).count();
    assert!(
        covered > (size * size) as usize * 9 / 10,
        "the plane fills the map: {covered}"
    );
    let differ = (0..want.len()).filter(|&i| words[i] != want[i]).count();
    assert_eq!(
        differ, 0,
        "{differ} of {covered} covered texels differ from the twin"
    );
}

/// A chain whose words are not a whole number of `clear`'s runs (3 maps of 20², 1,200 words) is
/// cleared to the end: recorded over the maps of other samples, it still equals the twin.
#[test]
fn a_second_chain_of_odd_size_clears_the_first() {
    let ctx = common::gpu();
    let scene = Scene::load("default", &[]).unwrap();
    let size = 20;
    let samples: Vec<GpuSample> = [(0.0, 0.0), (0.5, 0.5), (1.0, 0.25)]
        .iter()
        .enumerate()
        .map(|(k, &(u, v))| {
            sample_view(
                &scene.light,
                scene.light.point(u, v),
                &scene.bounds,
                size,
                k as u32,
            )
        })
        .collect();
    let gpu = SceneGpu::upload(ctx, &scene);
    let buffer = readback::storage_buffer(ctx, "samples", &samples, wgpu::BufferUsages::empty());
    let pass = RasterCompute::new(
        ctx,
        size,
        scene.render.cull,
        3,
        scene.render.shadow_map_budget_mib,
    )
    .unwrap();
    let pos = positions(&scene);
    let twin: Vec<Vec<u32>> = samples
        .iter()
        .map(|s| twin::rasterize(&pos, &gpu.shadow_order, s, size, scene.render.cull))
        .collect();
    // The stale chain must differ from the wanted one, or a missing clear would go unseen.
    assert_ne!(twin[0], twin[2], "maps 0 and 2 differ");
    for order in [[2, 1, 0], [0, 1, 2]] {
        let jobs = order.map(|k| GpuRasterJob::whole(k, size));
        let mut enc = ctx.device.create_command_encoder(&Default::default());
        pass.record(ctx, &mut enc, &gpu, &buffer, &jobs);
        ctx.queue.submit([enc.finish()]);
    }
    let words = pass.read_words(ctx, 3).unwrap();
    for (m, want) in twin.iter().enumerate() {
        assert!(want.iter().any(|&w| w != FAR), "map {m} covers texels");
        assert_eq!(&words[m * 400..(m + 1) * 400], &want[..], "map {m}");
    }
}

/// A welded icosphere of radius `r` at `centre`, subdivided `levels` times (closed and convex).
fn icosphere(levels: u32, r: f32, centre: Vec3) -> (Vec<Vec3>, Vec<u32>) {
    let g = (1.0 + 5f32.sqrt()) / 2.0;
    let mut p: Vec<Vec3> = [
        (-1.0, g, 0.0),
        (1.0, g, 0.0),
        (-1.0, -g, 0.0),
        (1.0, -g, 0.0),
        (0.0, -1.0, g),
        (0.0, 1.0, g),
        (0.0, -1.0, -g),
        (0.0, 1.0, -g),
        (g, 0.0, -1.0),
        (g, 0.0, 1.0),
        (-g, 0.0, -1.0),
        (-g, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| Vec3::new(x, y, z).normalize())
    .collect();
    let mut tris: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..levels {
        let mut mid = std::collections::HashMap::new();
        let mut next = Vec::new();
        for [a, b, c] in tris {
            let mut m = |a: u32, b: u32| {
                *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                    p.push(((p[a as usize] + p[b as usize]) * 0.5).normalize());
                    p.len() as u32 - 1
                })
            };
            let (ab, bc, ca) = (m(a, b), m(b, c), m(c, a));
            next.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
        }
        tris = next;
    }
    (
        p.iter().map(|&q| centre + r * q).collect(),
        tris.into_iter().flatten().collect(),
    )
}

/// Points the scene's light at `target` from `from` (the view every sample of it looks along).
fn aim(scene: &mut Scene, from: Vec3, target: Vec3) {
    let dir = (target - from).normalize();
    let u = dir.any_orthonormal_vector();
    scene.light.center = from;
    scene.light.edge_u = u * 0.5;
    scene.light.edge_v = dir.cross(u) * 0.5;
    assert!(scene.light.normal().dot(dir) > 0.999);
}

/// Every texel centre inside the silhouette of a closed convex mesh is hit by exactly one front face
/// (and one back face), for random views; no cracks, no double hits. The counts are the twin's;
/// the GPU's depths equal the twin's bit for bit on each of these views, so they are the GPU's too.
#[test]
fn closed_meshes_are_covered_once_per_texel() {
    let ctx = common::gpu();
    let mut rng = Rng(7);
    let box_scene = scene(
        "[[mesh]]\nbuiltin = \"box\"\nscale = 1.7\nsubdivide = 4\nrotate_deg = [23.0, 41.0, 7.0]\n",
    );
    let (p, i) = icosphere(4, 1.0, Vec3::new(0.1, 0.2, -0.1));
    let mut sphere = box_scene.clone();
    sphere.vertices = p
        .iter()
        .map(|q| Vertex {
            position: q.to_array(),
            normal: [0.0, 1.0, 0.0],
            material: 0,
        })
        .collect();
    sphere.indices = i;
    for mut s in [box_scene, sphere] {
        assert!(
            s.triangle_count() >= 3000,
            "{} triangles",
            s.triangle_count()
        );
        let mut inside_total = 0;
        for view in 0..4 {
            let dir = Vec3::new(
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
            )
            .normalize();
            aim(&mut s, dir * rng.range(3.0, 6.0), Vec3::ZERO);
            let gpu = SceneGpu::upload(ctx, &s);
            let sample = samples(&s, &[(rng.unit(), rng.unit())]);
            let pos = positions(&s);
            let words = gpu_words(ctx, &s, &gpu, &sample, CullMode::Back);
            assert_eq!(
                words[0],
                twin::rasterize(&pos, &gpu.shadow_order, &sample[0], MAP, CullMode::Back),
                "view {view}: GPU and twin"
            );
            let (front, back) = twin::face_hits(&pos, &gpu.shadow_order, &sample[0], MAP);
            for t in 0..front.len() {
                assert!(
                    front[t] <= 1 && front[t] == back[t],
                    "view {view}, texel {t}: {} front and {} back hits",
                    front[t],
                    back[t]
                );
                // Back-face culling keeps exactly the front hits.
                assert_eq!(words[0][t] != FAR, front[t] == 1, "view {view}, texel {t}");
            }
            inside_total += front.iter().filter(|&&h| h == 1).count();
        }
        assert!(
            inside_total > 4 * 2000,
            "the silhouettes hold {inside_total} texels over 4 views"
        );
    }
}

/// Against the fixed-function raster on `default` at 256², 5 light samples: texels where one raster
/// covers and the other does not, and texels covered by both whose depths differ by more than a
/// tenth of a texel's width in linear depth (a fifth of shadow_test's constant bias, 0.5 texel, so
/// below it no lookup's outcome can change). lavapipe interpolates depth on the unsnapped vertices,
/// this raster on the snapped ones: on steep triangles the 1/512-texel snap moves the plane.
#[test]
fn few_texels_differ_from_the_fixed_function_raster() {
    let ctx = common::gpu();
    let sets = [("shadow_map_size", "256")].map(|(k, v)| (k.to_string(), v.to_string()));
    let scene = Scene::load("default", &sets).unwrap();
    let gpu = SceneGpu::upload(ctx, &scene);
    let points = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0), (0.5, 0.5)];
    let samples = samples(&scene, &points);
    let words = gpu_words(ctx, &scene, &gpu, &samples, scene.render.cull);
    let pass = ShadowRasterPass::new(ctx, scene.render.cull).unwrap();
    let array = shadow_raster::allocate(ctx, MAP, points.len() as u32);
    let buffer = readback::storage_buffer(ctx, "samples", &samples, wgpu::BufferUsages::empty());
    let jobs: Vec<RasterJob> = (0..points.len() as u32)
        .map(|k| RasterJob {
            sample: k,
            layer: k,
            scissor: None,
        })
        .collect();
    let mut enc = ctx.device.create_command_encoder(&Default::default());
    pass.record(ctx, &mut enc, &gpu, &buffer, &array, &jobs);
    ctx.queue.submit([enc.finish()]);
    let mut d = raster_compute::RasterDifference::default();
    for (k, s) in samples.iter().enumerate() {
        let hw: Vec<f32> = readback::read_texture(ctx, &array.texture, k as u32, 4).unwrap();
        d.add(s, &hw, &words[k]);
    }
    let texels = points.len() * (MAP * MAP) as usize;
    assert_eq!(d.texels, texels);
    println!(
        "raster_compute vs shadow_raster, default 256², 5 maps: {}",
        d.summary()
    );
    let (covered, coverage, tenth) = (d.covered, d.coverage, d.tenth);
    let share = |n: usize| d.share(n);
    assert!(covered > texels / 4, "{covered} texels covered");
    // Measured on lavapipe: coverage differs at 0 texels, depth by > 0.1 texel at 3 (0.0009%);
    // the bound leaves ten times that for another driver's snap and interpolation.
    assert!(
        share(coverage) < 1e-4 && share(tenth) < 1e-4,
        "coverage {}, depth {}",
        share(coverage),
        share(tenth)
    );
}

/// The chain holds what the budget allows; a budget below one map is a one-line error naming it.
#[test]
fn chains_stay_inside_the_map_budget() {
    let ctx = common::gpu();
    // 256² maps are 256 KiB each: 1 MiB holds 4.
    assert_eq!(raster_compute::maps_per_chain(ctx, 256, 1).unwrap(), 4);
    assert_eq!(
        RasterCompute::new(ctx, 256, CullMode::Back, 25, 1)
            .unwrap()
            .capacity,
        4
    );
    let e = raster_compute::maps_per_chain(ctx, 1024, 3)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("shadow_map_budget_mib = 3") && e.contains("1024x1024") && !e.contains('\n'),
        "{e}"
    );
}

/// The constants the twin mirrors hold the kernel's values (naga reads them).
#[test]
fn twin_constants_match_the_kernel() {
    let (module, _) = kernels::validate("raster_compute").unwrap();
    let constant = |name: &str| -> f64 {
        let (_, c) = module
            .constants
            .iter()
            .find(|(_, c)| c.name.as_deref() == Some(name))
            .unwrap_or_else(|| panic!("no `{name}`"));
        match module.global_expressions[c.init] {
            naga::Expression::Literal(naga::Literal::U32(v)) => v as f64,
            naga::Expression::Literal(naga::Literal::I32(v)) => v as f64,
            naga::Expression::Literal(naga::Literal::F32(v)) => v as f64,
            ref e => panic!("`{name}` is {e:?}"),
        }
    };
    assert_eq!(
        constant("RASTER_SUBTEXEL_BITS"),
        twin::RASTER_SUBTEXEL_BITS as f64
    );
    assert_eq!(
        constant("RASTER_COORD_LIMIT"),
        twin::RASTER_COORD_LIMIT as f64
    );
    assert_eq!(
        constant("RASTER_SMALL_SIDE"),
        twin::RASTER_SMALL_SIDE as f64
    );
    assert_eq!(
        constant("RASTER_LARGE_TILE"),
        twin::RASTER_LARGE_TILE as f64
    );
    assert_eq!(constant("RASTER_FAR"), FAR as f64);
    assert_eq!(
        constant("RASTER_CLEAR_RUN"),
        raster_compute::CLEAR_RUN as f64
    );
    assert_eq!(
        constant("STEER_ARGS_CLEAR"),
        raster_compute::STEER_ARGS_CLEAR as f64
    );
    assert_eq!(
        constant("STEER_ARGS_MAIN"),
        raster_compute::STEER_ARGS_MAIN as f64
    );
    assert_eq!(
        constant("STEER_ARGS_STORE"),
        raster_compute::STEER_ARGS_STORE as f64
    );
    assert_eq!(
        constant("RASTER_WHOLE_MESH"),
        GpuRasterJob::WHOLE_MESH as f64
    );
    assert_eq!(
        constant("RASTER_KEPT_ARGS"),
        penumbra::research::stages::cull::ARGS_WORDS as f64
    );
    assert_eq!(
        constant("RASTER_RUN"),
        penumbra::research::stages::cull::CULL_RUN as f64
    );
}

/// Under the GPU-steered loop the chain's jobs and dispatches come from a level's request list:
/// `requested` equals its twin for chains before, across and past the list's end, and `store`
/// puts each requested map, equal to the twin's raster, into the layer its sample names, leaving
/// every other layer as it was.
#[test]
fn requested_maps_go_to_their_samples_layers() {
    let ctx = common::gpu();
    let scene = soup(5, 2000);
    let points: Vec<(f32, f32)> = (0..10)
        .map(|k| ((k % 4) as f32 / 3.0, (k / 4) as f32 / 2.0))
        .collect();
    let mut samples = samples(&scene, &points);
    // Layers are a permutation of the samples, as the steered loop assigns them per candidate.
    for (k, s) in samples.iter_mut().enumerate() {
        s.layer = ((k * 7 + 3) % 10) as u32;
    }
    let list = [7u32, 3, 9, 1, 4, 8];
    let control = [0u32, list.len() as u32, 0, 0, 0, 0, 0, 0];
    let gpu = SceneGpu::upload(ctx, &scene);
    let pass = RasterCompute::new(
        ctx,
        MAP,
        CullMode::Back,
        4,
        scene.render.shadow_map_budget_mib,
    )
    .unwrap();
    assert_eq!(pass.capacity, 4);
    let buffer = readback::storage_buffer(ctx, "samples", &samples, wgpu::BufferUsages::empty());
    let control_buffer =
        readback::storage_buffer(ctx, "control", &control, wgpu::BufferUsages::empty());
    let list_buffer = readback::storage_buffer(ctx, "list", &list, wgpu::BufferUsages::empty());
    let array = shadow_raster::allocate_as(ctx, MAP, 10, true);
    shadow_raster::clear_all(ctx, &array).unwrap();
    for first in [0u32, 4, 8] {
        let mut enc = ctx.device.create_command_encoder(&Default::default());
        pass.record_requested(
            ctx,
            &mut enc,
            &gpu,
            &buffer,
            &raster_compute::Requests {
                control: &control_buffer,
                list: &list_buffer,
                first,
            },
            &array.array_view,
        );
        ctx.queue.submit([enc.finish()]);
        let (_, want) = twin::requested(
            list.len() as u32,
            &list,
            first,
            4,
            MAP,
            scene.triangle_count() as u32,
        );
        assert_eq!(
            pass.read_steer_args(ctx).unwrap(),
            want,
            "chain from request {first}"
        );
    }
    let pos = positions(&scene);
    for (k, s) in samples.iter().enumerate() {
        let layer: Vec<u32> = readback::read_texture(ctx, &array.texture, s.layer, 4).unwrap();
        if list.contains(&(k as u32)) {
            let want = twin::rasterize(&pos, &gpu.shadow_order, s, MAP, CullMode::Back);
            assert!(want.iter().any(|&w| w != FAR), "sample {k} covers texels");
            assert_eq!(layer, want, "requested sample {k} in layer {}", s.layer);
        } else {
            assert!(
                layer.iter().all(|&w| w == FAR),
                "sample {k} was not requested: layer {} untouched",
                s.layer
            );
        }
    }
}

/// Jobs that draw the cull pass's kept lists: each map reads its slot's triangles (a whole-mesh
/// slot of indices) and count (the draw arguments' first word), and equals the twin over that list.
#[test]
fn kept_lists_are_drawn_per_slot() {
    let ctx = common::gpu();
    let scene = soup(6, 1500);
    let samples = samples(&scene, &[(0.0, 0.0), (1.0, 1.0), (0.5, 0.5)]);
    let gpu = SceneGpu::upload(ctx, &scene);
    let order = &gpu.shadow_order;
    let triangles = order.len() / 3;
    // Slot 0 keeps every other triangle, slot 1 the first third, slot 2 nothing; slot 3's list is
    // the whole mesh. Past each count the slot holds stale indices that must not be drawn.
    let keep: [Vec<usize>; 4] = [
        (0..triangles).step_by(2).collect(),
        (0..triangles / 3).collect(),
        vec![],
        (0..triangles).collect(),
    ];
    let mut lists = vec![0u32; 4 * order.len()];
    let mut args = vec![0u32; 4 * 5];
    for (slot, kept) in keep.iter().enumerate() {
        for (i, &t) in kept.iter().enumerate() {
            lists[slot * order.len() + i * 3..][..3].copy_from_slice(&order[t * 3..t * 3 + 3]);
        }
        for i in kept.len() * 3..order.len() {
            lists[slot * order.len() + i] = order[i];
        }
        args[slot * 5] = kept.len() as u32 * 3;
    }
    let lists_buffer =
        readback::storage_buffer(ctx, "kept lists", &lists, wgpu::BufferUsages::empty());
    let args_buffer =
        readback::storage_buffer(ctx, "kept arguments", &args, wgpu::BufferUsages::empty());
    // Maps: sample 0 with slot 0, sample 1 with slot 1, sample 2 with slot 2, sample 0 with slot 3.
    let jobs: Vec<GpuRasterJob> = [(0, 0), (1, 1), (2, 2), (0, 3)]
        .iter()
        .map(|&(s, slot)| GpuRasterJob {
            kept_slot: slot,
            ..GpuRasterJob::whole(s, MAP)
        })
        .collect();
    let pass = RasterCompute::new(
        ctx,
        MAP,
        CullMode::Back,
        4,
        scene.render.shadow_map_budget_mib,
    )
    .unwrap();
    let buffer = readback::storage_buffer(ctx, "samples", &samples, wgpu::BufferUsages::empty());
    let mut enc = ctx.device.create_command_encoder(&Default::default());
    pass.record_kept(
        ctx,
        &mut enc,
        &gpu,
        &buffer,
        &jobs,
        Some((&lists_buffer, &args_buffer)),
    );
    ctx.queue.submit([enc.finish()]);
    let words = pass.read_words(ctx, 4).unwrap();
    let pos = positions(&scene);
    for (m, job) in jobs.iter().enumerate() {
        let slot = job.kept_slot as usize;
        let list: Vec<u32> = keep[slot]
            .iter()
            .flat_map(|&t| order[t * 3..t * 3 + 3].to_vec())
            .collect();
        let want = twin::rasterize(
            &pos,
            &list,
            &samples[job.sample as usize],
            MAP,
            CullMode::Back,
        );
        assert_eq!(
            &words[m * (MAP * MAP) as usize..][..(MAP * MAP) as usize],
            &want[..],
            "map {m} (slot {slot}, {} triangles)",
            keep[slot].len()
        );
        let covered = want.iter().filter(|&&w| w != FAR).count();
        assert_eq!(covered == 0, slot == 2, "map {m}: {covered} texels covered");
    }
    // The whole-mesh slot equals the whole mesh drawn without lists.
    assert_eq!(
        &words[3 * (MAP * MAP) as usize..],
        &twin::rasterize(&pos, order, &samples[0], MAP, CullMode::Back)[..]
    );
}

/// One name per stage: a frame drawn by the compute raster times its maps as `raster_compute` and
/// the fixed-function one as `shadow_raster`, never one under the other's key, for the plain
/// maps of a fixed set (`regular`) and the adaptive loop's.
#[test]
fn each_raster_reports_its_own_timing_key() {
    use penumbra::research::frame::{self, FrameOptions};
    use penumbra::research::gpu::timing::TimingMode;
    use penumbra::research::methods::Method;
    let ctx = common::gpu();
    for (raster, key, other) in [
        ("compute", "raster_compute", "shadow_raster"),
        ("hardware", "shadow_raster", "raster_compute"),
    ] {
        let sets = [
            ("resolution", "64"),
            ("shadow_map_size", "128"),
            ("raster", raster),
        ]
        .map(|(k, v)| (k.to_string(), v.to_string()));
        let scene = Scene::load("default", &sets).unwrap();
        for method in ["regular:n=3", "adaptive:max_level=1"] {
            let method = Method::parse(method, &[]).unwrap();
            let r = frame::render(
                ctx,
                &scene,
                &method,
                FrameOptions {
                    mode: TimingMode::Stages,
                    pictures: false,
                },
            )
            .unwrap();
            assert_eq!(r.raster.used, raster, "{method:?}");
            let ms = r.stages_ms.get(key).copied();
            assert!(
                ms.is_some_and(|ms| ms > 0.0),
                "raster = {raster}, {method:?}: `{key}` is {ms:?} in {:?}",
                r.stages_ms.keys().collect::<Vec<_>>()
            );
            assert!(
                !r.stages_ms.contains_key(other),
                "raster = {raster}, {method:?}: `{other}` in {:?}",
                r.stages_ms
            );
        }
    }
}
