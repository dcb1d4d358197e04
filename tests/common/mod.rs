//! Helpers shared by the engine's integration tests, and by the lab's (lab/tests/common adds
//! the runners of the `penumbra` binary).
#![allow(dead_code)]

/// Camera, light and render settings of a tiny 32x32 test scene; tests append their meshes.
/// A macro so that `concat!` can build whole scenes as literals.
#[allow(unused_macros)]
macro_rules! tiny_scene_head {
    () => {
        r#"
[camera]
eye = [0.0, 6.0, 8.0]
target = [0.0, 0.0, 0.0]
fov_y_deg = 45.0

[light]
center = [0.0, 8.0, 0.0]
edge_u = [2.0, 0.0, 0.0]
edge_v = [0.0, 0.0, 2.0]

[render]
width = 32
height = 32
shadow_map_size = 64
"#
    };
}

pub mod layers;

/// The same 32x32 camera and render settings with no `[light]`: tests that vary the light put
/// `[light]` and its keys in front and append their meshes.
#[allow(unused_macros)]
macro_rules! unlit_scene_head {
    () => {
        r#"
[camera]
eye = [0.0, 6.0, 8.0]
target = [0.0, 0.0, 0.0]
fov_y_deg = 45.0

[render]
width = 32
height = 32
shadow_map_size = 64
"#
    };
}

use penumbra::research::gpu::GpuContext;
use std::path::PathBuf;
use std::process::Output;

/// The tiny scene of the sweep and gate tests (lab/tests/shards.rs, slurm_scripts.rs, check.rs): a box over
/// a plane at 32x32 with 64² shadow maps.
pub const SWEEP_SCENE: &str = concat!(
    "name = \"tiny\"\n",
    tiny_scene_head!(),
    r#"
[[mesh]]
builtin = "plane"
scale = 10.0

[[mesh]]
builtin = "box"
translate = [0.0, 1.0, 0.0]
"#
);

/// Their sweep spec: six configurations, from 1 to 25 shadow maps.
pub const SWEEP_SPEC: &str = r#"
methods = ["hard"]
[[grid]]
method = "regular"
n = [2, 3, 5]
[[grid]]
method = "adaptive"
p_m = [0, 5]
"#;

/// The rows of `dir/results.jsonl`.
pub fn rows(dir: &std::path::Path) -> Vec<serde_json::Value> {
    std::fs::read_to_string(dir.join("results.jsonl"))
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

/// A row without what differs between runs of one sweep: timings, and the shard it came from.
pub fn untimed(r: &serde_json::Value) -> serde_json::Value {
    let mut r = r.clone();
    let o = r.as_object_mut().unwrap();
    for k in [
        "frame_ms",
        "frame_ms_min",
        "frame_ms_max",
        "frame_ms_runs",
        "stages_ms",
        "setup_ms",
    ] {
        o.remove(k);
    }
    o["provenance"]["spec"]
        .as_object_mut()
        .unwrap()
        .remove("shard");
    r
}

/// `out`, after checking that its command succeeded (else fails with its stdout and stderr).
pub fn ok(out: Output, what: &str) -> Output {
    assert!(
        out.status.success(),
        "{what} failed: {}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// The test binary's one GPU context, opened on first use and shared by every test (opening a
/// device costs more than most tests); a missing adapter fails each test with instructions, never
/// skips it.
pub fn gpu() -> &'static GpuContext {
    static CTX: std::sync::OnceLock<Result<GpuContext, String>> = std::sync::OnceLock::new();
    match CTX.get_or_init(|| GpuContext::new().map_err(|e| e.to_string())) {
        Ok(ctx) => ctx,
        Err(e) => panic!("GPU test needs an adapter: {e}"),
    }
}

/// A fresh temporary folder under the target dir.
pub fn temp_dir(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Small deterministic generator (tests must not depend on an RNG crate's stream).
pub struct Lcg(pub u64);

impl Lcg {
    pub fn next_f32(&mut self) -> f32 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 40) as f32) / (1u64 << 24) as f32
    }
    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.next_f32()
    }
}

