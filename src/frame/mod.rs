//! The frame driver: builds a scene's GPU state and a method's pipelines once ([`Renderer::new`]),
//! then runs frames on them ([`Renderer::frame`]): G-buffer, the method's maps and compute
//! stages, read-back. It knows methods only through `methods::MethodState`.

/// A certified bound on any frame's RMSE (docs/certify.md): it renders a second opinion, so it sits
/// above the methods, beside the renderer it certifies.
pub(crate) mod certify;

use crate::gpu::kernels::MapAccess;
use crate::gpu::structs::{GpuCamera, GpuFrame};
use crate::gpu::timing::{StageTimer, TimingMode};
use crate::gpu::{readback, GpuContext, Stage};
use crate::methods::{Method, MethodOutput, MethodState};
use crate::render::gbuffer::{self, GBuffer, GBufferCpu, GBufferPass};
use crate::render::kept_maps::{self, MapCache, Moved, ReuseCounts};
use crate::render::SceneGpu;
use crate::scene::{CullMode, Scene, Vertex};
use crate::stages::raster::Raster;
use crate::stages::shade::GeometryTiles;
use crate::stages::shade::ShadePass;
use crate::stages::{FrameGpu, FrameParts};
use crate::{Error, Result};
use std::collections::BTreeMap;
use std::sync::Arc;
use std::time::Instant;

/// What a renderer draws with, the context and the scene: borrowed from the caller (`&ctx`, the
/// lab's studies), or shared with it (`Arc`), so that a renderer owns what it needs and can be kept
/// by an object that outlives the caller's borrow (a Python `Renderer`).
pub enum Held<'a, T> {
    Borrowed(&'a T),
    Shared(Arc<T>),
}

impl<T> std::ops::Deref for Held<'_, T> {
    type Target = T;
    fn deref(&self) -> &T {
        match self {
            Held::Borrowed(t) => t,
            Held::Shared(t) => t,
        }
    }
}

impl<'a, T> From<&'a T> for Held<'a, T> {
    fn from(t: &'a T) -> Self {
        Held::Borrowed(t)
    }
}

impl<T> From<Arc<T>> for Held<'_, T> {
    fn from(t: Arc<T>) -> Self {
        Held::Shared(t)
    }
}

/// How to run a frame.
#[derive(Clone, Copy, Debug)]
pub struct FrameOptions {
    pub mode: TimingMode,
    /// Read back the decision pictures (comparison map, flags, samples per pixel): this makes the
    /// per-level read-back larger, so timed runs turn it off.
    pub pictures: bool,
}

impl From<TimingMode> for FrameOptions {
    /// Pictures on: what `penumbra render` writes.
    fn from(mode: TimingMode) -> Self {
        FrameOptions {
            mode,
            pictures: true,
        }
    }
}

pub struct FrameResult {
    pub visibility: Vec<f32>,
    pub gbuffer: GBufferCpu,
    pub output: MethodOutput,
    /// Wall time per stage. `setup` is the work before the frame's clock starts (zero fills; on
    /// a renderer's first frame also `build`: pipelines, buffers and the upload).
    pub stages_ms: BTreeMap<String, f64>,
    pub total_ms: f64,
    pub timing_waits: u32,
    /// How the frame was timed: `stages_ms` holds every stage only in stages mode; in frame mode
    /// it holds the frame's waits.
    pub timing: TimingMode,
    /// GPU timestamps per stage, where the adapter's are trusted; None otherwise.
    pub gpu_stages_ms: Option<BTreeMap<String, f64>>,
    /// Who rasterized the maps, and why (run.json's `raster`).
    pub raster: RasterUsed,
    /// Maps rendered, kept and partly drawn again this frame (docs/reuse.md).
    pub reuse: ReuseCounts,
}

/// The raster a frame used: `hardware` or `compute`, the `raster` setting that chose it, and what
/// `auto` measured when it chose.
#[derive(Clone, Debug, serde::Serialize)]
pub struct RasterUsed {
    pub used: &'static str,
    pub(crate) setting: crate::scene::RasterChoice,
    pub(crate) auto: Option<crate::stages::raster_auto::AutoTiming>,
}

