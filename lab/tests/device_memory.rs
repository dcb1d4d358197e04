//! A shadow-map array past what the device can allocate at once (its largest memory heap): the
//! size plan refuses it before anything is allocated or traced, naming `shadow_map_budget_mib`, and
//! what slips past the plan becomes one error instead of wgpu's panic (exit 101).

mod common;
use common::{gpu, temp_dir, SWEEP_SCENE};
use penumbra::research::gpu::GpuContext;
use std::path::Path;

/// 4096² maps, 64 MiB each, as in the report that found the panic.
const MAP: u64 = 4096;
const MAP_BYTES: u64 = MAP * MAP * 4;

/// `regular:n=N` whose N² maps of 4096² are past the device's largest heap, and a budget that
/// holds them all in one array. On lavapipe's 2 GiB heap: n = 6 (36 maps, 2.25 GiB), budget 4096,
/// the setting of the report.
fn past_the_heap(heap: u64) -> (u32, u64) {
    let maps = heap / MAP_BYTES + 1;
    let n = (maps as f64).sqrt().ceil() as u32;
    let budget_mib = (((n as u64).pow(2) * MAP_BYTES) >> 20).max(4096);
    (n, budget_mib)
}

fn heap() -> u64 {
    gpu()
        .largest_heap
        .expect("a Vulkan device reports its memory heaps")
}

