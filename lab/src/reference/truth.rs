//! The reference image of a scene: its camera G-buffer traced on the CPU (`reference`), cached on
//! disk under a key of everything that changes the result, so a rerun costs a hash, not minutes.

use crate::gpu::GpuContext;
use crate::reference::{self, RefEmitter, RefLight, ReferenceMode, SurfacePoint, Tracer};
pub use crate::reference::{env_ray_length, ray_offset, RELATIVE_RAY_OFFSET};
use crate::render::gbuffer::GBufferCpu;
use crate::scene::Emitter;
use crate::scene::Scene;
use crate::{frame, progress, Error, Result};
use glam::Vec3;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The fixed seed of the continuous mode (method.md §5: "fixed seed").
pub const CONTINUOUS_SEED: u64 = 0x5eed;

/// `lattice`, `continuous` (with `samples` per side, M×M stratified), or `point` (the light's
/// centre) / `point:S,T` (light coordinates in [0, 1]).
pub fn parse_mode(name: &str, samples: u32) -> Result<ReferenceMode> {
    match name {
        "lattice" => Ok(ReferenceMode::Lattice),
        "continuous" if (1..=256).contains(&samples) => Ok(ReferenceMode::Continuous {
            m: samples,
            seed: CONTINUOUS_SEED,
        }),
        "continuous" => Err(Error::param(format!(
            "--samples must be in 1..=256, got {samples}"
        ))),
        "point" => Ok(ReferenceMode::Point { s: 0.5, t: 0.5 }),
        _ => match name.strip_prefix("point:") {
            Some(at) => parse_point(at).map(|(s, t)| ReferenceMode::Point { s, t }),
            None => Err(Error::param(format!(
                "reference mode `{name}`: use `lattice`, `continuous`, `point` or `point:S,T`"
            ))),
        },
    }
}

/// `S,T` light coordinates, each in [0, 1].
fn parse_point(at: &str) -> Result<(f32, f32)> {
    let bad = || {
        Error::param(format!("reference point `{at}`: give S,T, two numbers in [0, 1] (0.5,0.5 is the light's centre)"))
    };
    let (s, t) = at.split_once(',').ok_or_else(bad)?;
    let parse = |v: &str| {
        v.trim()
            .parse::<f32>()
            .ok()
            .filter(|x| (0.0..=1.0).contains(x))
    };
    Ok((parse(s).ok_or_else(bad)?, parse(t).ok_or_else(bad)?))
}

/// Short description for tables and records: `continuous 32x32` or `lattice 17x17`.
pub fn mode_label(mode: &ReferenceMode) -> String {
    match *mode {
        ReferenceMode::Lattice => "lattice 17x17".into(),
        ReferenceMode::Continuous { m, .. } => format!("continuous {m}x{m}"),
        ReferenceMode::Point { s, t } if s == 0.5 && t == 0.5 => "point (light centre)".into(),
        ReferenceMode::Point { s, t } => format!("point ({s}, {t})"),
    }
}

/// `$PENUMBRA_CACHE/reference`, else `$XDG_CACHE_HOME/penumbra/reference`, else
/// `~/.cache/penumbra/reference` (the asset cache's root, one folder per kind of entry).
pub fn default_cache_dir() -> Option<PathBuf> {
    let var = |k| {
        std::env::var_os(k)
            .filter(|v| !v.is_empty())
            .map(PathBuf::from)
    };
    let root = var("PENUMBRA_CACHE")
        .or_else(|| {
            var("XDG_CACHE_HOME")
                .filter(|p| p.is_absolute())
                .map(|p| p.join("penumbra"))
        })
        .or_else(|| var("HOME").map(|h| h.join(".cache/penumbra")))?;
    Some(root.join("reference"))
}

/// What the reference cache may do in one call.
#[derive(Clone, Debug)]
pub enum Cache {
    /// Neither read nor write (`--no-cache`: the cache is not touched, so a read-only or damaged
    /// cache folder cannot stop the run).
    Off,
    /// Read a stored result; store a fresh one.
    Use(PathBuf),
    /// Trace regardless, then store the result.
    Refresh(PathBuf),
}

impl Cache {
    /// The default folder, or `Off` with `no_cache` (`--no-cache`) or when no folder can be named
    /// (no HOME).
    pub fn default_for(no_cache: bool) -> Cache {
        match default_cache_dir() {
            Some(dir) if !no_cache => Cache::Use(dir),
            _ => Cache::Off,
        }
    }
}

