//! Per-stage benchmarks, one criterion group per stage: shadow_raster, gbuffer, raster_compute
//! (against shadow_raster on the same 25 maps), reproject_count,
//! neighbourhood, quad_count + subdivide, shade, hybrid_build (and shade on hybrid maps). Throughput is in the stage's own unit (triangles,
//! pixels, pixel·quad evaluations, pixel·map lookups). The adapter is printed first: absolute
//! figures mean nothing without it.
//!
//! shadow_raster and gbuffer drive their passes directly. The adaptive count stages are measured
//! twice: inside whole adaptive frames in TimingMode::Stages (submit + wait after every stage,
//! each iteration charged the stage's wall time from FrameResult::stages_ms: the real inputs), and
//! driven alone on synthetic inputs (`adaptive_stage_alone`, and compact, probe and weights in
//! `adaptive_local_stage_alone`: typed inputs, one pass per iteration).
//!
//! reference_tracer (the CPU ground truth's rays per second) is the lab's: lab/benches/tracer.rs.
//!
//! Short run: `cargo bench --bench stages -- --warm-up-time 1 --measurement-time 3`.

mod alone;
mod frames;
mod raster;
mod raster_compute;
mod scenes;

use criterion::Criterion;
use penumbra::research::gpu::GpuContext;

fn main() {
    // Headless: the Vulkan loader probes Wayland, which prints an error line when this is unset.
    if std::env::var_os("XDG_RUNTIME_DIR").is_none() {
        std::env::set_var("XDG_RUNTIME_DIR", std::env::temp_dir());
    }
    std::env::set_var("PENUMBRA_NO_PROGRESS", "1");
    let ctx = GpuContext::new().unwrap_or_else(|e| panic!("benches need a GPU adapter: {e}"));
    let s = &ctx.summary;
    println!(
        "adapter: {} ({}, {}, {} {})",
        s.name, s.backend, s.device_type, s.driver, s.driver_info
    );
    println!("clock: wall clock, submit → device wait (GPU timestamps are not used)");
    let mut c = Criterion::default().configure_from_args();
    raster::shadow_raster(&mut c, &ctx);
    raster::gbuffer(&mut c, &ctx);
    raster_compute::raster_compute(&mut c, &ctx);
    let mut adaptive = frames::FramePool::new(&ctx, scenes::stage_scene(), "adaptive:p_m=0");
    frames::adaptive_stages(&mut c, &mut adaptive);
    alone::adaptive_stages_alone(&mut c, &ctx);
    alone::local_stages_alone(&mut c, &ctx);
    let mut regular = frames::FramePool::new(&ctx, scenes::stage_scene(), "regular:n=17");
    frames::shade(&mut c, &mut adaptive, &mut regular);
    frames::hybrid(&mut c, &ctx, scenes::stage_scene());
    c.final_summary();
}