pub fn frame_uniform(scene: &Scene) -> GpuFrame {
    let b = scene.render.bias;
    GpuFrame {
        width: scene.render.width,
        height: scene.render.height,
        map_size: scene.render.shadow_map_size,
        flags: if scene.render.self_shadow == crate::scene::SelfShadow::Facing { crate::gpu::structs::FRAME_FACING_TEST } else { 0 }
            // A point light has no back side (the reference sees no plane), and its cube faces
            // share the receivers out by their direction from light_center, the sphere's centre.
            | if scene.emitter.kind() == crate::scene::LightKind::Point { crate::gpu::structs::FRAME_EVERY_WAY } else { 0 }
            | match scene.render.maps {
                crate::scene::MapKind::Plain => 0,
                crate::scene::MapKind::Hybrid => scene.render.hybrid.levels << crate::stages::hybrid_build::FRAME_LEVELS_SHIFT,
            },
        light_center: [
            scene.light.center.x,
            scene.light.center.y,
            scene.light.center.z,
            1.0,
        ],
        light_normal: scene.light.normal().extend(0.0).to_array(),
        bias_constant: b.constant,
        bias_slope: b.slope,
        normal_offset: b.normal_offset,
        max_slope: b.max_slope,
        // One band until the frame's tile list says otherwise (`GeometryTiles::stamp`).
        ..Default::default()
    }
}

pub use crate::render::gbuffer::camera_uniform;

/// One scene and one method, built once: every frame reuses the pipelines and buffers. A study
/// whose scene changes between frames moves it to the next scene with [`Renderer::detach`] and
/// [`Detached::attach`] rather than building a new one.
pub struct Renderer<'a> {
    ctx: Held<'a, GpuContext>,
    scene: Held<'a, Scene>,
    parts: FrameParts,
    method: Method,
    gbuffer_pass: GBufferPass,
    camera: GpuCamera,
    /// The camera `set_camera` gave, when it is no longer the scene's: errors must name it.
    moved_camera: Option<crate::scene::Camera>,
    state: Box<dyn MethodState>,
    /// Wall time of building (pipelines, buffers, upload), charged to the first frame's `setup`.
    build: Option<(f64, f64)>,
    /// Record GPU timestamps even where the adapter's are not trusted (tests of the mechanics).
    force_timestamps: bool,
    /// What `raster = auto` measured when it chose this renderer's raster.
    raster_auto: Option<crate::stages::raster_auto::AutoTiming>,
}

impl<'a> Renderer<'a> {
    /// `ctx` and `scene` by reference (`&ctx`), or shared (`Arc`) for a renderer that owns them.
    pub fn new(
        ctx: impl Into<Held<'a, GpuContext>>,
        scene: impl Into<Held<'a, Scene>>,
        method: &Method,
    ) -> Result<Self> {
        Self::assemble(ctx.into(), scene.into(), method, None, false)
    }

    /// `new` whose method keeps its shadow maps from frame to frame where nothing they depend on
    /// changed (`reuse`; docs/reuse.md): V is the same bit for bit, the frame rasterizes less.
    pub fn with_reuse(
        ctx: impl Into<Held<'a, GpuContext>>,
        scene: impl Into<Held<'a, Scene>>,
        method: &Method,
        reuse: bool,
    ) -> Result<Self> {
        Self::assemble(ctx.into(), scene.into(), method, None, reuse)
    }

    /// Builds what `kept` lacks for `scene`. The method's state is always built anew: methods
    /// place their samples and frusta from the light and the bounds when they are built, so a
    /// fresh state is what keeps V exactly that of a new renderer.
    fn assemble(
        ctx: Held<'a, GpuContext>,
        scene: Held<'a, Scene>,
        method: &Method,
        kept: Option<Detached>,
        reuse: bool,
    ) -> Result<Self> {
        // Every size against the device and the host first: one line, not a wgpu panic later.
        crate::methods::sizes::check(&ctx, &scene, method)?;
        // What the plan cannot foresee (memory another process holds) fails here as one line too.
        let c = ctx.scoped(
            &format!("building {} on {}", method.label(), ctx.summary.name),
            || create(&ctx, &scene, method, kept, reuse),
        )?;
        let Created {
            parts,
            gbuffer_pass,
            camera,
            state,
            build,
            force_timestamps,
            raster_auto,
        } = c;
        Ok(Self {
            ctx,
            scene,
            parts,
            method: method.clone(),
            gbuffer_pass,
            camera,
            moved_camera: None,
            state,
            build: Some(build),
            force_timestamps,
            raster_auto,
        })
    }
}