/// Runs `args` in `dir` with its own reference cache; it must fail with exactly `want`, exit 1,
/// no panic, nothing written, the cache untouched (nothing was traced).
fn refused(dir: &Path, args: &[&str], want: &str) {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_penumbra"))
        .current_dir(dir)
        .args(args)
        .args(["--out", "out"])
        .env("PENUMBRA_NO_PROGRESS", "1")
        .env("PENUMBRA_CACHE", dir.join("cache"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{args:?}: {stderr}");
    assert_eq!(stderr.trim_end(), format!("error: {want}"), "{args:?}");
    assert!(
        out.stdout.is_empty(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stdout)
    );
    assert!(
        !dir.join("out").exists(),
        "{args:?} wrote its output folder"
    );
    assert!(!dir.join("cache").exists(), "{args:?} traced a reference");
}

#[test]
fn an_array_past_the_heap_is_refused_by_render_and_compare_naming_the_budget() {
    let heap = heap();
    let (n, budget) = past_the_heap(heap);
    let dir = temp_dir("device_memory_array");
    std::fs::write(dir.join("scene.toml"), SWEEP_SCENE).unwrap();
    let method = format!("regular:n={n}");
    let maps = format!("shadow_map_size={MAP}");
    // The report's second setting: a budget far past host memory still names the budget, not the
    // resolution.
    for budget in [budget, 100_000] {
        let want = format!(
            "shadow_map_budget_mib = {budget}: the shadow-map array ({0} maps of {MAP}x{MAP}, shadow_map_size = {MAP}) needs {1} bytes ({2:.1} GiB), \
             over this device's largest memory heap (one allocation must fit in one heap) {heap} ({3:.1} GiB); lower it to split the maps into smaller arrays",
            n * n,
            (n * n) as u64 * MAP_BYTES,
            ((n * n) as u64 * MAP_BYTES) as f64 / (1u64 << 30) as f64,
            heap as f64 / (1u64 << 30) as f64,
        );
        let budget = format!("shadow_map_budget_mib={budget}");
        refused(
            &dir,
            &[
                "render",
                "--scene",
                "scene.toml",
                "--method",
                &method,
                "--set",
                &maps,
                "--set",
                &budget,
            ],
            &want,
        );
        refused(
            &dir,
            &[
                "compare",
                "--scene",
                "scene.toml",
                "--methods",
                &method,
                "--samples",
                "2",
                "--set",
                &maps,
                "--set",
                &budget,
            ],
            &want,
        );
    }
}

#[test]
fn lavapipe_reports_one_heap_of_2_gib() {
    let ctx = gpu();
    if ctx.summary.name.contains("llvmpipe") {
        assert_eq!(ctx.largest_heap, Some(2 << 30));
    }
    assert!(heap() >= 1 << 30, "a heap of {} bytes", heap());
}

/// An array the plan never saw (created directly): inside a scope it is an `Err`, outside one the
/// next wait returns it. wgpu's default handler would have panicked at `create_texture`.
#[test]
fn what_slips_past_the_plan_is_an_error_not_a_panic() {
    // Its own device: the uncaptured error is kept per device.
    let ctx = GpuContext::new().unwrap();
    let layers = (ctx.largest_heap.unwrap() / MAP_BYTES + 1) as u32;
    let make = || {
        ctx.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("too large"),
            size: wgpu::Extent3d {
                width: MAP as u32,
                height: MAP as u32,
                depth_or_array_layers: layers,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Depth32Float,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        })
    };
    let e = ctx
        .scoped("the test's array", || Ok(make()))
        .expect_err("the device refuses the array")
        .to_string();
    assert_eq!(e, "gpu: the test's array: Out of Memory: In Device::create_texture, label = 'too large': Not enough memory left.");
    ctx.wait().expect("the scope kept the error");
    let _unscoped = make();
    assert_eq!(ctx.wait().unwrap_err().to_string(), "gpu: Out of Memory: In Device::create_texture, label = 'too large': Not enough memory left.");
    // Reported once.
    ctx.wait().unwrap();
}

/// `regions` across its documented `force` range (1..=128): a batch of culled maps binds 256 KiB
/// of culling tiles a map, so it holds at most one binding's worth (512 maps on lavapipe) and a
/// larger grid takes several batches. Before, every `force` from 23 up (529 maps) failed with
/// wgpu's `Buffer binding 4 range 138674176 exceeds …` ('footprint'), and `max_n` 32 or 64 once the
/// top class reached 23. force = 23 (two batches) renders, and its V equals the grid it forces,
/// `regular:n=23,layout=centred` on the same map size, bit for bit (culling never changes V).
#[test]
fn regions_past_one_batch_of_culled_maps_renders_the_grid_it_forces() {
    use penumbra::research::frame::{self, FrameResult};
    use penumbra::research::gpu::timing::TimingMode;
    use penumbra::research::methods::Method;
    use penumbra::research::scene::Scene;
    let ctx = gpu();
    let sets = [
        ("resolution".to_string(), "32".to_string()),
        ("shadow_map_size".to_string(), "16".to_string()),
    ];
    let scene = Scene::load("analytic-square", &sets).unwrap();
    let run = |spec: &str| -> FrameResult {
        frame::render(
            ctx,
            &scene,
            &Method::parse(spec, &[]).unwrap(),
            TimingMode::Frame,
        )
        .unwrap_or_else(|e| panic!("{spec}: {e}"))
    };
    let forced = run("regions:force=23,force_size=16,cull=on");
    let grid = run("regular:n=23,layout=centred");
    assert_eq!(
        forced.output.shadow_maps,
        529 + 1,
        "the grid and the decision's centre map"
    );
    assert!(
        forced.visibility == grid.visibility,
        "regions:force=23 differs from regular:n=23,layout=centred"
    );
    assert!(
        forced.visibility.iter().any(|v| *v > 0.0 && *v < 1.0),
        "a penumbra to compare"
    );
}

/// A map size `force_size` sets is known before the frame: its array is planned with the rest and
/// refused up front, naming the budget, where it ended in `Out of Memory … 'shadow maps'`.
#[test]
fn a_forced_map_size_past_the_heap_is_refused_up_front() {
    let heap = heap();
    let dir = temp_dir("device_memory_regions");
    std::fs::write(dir.join("scene.toml"), SWEEP_SCENE).unwrap();
    // 36 maps of 4096² are 2.25 GiB: past lavapipe's 2 GiB heap in one array of a budget that holds them.
    let n = ((heap / MAP_BYTES + 1) as f64).sqrt().ceil() as u32;
    let want = format!(
        "shadow_map_budget_mib = 100000: the shadow-map array ({0} maps of {MAP}x{MAP}, regions:force = {n}, force_size = {MAP}) needs {1} bytes ({2:.1} GiB), \
         over this device's largest memory heap (one allocation must fit in one heap) {heap} ({3:.1} GiB); lower it to split the maps into smaller arrays",
        n * n,
        (n * n) as u64 * MAP_BYTES,
        ((n * n) as u64 * MAP_BYTES) as f64 / (1u64 << 30) as f64,
        heap as f64 / (1u64 << 30) as f64,
    );
    let method = format!("regions:force={n},force_size={MAP}");
    refused(
        &dir,
        &[
            "render",
            "--scene",
            "scene.toml",
            "--method",
            &method,
            "--set",
            "shadow_map_budget_mib=100000",
        ],
        &want,
    );
}