/// Says once that the cache folder `dir` cannot take this entry (`why`): the reference is traced
/// and not stored, and the run goes on (a read-only cache only costs the time of tracing).
fn unwritable(dir: &Path, why: &dyn std::fmt::Display) {
    progress::suspend(|| {
        eprintln!("warning: reference cache folder {}: {why}: the reference is traced and not stored (make the folder writable, or run with --no-cache to leave the cache alone)", dir.display())
    });
}

/// A traced (or cached) reference: V per pixel, row-major, 0 on background.
pub struct ReferenceImage {
    pub values: Vec<f32>,
    pub width: u32,
    pub height: u32,
    pub mode: ReferenceMode,
    pub ray_offset: f32,
    pub key: String,
    /// `Some(path)` when read from or written to the cache.
    pub cache_file: Option<PathBuf>,
    pub cached: bool,
    /// Tracing figures; `None` when the image came from the cache.
    pub trace: Option<TraceStats>,
    /// Environment scenes: the Monte Carlo standard error of V over geometry pixels (mean, max);
    /// `None` when the image came from the cache or the light is an area light.
    pub std_error: Option<(f32, f32)>,
}

#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct TraceStats {
    /// Who traced it: `cpu` (the lab's tracer, `threads` of them) or `gpu` (`truth_trace`).
    pub tracer: &'static str,
    pub seconds: f64,
    /// Shadow rays actually traced (samples below p's tangent plane need none).
    pub rays: u64,
    pub rays_per_s: f64,
    /// Geometry pixels × samples per pixel, per second: the figure comparable across scenes.
    pub samples_per_s: f64,
    pub bvh_build_s: f64,
    pub threads: usize,
    /// The GPU tracer's rays a tie in f32 decided (docs/certify.md §2); None on the CPU.
    pub ties: Option<u64>,
}

/// Who traces a reference: the lab's CPU tracer, or `truth_trace` on the GPU (the same values,
/// lab/tests/truth_trace.rs). `Auto` takes the GPU where the adapter is a real GPU and the
/// scene's light is one it traces, else the CPU.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TracerChoice {
    Auto,
    Cpu,
    Gpu,
}

impl TracerChoice {
    pub fn parse(name: &str) -> Result<TracerChoice> {
        match name {
            "auto" => Ok(TracerChoice::Auto),
            "cpu" => Ok(TracerChoice::Cpu),
            "gpu" => Ok(TracerChoice::Gpu),
            _ => Err(Error::param(format!(
                "--tracer {name}: use auto, cpu or gpu"
            ))),
        }
    }

    /// Whether this reference goes to the GPU (`Gpu` where it cannot: an error naming why).
    fn on_gpu(self, ctx: &GpuContext, scene: &Scene, mode: &ReferenceMode) -> Result<bool> {
        let why = gpu_unsupported(scene, mode);
        match (self, why) {
            (TracerChoice::Cpu, _) => Ok(false),
            (TracerChoice::Gpu, Some(why)) => Err(Error::param(format!(
                "--tracer gpu: {}: {why}",
                scene.origin
            ))),
            (TracerChoice::Gpu, None) => Ok(true),
            (TracerChoice::Auto, why) => Ok(why.is_none() && ctx.summary.device_type != "Cpu"),
        }
    }
}

/// Why the GPU tracer cannot trace this reference, if it cannot.
fn gpu_unsupported(scene: &Scene, mode: &ReferenceMode) -> Option<&'static str> {
    if let Some(why) = penumbra::research::certify::truth::unsupported(scene) {
        return Some(why);
    }
    let maps_points = matches!(scene.emitter, Emitter::Point(_) | Emitter::Spot(_))
        && !matches!(mode, ReferenceMode::Continuous { .. });
    maps_points.then_some("the lattice and point modes of a point or spot light trace its maps' own light points, which the CPU tracer alone does")
}

/// The mode as the GPU tracer takes it.
fn truth_samples(mode: &ReferenceMode) -> penumbra::research::certify::truth::TruthSamples {
    use penumbra::research::certify::truth::TruthSamples;
    match *mode {
        ReferenceMode::Continuous { m, seed } => TruthSamples::Continuous { m, seed },
        ReferenceMode::Lattice => TruthSamples::Lattice,
        ReferenceMode::Point { s, t } => TruthSamples::Point { s, t },
    }
}

