//! Sweeps in constant memory (docs/robustness.md, "Sweep memory"): the measure loop builds a
//! window of renderers at a time and carries what no method owns from one to the next, so peak
//! memory does not grow with the number of configurations, V stays that of a fresh renderer, and
//! a grid over `--max-configs` is refused before anything runs.

mod common;
use penumbra::research::frame::{FrameOptions, Renderer};
use penumbra::research::gpu::timing::TimingMode;
use penumbra::research::methods::Method;
use penumbra::research::scene::Scene;
use penumbra_lab::record::measure::{self, WINDOW};
use std::path::Path;
use std::process::Command;

/// An adaptive grid of `n` configurations (p_m = 0..n).
fn adaptive_spec(dir: &Path, n: usize) -> String {
    let p_m: Vec<String> = (0..n).map(|i| i.to_string()).collect();
    let path = dir.join(format!("adaptive-{n}.toml"));
    std::fs::write(
        &path,
        format!(
            "[[grid]]\nmethod = \"adaptive\"\np_m = [{}]\n",
            p_m.join(", ")
        ),
    )
    .unwrap();
    path.to_string_lossy().into_owned()
}

/// Runs the binary to the end and returns its exit code, stderr and peak resident set (KiB), read
/// from `wait4`'s rusage of that one child.
#[allow(clippy::zombie_processes)] // the child is reaped by wait4 below, which also gives its rusage
fn run_measured(args: &[&str], cache: &Path) -> (Option<i32>, String, i64) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_penumbra"))
        .args(args)
        .env("PENUMBRA_NO_PROGRESS", "1")
        .env("PENUMBRA_CACHE", cache)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("run penumbra");
    let mut stderr = String::new();
    std::io::Read::read_to_string(child.stderr.as_mut().unwrap(), &mut stderr).unwrap();
    let mut status = 0;
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: the pid is our own child, not yet waited for; both pointers are to live locals.
    let pid = unsafe { libc::wait4(child.id() as libc::pid_t, &mut status, 0, &mut usage) };
    assert_eq!(pid, child.id() as libc::pid_t, "wait4 failed");
    let code = libc::WIFEXITED(status).then(|| libc::WEXITSTATUS(status));
    (code, stderr, usage.ru_maxrss)
}

/// 4 and 20 adaptive configurations at 64² with 256² maps (each adaptive state holds its 289
/// maps, about 76 MB): the larger sweep's peak is at most 1.5 times the smaller's. Measuring every
/// configuration at once, as before the windows, the 20 peaked at about 4 times the 4.
#[test]
fn peak_memory_does_not_grow_with_the_configuration_count() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let dir = common::temp_dir("sweep_memory_peak");
    let cache = dir.join("cache");
    let mut peaks = Vec::new();
    for n in [4, 20] {
        let spec = adaptive_spec(&dir, n);
        let out = dir.join(format!("out-{n}"));
        let args = [
            "sweep",
            "--scene",
            "analytic-square",
            "--spec",
            &spec,
            "--set",
            "resolution=64",
            "--set",
            "shadow_map_size=256",
            "--repeats",
            "1",
            "--out",
            out.to_str().unwrap(),
        ];
        let (code, stderr, peak_kib) = run_measured(&args, &cache);
        assert_eq!(code, Some(0), "{stderr}");
        assert!(
            stderr.starts_with(&format!("{n} configurations, {} frames: about ", 3 * n)),
            "the count comes first: {stderr}"
        );
        assert_eq!(common::rows(&out).len(), n);
        peaks.push(peak_kib);
    }
    let (small, large) = (peaks[0] as f64, peaks[1] as f64);
    assert!(
        large <= 1.5 * small,
        "peak RSS {:.0} MiB for 20 configurations against {:.0} MiB for 4",
        large / 1024.0,
        small / 1024.0
    );
}