/// A random scene: boxes and spheres over a ground plane, a random camera, a tilted square light.
pub fn random_scene_toml(seed: u64, size: u32, map: u32) -> String {
    let mut r = Lcg(seed.wrapping_mul(0x9E3779B97F4A7C15) ^ 0xD1B54A32D192ED03);
    for _ in 0..4 {
        r.next_f32();
    }
    let angle = r.range(0.0, std::f32::consts::TAU);
    let dist = r.range(14.0, 20.0);
    let (ex, ez) = (angle.cos() * dist, angle.sin() * dist);
    let ey = r.range(8.0, 16.0);
    let (lx, ly, lz) = (r.range(-4.0, 4.0), r.range(9.0, 14.0), r.range(-4.0, 4.0));
    let (su, sv) = (r.range(1.0, 4.5), r.range(1.0, 4.5));
    let tilt = r.range(-0.25, 0.25);
    let mut s = format!(
        "[camera]\neye = [{ex}, {ey}, {ez}]\ntarget = [0.0, 1.0, 0.0]\nfov_y_deg = 45.0\n\n\
         [light]\ncenter = [{lx}, {ly}, {lz}]\nedge_u = [{su}, {}, 0.0]\nedge_v = [0.0, {}, {sv}]\n\n\
         [render]\nwidth = {size}\nheight = {size}\nshadow_map_size = {map}\n\n\
         [[mesh]]\nbuiltin = \"plane\"\nscale = [18.0, 1.0, 18.0]\n",
        su * tilt,
        -sv * tilt * 0.5
    );
    let objects = 2 + (r.next_f32() * 3.0) as u32;
    for _ in 0..objects {
        let kind = if r.next_f32() < 0.5 { "box" } else { "sphere" };
        let (x, z) = (r.range(-4.0, 4.0), r.range(-4.0, 4.0));
        let scale = r.range(0.6, 2.0);
        let y = r.range(scale * 0.5, 5.0);
        s += &format!(
            "\n[[mesh]]\nbuiltin = \"{kind}\"\nsegments = 12\ntranslate = [{x}, {y}, {z}]\nrotate_deg = [0.0, {}, 0.0]\nscale = {scale}\n",
            r.range(0.0, 90.0)
        );
    }
    s
}

/// One frame of `method` with the intermediates it would overwrite kept, and its buffers as
/// `Renderer::inspect` reads them after the frame (the CPU twins' inputs).
pub fn inspected<T: 'static>(
    ctx: &GpuContext,
    scene: &penumbra::research::scene::Scene,
    method: &penumbra::research::methods::Method,
    options: penumbra::research::frame::FrameOptions,
) -> (penumbra::research::frame::FrameResult, T) {
    let mut renderer =
        penumbra::research::frame::Renderer::new(ctx, scene, method).expect("renderer");
    renderer.keep_intermediates();
    let r = renderer.frame(options).expect("frame");
    let t = renderer
        .inspect::<T>()
        .expect("read back")
        .unwrap_or_else(|| panic!("{method:?} shows no {}", std::any::type_name::<T>()));
    (r, t)
}

/// One adaptive frame with pictures, and its trace (`keep`: with the twins' intermediate buffers).
pub fn traced(
    ctx: &GpuContext,
    scene: &penumbra::research::scene::Scene,
    p: &penumbra::research::methods::AdaptiveParams,
    keep: bool,
) -> (
    penumbra::research::frame::FrameResult,
    penumbra::research::methods::adaptive::AdaptiveTrace,
) {
    let options = penumbra::research::frame::FrameOptions {
        mode: penumbra::research::gpu::timing::TimingMode::Frame,
        pictures: true,
    };
    let method = penumbra::research::methods::Method::adaptive(p.clone());
    if keep {
        return inspected(ctx, scene, &method, options);
    }
    let mut renderer =
        penumbra::research::frame::Renderer::new(ctx, scene, &method).expect("renderer");
    let r = renderer.frame(options).expect("adaptive frame");
    let t = renderer
        .inspect()
        .expect("read back")
        .expect("the adaptive method keeps a trace");
    (r, t)
}

/// `text` (a scene with a `[light]` table before `[render]`, as `random_scene_toml` writes it)
/// under a sun instead: for the methods that take the sun alone (`cascades`).
pub fn with_sun(text: &str) -> String {
    let (head, rest) = text.split_once("[light]\n").expect("a [light] table");
    let (_, tail) = rest
        .split_once("\n\n[render]")
        .expect("[render] after [light]");
    format!("{head}[light]\nkind = \"sun\"\ndirection = [-0.4, -1.0, 0.3]\nangular_diameter_deg = 3.0\n\n[render]{tail}")
}