impl ReferenceImage {
    pub fn record(&self, scene: &Scene, geometry_pixels: usize) -> serde_json::Value {
        serde_json::json!({
            "scene": scene.name,
            "scene_origin": scene.origin,
            "triangles": scene.triangle_count(),
            "resolution": [self.width, self.height],
            "geometry_pixels": geometry_pixels,
            "mode": mode_label(&self.mode),
            "samples_per_pixel": self.mode.samples_per_pixel(),
            "seed": match self.mode { ReferenceMode::Continuous { seed, .. } => Some(seed), _ => None },
            "point": match self.mode { ReferenceMode::Point { s, t } => Some([s, t]), _ => None },
            "ray_offset": self.ray_offset,
            "key": self.key,
            "cached": self.cached,
            "cache_file": self.cache_file.as_ref().map(|p| p.display().to_string()),
            "trace": self.trace,
            "std_error_mean_max": self.std_error,
            "version": crate::version(),
        })
    }
}

/// One G-buffer pixel as the tracer sees it; background is `None`.
pub fn surface_points(g: &GBufferCpu) -> Vec<Option<SurfacePoint>> {
    (0..g.position.len())
        .map(|i| {
            g.is_geometry(i).then(|| SurfacePoint {
                position: Vec3::from_slice(&g.position[i][..3]),
                normal: Vec3::from_slice(&g.normal[i][..3]),
            })
        })
        .collect()
}

fn light_of(scene: &Scene) -> RefLight {
    RefLight {
        center: scene.light.center,
        edge_u: scene.light.edge_u,
        edge_v: scene.light.edge_v,
    }
}

/// The emitter the reference samples when it is not the rectangle (`None`: `light_of`).
pub fn emitter_of(scene: &Scene) -> Option<RefEmitter> {
    match scene.emitter {
        Emitter::Rect => None,
        Emitter::Disk(d) => Some(RefEmitter::Disk {
            center: d.center,
            normal: d.normal,
            radius: d.radius,
        }),
        Emitter::Sun(s) => Some(RefEmitter::Sun {
            toward: s.toward(),
            tan_half: s.tan_half_angle(),
            reach: env_ray_length(scene),
        }),
        Emitter::Spot(s) => Some(RefEmitter::Spot {
            light: scene.light,
            spot: s,
        }),
        Emitter::Point(p) => Some(RefEmitter::Point {
            center: p.position,
            radius: p.radius,
        }),
    }
}

/// Cache key: triangles, camera, the G-buffer itself (it fixes the resolution and every traced
/// point), light, mode, ray offset, the tracer's `REFERENCE_VERSION` and the crate version.
pub fn cache_key(scene: &Scene, g: &GBufferCpu, mode: &ReferenceMode, offset: f32) -> String {
    let floats = |v: &mut Vec<u8>, xs: &[f32]| {
        xs.iter()
            .for_each(|x| v.extend_from_slice(&x.to_le_bytes()))
    };
    let mut tris = Vec::with_capacity(scene.triangle_count() * 36);
    for t in scene.triangles() {
        for p in t {
            floats(&mut tris, &p.to_array());
        }
    }
    let c = &scene.camera;
    let mut camera = Vec::new();
    floats(
        &mut camera,
        &[
            c.eye.x,
            c.eye.y,
            c.eye.z,
            c.target.x,
            c.target.y,
            c.target.z,
            c.up.x,
            c.up.y,
            c.up.z,
            c.fov_y_deg,
        ],
    );
    let size = [g.width.to_le_bytes(), g.height.to_le_bytes()].concat();
    let digest = reference::cache_key(&[
        env!("CARGO_PKG_VERSION").as_bytes(),
        &tris,
        &camera,
        &size,
        bytemuck::cast_slice(&g.position),
        bytemuck::cast_slice(&g.normal),
    ]);
    // An environment replaces the light: its panorama, rotation and intensity are in the key.
    let digest = match &scene.environment {
        Some(env) => reference::cache_key(&[digest.as_bytes(), b"environment", &env.key_bytes()]),
        None => digest,
    };
    // Another kind than the rectangle: its shape joins the key (a rectangle's key is as before).
    let digest = match emitter_of(scene) {
        Some(e) => reference::cache_key(&[digest.as_bytes(), b"emitter", &e.key_bytes()]),
        None => digest,
    };
    reference::reference_key(digest.as_bytes(), &light_of(scene), mode, offset)
}

/// Traces `scene`'s reference over `g` on the CPU, or reads it from the cache (written after a trace).
pub fn compute(
    scene: &Scene,
    g: &GBufferCpu,
    mode: ReferenceMode,
    cache: &Cache,
) -> Result<ReferenceImage> {
    compute_with(scene, g, mode, cache, None)
}