/// What [`create`] builds: the renderer but for its context and scene.
struct Created {
    parts: FrameParts,
    gbuffer_pass: GBufferPass,
    camera: GpuCamera,
    state: Box<dyn MethodState>,
    build: (f64, f64),
    force_timestamps: bool,
    raster_auto: Option<crate::stages::raster_auto::AutoTiming>,
}

/// `assemble` once the sizes are checked: every buffer, texture and pipeline of the frame.
fn create(
    ctx: &GpuContext,
    scene: &Scene,
    method: &Method,
    kept: Option<Detached>,
    reuse: bool,
) -> Result<Created> {
    let start = Instant::now();
    let (w, h) = (scene.render.width, scene.render.height);
    // Per-pixel buffers past one binding are bound by bands of rows (stages::shade::Band).
    let band_rows = crate::methods::sizes::band_rows(scene, method, &ctx.limits());
    let mut force_timestamps = false;
    let (mut gbuffer_pass, mut targets, mut shade, mut raster, mut meshes) =
        (None, None, None, None, None);
    // What the same method's last state remembered (auto's choice), handed to the new one.
    let memory = kept
        .as_ref()
        .filter(|k| k.method == *method)
        .and_then(|k| k.memory.clone());
    let mut maps_kept = MapCache::new(reuse);
    if let Some(k) = kept {
        force_timestamps = k.force_timestamps;
        gbuffer_pass = Some(k.gbuffer_pass);
        // The G-buffer, the tile list and V are cleared or rewritten by every frame.
        if (k.gbuffer.width, k.gbuffer.height) == (w, h) && k.geometry_tiles.band_rows == band_rows
        {
            targets = Some((k.gbuffer, k.geometry_tiles, k.visibility));
        }
        shade = Some((k.maps, k.shade));
        raster = Some((k.cull, k.budget_mib, k.raster));
        let same_mesh = k.indices == scene.indices
            && bytemuck::cast_slice::<_, u8>(&k.vertices)
                == bytemuck::cast_slice::<_, u8>(&scene.vertices);
        if reuse && k.maps_kept.on {
            maps_kept = k.maps_kept;
            // Kept maps draw again what a moved mesh covered before or covers now; other
            // meshes, or other triangles, leave nothing to keep.
            if !same_mesh {
                match (k.indices == scene.indices)
                    .then(|| kept_maps::moved_boxes(&k.vertices, &scene.vertices, &scene.indices))
                {
                    Some(Moved::Boxes(before, after)) => maps_kept.moved(&before, &after),
                    Some(Moved::Nothing) => {}
                    _ => maps_kept.clear(),
                }
            }
        }
        meshes = same_mesh.then_some(k.scene_gpu);
    }
    let gbuffer_pass = match gbuffer_pass {
        Some(p) => p,
        None => GBufferPass::new(ctx)?,
    };
    let upload_start = Instant::now();
    let scene_gpu = match meshes {
        Some(m) => m,
        None => SceneGpu::upload(ctx, scene),
    };
    let upload_ms = upload_start.elapsed().as_secs_f64() * 1e3;
    let mut frame = frame_uniform(scene);
    // The raster first: whether it is compute decides how every kernel reads the maps.
    let (compute, raster_auto) =
        crate::stages::raster_auto::compute_raster(ctx, scene, &scene_gpu)?;
    let raster = match raster {
        Some((cull, budget, r))
            if cull == scene.render.cull
                && budget == scene.render.shadow_map_budget_mib
                && r.is_compute() == compute =>
        {
            r
        }
        _ => {
            // Another raster fills other layers (format, culled faces): nothing kept holds.
            maps_kept.clear();
            Raster::new(
                ctx,
                scene.render.cull,
                compute,
                scene.render.shadow_map_budget_mib,
            )?
        }
    };
    let access = raster.access(scene.render.maps);
    let shade = match shade {
        Some((a, s)) if a == access => s,
        _ => ShadePass::new(ctx, access)?,
    };
    let (gbuffer, geometry_tiles, visibility) = match targets {
        Some(t) => t,
        None => {
            let gbuffer = GBufferPass::allocate(ctx, w, h)?;
            let tiles = shade.tile_list_in_bands(ctx, &gbuffer, band_rows);
            (
                gbuffer,
                tiles,
                readback::zeroed_storage(ctx, "visibility", w as u64 * h as u64 * 4),
            )
        }
    };
    geometry_tiles.stamp(ctx, &mut frame);
    let parts = FrameParts {
        frame_buffer: readback::uniform_buffer(ctx, "frame", &frame),
        frame,
        raster,
        shade,
        geometry_tiles,
        visibility,
        scene_gpu,
        gbuffer,
        maps_kept,
    };
    let fg = FrameGpu {
        ctx,
        scene,
        parts: &parts,
    };
    let camera = camera_uniform(scene);
    if method.times_frames_at_build() {
        // The screen as the first frame will draw it, so frames timed at build shade what a
        // frame shades (every frame draws it again).
        let mut enc = ctx.device.create_command_encoder(&Default::default());
        gbuffer_pass.record(ctx, &mut enc, &fg.scene_gpu, &camera, &fg.gbuffer);
        fg.shade.record_geometry_tiles(
            ctx,
            &mut enc,
            &fg.frame_buffer,
            &fg.gbuffer,
            &fg.geometry_tiles,
        );
        ctx.queue.submit([enc.finish()]);
    }
    let mut state = method.build(&fg)?;
    if let Some(m) = &memory {
        state.recall(m);
    }
    ctx.wait()?;
    let build_ms = start.elapsed().as_secs_f64() * 1e3;
    Ok(Created {
        parts,
        gbuffer_pass,
        camera,
        state,
        build: (build_ms, upload_ms),
        force_timestamps,
        raster_auto,
    })
}