/// Over the limit: one line naming --max-configs, exit 1, nothing written, nothing rendered;
/// `--max-configs` lets the same spec through.
#[test]
fn the_configuration_limit_refuses_in_one_line_and_max_configs_raises_it() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let dir = common::temp_dir("sweep_memory_limit");
    let cache = dir.join("cache");
    let spec = adaptive_spec(&dir, 3);
    let out = dir.join("out");
    let base = [
        "sweep",
        "--scene",
        "analytic-square",
        "--spec",
        &spec,
        "--set",
        "resolution=32",
        "--set",
        "shadow_map_size=64",
        "--repeats",
        "1",
        "--out",
        out.to_str().unwrap(),
    ];
    let refused: Vec<&str> = base.iter().copied().chain(["--max-configs", "2"]).collect();
    let (code, stderr, _) = run_measured(&refused, &cache);
    assert_eq!(code, Some(1), "{stderr}");
    assert_eq!(stderr.trim(), format!("error: {spec}: 3 configurations, more than --max-configs 2; pass --max-configs 3 to run them all"));
    assert!(
        !out.exists() && !cache.exists(),
        "a refused sweep writes nothing"
    );
    let methods: Vec<&str> = [
        "compare",
        "--scene",
        "analytic-square",
        "--methods",
        "hard,pcss,msm",
        "--max-configs",
        "2",
        "--out",
        out.to_str().unwrap(),
    ]
    .to_vec();
    let (code, stderr, _) = run_measured(&methods, &cache);
    assert_eq!((code, stderr.trim()), (Some(1), "error: --methods: 3 configurations, more than --max-configs 2; pass --max-configs 3 to run them all"));
    assert!(!out.exists());
    let allowed: Vec<&str> = base.iter().copied().chain(["--max-configs", "3"]).collect();
    let (code, stderr, _) = run_measured(&allowed, &cache);
    assert_eq!(code, Some(0), "{stderr}");
    assert_eq!(common::rows(&out).len(), 3);
}

/// V of methods measured through the windowed loop (more than one window, so later windows run
/// on what earlier ones left) equals, bit for bit, a fresh renderer's; `after` sees every method
/// once, in order, on a renderer that still renders.
#[test]
fn windowed_v_equals_a_fresh_renderer() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let ctx = common::gpu();
    let scene = Scene::load(
        "analytic-square",
        &[
            ("resolution".into(), "64".into()),
            ("shadow_map_size".into(), "128".into()),
        ],
    )
    .unwrap();
    let specs = [
        "adaptive:p_m=0",
        "hard",
        "regular:n=3",
        "adaptive:p_m=2,scope=local",
        "pcss",
        "adaptive:p_m=-1,max_level=2",
    ];
    assert!(specs.len() > WINDOW);
    let methods: Vec<Method> = specs
        .iter()
        .map(|s| Method::parse(s, &[]).unwrap())
        .collect();
    let mut afters = Vec::new();
    let measured = measure::measure_with(
        ctx,
        &scene,
        &methods,
        1,
        &mut |_, _, _| {},
        &mut |_, f| Ok(f.visibility.clone()),
        &mut |i, r: &mut Renderer| {
            let v = r
                .frame(FrameOptions {
                    mode: TimingMode::Frame,
                    pictures: false,
                })?
                .visibility;
            afters.push((i, v));
            Ok(())
        },
    )
    .unwrap();
    assert_eq!(
        afters.iter().map(|(i, _)| *i).collect::<Vec<_>>(),
        (0..specs.len()).collect::<Vec<_>>()
    );
    for ((m, got), (_, again)) in methods.iter().zip(&measured).zip(&afters) {
        let fresh = Renderer::new(ctx, &scene, m)
            .unwrap()
            .frame(FrameOptions {
                mode: TimingMode::Frame,
                pictures: false,
            })
            .unwrap()
            .visibility;
        let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        let got = got
            .as_ref()
            .unwrap_or_else(|e| panic!("{}: failed: {e}", m.label()));
        assert_eq!(
            bits(&got.judged),
            bits(&fresh),
            "{}: V differs from a fresh renderer's",
            m.label()
        );
        assert_eq!(
            bits(again),
            bits(&fresh),
            "{}: the after frame differs",
            m.label()
        );
        assert!(
            fresh.iter().any(|&v| v > 0.0) && fresh.iter().any(|&v| v < 1.0),
            "{}: lit and unlit pixels to compare",
            m.label()
        );
    }
}