/// [`compute`], traced by `gpu` (`truth_trace` on its context) where given. The cache's file and
/// key are the same whoever traces: the values are.
pub fn compute_with(
    scene: &Scene,
    g: &GBufferCpu,
    mode: ReferenceMode,
    cache: &Cache,
    gpu: Option<&GpuContext>,
) -> Result<ReferenceImage> {
    let offset = ray_offset(scene);
    let key = cache_key(scene, g, &mode, offset);
    let mut image = ReferenceImage {
        values: Vec::new(),
        width: g.width,
        height: g.height,
        mode,
        ray_offset: offset,
        key: key.clone(),
        cache_file: None,
        cached: false,
        trace: None,
        std_error: None,
    };
    // Concurrent runs (shards) share the cache: the first to miss traces under the entry's lock,
    // the others wait for the lock and then read what it wrote. A damaged entry (digest, values
    // outside [0, 1], the old format) is never used: one warning names it, and it is traced
    // again and replaced, so the figures equal a clean run's.
    let mut _lock = None;
    let mut store = true;
    if let Cache::Use(dir) | Cache::Refresh(dir) = cache {
        let mut warned = false;
        let mut hit = |image: &mut ReferenceImage| -> Result<bool> {
            if !matches!(cache, Cache::Use(_)) {
                return Ok(false);
            }
            let path = reference::cache_path(dir, &key);
            match reference::load_cached(dir, &key, g.width, g.height)? {
                reference::Lookup::Hit(values) => {
                    image.values = values;
                    image.cache_file = Some(path);
                    image.cached = true;
                    Ok(true)
                }
                reference::Lookup::Miss => Ok(false),
                reference::Lookup::Damaged(why) => {
                    if !std::mem::replace(&mut warned, true) {
                        progress::suspend(|| {
                            eprintln!("warning: reference cache file {} {why}: not used; tracing the reference again", path.display())
                        });
                    }
                    Ok(false)
                }
            }
        };
        if hit(&mut image)? {
            return Ok(image);
        }
        let say = &mut |who: &str| {
            progress::suspend(|| {
                eprintln!(
                    "reference: waiting for {} (held by pid/host {who})",
                    dir.join(format!("{key}.lock")).display()
                )
            })
        };
        match reference::lock(dir, &key, say) {
            Ok(l) => _lock = Some(l),
            Err(e) => {
                unwritable(dir, &e.to_string().trim_start_matches("reference cache: "));
                store = false;
            }
        }
        if store && hit(&mut image)? {
            return Ok(image);
        }
    }
    if let Some(ctx) = gpu {
        let (values, trace) = trace_on_gpu(ctx, scene, g, &mode)?;
        image.trace = Some(trace);
        if let Cache::Use(dir) | Cache::Refresh(dir) = cache {
            image.cache_file = Some(reference::save_cached(
                dir, &key, g.width, g.height, &values,
            )?);
        }
        image.values = values;
        return Ok(image);
    }
    let build = Instant::now();
    let tracer = Tracer::new(&scene.triangles());
    let bvh_build_s = build.elapsed().as_secs_f64();
    let points = surface_points(g);
    let bar = progress::bar(
        points.len() as u64,
        &format!("reference {}", mode_label(&mode)),
    );
    let start = Instant::now();
    let values = match &scene.environment {
        // Importance sampling of the panorama, M×M samples per pixel (docs/environment.md §3).
        Some(env) => {
            let (samples, seed) = match mode {
                ReferenceMode::Continuous { m, seed } => (m * m, seed),
                ReferenceMode::Lattice | ReferenceMode::Point { .. } => {
                    return Err(Error::param("an environment scene's reference is `continuous` (lattice and point modes belong to the area light)".into()))
                }
            };
            let r = crate::reference::environment::trace(
                &tracer,
                env,
                &points,
                samples,
                offset,
                env_ray_length(scene),
                seed,
                &|n| bar.set_position(n as u64),
            );
            image.std_error = Some(crate::reference::environment::error_summary(&r, &points));
            r.values
        }
        None => match emitter_of(scene) {
            None => reference::try_trace_visibility(
                &tracer,
                &points,
                &light_of(scene),
                &mode,
                offset,
                &|n| bar.set_position(n as u64),
            )?,
            Some(e) => reference::try_trace_emitter(&tracer, &points, &e, &mode, offset, &|n| {
                bar.set_position(n as u64)
            })?,
        },
    };
    let seconds = start.elapsed().as_secs_f64();
    bar.finish_and_clear();
    let geometry = points.iter().filter(|p| p.is_some()).count();
    let rays = tracer.rays_traced();
    image.trace = Some(TraceStats {
        tracer: "cpu",
        seconds,
        rays,
        rays_per_s: rays as f64 / seconds.max(1e-9),
        samples_per_s: (geometry * mode.samples_per_pixel()) as f64 / seconds.max(1e-9),
        bvh_build_s,
        threads: rayon::current_num_threads(),
        ties: None,
    });
    if let (Cache::Use(dir) | Cache::Refresh(dir), true) = (cache, store) {
        match reference::save_cached(dir, &key, g.width, g.height, &values) {
            Ok(path) => image.cache_file = Some(path),
            // The figures are the traced ones either way: a cache that cannot store them is a warning.
            Err(e) => unwritable(dir, &e),
        }
    }
    image.values = values;
    Ok(image)
}