impl<'a> Renderer<'a> {
    /// Lets go of the scene and the method's state, keeping what another scene can reuse.
    pub fn detach(mut self) -> Detached {
        for maps in self.state.release_maps() {
            self.parts.maps_kept.give(maps);
        }
        self.parts
            .maps_kept
            .trim(self.scene.render.shadow_map_budget_mib as u64 * 1024 * 1024);
        let FrameParts {
            scene_gpu,
            gbuffer,
            frame: _,
            frame_buffer: _,
            raster,
            shade,
            geometry_tiles,
            visibility,
            maps_kept,
        } = self.parts;
        let (ctx, scene) = (&*self.ctx, &*self.scene);
        Detached {
            maps_kept,
            device: ctx.device.clone(),
            memory: self.state.memory(),
            method: self.method,
            gbuffer_pass: self.gbuffer_pass,
            maps: raster.access(scene.render.maps),
            budget_mib: scene.render.shadow_map_budget_mib,
            shade,
            cull: scene.render.cull,
            raster,
            gbuffer,
            geometry_tiles,
            visibility,
            scene_gpu,
            vertices: scene.vertices.clone(),
            indices: scene.indices.clone(),
            force_timestamps: self.force_timestamps,
        }
    }

    /// Draws from `camera` from the next frame on. Only the G-buffer reads the camera, and it is
    /// drawn every frame: nothing is rebuilt. (The light, by contrast, is baked into the methods'
    /// shadow-map frusta when they are built.)
    pub fn set_camera(&mut self, camera: &crate::scene::Camera) {
        self.camera = crate::render::gbuffer::camera_uniform_for(&self.scene, camera);
        self.moved_camera = Some(camera.clone());
        self.state.camera_moved();
    }

    /// The screen-sized buffers the frame and the method created, by label (the size plan's
    /// names: tests check that `methods::sizes::plan` agrees).
    pub fn buffer_sizes(&self) -> Vec<(String, u64)> {
        let mut out = vec![
            ("visibility".to_string(), self.parts.visibility.size()),
            (
                "geometry tiles".to_string(),
                self.parts.geometry_tiles.bytes,
            ),
        ];
        out.extend(self.state.buffer_sizes());
        out
    }

    /// Records GPU timestamps from now on even on a CPU adapter, where the figures mean little
    /// (run.json never does this); tests use it to check the mechanics.
    pub fn force_gpu_timestamps(&mut self) {
        self.force_timestamps = true;
    }

    /// Tests: from the next frame on, the method keeps what its frame overwrites as it goes (each
    /// chunk's maps, each level's buffers) for [`Renderer::inspect`]. It adds read-backs.
    pub fn keep_intermediates(&mut self) {
        self.state.keep_intermediates();
    }

    /// After a frame: the method's maps and intermediate buffers as its CPU twins read them
    /// (`fixed_samples::FixedBuffers`, `single_map::SingleMapBuffers`, `adaptive::AdaptiveTrace`…);
    /// None when the method shows none or `T` is not its type.
    pub fn inspect<T: std::any::Any>(&mut self) -> Result<Option<T>> {
        let fg = FrameGpu {
            ctx: &self.ctx,
            scene: &self.scene,
            parts: &self.parts,
        };
        Ok(self
            .state
            .inspect(&fg)?
            .and_then(|b| b.downcast::<T>().ok())
            .map(|b| *b))
    }