/// Every geometry pixel of `g` traced by `truth_trace` on `ctx`: V and the figures.
fn trace_on_gpu(
    ctx: &GpuContext,
    scene: &Scene,
    g: &GBufferCpu,
    mode: &ReferenceMode,
) -> Result<(Vec<f32>, TraceStats)> {
    let tracer = penumbra::research::certify::truth::TruthTracer::new(ctx, scene)?;
    let pixels: Vec<u32> = (0..g.position.len() as u32)
        .filter(|&i| g.is_geometry(i as usize))
        .collect();
    let points: Vec<_> = pixels
        .iter()
        .map(|&p| penumbra::research::certify::truth::point_of(g, p))
        .collect();
    let bar = progress::bar(
        points.len() as u64,
        &format!("reference {} (GPU)", mode_label(mode)),
    );
    let counts = tracer.trace(ctx, &truth_samples(mode), &points, &|n| {
        bar.set_position(n as u64)
    })?;
    bar.finish_and_clear();
    let mut values = vec![0.0f32; g.position.len()];
    for (k, &p) in pixels.iter().enumerate() {
        values[p as usize] = counts.visibility(k);
    }
    let seconds = counts.ms / 1e3;
    let stats = TraceStats {
        tracer: "gpu",
        seconds,
        rays: counts.rays(),
        rays_per_s: counts.rays() as f64 / seconds.max(1e-9),
        samples_per_s: (pixels.len() as f64 * counts.samples_per_pixel as f64) / seconds.max(1e-9),
        bvh_build_s: tracer.build_ms / 1e3,
        threads: 0,
        ties: Some(counts.ties()),
    };
    Ok((values, stats))
}

/// The G-buffer of `scene` rendered on `ctx`, then [`compute`]: traced on the GPU where the
/// adapter is a real GPU (`TracerChoice::Auto`), else on the CPU.
pub fn for_scene(
    ctx: &GpuContext,
    scene: &Scene,
    mode: ReferenceMode,
    cache: &Cache,
) -> Result<(GBufferCpu, ReferenceImage)> {
    for_scene_with(ctx, scene, mode, cache, TracerChoice::Auto)
}

/// [`for_scene`] with the tracer chosen (`penumbra reference --tracer`).
pub fn for_scene_with(
    ctx: &GpuContext,
    scene: &Scene,
    mode: ReferenceMode,
    cache: &Cache,
    tracer: TracerChoice,
) -> Result<(GBufferCpu, ReferenceImage)> {
    let g = frame::gbuffer_only(ctx, scene)?;
    if g.geometry_count() == 0 {
        return Err(scene.nothing_visible().into());
    }
    let gpu = tracer.on_gpu(ctx, scene, &mode)?.then_some(ctx);
    let image = compute_with(scene, &g, mode, cache, gpu)?;
    Ok((g, image))
}

/// The visibility of `scene` over `g` for each of `modes` (area lights only), uncached, with one
/// tracer built for all of them: the estimate study's exact visibility at a grid's points is the
/// mean of hundreds of point modes, and a million-triangle scene's BVH takes seconds to build.
pub fn trace_modes(
    scene: &Scene,
    g: &GBufferCpu,
    modes: &[ReferenceMode],
) -> Result<Vec<Vec<f32>>> {
    if scene.environment.is_some() {
        return Err(Error::param(
            "trace_modes: an environment scene's reference is `continuous`".into(),
        ));
    }
    let offset = ray_offset(scene);
    let tracer = Tracer::new(&scene.triangles());
    let points = surface_points(g);
    let bar = progress::bar(modes.len() as u64, "exact visibility");
    let images = modes
        .iter()
        .map(|mode| {
            bar.inc(1);
            Ok(match emitter_of(scene) {
                None => reference::try_trace_visibility(
                    &tracer,
                    &points,
                    &light_of(scene),
                    mode,
                    offset,
                    &|_| {},
                )?,
                Some(e) => {
                    reference::try_trace_emitter(&tracer, &points, &e, mode, offset, &|_| {})?
                }
            })
        })
        .collect();
    bar.finish_and_clear();
    images
}