    /// `hardware` or `compute`: who rasterizes this renderer's maps (the `raster` setting, `auto` resolved).
    pub fn raster_name(&self) -> &'static str {
        self.parts.raster.name()
    }

    /// Runs one frame. The method's per-frame state is reset before the clock starts (`setup`);
    /// `total_ms` is the wall time from the G-buffer (and the clear of V) to the visibility read-back.
    /// A frame that overflowed a list its method can grow (`MethodState::grow`) runs again; the
    /// time of the runs that overflowed is added to `total_ms`, their read-backs to the syncs.
    pub fn frame(&mut self, options: impl Into<FrameOptions>) -> Result<FrameResult> {
        let options = options.into();
        let mut lost_ms = 0.0;
        loop {
            let start = Instant::now();
            match self.attempt(options) {
                Err(Error::Overflow(_))
                    if self.state.grow(&FrameGpu {
                        ctx: &self.ctx,
                        scene: &self.scene,
                        parts: &self.parts,
                    })? =>
                {
                    lost_ms += start.elapsed().as_secs_f64() * 1e3
                }
                Ok(mut f) => {
                    f.total_ms += lost_ms;
                    return Ok(f);
                }
                Err(e) => return Err(e),
            }
        }
    }

    /// One run of a frame (`frame`).
    fn attempt(&mut self, options: FrameOptions) -> Result<FrameResult> {
        let setup_start = Instant::now();
        let fg = FrameGpu {
            ctx: &self.ctx,
            scene: &self.scene,
            parts: &self.parts,
        };
        let ctx = fg.ctx;
        let (w, h) = (fg.gbuffer.width, fg.gbuffer.height);
        let mut timer =
            StageTimer::new(options.mode).with_gpu_timestamps(ctx, self.force_timestamps);
        // A method's reset waits for its own zero fills; most have nothing to reset.
        self.state.reset(&fg)?;
        let mut setup_ms = setup_start.elapsed().as_secs_f64() * 1e3;
        let mut build_stages = BTreeMap::new();
        if let Some((build_ms, upload_ms)) = self.build.take() {
            setup_ms += build_ms;
            build_stages.insert(Stage::BUILD.name.to_string(), build_ms);
            build_stages.insert(Stage::UPLOAD.name.to_string(), upload_ms);
        }

        let frame_start = Instant::now();
        let fg = &fg;
        timer.stage(ctx, Stage::GBUFFER, |enc| {
            // Methods accumulate into V: clearing it is part of every frame.
            enc.clear_buffer(&fg.visibility, 0, None);
            self.gbuffer_pass
                .record(ctx, enc, &fg.scene_gpu, &self.camera, &fg.gbuffer);
            fg.shade.record_geometry_tiles(
                ctx,
                enc,
                &fg.frame_buffer,
                &fg.gbuffer,
                &fg.geometry_tiles,
            );
            Ok(())
        })?;
        let mut output = self.state.run(fg, &mut timer, options.pictures)?;
        timer.flush(ctx);
        let mut visibility: Vec<f32> = timer.cpu(Stage::READBACK, || {
            readback::read_buffer(ctx, &fg.visibility, w as u64 * h as u64 * 4)
        })?;
        let total_ms = frame_start.elapsed().as_secs_f64() * 1e3;
        self.state.finish(fg, &mut output)?;
        // Maps rendered and kept: the method's count, or (a method that keeps none) every map rendered.
        let size = fg.scene.render.shadow_map_size;
        let reuse = self
            .state
            .reuse()
            .unwrap_or_else(|| ReuseCounts::all_rendered(output.shadow_maps, size));
        let gbuffer = gbuffer::read_back(ctx, &fg.gbuffer)?;
        if gbuffer.geometry_count() == 0 {
            return Err(match &self.moved_camera {
                Some(c) => fg.scene.nothing_visible_from(c),
                None => fg.scene.nothing_visible(),
            });
        }
        // Σŵ = 1 up to rounding: clamp so V ∈ [0, 1] holds exactly; background stays 0.
        for (i, v) in visibility.iter_mut().enumerate() {
            *v = if gbuffer.is_geometry(i) {
                v.clamp(0.0, 1.0)
            } else {
                0.0
            };
        }
        let mut stages_ms = timer.stages_ms.clone();
        stages_ms.insert(Stage::SETUP.name.into(), setup_ms);
        stages_ms.extend(build_stages);
        let gpu_stages_ms = timer.gpu_stages_ms(ctx)?;
        let raster = RasterUsed {
            used: fg.raster.name(),
            setting: fg.scene.render.raster,
            auto: self.raster_auto,
        };
        Ok(FrameResult {
            visibility,
            gbuffer,
            output,
            stages_ms,
            total_ms,
            timing_waits: timer.timing_waits,
            timing: options.mode,
            gpu_stages_ms,
            raster,
            reuse,
        })
    }
}

/// A renderer between two scenes (frames of a sequence whose light, camera or mesh moves, the
/// scenes of a gallery): its G-buffer, shade and raster passes, targets, V and uploaded meshes,
/// without a method state. The shade kernels are most of what a new renderer compiles besides the
/// method's own.
pub struct Detached {
    /// The device every kept object belongs to.
    device: wgpu::Device,
    method: Method,
    /// The method state's memory across frames (`MethodState::memory`).
    memory: Option<serde_json::Value>,
    gbuffer_pass: GBufferPass,
    /// `shade` was built for this map access, `raster` for this culling and budget.
    maps: MapAccess,
    budget_mib: u32,
    shade: ShadePass,
    cull: CullMode,
    raster: Raster,
    gbuffer: GBuffer,
    geometry_tiles: GeometryTiles,
    visibility: wgpu::Buffer,
    scene_gpu: SceneGpu,
    /// The method's shadow maps, kept for the next frame where reuse is on (docs/reuse.md).
    maps_kept: MapCache,
    /// What `scene_gpu` holds: a scene with the same meshes is not uploaded again.
    vertices: Vec<Vertex>,
    indices: Vec<u32>,
    force_timestamps: bool,
}

impl Detached {
    /// The maps the renderer keeps for its next frame (docs/reuse.md).
    pub fn maps_kept(&self) -> &MapCache {
        &self.maps_kept
    }

    /// The same method's renderer for `scene`, on the context it was built on: what the scene
    /// changes is built again, the method's state always (see `Renderer::assemble`). Its first frame
    /// carries `build`.
    pub fn attach<'a>(
        self,
        ctx: impl Into<Held<'a, GpuContext>>,
        scene: impl Into<Held<'a, Scene>>,
    ) -> Result<Renderer<'a>> {
        let method = self.method.clone();
        self.attach_as(ctx, scene, &method)
    }

    /// As [`Detached::attach`], for any method: nothing kept here belongs to a method (what a
    /// method's sizes change, `assemble` builds again), so the configurations of a sweep hand it
    /// from one to the next.
    pub fn attach_as<'a>(
        self,
        ctx: impl Into<Held<'a, GpuContext>>,
        scene: impl Into<Held<'a, Scene>>,
        method: &Method,
    ) -> Result<Renderer<'a>> {
        let ctx = ctx.into();
        if self.device != ctx.device {
            return Err(crate::Error::Gpu(
                "a detached renderer was attached on another device than its own".into(),
            ));
        }
        let reuse = self.maps_kept.on;
        Renderer::assemble(ctx, scene.into(), method, Some(self), reuse)
    }
}

/// One frame of `scene` with `method` on a fresh renderer (build included in `setup`). Several
/// frames of the same scene and method should share one [`Renderer`].
pub fn render(
    ctx: &GpuContext,
    scene: &Scene,
    method: &Method,
    options: impl Into<FrameOptions>,
) -> Result<FrameResult> {
    Renderer::new(ctx, scene, method)?.frame(options)
}

/// Only the camera G-buffer of `scene`: what the CPU reference traces from. Same pass, same
/// uniforms as `render`, so its pixels are the points every method shades.
pub fn gbuffer_only(ctx: &GpuContext, scene: &Scene) -> Result<GBufferCpu> {
    crate::methods::sizes::check(ctx, scene, &Method::hard())?;
    let pass = GBufferPass::new(ctx)?;
    let target = GBufferPass::allocate(ctx, scene.render.width, scene.render.height)?;
    let scene_gpu = SceneGpu::upload(ctx, scene);
    let mut encoder = ctx
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some(Stage::GBUFFER.name),
        });
    pass.record(
        ctx,
        &mut encoder,
        &scene_gpu,
        &camera_uniform(scene),
        &target,
    );
    ctx.queue.submit([encoder.finish()]);
    gbuffer::read_back(ctx, &target)
}
